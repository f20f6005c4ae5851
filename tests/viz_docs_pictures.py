"""Draw docs/outputs.md's pictures and measure the renderer's cost per frame (the numbers quoted there).

``python tests/viz_docs_pictures.py [--out docs]`` (needs the ``video`` extra) writes

* ``video-frames.png``: four frames of an MP4 of a synth-cmu walk (world camera: the path on the ground), decoded
  back from the file, two by two;
* ``mesh-rendering.png``: one frame of two synth-cmu clips (a walk, a dance; follow camera) drawn as meshes of the
  toy box body
  (:mod:`toy_body`; a real SMPL file gives the real body);

and prints seconds per frame (drawing, posing included) for sticks, the toy body (208 vertices) and a box body
subdivided to SMPL's size (6 890 vertices, 13 524 faces).
"""

from __future__ import annotations

import argparse
import tempfile
import time
from pathlib import Path

import numpy as np
from PIL import Image

from jaxmotion.data import synthetic
from jaxmotion.geometry import axis_angle_to_matrix, forward_kinematics, load_body_model, save_body_model
from jaxmotion.geometry.skeletons import SMPL24
from jaxmotion.viz.scene import FrameRenderer, make_scene
from jaxmotion.viz.video import render_video
from toy_body import box_body

SMPL_VERTICES = 6890


def _subdivided_cube(k: int) -> tuple[np.ndarray, np.ndarray]:
    """A cube [-1, 1]^3 whose faces are k x k grids: ``(vertices [V, 3], triangles [F, 3])``, shared corners once."""
    index: dict[tuple[int, int, int], int] = {}
    triangles = []
    steps = range(k + 1)
    for axis in range(3):
        for side in (0, k):
            u_axis, v_axis = [a for a in range(3) if a != axis]

            def vertex(u, v):
                cell = [0, 0, 0]
                cell[axis], cell[u_axis], cell[v_axis] = side, u, v
                return index.setdefault(tuple(cell), len(index))

            for u in steps[:-1]:
                for v in steps[:-1]:
                    a, b, c, d = vertex(u, v), vertex(u + 1, v), vertex(u + 1, v + 1), vertex(u, v + 1)
                    triangles += [(a, b, c), (a, c, d)]
    vertices = np.array(sorted(index, key=index.get), float) * 2 / k - 1
    return vertices, np.array(triangles)


def subdivided_body(path: Path, half_width: float = 0.04) -> Path:
    """The toy body with each bone's box subdivided (7 x 7 squares a side), padded to SMPL's 6 890 vertices with
    unused ones at the pelvis: a body of SMPL's size for timing."""
    cube, cube_faces = _subdivided_cube(7)
    rest = np.asarray(forward_kinematics(np.broadcast_to(np.eye(3, dtype=np.float32), (24, 3, 3)),
                                         np.array([0.0, 0.95, 0.0], np.float32), SMPL24.offsets, SMPL24.parents))
    vertices, weights, faces = [rest], [np.eye(24)], []
    for child, parent in enumerate(SMPL24.parents):
        if parent < 0:
            continue
        middle, half = (rest[child] + rest[parent]) / 2, np.abs(rest[child] - rest[parent]) / 2 + half_width
        faces.append(cube_faces + sum(len(v) for v in vertices))
        vertices.append(middle + cube * half)
        weights.append(np.eye(24)[[parent] * len(cube)])
    count = sum(len(v) for v in vertices)
    vertices.append(np.broadcast_to(rest[0], (SMPL_VERTICES - count, 3)))
    weights.append(np.eye(24)[[0] * (SMPL_VERTICES - count)])
    save_body_model(path, {"v_template": np.concatenate(vertices).astype(np.float32),
                           "shapedirs": np.zeros((SMPL_VERTICES, 3, 10)), "posedirs": np.zeros((SMPL_VERTICES, 3, 207)),
                           "J_regressor": np.eye(24, SMPL_VERTICES), "weights": np.concatenate(weights),
                           "f": np.concatenate(faces).astype(np.int32),
                           "kintree_table": np.stack([np.asarray(SMPL24.parents), np.arange(24)])})
    return path


def _seconds_per_frame(scene, fps: float, frames: int = 20) -> float:
    renderer = FrameRenderer([scene], fps, camera="follow")
    renderer.draw(0)  # the first draw lays out the text and compiles the posing
    start = time.perf_counter()
    for t in range(1, frames + 1):
        renderer.draw(t)
    return (time.perf_counter() - start) / frames


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default=str(Path(__file__).resolve().parents[1] / "docs"))
    out = Path(parser.parse_args().out)
    import imageio_ffmpeg

    cmu = synthetic.generate("synth-cmu", "train", seed=0, count=8)
    walk = 5  # a curving walk: its path shows on the ground
    with tempfile.TemporaryDirectory() as folder:
        video = render_video(Path(folder) / "walk.mp4", cmu, indices=[walk])
        reader = imageio_ffmpeg.read_frames(str(video))
        width, height = reader.__next__()["size"]
        frames = [np.frombuffer(f, np.uint8).reshape(height, width, 3) for f in reader]
        picks = np.linspace(0, len(frames) - 1, 4).round().astype(int)
        w, h = int(0.75 * width), int(0.75 * height)
        sheet = Image.new("RGB", (2 * w, 2 * h), "white")
        for k, i in enumerate(picks):
            sheet.paste(Image.fromarray(frames[i]).resize((w, h), Image.LANCZOS), ((k % 2) * w, (k // 2) * h))
        sheet.quantize(256).save(out / "video-frames.png", optimize=True)

        toy = load_body_model(box_body(Path(folder) / "boxes.npz"))
        large = load_body_model(subdivided_body(Path(folder) / "large.npz"))
        clips = [cmu[i] for i in (walk, 3)]  # a walk and a dance

        def template_joints(m):  # forward kinematics on the template: the body's own skeleton
            return np.asarray(forward_kinematics(axis_angle_to_matrix(m.rotations), m.translation, SMPL24.offsets,
                                                 SMPL24.parents))

        scenes = [make_scene(template_joints(m), SMPL24, captions=cmu.class_names[m.action], rotations=m.rotations,
                             translation=m.translation, body=toy) for m in clips]
        renderer = FrameRenderer(scenes, cmu.fps, columns=2, camera="follow", cell=3.6)
        Image.fromarray(renderer.draw(40)).quantize(256).save(out / "mesh-rendering.png", optimize=True)

        m = clips[0]
        for name, body in (("sticks", None), ("toy body", toy), ("6 890-vertex body", large)):
            scene = make_scene(template_joints(m), SMPL24, rotations=m.rotations, translation=m.translation, body=body)
            print(f"{name}: {_seconds_per_frame(scene, cmu.fps):.3f} s a frame")
    for name in ("video-frames.png", "mesh-rendering.png"):
        print(f"{out / name}: {(out / name).stat().st_size / 1000:.0f} kB")


if __name__ == "__main__":
    main()
