"""Look at motion datasets: stick-figure grids (classes x modes) as GIF or PNG, filmstrips, and for multi-action
datasets a whole take with its tag timeline and the tag transition matrix.

    python -m jaxmotion.data.preview synth-humanact12 --classes 0,1,2 --out preview.gif
    python -m jaxmotion.data.preview synth-humanact12 --classes 0,1,2 --out preview.png --png
    python -m jaxmotion.data.preview synth-mag --take 0 --out take.gif          # or --png for a strip
    python -m jaxmotion.data.preview synth-mag --transitions --out transitions.png

Rendering is matplotlib (Agg); the GIF uses matplotlib's PillowWriter. Colours: the subject's left
side blue, right side red, midline black; the floor (y = 0) is grey. 2D views are orthographic and never
mirrored, with the subject turned to face +Z at frame 0: ``front`` (the subject's left on the viewer's
right), ``side`` (seen from the subject's right, forward to the right) and ``oblique`` (in between); the
GIF grid is 3D, each cell following its root.

Several persons (interactions, fights) are drawn together, each in its own colours (person 0 as above,
then cyan/orange, green/olive, purple/pink, brown/gold), turned so that person 0 faces +Z at frame 0, each
pose or cell centred on the persons' mean root instead of one root.
"""

from __future__ import annotations

import argparse
from collections.abc import Sequence
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
from matplotlib.animation import FuncAnimation, PillowWriter

from jaxmotion.data.motion import Motion, MotionDataset, person_axis
from jaxmotion.data.segments import Segments, transition_counts
from jaxmotion.geometry.skeletons import Skeleton
from jaxmotion.progress import phase

# Each view is the world direction drawn to the image's right (vertical is always +Y), in the frame where
# the subject faces +Z. The camera then sits at right x up: front (+X right) looks at the subject's front,
# side (+Z right) from the subject's right, oblique in between. None of them is mirrored.
_VIEWS = {"front": np.array([1.0, 0.0, 0.0]), "side": np.array([0.0, 0.0, 1.0]),
          "oblique": np.array([0.8, 0.0, 0.6])}
#: Per person: (left, right, midline) colours.
_PALETTES = (("tab:blue", "tab:red", "black"), ("tab:cyan", "tab:orange", "dimgray"),
             ("tab:green", "tab:olive", "darkgreen"), ("tab:purple", "tab:pink", "indigo"),
             ("tab:brown", "gold", "saddlebrown"))


def _side_of(joint_name: str) -> str:
    """``left`` / ``right`` / ``""`` from names like ``left_knee`` or VIBE's ``LKnee``."""
    for side in ("left", "right"):
        letter = side[0].upper()
        if joint_name.lower().startswith(side) or (joint_name[:1] == letter and joint_name[1:2].isupper()):
            return side
    return ""


def _bone_colours(skeleton: Skeleton, person: int = 0) -> list[str]:
    left, right, mid = _PALETTES[person % len(_PALETTES)]
    return [{"left": left, "right": right}.get(_side_of(skeleton.joint_names[child]), mid) for _, child in skeleton.bones]


def _people(motion: Motion) -> np.ndarray:
    """``[P, T, J, 3]`` a record's joints, with the persons axis whatever its number of persons."""
    return person_axis(motion.joints, motion.persons, axis=0)


def _draw_2d(ax, people: np.ndarray, skeleton: Skeleton, view: str, shift: float = 0.0, lw: float = 2.0):
    """One pose ``[P, J, 3]`` of the persons seen from ``view``, centred on their mean root and moved ``shift``
    to the right."""
    centre = people[:, 0].mean(axis=0)
    for person, joints in enumerate(people):
        across = (joints - centre) @ _VIEWS[view] + shift
        for (parent, child), colour in zip(skeleton.bones, _bone_colours(skeleton, person), strict=True):
            ax.plot([across[parent], across[child]], [joints[parent, 1], joints[child, 1]], color=colour, lw=lw,
                    solid_capstyle="round")


def _strip(ax, people: np.ndarray, skeleton: Skeleton, frames: np.ndarray, view: str, spacing: float,
           lw: float = 2.0, labels: bool = True) -> None:
    """Poses ``people[:, frames]`` (``[P, T, J, 3]``) side by side on ``ax``, each centred on its mean root, over
    the floor line."""
    for k, f in enumerate(frames):
        _draw_2d(ax, people[:, f], skeleton, view, shift=k * spacing, lw=lw)
        if labels:
            ax.text(k * spacing, -0.12, f"{f}", ha="center", fontsize=7)
    ax.axhline(0.0, color="0.6", lw=1)
    ax.set_xlim(-0.6 * spacing, (len(frames) - 0.4) * spacing)
    ax.set_ylim(-0.2, 2.2)
    ax.set_aspect("equal")
    ax.set_xticks([])


def _facing_viewer(people: np.ndarray, skeleton: Skeleton) -> np.ndarray:
    """``[P, T, J, 3]`` turned about +Y so that person 0 faces +Z at frame 0 (the ``front`` view sees its front)."""
    names = [n.lower() for n in skeleton.joint_names]
    left = next(i for i, n in enumerate(skeleton.joint_names) if _side_of(n) == "left" and "hip" in names[i])
    right = next(i for i, n in enumerate(skeleton.joint_names) if _side_of(n) == "right" and "hip" in names[i])
    across = people[0, 0, left] - people[0, 0, right]
    angle = np.arctan2(-across[2], across[0])  # rotation taking the hip axis onto +X
    c, s = np.cos(angle), np.sin(angle)
    turn = np.array([[c, 0.0, -s], [0.0, 1.0, 0.0], [s, 0.0, c]])
    return people @ turn.T


def filmstrip(motion: Motion, skeleton: Skeleton, path: str, *, frames: int = 8, views=("front", "side"),
              title: str = "") -> None:
    """Save a PNG: ``frames`` evenly spaced poses side by side, one row per view, each pose centred on its
    own root (several persons: on their mean root, spaced wider); the floor line shows contact."""
    index = np.linspace(0, motion.num_frames - 1, frames).round().astype(int)
    people = _facing_viewer(_people(motion), skeleton)
    spacing = 1.0 if motion.persons == 1 else 1.2 + 0.8 * motion.persons
    fig, axes = plt.subplots(len(views), 1, figsize=(1.3 * spacing * frames, 2.6 * len(views)), squeeze=False)
    for ax, view in zip(axes[:, 0], views, strict=True):
        _strip(ax, people, skeleton, index, view, spacing=spacing)
        ax.set_ylabel(view)
    axes[0, 0].set_title(title, fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=80)
    plt.close(fig)


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


def _grid_axes(rows, data: MotionDataset, *, three_d: bool, cell_width: float):
    width = max(len(r) for r in rows)
    fig = plt.figure(figsize=(cell_width * width, 2.6 * len(rows)))
    cells = []
    for i, row in enumerate(rows):
        for j, (c, m, motion) in enumerate(row):
            options = {"projection": "3d", "proj_type": "ortho"} if three_d else {}
            ax = fig.add_subplot(len(rows), width, i * width + j + 1, **options)
            label = data.class_names[c] + (f" / {data.mode_names[c][m]}" if data.mode_names else "")
            ax.set_title(label, fontsize=8)
            if not three_d:
                ax.set_axis_off()
            cells.append((ax, motion))
    return fig, cells


def _draw_3d(ax, people: np.ndarray, skeleton: Skeleton, half: float = 1.0) -> None:
    """One pose ``[P, J, 3]`` of the persons in a 3D cell that follows their mean root, over a floor grid
    ``2 half`` metres wide."""
    title = ax.get_title()
    ax.cla()
    ax.set_title(title, fontsize=8)
    centre = people[:, 0].mean(axis=0)
    for person, joints in enumerate(people):
        p = joints - np.array([centre[0], 0.0, centre[2]])
        for (parent, child), colour in zip(skeleton.bones, _bone_colours(skeleton, person), strict=True):
            # Library +Y up -> matplotlib's vertical z; world z (forward) -> plot y.
            ax.plot([p[parent, 0], p[child, 0]], [p[parent, 2], p[child, 2]], [p[parent, 1], p[child, 1]],
                    color=colour, lw=1.8)
    for x in np.linspace(-half, half, 5):
        ax.plot([x, x], [-half, half], [0, 0], color="0.85", lw=0.6)
        ax.plot([-half, half], [x, x], [0, 0], color="0.85", lw=0.6)
    ax.set_xlim(-half, half)
    ax.set_ylim(-half, half)
    ax.set_zlim(0, max(2.0, half))
    ax.set_box_aspect((1, 1, 1) if half <= 2.0 else (1, 1, 2.0 / half))
    ax.view_init(elev=12, azim=60)
    ax.set_axis_off()


def _on_floor(people: np.ndarray) -> np.ndarray:
    """``[P, T, J, 3]`` raised or lowered so the lowest joint of the clip touches the floor (y = 0): motions
    in a model's frame (root of frame 0 at the origin) are then drawn like captured ones."""
    return people - np.array([0.0, people[..., 1].min(), 0.0])


def render_grid(data: MotionDataset, classes: Sequence[int], path: str, *, still: bool = False,
                max_frames: int = 80, key_frames: int = 5) -> None:
    """Save a grid (rows = classes, columns = modes; one example each): an animated GIF of 3D skeletons
    following their root, or with ``still`` a PNG where each cell shows ``key_frames`` evenly spaced poses
    side by side (oblique view, each centred on its root, facing the viewer at frame 0). Each motion
    stands on the floor line (its lowest joint over the clip at height 0)."""
    rows = _examples(data, classes)
    skeleton = data.skeleton
    wide = 1.0 if data.persons == 1 else (0.6 + 0.7 * data.persons) / 0.9  # a still cell per scene, not per body
    fig, cells = _grid_axes(rows, data, three_d=not still, cell_width=0.75 * wide * key_frames if still else 2.4 * wide)
    if still:
        for ax, motion in cells:
            if motion is not None:
                index = np.linspace(0, motion.num_frames - 1, key_frames).round().astype(int)
                _strip(ax, _facing_viewer(_on_floor(_people(motion)), skeleton), skeleton, index, "oblique",
                       spacing=0.9 if data.persons == 1 else 0.6 + 0.7 * data.persons, lw=1.4, labels=False)
                ax.set_axis_off()
        fig.tight_layout()
        fig.savefig(path, dpi=70)
        plt.close(fig)
        return
    length = min(max((m.num_frames for _, m in cells if m is not None), default=1), max_frames)
    grounded = [(ax, _on_floor(_people(motion))) for ax, motion in cells if motion is not None]  # once per clip
    half = 1.0 if data.persons == 1 else 0.6 + 0.5 * data.persons

    def update(frame):
        for ax, people in grounded:
            _draw_3d(ax, people[:, min(frame, people.shape[1] - 1)], skeleton, half)
        return []

    with phase(f"[render] {Path(path).name}", length, unit="frame") as bar:  # a GIF of a large grid takes minutes
        FuncAnimation(fig, update, frames=length).save(path, writer=PillowWriter(fps=data.fps),
                                                       progress_callback=lambda i, _: bar.update(i + 1))
    plt.close(fig)


def _timeline(ax, segments: Segments, tag_names: Sequence[str], fps: float, num_frames: int) -> None:
    """The actions of one take as labelled bars over time (s): a row per tag an action carries, lead-in bare."""
    rows = max(int(segments.tags.sum(axis=1).max()), 1) if len(segments) else 1
    for start, end, tags in zip(segments.start, segments.end, segments.tags, strict=True):
        for row, tag in enumerate(np.flatnonzero(tags)):
            colour = plt.cm.tab20(tag % 20)
            ax.barh(rows - 1 - row, (end - start) / fps, left=start / fps, height=0.8, color=colour,
                    edgecolor="white")
            ax.text((start + end) / (2 * fps), rows - 1 - row, tag_names[tag], ha="center", va="center", fontsize=6,
                    clip_on=True)
    ax.set_xlim(0, num_frames / fps)
    ax.set_ylim(-0.6, rows - 0.4)
    ax.set_yticks([])
    ax.set_xlabel("time (s)", fontsize=8)
    ax.tick_params(labelsize=7)


def take_strip(data: MotionDataset, index: int, path: str, *, frames: int = 12) -> None:
    """Save a PNG of take ``index`` of a multi-action dataset: ``frames`` evenly spaced poses (oblique view) above
    its tag timeline, each pose's time marked on it."""
    motion = _take(data, index)
    people = _facing_viewer(_on_floor(_people(motion)), data.skeleton)
    picks = np.linspace(0, motion.num_frames - 1, frames).round().astype(int)
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(0.9 * frames, 3.6), height_ratios=(3, 1.2))
    _strip(top, people, data.skeleton, picks, "oblique", spacing=0.9, lw=1.4, labels=False)
    top.set_axis_off()
    top.set_title(f"{data.name}/{data.split}: {motion.name}", fontsize=9)
    _timeline(bottom, motion.segments, data.class_names, data.fps, motion.num_frames)
    for f in picks:
        bottom.axvline(f / data.fps, color="0.3", lw=0.6, ls=":")
    fig.tight_layout()
    fig.savefig(path, dpi=80)
    plt.close(fig)


def take_animation(data: MotionDataset, index: int, path: str) -> None:
    """Save a GIF of take ``index`` of a multi-action dataset: the body in 3D following its root, the current
    action's tags as the title, and the tag timeline with a moving cursor."""
    motion = _take(data, index)
    people = _on_floor(_people(motion))
    seg = motion.segments
    fig = plt.figure(figsize=(4.8, 5.4))
    ax = fig.add_axes((0.0, 0.28, 1.0, 0.66), projection="3d", proj_type="ortho")
    line = fig.add_axes((0.06, 0.08, 0.9, 0.16))
    _timeline(line, seg, data.class_names, data.fps, motion.num_frames)
    cursor = line.axvline(0.0, color="black", lw=1.2)

    def update(frame):
        row = np.flatnonzero((seg.start <= frame) & (frame < seg.end))
        label = " + ".join(data.class_names[t] for t in np.flatnonzero(seg.tags[row[0]])) if len(row) else "(lead-in)"
        ax.set_title(label, fontsize=9)
        _draw_3d(ax, people[:, frame], data.skeleton, 1.2)
        cursor.set_xdata([frame / data.fps])
        return []

    with phase(f"[render] {Path(path).name}", motion.num_frames, unit="frame") as bar:
        FuncAnimation(fig, update, frames=motion.num_frames).save(
            path, writer=PillowWriter(fps=data.fps), dpi=64, progress_callback=lambda i, _: bar.update(i + 1))
    plt.close(fig)


def transition_heatmap(data: MotionDataset, path: str) -> None:
    """Save a PNG of the dataset's tag transition counts (row: an action's tag, column: the next action's), on a
    log colour scale; empty pairs white."""
    if data.segments is None:
        raise ValueError(f"{data.name}/{data.split}: holds one action per sequence; the transition matrix needs "
                         f"a multi-action dataset")
    counts = transition_counts(data.segments).astype(float)
    fig, ax = plt.subplots(figsize=(8.5, 8))
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
    plt.close(fig)


def _take(data: MotionDataset, index: int) -> Motion:
    if data.segments is None:
        raise ValueError(f"{data.name}/{data.split}: holds one action per sequence; --take needs a multi-action "
                         f"dataset (synth-mag)")
    if not 0 <= index < len(data):
        raise ValueError(f"take: expected an index in [0, {len(data)}) of {data.name}/{data.split}, got {index}")
    return data[index]


def main(argv: Sequence[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("dataset", help="a synthetic variant name, e.g. synth-humanact12")
    parser.add_argument("--classes", default="0,1,2", help="comma-separated class indices")
    parser.add_argument("--out", default="preview.gif")
    parser.add_argument("--png", action="store_true", help="save a still grid of key frames instead of a GIF")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--count", type=int, default=None,
                        help="generate only the first COUNT sequences (faster; enough for one per mode)")
    parser.add_argument("--split", default="train", help="the split to draw from (default: train)")
    parser.add_argument("--take", type=int, default=None,
                        help="a multi-action dataset: draw this take with its tag timeline (GIF, or --png a strip)")
    parser.add_argument("--transitions", action="store_true",
                        help="a multi-action dataset: draw the tag transition matrix (a PNG heat map)")
    args = parser.parse_args(argv)

    from jaxmotion.data import synthetic

    try:
        classes = [int(c) for c in args.classes.split(",")]
    except ValueError:
        parser.error(f"--classes: expected comma-separated class indices, got {args.classes!r}")
    try:
        data = synthetic.generate(args.dataset, args.split, seed=args.seed, count=args.count) if args.count else \
            synthetic.load(args.dataset, args.split, seed=args.seed)
        if args.transitions:
            transition_heatmap(data, args.out)
        elif args.take is not None:
            (take_strip if args.png else take_animation)(data, args.take, args.out)
        else:
            render_grid(data, classes, args.out, still=args.png)
    except (ValueError, FileNotFoundError) as err:  # what the checks raise: one line, as an experiment's
        raise SystemExit(f"jaxmotion.data.preview: {err}") from None
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
