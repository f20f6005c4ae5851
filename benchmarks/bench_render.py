"""Benchmark: the motion renderer's cost per frame, and the pictures of docs/outputs.md.

    python benchmarks/bench_render.py [--frames 20] [--pictures docs]

Times :class:`~jaxmotion.viz.scene.FrameRenderer` drawing one clip (a synth-cmu walk, follow camera) after a first
draw that lays out the text and compiles the posing: seconds per frame, posing included, for sticks, the toy box
body of the tests (208 vertices) and the same boxes subdivided and padded to SMPL's size (6 890 vertices, 13 524
faces). No peer: the renderer is matplotlib's Agg (docs/outputs.md says why no OpenGL one).

``--pictures DIR`` (the ``video`` extra) also writes ``video-frames.png``, four frames of an MP4 of a curving
synth-cmu walk (world camera: the path on the ground) decoded back from the file, and ``mesh-rendering.png``, one
frame of a walk and a dance drawn as the toy body's meshes (a real SMPL file gives the real body).
"""

from __future__ import annotations

import argparse
import sys
import tempfile
import time
import warnings
from pathlib import Path

import numpy as np
from PIL import Image

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # runnable from a checkout without installing
sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))  # the tests' toy body

from benchmarks.timing import machine_header  # noqa: E402
from jaxmotion.data import synthetic  # noqa: E402
from jaxmotion.geometry import axis_angle_to_matrix, forward_kinematics, load_body_model  # noqa: E402
from jaxmotion.geometry.skeletons import SMPL24  # noqa: E402
from jaxmotion.viz.scene import FrameRenderer, make_scene  # noqa: E402
from jaxmotion.viz.video import render_video  # noqa: E402
from toy_body import box_body  # noqa: E402

SMPL_VERTICES = 6890
WALK, DANCE = 5, 3  # synth-cmu train clips (seed 0): a curving walk, a dance


def template_joints(motion) -> np.ndarray:
    """The clip posed on the template skeleton, the toy body's own: ``[T, 24, 3]``."""
    return np.asarray(forward_kinematics(axis_angle_to_matrix(motion.rotations), motion.translation, SMPL24.offsets,
                                         SMPL24.parents))


def seconds_per_frame(scene, fps: float, frames: int) -> float:
    renderer = FrameRenderer([scene], fps, camera="follow")
    renderer.draw(0)  # the first draw lays out the text and compiles the posing
    start = time.perf_counter()
    for t in range(1, frames + 1):
        renderer.draw(t)
    return (time.perf_counter() - start) / frames


def pictures(cmu, toy, out: Path, folder: Path) -> None:
    import imageio_ffmpeg

    out.mkdir(parents=True, exist_ok=True)
    video = render_video(folder / "walk.mp4", cmu, indices=[WALK])
    with warnings.catch_warnings():  # JAX's at ffmpeg's fork, harmless before its exec
        warnings.filterwarnings("ignore", message=r"os\.fork\(\) was called", category=RuntimeWarning)
        reader = imageio_ffmpeg.read_frames(str(video))
        width, height = reader.__next__()["size"]
    frames = [np.frombuffer(f, np.uint8).reshape(height, width, 3) for f in reader]
    w, h = int(0.75 * width), int(0.75 * height)
    sheet = Image.new("RGB", (2 * w, 2 * h), "white")
    for k, i in enumerate(np.linspace(0, len(frames) - 1, 4).round().astype(int)):
        sheet.paste(Image.fromarray(frames[i]).resize((w, h), Image.LANCZOS), ((k % 2) * w, (k // 2) * h))
    sheet.quantize(256).save(out / "video-frames.png", optimize=True)
    scenes = [make_scene(template_joints(cmu[i]), SMPL24, captions=cmu.class_names[cmu[i].action],
                         rotations=cmu[i].rotations, translation=cmu[i].translation, body=toy) for i in (WALK, DANCE)]
    renderer = FrameRenderer(scenes, cmu.fps, columns=2, camera="follow", cell=3.6)
    Image.fromarray(renderer.draw(40)).quantize(256).save(out / "mesh-rendering.png", optimize=True)
    for name in ("video-frames.png", "mesh-rendering.png"):
        print(f"wrote {out / name}: {(out / name).stat().st_size / 1000:.0f} kB")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--frames", type=int, default=20, help="frames timed per body (default 20)")
    parser.add_argument("--pictures", metavar="DIR", help="also write docs/outputs.md's two pictures to DIR")
    args = parser.parse_args()
    cmu = synthetic.generate("synth-cmu", "train", seed=0, count=8)
    with tempfile.TemporaryDirectory() as folder:
        folder = Path(folder)
        toy = load_body_model(box_body(folder / "boxes.npz"))
        large = load_body_model(box_body(folder / "large.npz", subdivisions=7, vertices=SMPL_VERTICES))
        print(machine_header())
        print(f"\nseconds a frame, one clip, follow camera ({args.frames} frames after the first)\n")
        print("| drawn as | vertices | faces | s / frame |\n| --- | ---: | ---: | ---: |")
        walk = cmu[WALK]
        for name, body in (("sticks", None), ("toy box body", toy), ("boxes at SMPL's size", large)):
            scene = make_scene(template_joints(walk), SMPL24, rotations=walk.rotations, translation=walk.translation,
                               body=body)
            size = ("-", "-") if body is None else (body.num_vertices, len(body.faces))
            print(f"| {name} | {size[0]} | {size[1]} | {seconds_per_frame(scene, cmu.fps, args.frames):.3f} |")
        if args.pictures:
            pictures(cmu, toy, Path(args.pictures), folder)


if __name__ == "__main__":
    main()
