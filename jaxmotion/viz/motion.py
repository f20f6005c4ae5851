"""Pictures of motion datasets: grids of classes x modes (an animation, or a still of key poses), filmstrips, a
multi-action take (a strip of poses over its tag timeline, or an animation with a moving cursor) and a dataset's tag
transition matrix. ``python -m jaxmotion.viz.preview`` draws them from the command line.

Animations are :class:`~jaxmotion.viz.scene.FrameRenderer`'s (cameras, captions, frame counter, legend; see
:mod:`jaxmotion.viz.scene`), written by :func:`~jaxmotion.viz.video.write_video` as the path's suffix says: ``.gif``,
or ``.mp4`` with the ``video`` extra. Stills are PNGs drawn with the same colours and legend, orthographic and level
with the ground, never mirrored, each pose seen from the front of person 0 at frame 0: ``front`` (the subject's left
on the viewer's right), ``side`` (seen from the subject's right, forward to the right) and ``oblique`` (in between).
Poses stand side by side, each centred on its persons' mean root, over a floor line (y = 0); a strip that would be
wider than 3.5 times its height wraps into rows, and a picture is at least 300 pixels tall.

Several persons (interactions, fights) are drawn together, each in its own colours
(:data:`~jaxmotion.viz.scene.PALETTES`), the legend naming them.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from pathlib import Path

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.collections import LineCollection
from matplotlib.figure import Figure

from jaxmotion.data.motion import Motion, MotionDataset, person_axis
from jaxmotion.data.segments import transition_counts
from jaxmotion.geometry.skeletons import Skeleton
from jaxmotion.viz.scene import (
    VIEWS,
    Camera,
    FrameRenderer,
    Timeline,
    add_legend,
    bone_colours,
    draw_timeline,
    facing,
    legend_layout,
    make_scene,
    person_labels,
    take_captions,
    wrap,
)
from jaxmotion.viz.video import save_animation

#: The widest a still picture gets, as a multiple of its height, before its poses wrap into rows.
MAX_RATIO = 3.5
#: The fewest pixels a still picture is tall.
MIN_HEIGHT = 300
_SCALE = 1.1  # inches a metre in still pictures
_FLOOR_GAP = 0.25  # metres under the floor line, for labels


def _people(motion: Motion) -> np.ndarray:
    """``[P, T, J, 3]`` a record's joints, with the persons axis whatever its number of persons."""
    return person_axis(motion.joints, motion.persons, axis=0)


def _on_floor(people: np.ndarray) -> np.ndarray:
    """``[P, T, J, 3]`` raised or lowered so the lowest joint of the clip touches the floor (y = 0): motions
    in a model's frame (root of frame 0 at the origin) are then drawn like captured ones."""
    return people - np.array([0.0, people[..., 1].min(), 0.0])


def _still_camera(people: np.ndarray, skeleton: Skeleton, view: str) -> Camera:
    if view not in VIEWS:
        raise ValueError(f"views: expected names among {list(VIEWS)}, got {view!r}")
    return Camera.looking(*facing(people[0, 0], skeleton), VIEWS[view], 0.0)


def _rows(count: int, width: float, height: float, fixed_width: float, fixed_height: float, repeat: int = 1) -> int:
    """How many rows ``count`` items of ``width`` x ``height`` inches take, the fewest keeping the picture (with
    ``fixed_width`` and ``fixed_height`` inches of margins, ``repeat`` blocks of rows stacked) at most
    :data:`MAX_RATIO` wide."""
    for rows in range(1, count + 1):
        across = math.ceil(count / rows)
        if across * width + fixed_width <= MAX_RATIO * (repeat * rows * height + fixed_height):
            return rows
    return count


def _figure(width: float, height: float, dpi: float = 80) -> tuple[Figure, float]:
    """A figure of ``width`` x ``height`` inches on an Agg canvas, and the dpi it is saved at (raised to
    :data:`MIN_HEIGHT` pixels)."""
    fig = Figure(figsize=(width, height), facecolor="white")
    FigureCanvasAgg(fig)
    return fig, max(dpi, MIN_HEIGHT / height)


def _axes(fig: Figure, left: float, bottom: float, width: float, height: float):
    """An axes at a rectangle given in inches from the figure's bottom left."""
    w, h = fig.get_size_inches()
    return fig.add_axes((left / w, bottom / h, width / w, height / h))


def _top(people: np.ndarray) -> float:
    return max(2.2, float(people[..., 1].max()) + 0.1)


def _spacing(people: np.ndarray, camera: Camera, frames: np.ndarray, single: float) -> float:
    """Metres between neighbouring poses ``people[:, frames]``: ``single`` for one person (outstretched arms may
    touch the next pose's, as a strip stays compact), and for several so that no group overlaps the next: the
    widest group's reach either side of its mean root, twice, plus 0.6 m."""
    if len(people) == 1:
        return single
    screen = camera.project(people[:, frames])[..., 0]  # [P, K, J]
    reach = np.abs(screen - screen[:, :, :1].mean(axis=0, keepdims=True)).max()
    return max(single, 2 * float(reach) + 0.6)


def _poses(ax, people: np.ndarray, skeleton: Skeleton, camera: Camera, frames: np.ndarray, *, spacing: float,
           per_row: int, top: float, linewidth: float, labels: Sequence[str] = ()) -> None:
    """Poses ``people[:, frames]`` (``[P, T, J, 3]``) in rows of ``per_row``, ``spacing`` metres apart, each
    centred on its persons' mean root and standing on its row's floor line, ``labels`` under them; the axes'
    limits are the rows' extent, so that an axes of that shape in inches draws one metric scale."""
    screen = camera.project(people)  # [P, T, J, 3]
    row_height = top + _FLOOR_GAP
    bones = np.array(skeleton.bones).reshape(-1, 2)
    for k, f in enumerate(frames):
        row, column = divmod(k, per_row)
        shift = np.array([column * spacing - screen[:, f, 0, 0].mean(), -row * row_height])
        for person in range(len(people)):
            segments = screen[person, f][bones][..., :2] + shift
            ax.add_collection(LineCollection(segments, colors=bone_colours(skeleton, person), linewidths=linewidth,
                                             capstyle="round"))
        if labels:
            ax.text(column * spacing, -row * row_height - 0.12, labels[k], ha="center", va="center", fontsize=7)
    rows = math.ceil(len(frames) / per_row)
    for row in range(rows):
        ax.plot([-0.5 * spacing, (per_row - 0.5) * spacing], [-row * row_height] * 2, color="0.6", lw=1)
    ax.set_xlim(-0.5 * spacing, (per_row - 0.5) * spacing)
    ax.set_ylim(-(rows - 1) * row_height - _FLOOR_GAP, top)
    ax.set_axis_off()


def _legend(fig: Figure, persons: int, bottom: float, width: float) -> float:
    """The legend at the figure's foot, ``bottom`` inches up; returns the inches it takes."""
    labels = person_labels(persons)
    columns, rows = legend_layout(labels, mesh=False, width=width)
    height = 0.1 + 0.22 * rows
    add_legend(fig, labels, mesh=False, y=(bottom + height / 2) / fig.get_size_inches()[1], columns=columns)
    return height


def _legend_height(persons: int, width: float) -> float:
    return 0.1 + 0.22 * legend_layout(person_labels(persons), mesh=False, width=width)[1]


def filmstrip(motion: Motion, skeleton: Skeleton, path: str | Path, *, frames: int = 8,
              views: Sequence[str] = ("front", "side"), title: str = "") -> None:
    """Save a PNG: ``frames`` evenly spaced poses of ``motion`` (frame numbers under them), one block per view
    (:data:`~jaxmotion.viz.scene.VIEWS`), each pose centred on its own root (several persons: on their mean root,
    spaced wider); the floor line (y = 0) shows contact."""
    if frames < 1:
        raise ValueError(f"frames: expected >= 1, got {frames}")
    people = _people(motion)
    index = np.linspace(0, motion.num_frames - 1, frames).round().astype(int)
    cameras = [_still_camera(people, skeleton, view) for view in views]
    spacing = max(_spacing(people, camera, index, 1.0) for camera in cameras)
    top = _top(people)
    row_height = (top + _FLOOR_GAP) * _SCALE
    margin_left, margin_right, header = 0.3, 0.1, 0.35
    rows = _rows(frames, spacing * _SCALE, row_height, margin_left + margin_right, header + 0.4, len(views))
    per_row = math.ceil(frames / rows)
    width = margin_left + per_row * spacing * _SCALE + margin_right
    footer = _legend_height(motion.persons, width)
    height = header + len(views) * rows * row_height + footer
    fig, dpi = _figure(width, height)
    for v, (view, camera) in enumerate(zip(views, cameras, strict=True)):
        bottom = footer + (len(views) - 1 - v) * rows * row_height
        ax = _axes(fig, margin_left, bottom, per_row * spacing * _SCALE, rows * row_height)
        _poses(ax, people, skeleton, camera, index, spacing=spacing, per_row=per_row, top=top, linewidth=2.0,
               labels=[str(f) for f in index])
        fig.text(0.12 / width, (bottom + rows * row_height / 2) / height, view, rotation=90, ha="center",
                 va="center", fontsize=8)
    if title:
        fig.text(0.5, 1 - 0.05 / height, wrap(title, width - 0.2, 9), ha="center", va="top", fontsize=9)
    _legend(fig, motion.persons, 0.0, width)
    fig.savefig(path, dpi=dpi)


def _examples(data: MotionDataset, classes: Sequence[int]) -> list[list[tuple[int, int, Motion | None]]]:
    """For each class, one motion per mode (the first of that mode), or None where the mode is missing."""
    outside = [c for c in classes if not 0 <= c < data.num_classes]
    if outside:
        raise ValueError(f"classes: expected class indices of {data.name} in [0, {data.num_classes}), got {outside}")
    rows = []
    for c in classes:
        modes = data.mode_names[c] if data.mode_names else ("",)
        row = []
        for m in range(len(modes)):
            hit = np.flatnonzero((data.actions == c) & ((data.modes == m) if data.mode_names else True))
            row.append((c, m, data[int(hit[0])] if len(hit) else None))
        rows.append(row)
    return rows


def _cell_title(data: MotionDataset, c: int, m: int) -> str:
    return data.class_names[c] + (f" / {data.mode_names[c][m]}" if data.mode_names else "")


def grid_figure(data: MotionDataset, classes: Sequence[int], *, key_frames: int = 5) -> tuple[Figure, float]:
    """The still grid of :func:`render_grid` and the dpi to save it at: per class a row, per mode a cell showing
    ``key_frames`` evenly spaced poses (oblique view), the cells' poses wrapped into rows when the grid would be
    wider than :data:`MAX_RATIO` times its height; each cell titled ``class / mode``, wrapped to its width."""
    if key_frames < 1:
        raise ValueError(f"key_frames: expected >= 1, got {key_frames}")
    rows = _examples(data, classes)
    columns = max(len(r) for r in rows)
    drawn = []
    for i, row in enumerate(rows):
        for j, (_, _, motion) in enumerate(row):
            if motion is not None:
                people = _on_floor(_people(motion))
                picks = np.linspace(0, people.shape[1] - 1, key_frames).round().astype(int)
                drawn.append((i, j, people, _still_camera(people, data.skeleton, "oblique"), picks))
    spacing = max(_spacing(people, camera, picks, 0.9) for *_, people, camera, picks in drawn)
    top = max(_top(people) for _, _, people, _, _ in drawn)
    row_height = (top + _FLOOR_GAP) * _SCALE
    gap = 0.15  # inches between cells
    cell_width = key_frames * spacing * _SCALE
    size = 8.0
    titles = [[wrap(_cell_title(data, c, m), cell_width, size) for c, m, _ in row] for row in rows]
    band = max(t.count("\n") + 1 for row in titles for t in row) * size * 1.3 / 72 + 0.08
    # the titles' band as wrapped at the widest cells (the fewest lines): the height is then never overestimated
    pose_rows = _rows(key_frames, columns * spacing * _SCALE, row_height, columns * gap,
                      (band + gap) * len(rows) + 0.4, len(rows))
    per_row = math.ceil(key_frames / pose_rows)
    cell_width = per_row * spacing * _SCALE
    cell_height = pose_rows * row_height
    width = columns * (cell_width + gap)
    titles = [[wrap(_cell_title(data, c, m), cell_width, size) for c, m, _ in row] for row in rows]
    band = max(t.count("\n") + 1 for row in titles for t in row) * size * 1.3 / 72 + 0.08
    footer = _legend_height(data.persons, width)
    height = len(rows) * (band + cell_height + gap) + footer
    fig, dpi = _figure(width, height, dpi=70)
    for i, j, people, camera, picks in drawn:
        bottom = height - (i + 1) * (band + cell_height + gap) + gap
        ax = _axes(fig, j * (cell_width + gap) + gap / 2, bottom, cell_width, cell_height)
        _poses(ax, people, data.skeleton, camera, picks, spacing=spacing, per_row=per_row, top=top, linewidth=1.4)
    for i, row in enumerate(titles):
        for j, title in enumerate(row):
            fig.text((j * (cell_width + gap) + gap / 2 + cell_width / 2) / width,
                     (height - i * (band + cell_height + gap) - 0.04) / height, title, ha="center", va="top",
                     fontsize=size, linespacing=1.1)
    _legend(fig, data.persons, 0.0, width)
    return fig, dpi


def grid_scenes(data: MotionDataset, classes: Sequence[int]) -> tuple[list, int]:
    """The scenes of :func:`render_grid`'s animation, row-major (None where a mode has no example), and the
    number of columns."""
    rows = _examples(data, classes)
    columns = max(len(r) for r in rows)
    scenes = []
    for row in rows:
        for c, m, motion in row + [(0, 0, None)] * (columns - len(row)):
            scenes.append(None if motion is None else make_scene(_people(motion), data.skeleton,
                                                                 captions=_cell_title(data, c, m)))
    return scenes, columns


def render_grid(data: MotionDataset, classes: Sequence[int], path: str | Path, *, still: bool = False,
                max_frames: int = 80, key_frames: int = 5, camera: str = "auto") -> None:
    """Save a grid (rows = classes, columns = modes; one example each): an animation (``.gif``, or ``.mp4`` with
    the ``video`` extra) of the first ``max_frames`` frames with ``camera`` per cell (``auto``: ``world`` for
    locomotion; :mod:`jaxmotion.viz.scene`), or with ``still`` a PNG (:func:`grid_figure`). Each motion stands on
    the floor line (its lowest joint over the clip at height 0)."""
    if still:
        fig, dpi = grid_figure(data, classes, key_frames=key_frames)
        fig.savefig(path, dpi=dpi)
        return
    scenes, columns = grid_scenes(data, classes)
    longest = max(s.num_frames for s in scenes if s is not None)
    save_animation(path, FrameRenderer(scenes, data.fps, columns=columns, camera=camera,
                                       frames=min(longest, max_frames)))


def take_strip(data: MotionDataset, index: int, path: str | Path, *, frames: int = 12) -> None:
    """Save a PNG of take ``index`` of a multi-action dataset: ``frames`` evenly spaced poses (oblique view, their
    times under them; in rows when one would be too wide) above its tag timeline, each pose's time marked on it."""
    if frames < 1:
        raise ValueError(f"frames: expected >= 1, got {frames}")
    motion = _take(data, index)
    people = _on_floor(_people(motion))
    picks = np.linspace(0, motion.num_frames - 1, frames).round().astype(int)
    camera = _still_camera(people, data.skeleton, "oblique")
    spacing = _spacing(people, camera, picks, 0.9)
    top = _top(people)
    row_height = (top + _FLOOR_GAP) * _SCALE
    header, strip, margin = 0.35, 1.0, 0.2
    rows = _rows(frames, spacing * _SCALE, row_height, 2 * margin, header + strip + 0.4)
    per_row = math.ceil(frames / rows)
    width = max(2 * margin + per_row * spacing * _SCALE, 5.0)
    footer = _legend_height(motion.persons, width)
    height = header + rows * row_height + strip + footer
    fig, dpi = _figure(width, height)
    ax = _axes(fig, (width - per_row * spacing * _SCALE) / 2, footer + strip, per_row * spacing * _SCALE,
               rows * row_height)
    _poses(ax, people, data.skeleton, camera, picks, spacing=spacing, per_row=per_row, top=top, linewidth=1.4,
           labels=[f"{f / data.fps:.1f} s" for f in picks])
    fig.text(0.5, 1 - 0.05 / height, wrap(f"{data.name}/{data.split}: {motion.name}", width - 0.2, 9), ha="center",
             va="top", fontsize=9)
    line = _axes(fig, 0.4, footer + 0.45, width - 0.6, strip - 0.55)
    draw_timeline(line, motion.segments, data.class_names, data.fps, motion.num_frames)
    for f in picks:
        line.axvline(f / data.fps, color="0.3", lw=0.6, ls=":")
    _legend(fig, motion.persons, 0.0, width)
    fig.savefig(path, dpi=dpi)


def take_animation(data: MotionDataset, index: int, path: str | Path, *, camera: str = "auto") -> None:
    """Save an animation (``.gif``, or ``.mp4`` with the ``video`` extra) of take ``index`` of a multi-action
    dataset: the body in 3D (``camera``: :mod:`jaxmotion.viz.scene`), the current action's tags as the caption,
    and the tag timeline with a moving cursor."""
    motion = _take(data, index)
    scene = make_scene(_people(motion), data.skeleton,
                       captions=take_captions(motion.segments, data.class_names, motion.num_frames))
    renderer = FrameRenderer([scene], data.fps, camera=camera, timeline=Timeline(motion.segments, data.class_names),
                             cell=4.8, dpi=80)
    save_animation(path, renderer)


def transition_heatmap(data: MotionDataset, path: str | Path) -> None:
    """Save a PNG of the dataset's tag transition counts (row: an action's tag, column: the next action's), on a
    log colour scale; empty pairs white."""
    if data.segments is None:
        raise ValueError(f"{data.name}/{data.split}: holds one action per sequence; the transition matrix needs "
                         f"a multi-action dataset")
    counts = transition_counts(data.segments).astype(float)
    fig = Figure(figsize=(8.5, 8))
    ax = fig.subplots()
    shown = np.ma.masked_equal(np.log10(np.maximum(counts, 1)) + (counts > 0), 0.0)  # 1 -> 1, 10 -> 2, ...
    image = ax.imshow(shown, cmap="viridis", vmin=1.0)
    ticks = np.arange(data.num_classes)
    ax.set_xticks(ticks, data.class_names, rotation=90, fontsize=7)
    ax.set_yticks(ticks, data.class_names, fontsize=7)
    ax.set_xlabel("next action's tag")
    ax.set_ylabel("action's tag")
    occupied = (counts > 0).mean()
    ax.set_title(f"{data.name}/{data.split}: tag transitions ({int(counts.sum())} in all, {100 * occupied:.0f}% "
                 f"of pairs occur)", fontsize=9)
    bar = fig.colorbar(image, ax=ax, shrink=0.7)
    decades = np.arange(1, int(shown.max()) + 1)
    bar.set_ticks(decades, labels=[f"{10 ** (d - 1):g}" for d in decades])
    fig.tight_layout()
    fig.savefig(path, dpi=80)


def _take(data: MotionDataset, index: int) -> Motion:
    if data.segments is None:
        raise ValueError(f"{data.name}/{data.split}: holds one action per sequence; --take needs a multi-action "
                         f"dataset (synth-mag)")
    if not 0 <= index < len(data):
        raise ValueError(f"take: expected an index in [0, {len(data)}) of {data.name}/{data.split}, got {index}")
    return data[index]
