"""Draw a motion to a video: a motion file the library exports, or what a trained run generates.

    python -m jaxmotion.render motion.npz --out motion.mp4                       # AMASS-layout SMPL parameters
    python -m jaxmotion.render motion.bvh --out motion.gif --camera world
    python -m jaxmotion.render joints.npy --out joints.mp4 --fps 20              # SMPL-24 joint positions
    python -m jaxmotion.render motion.npz --out body.mp4 --body-model SMPL_NEUTRAL.npz   # shaded meshes
    python -m jaxmotion.render results/actor_uestc/cpu/seed-0 --actions 0,walk,3 --seed 1 --out generated.mp4

``SOURCE`` is a file (by its suffix: ``.npz`` AMASS layout, read by :func:`~jaxmotion.data.export.load_amass_npz`;
``.bvh``, read by :func:`~jaxmotion.data.export.load_bvh`, its joints put in SMPL-24's order when it names SMPL-24's
joints; ``.npy`` joint positions ``[T, 24, 3]`` in the library frame, drawn on SMPL-24) or a trained run folder
(:func:`jaxmotion.load_generator`; ``--row`` when it holds several): then one clip per ``--actions`` entry (a class
index or name), drawn from ``--seed``, ``--frames`` long (default the generator's), captioned with its class name,
in a grid. ``--out``: ``.mp4`` (the ``video`` extra: ``pip install "jaxmotion[video]"``) or ``.gif``. ``--fps``
overrides the source's frame rate (a ``.npy`` has none: 30 unless given). ``--body-model``: an SMPL-format model
file, to draw shaded meshes (needs rotations: not for a ``.npy``). Cameras, captions and legends:
:mod:`jaxmotion.viz.scene`.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from jaxmotion.compose import canonical_tag
from jaxmotion.data.export import load_amass_npz, load_bvh
from jaxmotion.data.motion import Motion, MotionDataset
from jaxmotion.data.retarget import mixamo_names
from jaxmotion.geometry.body import BodyModel, load_body_model
from jaxmotion.geometry.kinematics import forward_kinematics
from jaxmotion.geometry.rotations import axis_angle_to_matrix
from jaxmotion.geometry.skeletons import SMPL24, Skeleton
from jaxmotion.pipelines.load import load_generator
from jaxmotion.viz.scene import CAMERAS
from jaxmotion.viz.video import MAX_CELLS, check_video_path, render_video

#: Motion files :func:`load_motion` reads, by suffix.
MOTION_SUFFIXES = (".npz", ".bvh", ".npy")
#: The frame rate of a ``.npy`` joints file, which stores none.
NPY_FPS = 30.0


def _bvh_motion(path: Path) -> tuple[Motion, Skeleton, float]:
    """A BVH file's motion on its own tree, or on SMPL-24 (joints reordered) when it names SMPL-24's joints (or
    their Mixamo names, :mod:`jaxmotion.data.retarget`) with SMPL-24's parents, so that a body model can pose it."""
    bvh = load_bvh(path)
    rotations, offsets = bvh.rotations, bvh.offsets
    skeleton = Skeleton(path.stem, bvh.names, bvh.parents, offsets)
    names = next((names for names in (SMPL24.joint_names, mixamo_names(), mixamo_names(""))
                  if sorted(bvh.names) == sorted(names)), None)  # the library's BVH, or with --rig mixamo
    if names is not None:
        order = [bvh.names.index(name) for name in names]
        if all(bvh.parents[order[j]] == (order[p] if p >= 0 else -1) for j, p in enumerate(SMPL24.parents)):
            rotations, offsets, skeleton = rotations[:, order], offsets[order], SMPL24
    joints = np.asarray(forward_kinematics(axis_angle_to_matrix(rotations), bvh.translation, offsets,
                                           skeleton.parents))
    return Motion(joints, bvh.translation, rotations, action=-1, name=path.stem), skeleton, bvh.fps


def load_motion(path: str | Path, *, body: BodyModel | None = None) -> tuple[Motion, Skeleton, float | None]:
    """``(motion, skeleton, fps)`` from a motion file (``.npz`` AMASS layout, ``.bvh``, ``.npy`` SMPL-24 joints;
    fps None for ``.npy``). With ``body``, an AMASS file's ``trans`` is read as SMPL's (root at ``J_0 + trans``)."""
    path = Path(path)
    suffix = path.suffix.lower()
    if suffix not in MOTION_SUFFIXES:
        raise ValueError(f"SOURCE: expected a {', '.join(MOTION_SUFFIXES)} motion file or a trained run folder, "
                         f"got {path.name!r}")
    if not path.is_file():
        raise FileNotFoundError(f"SOURCE: {path} does not exist")
    if suffix == ".npz":
        motion, fps = load_amass_npz(path, body=body)
        return motion, SMPL24, fps
    if suffix == ".bvh":
        return _bvh_motion(path)
    joints = np.load(path, allow_pickle=False)
    if joints.ndim != 3 or joints.shape[1:] != (24, 3) or len(joints) < 1:
        raise ValueError(f"{path.name}: expected joint positions [T, 24, 3] (SMPL-24, library frame), got "
                         f"{joints.shape}; other skeletons: export .bvh")
    joints = joints.astype(np.float32)
    return Motion(joints, joints[:, 0], None, action=-1, name=path.stem), SMPL24, None


def action_ids(actions: str, class_names: Sequence[str]) -> list[int]:
    """Class indices from ``"0,walk,3"``: each entry an index or a class name (any case, any spacing)."""
    ids = []
    for entry in (a.strip() for a in actions.split(",")):
        if entry.lstrip("-").isdigit():
            index = int(entry)
            if not 0 <= index < len(class_names):
                raise ValueError(f"--actions: class index {index} outside [0, {len(class_names)}); the classes: "
                                 f"{', '.join(class_names)}")
            ids.append(index)
        elif entry:
            try:
                ids.append(list(class_names).index(canonical_tag(entry, class_names)))
            except ValueError as error:
                raise ValueError(f"--actions: {error}") from None
    if not ids:
        raise ValueError(f"--actions: expected class indices or names separated by commas, got {actions!r}")
    if len(ids) > MAX_CELLS:
        raise ValueError(f"--actions: at most {MAX_CELLS} clips in one video, got {len(ids)}")
    return ids


def generated_motions(run: str | Path, *, row: str | None = None, actions: str | None = None, seed: int = 0,
                      frames: int | None = None) -> MotionDataset:
    """One motion per entry of ``actions`` (default the first four classes) from the trained generator in ``run``,
    drawn from ``seed``, ``frames`` long (default the generator's)."""
    generator = load_generator(run, row=row)
    names = generator.class_names
    ids = action_ids(actions, names) if actions else list(range(min(4, len(names))))
    if frames is not None and frames < 1:
        raise ValueError(f"--frames: expected >= 1, got {frames}")
    return generator.generate(seed, ids, None if frames is None else [frames] * len(ids))


def render_source(source: str | Path, out: str | Path, *, camera: str = "auto", body_model: str | Path | None = None,
                  fps: float | None = None, row: str | None = None, actions: str | None = None, seed: int = 0,
                  frames: int | None = None) -> Path:
    """What the command does: ``source`` (a motion file or a trained run folder) drawn to ``out``."""
    out = check_video_path(out, "--out")
    if fps is not None and not fps > 0:
        raise ValueError(f"--fps: expected frames per second > 0, got {fps}")
    body = None if body_model is None else load_body_model(body_model)
    source = Path(source)
    if source.is_dir():
        motions = generated_motions(source, row=row, actions=actions, seed=seed, frames=frames)
        return render_video(out, motions, fps=fps, camera=camera, body=body)
    if row is not None or actions is not None or frames is not None:
        raise ValueError("--row, --actions, --frames: for a trained run folder; SOURCE is a file")
    motion, skeleton, file_fps = load_motion(source, body=body)
    if body is not None and motion.rotations is None:
        raise ValueError(f"--body-model: {source.name} holds joint positions only; a mesh needs rotations "
                         f"(.npz or .bvh)")
    return render_video(out, motion, skeleton, fps or file_fps or NPY_FPS, captions=motion.name, camera=camera,
                        body=body)


def main(argv: Sequence[str] | None = None) -> Path:
    parser = argparse.ArgumentParser(prog="python -m jaxmotion.render", description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("source", metavar="SOURCE", help="a .npz (AMASS layout), .bvh or .npy (SMPL-24 joints) file, "
                                                         "or a trained run folder")
    parser.add_argument("--out", required=True, help="the video: .mp4 (the video extra) or .gif")
    parser.add_argument("--camera", choices=CAMERAS, default="auto",
                        help="world (fixed, the paths on the ground), follow (on the root) or auto (world when a "
                             "root travels more than 1 m; default)")
    parser.add_argument("--body-model", metavar="FILE", help="an SMPL-format body model (.npz or .pkl): shaded meshes")
    parser.add_argument("--fps", type=float, help="frames per second (default the source's; 30 for .npy)")
    parser.add_argument("--row", help="a run folder holding several generators: the row's folder (e.g. actor)")
    parser.add_argument("--actions", help="a run folder: class indices or names, e.g. 0,walk,3 (default the first 4)")
    parser.add_argument("--seed", type=int, default=0, help="a run folder: the generation's seed (default 0)")
    parser.add_argument("--frames", type=int, help="a run folder: frames per clip (default the generator's)")
    args = parser.parse_args(argv)
    try:
        written = render_source(args.source, args.out, camera=args.camera, body_model=args.body_model, fps=args.fps,
                                row=args.row, actions=args.actions, seed=args.seed, frames=args.frames)
    except (ValueError, FileNotFoundError, ImportError) as error:
        parser.exit(2, f"{parser.prog}: error: {error}\n")
    print(f"wrote {written}", file=sys.stderr)
    return written


if __name__ == "__main__":
    main()
