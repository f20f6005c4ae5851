"""Look at motion datasets: stick-figure grids (classes x modes) as GIF or PNG, and filmstrips.

    python -m jaxmotion.data.preview synth-humanact12 --classes 0,1,2 --out preview.gif
    python -m jaxmotion.data.preview synth-humanact12 --classes 0,1,2 --out preview.png --png

Rendering is matplotlib (Agg); the GIF uses matplotlib's PillowWriter. Colours: the subject's left
side blue, right side red, midline black; the floor (y = 0) is grey. Views are orthographic: ``front``
(looking at the subject's front, so their left is on the viewer's right), ``side`` (from their left)
and ``three_quarter`` (3D).
"""

from __future__ import annotations

import argparse
from collections.abc import Sequence

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
from matplotlib.animation import FuncAnimation, PillowWriter

from jaxmotion.data.motion import Motion, MotionDataset
from jaxmotion.geometry.skeletons import Skeleton

_VIEWS = {"front": (0, 1), "side": (2, 1)}  # projected (horizontal, vertical) world axes
_SIDE_COLOURS = {"left": "tab:blue", "right": "tab:red"}


def _side_of(joint_name: str) -> str:
    """``left`` / ``right`` / ``""`` from names like ``left_knee`` or VIBE's ``LKnee``."""
    for side in ("left", "right"):
        letter = side[0].upper()
        if joint_name.lower().startswith(side) or (joint_name[:1] == letter and joint_name[1:2].isupper()):
            return side
    return ""


def _bone_colours(skeleton: Skeleton) -> list[str]:
    return [_SIDE_COLOURS.get(_side_of(skeleton.joint_names[child]), "black") for _, child in skeleton.bones]


def _draw_2d(ax, joints: np.ndarray, skeleton: Skeleton, view: str, shift: float = 0.0, alpha: float = 1.0):
    """One pose ``[J, 3]`` projected on ``view``, moved ``shift`` along the horizontal axis."""
    h, v = _VIEWS[view]
    sign = -1.0 if view == "front" else 1.0  # front: the viewer faces the subject, their +X is on the right
    for (parent, child), colour in zip(skeleton.bones, _bone_colours(skeleton)):
        ax.plot([sign * joints[parent, h] + shift, sign * joints[child, h] + shift],
                [joints[parent, v], joints[child, v]], color=colour, lw=2, alpha=alpha, solid_capstyle="round")


def _facing_viewer(joints: np.ndarray, skeleton: Skeleton) -> np.ndarray:
    """``[T, J, 3]`` turned about +Y so that frame 0 faces +Z (the ``front`` view sees the subject's front)."""
    names = [n.lower() for n in skeleton.joint_names]
    left = next(i for i, n in enumerate(skeleton.joint_names) if _side_of(n) == "left" and "hip" in names[i])
    right = next(i for i, n in enumerate(skeleton.joint_names) if _side_of(n) == "right" and "hip" in names[i])
    across = joints[0, left] - joints[0, right]
    angle = np.arctan2(-across[2], across[0])  # rotation taking the hip axis onto +X
    c, s = np.cos(angle), np.sin(angle)
    turn = np.array([[c, 0.0, -s], [0.0, 1.0, 0.0], [s, 0.0, c]])
    return joints @ turn.T


def filmstrip(motion: Motion, skeleton: Skeleton, path: str, *, frames: int = 8, views=("front", "side"),
              title: str = "") -> None:
    """Save a PNG: ``frames`` evenly spaced poses side by side, one row per view, each pose centred on its
    own root; the floor line and the lowest joint are drawn to show contact."""
    index = np.linspace(0, motion.num_frames - 1, frames).round().astype(int)
    joints = _facing_viewer(motion.joints, skeleton)
    spacing = 1.0
    fig, axes = plt.subplots(len(views), 1, figsize=(1.3 * frames, 2.6 * len(views)), squeeze=False)
    for ax, view in zip(axes[:, 0], views):
        h = _VIEWS[view][0]
        sign = -1.0 if view == "front" else 1.0
        for k, f in enumerate(index):
            pose = joints[f]
            _draw_2d(ax, pose, skeleton, view, shift=k * spacing - sign * pose[0, h])
            ax.text(k * spacing, -0.12, f"{f}", ha="center", fontsize=7)
        ax.axhline(0.0, color="0.6", lw=1)
        ax.set_xlim(-0.6, (frames - 1) * spacing + 0.6)
        ax.set_ylim(-0.2, 2.2)
        ax.set_aspect("equal")
        ax.set_ylabel(view)
        ax.set_xticks([])
    axes[0, 0].set_title(title, fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=80)
    plt.close(fig)


def _examples(data: MotionDataset, classes: Sequence[int]) -> list[list[tuple[int, int, Motion | None]]]:
    """For each class, one motion per mode (the first of that mode), or None where the mode is missing."""
    rows = []
    for c in classes:
        modes = data.mode_names[c] if data.mode_names else ("",)
        row = []
        for m in range(len(modes)):
            hit = np.flatnonzero((data.actions == c) & ((data.modes == m) if data.mode_names else True))
            row.append((c, m, data[int(hit[0])] if len(hit) else None))
        rows.append(row)
    return rows


def _grid_axes(rows, data: MotionDataset):
    width = max(len(r) for r in rows)
    fig = plt.figure(figsize=(2.4 * width, 2.6 * len(rows)))
    cells = []
    for i, row in enumerate(rows):
        for j, (c, m, motion) in enumerate(row):
            ax = fig.add_subplot(len(rows), width, i * width + j + 1, projection="3d", proj_type="ortho")
            label = data.class_names[c] + (f"\n{data.mode_names[c][m]}" if data.mode_names else "")
            ax.set_title(label, fontsize=8)
            cells.append((ax, motion))
    return fig, cells


def _draw_3d(ax, joints: np.ndarray, skeleton: Skeleton, centre: np.ndarray) -> None:
    title = ax.get_title()
    ax.cla()
    ax.set_title(title, fontsize=8)
    p = joints - np.array([centre[0], 0.0, centre[2]])
    for (parent, child), colour in zip(skeleton.bones, _bone_colours(skeleton)):
        # Library +Y up -> matplotlib's vertical z; world z (forward) -> plot y.
        ax.plot([p[parent, 0], p[child, 0]], [p[parent, 2], p[child, 2]], [p[parent, 1], p[child, 1]],
                color=colour, lw=1.8)
    g = np.linspace(-1.0, 1.0, 5)
    for x in g:
        ax.plot([x, x], [-1, 1], [0, 0], color="0.85", lw=0.6)
        ax.plot([-1, 1], [x, x], [0, 0], color="0.85", lw=0.6)
    ax.set_xlim(-1, 1)
    ax.set_ylim(-1, 1)
    ax.set_zlim(0, 2)
    ax.set_box_aspect((1, 1, 1))
    ax.view_init(elev=12, azim=60)
    ax.set_axis_off()


def render_grid(data: MotionDataset, classes: Sequence[int], path: str, *, still: bool = False,
                max_frames: int = 80) -> None:
    """Save a grid (rows = classes, columns = modes; one example each) as an animated GIF, or with
    ``still`` as a PNG of each example's key frames overlaid (start, 1/3, 2/3, end; later ones darker)."""
    rows = _examples(data, classes)
    fig, cells = _grid_axes(rows, data)
    skeleton = data.skeleton
    if still:
        for ax, motion in cells:
            if motion is None:
                continue
            centre = motion.joints[:, 0].mean(axis=0)
            _draw_3d(ax, motion.joints[0], skeleton, centre)
            for f in np.linspace(0, motion.num_frames - 1, 4).round().astype(int)[1:]:
                p = motion.joints[f] - np.array([centre[0], 0.0, centre[2]])
                for (parent, child), colour in zip(skeleton.bones, _bone_colours(skeleton)):
                    ax.plot([p[parent, 0], p[child, 0]], [p[parent, 2], p[child, 2]], [p[parent, 1], p[child, 1]],
                            color=colour, lw=1.2, alpha=0.5)
        fig.savefig(path, dpi=70)
        plt.close(fig)
        return
    length = min(max((m.num_frames for _, m in cells if m is not None), default=1), max_frames)

    def update(frame):
        for ax, motion in cells:
            if motion is not None:
                f = min(frame, motion.num_frames - 1)
                _draw_3d(ax, motion.joints[f], skeleton, motion.joints[f, 0])
        return []

    FuncAnimation(fig, update, frames=length).save(path, writer=PillowWriter(fps=data.fps))
    plt.close(fig)


def main(argv: Sequence[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("dataset", help="a synthetic variant name, e.g. synth-humanact12")
    parser.add_argument("--classes", default="0,1,2", help="comma-separated class indices")
    parser.add_argument("--out", default="preview.gif")
    parser.add_argument("--png", action="store_true", help="save a still grid of key frames instead of a GIF")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--count", type=int, default=None,
                        help="generate only the first COUNT sequences (faster; enough for one per mode)")
    args = parser.parse_args(argv)

    from jaxmotion.data import synthetic

    data = synthetic.generate(args.dataset, "train", seed=args.seed, count=args.count) if args.count else \
        synthetic.load(args.dataset, "train", seed=args.seed)
    classes = [int(c) for c in args.classes.split(",")]
    render_grid(data, classes, args.out, still=args.png)
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
