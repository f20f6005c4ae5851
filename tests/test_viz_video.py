"""Videos and pictures of motions (jaxmotion.viz, jaxmotion.render): MP4 and GIF files decode back to the frames
drawn; the world camera shows a walk crossing the picture while the following one keeps the body still; every frame
carries its counter and caption, every picture a legend for its colours; a body model draws shaded meshes whose
joints are the motion's; still pictures keep their proportions and their titles apart; the render command draws
exported files and trained generators and refuses bad input in one line."""

import dataclasses
import itertools
import sys

import numpy as np
import pytest
from PIL import Image

from jaxmotion import render
from jaxmotion.data import Motion, pack, synthetic
from jaxmotion.data.export import ExportOptions, export_motions
from jaxmotion.data.motion import to_dataset
from jaxmotion.data.segments import Segments
from jaxmotion.geometry import axis_angle_to_matrix, forward_kinematics, load_body_model
from jaxmotion.geometry.skeletons import SMPL24
from jaxmotion.viz import motion as pictures
from jaxmotion.viz.scene import TRAVEL_THRESHOLD, FrameRenderer, camera_mode, make_scene, posed_body
from jaxmotion.viz.video import motion_scenes, render_video, write_video
from toy_body import box_body  # tests/ is on the path

FRAMES = 24  # of the walk drawn in most tests
# decoding starts ffmpeg as a subprocess: JAX warns at the fork, harmless before an exec (the writer silences it too)
pytestmark = pytest.mark.filterwarnings(r"ignore:os\.fork\(\) was called:RuntimeWarning")


@pytest.fixture(scope="module")
def cmu():
    return synthetic.generate("synth-cmu", "train", seed=0, count=8)


@pytest.fixture(scope="module")
def walk(cmu):
    """The first FRAMES frames of a synth-cmu walk (2 m), its joints forward kinematics on SMPL-24's template (the toy
    body's skeleton), so that a body posed by its rotations has exactly its joints."""
    m = cmu[0]
    assert cmu.class_names[m.action] == "Walk"
    rotations, translation = m.rotations[:FRAMES], m.translation[:FRAMES]
    joints = np.asarray(forward_kinematics(axis_angle_to_matrix(rotations), translation, SMPL24.offsets,
                                           SMPL24.parents))
    return Motion(joints, translation, rotations, m.action, name="walk")


@pytest.fixture(scope="module")
def body(tmp_path_factory):
    return load_body_model(box_body(tmp_path_factory.mktemp("body") / "boxes.npz"))


def _cell_pixels(renderer: FrameRenderer, image: np.ndarray) -> np.ndarray:
    """The pixels of the first cell's axes (no caption, legend or counter)."""
    box = renderer.cells[0].ax.get_window_extent()
    height = image.shape[0]
    return image[int(height - box.y1) + 1:int(height - box.y0) - 1, int(box.x0) + 1:int(box.x1) - 1]


def _coloured(pixels: np.ndarray) -> np.ndarray:
    """``[H, W]`` where a pixel has colour (not white, grey or black: bones of a side, or a mesh)."""
    pixels = pixels.astype(int)
    return pixels.max(axis=-1) - pixels.min(axis=-1) > 40


def _centroid_x(renderer: FrameRenderer, frame: int) -> float:
    """Where the body is drawn across the cell, as a fraction of its width."""
    cell = _cell_pixels(renderer, renderer.draw(frame))
    return np.flatnonzero(_coloured(cell).any(axis=0)).mean() / cell.shape[1]


# --- writers -----------------------------------------------------------------------------------------------


def test_an_mp4_decodes_back_to_the_frames_drawn(walk, tmp_path):
    imageio_ffmpeg = pytest.importorskip("imageio_ffmpeg")
    path = render_video(tmp_path / "walk.mp4", walk, SMPL24, 30.0, captions="Walk")
    reader = imageio_ffmpeg.read_frames(str(path))
    meta = reader.__next__()
    width, height = meta["size"]
    frames = [np.frombuffer(f, np.uint8).reshape(height, width, 3) for f in reader]
    assert len(frames) == FRAMES and width % 2 == 0 and height % 2 == 0
    drawn = FrameRenderer([make_scene(walk.joints, SMPL24, captions="Walk")], 30.0)
    assert (height - 1, width - 1) <= drawn.draw(0).shape[:2] <= (height, width)  # padded to even sizes only
    first, last = frames[0].astype(int), frames[-1].astype(int)
    for frame in (first, last):
        assert frame.std() > 5 and (frame < 128).mean() > 0.001  # not blank: lines and text
    assert np.abs(first - last).mean() > 0.5


def test_write_video_pads_odd_sizes_and_refuses_what_it_cannot_write(tmp_path):
    imageio_ffmpeg = pytest.importorskip("imageio_ffmpeg")
    frames = [np.full((31, 45, 3), 40 * k, np.uint8) for k in range(3)]
    reader = imageio_ffmpeg.read_frames(str(write_video(tmp_path / "odd.mp4", iter(frames), 10)))
    assert reader.__next__()["size"] == (46, 32)
    assert sum(1 for _ in reader) == 3
    with pytest.raises(ValueError, match="path: expected a .mp4 or .gif file, got 'x.avi'"):
        write_video(tmp_path / "x.avi", frames, 10)
    with pytest.raises(ValueError, match="frames: expected at least one frame"):
        write_video(tmp_path / "none.gif", [], 10)
    with pytest.raises(ValueError, match=r"frames\[1\]: expected every frame of the first one's size"):
        write_video(tmp_path / "sizes.gif", [frames[0], frames[0][:30]], 10)
    with pytest.raises(ValueError, match="fps"):
        write_video(tmp_path / "slow.gif", frames, 0)
    assert not list(tmp_path.glob("*.gif")) and not list(tmp_path.glob(".*"))  # nothing half written


def test_a_gif_holds_every_frame_or_the_stated_cap(walk, tmp_path):
    whole = render_video(tmp_path / "walk.gif", walk, SMPL24, 30.0)
    capped = render_video(tmp_path / "capped.gif", walk, SMPL24, 30.0, max_frames=10)
    for path, count in ((whole, FRAMES), (capped, 10)):
        with Image.open(path) as gif:
            assert gif.n_frames == count
            gif.seek(0)
            first = np.asarray(gif.convert("RGB"), int)
            gif.seek(count - 1)
            assert np.abs(np.asarray(gif.convert("RGB"), int) - first).mean() > 0.5


def test_a_missing_imageio_ffmpeg_names_the_extra(walk, tmp_path, monkeypatch):
    monkeypatch.setitem(sys.modules, "imageio_ffmpeg", None)
    with pytest.raises(ImportError, match=r'pip install "jaxmotion\[video\]"'):
        render_video(tmp_path / "walk.mp4", walk, SMPL24, 30.0)
    assert not (tmp_path / "walk.mp4").exists()
    render_video(tmp_path / "walk.gif", walk, SMPL24, 30.0, max_frames=2)  # a GIF needs no extra


# --- the frame renderer ------------------------------------------------------------------------------------


def test_the_world_camera_shows_the_walk_crossing_the_picture_and_follow_keeps_it_still(walk):
    assert camera_mode("auto", make_scene(walk.joints, SMPL24).joints) == "world"  # 2 m > 1 m: locomotion
    world = FrameRenderer([make_scene(walk.joints, SMPL24)], 30.0, camera="world")
    follow = FrameRenderer([make_scene(walk.joints, SMPL24)], 30.0, camera="follow")
    assert abs(_centroid_x(world, 0) - _centroid_x(world, FRAMES - 1)) > 0.2
    assert abs(_centroid_x(follow, 0) - _centroid_x(follow, FRAMES - 1)) < 0.05


def test_auto_follows_a_clip_that_stays_within_a_metre(walk):
    still = walk.joints - walk.joints[:, :1] * np.array([1.0, 0.0, 1.0])  # the root kept over one spot
    assert camera_mode("auto", still[None]) == "follow"
    nudged = still + np.linspace(0, 0.9 * TRAVEL_THRESHOLD, FRAMES)[:, None, None] * np.array([1.0, 0.0, 0.0])
    assert camera_mode("auto", nudged[None]) == "follow"
    with pytest.raises(ValueError, match="camera: expected one of"):
        camera_mode("orbit", still[None])


def test_every_frame_shows_its_counter_and_caption(walk):
    captions = [f"step {t // 12}" for t in range(FRAMES)]
    renderer = FrameRenderer([make_scene(walk.joints, SMPL24, captions=captions)], 30.0)
    renderer.draw(12)
    texts = [t.get_text() for t in renderer.figure.texts]
    assert "frame 13 / 24 · 0.40 s" in texts and "step 1" in texts
    with pytest.raises(ValueError, match="captions: expected one text for the clip or one per frame"):
        make_scene(walk.joints, SMPL24, captions=captions[:3])


def test_the_legend_names_the_persons_and_for_one_person_its_sides(walk, cmu):
    one = FrameRenderer([make_scene(walk.joints, SMPL24)], 30.0)
    assert [t.get_text() for t in one.legend.get_texts()] == ["person 1", "left", "right"]
    pair = np.stack([walk.joints, walk.joints + np.array([1.0, 0.0, 0.0])])
    two = FrameRenderer([make_scene(pair, SMPL24, labels=("attacker", "defender"))], 30.0)
    assert [t.get_text() for t in two.legend.get_texts()] == ["attacker", "defender"]
    three = FrameRenderer([make_scene(np.stack([walk.joints] * 3), SMPL24)], 30.0)
    assert len(three.legend.get_texts()) == 3
    with pytest.raises(ValueError, match="labels: expected one label per person"):
        make_scene(pair, SMPL24, labels=("alone",))


def test_the_body_posed_by_the_motion_has_the_motions_joints(walk, body):
    _, joints = posed_body(body, walk.rotations, walk.translation)
    np.testing.assert_allclose(joints, walk.joints, atol=1e-4)


def test_a_body_model_draws_shaded_meshes_instead_of_sticks(walk, body):
    mesh = FrameRenderer([make_scene(walk.joints, SMPL24, rotations=walk.rotations, translation=walk.translation,
                                     body=body)], 30.0, camera="follow")
    sticks = FrameRenderer([make_scene(walk.joints, SMPL24)], 30.0, camera="follow")
    drawn = _cell_pixels(mesh, mesh.draw(5))
    coloured = drawn[_coloured(drawn)]
    assert len(coloured) > 2000  # a body's surface, not lines
    shades = np.unique(coloured // 8, axis=0)  # flat shading: the faces turned differently differ in brightness
    assert len(shades) >= 4 and np.ptp(coloured.astype(int).sum(axis=1)) > 60
    assert np.abs(drawn.astype(int) - _cell_pixels(sticks, sticks.draw(5)).astype(int)).mean() > 2
    assert [t.get_text() for t in mesh.legend.get_texts()] == ["person 1"]  # one colour a person
    with pytest.raises(ValueError, match="body: a mesh needs the motion's rotations"):
        make_scene(walk.joints, SMPL24, body=body)


def test_a_sampler_batch_renders_each_clip_to_its_length(walk, tmp_path):
    batch = {"joints": np.stack([walk.joints, walk.joints]), "lengths": np.array([8, 16])}
    path = render_video(tmp_path / "batch.gif", batch, SMPL24, 30.0, captions=["short", "long"])
    with Image.open(path) as gif:
        assert gif.n_frames == 16
    with pytest.raises(ValueError, match="lengths: expected"):
        render_video(tmp_path / "bad.gif", {**batch, "lengths": np.array([8, 30])}, SMPL24, 30.0)


# --- pictures ----------------------------------------------------------------------------------------------


def _disjoint(boxes) -> bool:
    return not any(a.overlaps(b) for a, b in itertools.combinations(boxes, 2))


def test_grid_titles_never_overlap_even_when_long(cmu):
    names = tuple(f"{name} performed very slowly with both arms raised overhead, then lowered to the hips, twice"
                  for name in cmu.class_names)
    data = dataclasses.replace(cmu, class_names=names)
    fig, dpi = pictures.grid_figure(data, [0, 1, 2])  # 4 + 3 + 3 modes, a cell each (some without an example)
    fig.set_dpi(dpi)
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    titles = [t for t in fig.texts if " / " in t.get_text()]
    assert len(titles) == 10 and all("\n" in t.get_text() for t in titles)  # wrapped
    boxes = [t.get_window_extent(renderer) for t in titles]
    assert _disjoint(boxes) and not any(b.overlaps(ax.get_window_extent()) for b in boxes for ax in fig.axes)
    scenes = [make_scene(m.joints[:5], SMPL24, captions=names[m.action]) for m in cmu.subset([0, 1, 2, 3])]
    animated = FrameRenderer(scenes, cmu.fps, columns=2)
    animated.draw(0)
    renderer = animated.canvas.get_renderer()
    captions = [c.get_window_extent(renderer) for c in animated.captions]
    axes = [cell.ax.get_window_extent() for cell in animated.cells]
    assert _disjoint(captions) and not any(c.overlaps(a) for c in captions for a in axes)


def _proportions(path) -> tuple[float, int]:
    with Image.open(path) as image:
        return image.size[0] / image.size[1], image.size[1]


def test_still_pictures_wrap_into_rows_instead_of_growing_thin(cmu, walk, tmp_path):
    fights = synthetic.generate("synth-combat-5p", "train", seed=0, count=2)
    segments = Segments.from_rows([(0, 2, 12, [0], [1], 0), (0, 12, FRAMES, [1, 2], [1, 2], 0)], cmu.num_classes)
    take = pack([dataclasses.replace(walk, segments=segments)], name="synth-cmu", split="train",
                class_names=cmu.class_names, skeleton=SMPL24, fps=cmu.fps)
    pictures.filmstrip(fights[0], fights.skeleton, tmp_path / "fight.png")
    pictures.filmstrip(walk, SMPL24, tmp_path / "walk.png", frames=16, views=("front",))
    pictures.take_strip(take, 0, tmp_path / "take.png", frames=24)
    pictures.render_grid(fights, [0], tmp_path / "grid.png", still=True)
    pictures.render_grid(cmu, [0], tmp_path / "row.png", still=True, key_frames=8)
    for name in ("fight.png", "walk.png", "take.png", "grid.png", "row.png"):
        ratio, height = _proportions(tmp_path / name)
        assert ratio <= 3.6 and height >= 300, (name, ratio, height)


# --- the render command ------------------------------------------------------------------------------------


@pytest.fixture(scope="module")
def exported(walk, tmp_path_factory):
    folder = tmp_path_factory.mktemp("exported")
    batch = {"joints": walk.joints[None, :12], "rotations": walk.rotations[None, :12],
             "translation": walk.translation[None, :12]}
    export_motions(folder, batch, SMPL24, 30.0, names=["walk"])
    return folder


@pytest.mark.parametrize("suffix", [".npz", ".bvh", ".npy"])
def test_the_command_draws_every_exported_format(exported, suffix, tmp_path):
    out = render.main([str(exported / f"walk{suffix}"), "--out", str(tmp_path / "walk.gif"), "--fps", "15"])
    with Image.open(out) as gif:
        assert gif.n_frames == 12 and gif.info["duration"] == 70  # 1 / 15 s in the hundredths a GIF holds


def test_a_bvh_of_smpl_joints_comes_back_on_smpl24_and_takes_a_mesh(exported, walk, body, tmp_path):
    motion, skeleton, fps = render.load_motion(exported / "walk.bvh")
    assert skeleton is SMPL24 and fps == pytest.approx(30.0)
    np.testing.assert_allclose(motion.joints, walk.joints[:12], atol=1e-4)
    body_file = box_body(tmp_path / "boxes.npz")
    out = render.main([str(exported / "walk.bvh"), "--out", str(tmp_path / "mesh.gif"), "--body-model",
                       str(body_file), "--camera", "follow"])
    assert out.stat().st_size > 1000
    export_motions(tmp_path, {k: getattr(walk, k)[None, :12] for k in ("joints", "rotations", "translation")},
                   SMPL24, 30.0, formats=("bvh",), names=["mixamo"], options=ExportOptions(rig="mixamo"))
    mixamo, skeleton, _ = render.load_motion(tmp_path / "mixamo.bvh")  # Mixamo's names: SMPL-24 again
    assert skeleton is SMPL24
    np.testing.assert_allclose(mixamo.joints, walk.joints[:12], atol=1e-4)


def test_the_command_refuses_bad_input_in_one_line(exported, tmp_path, capsys, monkeypatch):
    np.save(tmp_path / "ntu.npy", np.zeros((5, 25, 3), np.float32))
    (tmp_path / "notes.txt").write_text("")
    body_file = box_body(tmp_path / "boxes.npz")
    cases = [
        ([str(tmp_path / "notes.txt"), "--out", "x.gif"], "SOURCE: expected a .npz, .bvh, .npy motion file"),
        ([str(exported / "walk.npz"), "--out", "x.avi"], "--out: expected a .mp4 or .gif file"),
        ([str(tmp_path / "ntu.npy"), "--out", "x.gif"], "expected joint positions [T, 24, 3]"),
        ([str(exported / "walk.npy"), "--out", "x.gif", "--body-model", str(body_file)],
         "--body-model: walk.npy holds joint positions only"),
        ([str(exported / "walk.npz"), "--out", "x.gif", "--actions", "0"], "--row, --actions, --frames: for a "
                                                                           "trained run folder"),
    ]
    for argv, message in cases:
        with pytest.raises(SystemExit) as exit_:
            render.main(argv)
        assert exit_.value.code == 2 and message in capsys.readouterr().err
    monkeypatch.setitem(sys.modules, "imageio_ffmpeg", None)
    with pytest.raises(SystemExit):
        render.main([str(exported / "walk.npz"), "--out", str(tmp_path / "walk.mp4")])
    assert 'pip install "jaxmotion[video]"' in capsys.readouterr().err


class FakeGenerator:
    """A generator's surface (class names, skeleton, fps, generate): each action's first synth-cmu clip, cut."""

    def __init__(self, data):
        self.data, self.class_names, self.skeleton, self.fps, self.frames = data, data.class_names, SMPL24, 12.0, 10
        self.asked = None

    def generate(self, key, actions, durations=None):
        self.asked = (key, list(actions), durations)
        length = durations[0] if durations else self.frames
        clips = [self.data[int(np.flatnonzero(self.data.actions == a)[0])] for a in actions]
        batch = {k: np.stack([getattr(c, k)[:length] for c in clips]) for k in ("joints", "translation", "rotations")}
        return to_dataset({**batch, "lengths": np.full(len(clips), length), "actions": np.asarray(actions)},
                          SMPL24, self.class_names, self.fps, name="fake")


def test_the_command_draws_a_run_one_clip_per_action_captioned(cmu, tmp_path, monkeypatch, capsys):
    fake = FakeGenerator(cmu)
    monkeypatch.setattr(render, "load_generator", lambda path, row=None: fake)
    out = render.main([str(tmp_path), "--actions", "0,run, JUMP", "--seed", "3", "--frames", "6", "--out",
                       str(tmp_path / "generated.gif")])
    assert fake.asked == (3, [0, 1, 2], [6, 6, 6])
    with Image.open(out) as gif:
        assert gif.n_frames == 6
    scenes = motion_scenes(fake.generate(0, [0, 1], [6, 6]))
    assert [s.captions[0] for s in scenes] == ["Walk", "Run"]
    with pytest.raises(SystemExit):
        render.main([str(tmp_path), "--actions", "0,flying", "--out", str(tmp_path / "x.gif")])
    assert "--actions: unknown tag 'flying'; the model knows: Walk, Run" in capsys.readouterr().err
    with pytest.raises(SystemExit):
        render.main([str(tmp_path), "--actions", "7", "--out", str(tmp_path / "x.gif")])
    assert "--actions: class index 7 outside [0, 7)" in capsys.readouterr().err
