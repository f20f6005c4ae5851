"""The compose command: a written list of actions read into a program (tags in any case, durations in seconds or
frames, Bézier paths), chained into one motion with its segment table, exported; bad text named by action."""

import json

import imageio_ffmpeg
import jax
import matplotlib.pyplot as plt
import numpy as np
import pytest
from PIL import Image

from jaxmotion.compose import compose, main, parse_actions, unseen_pairs
from jaxmotion.data import synthetic
from jaxmotion.data.export import load_bvh
from jaxmotion.data.mag_tags import TAG_NAMES
from jaxmotion.models.marionet import MarionetConfig, init_marionet
from jaxmotion.pipelines.artefacts import DataFacts
from jaxmotion.pipelines.marionette import ContextGenerator, start_bank
from jaxmotion.pipelines.multi_action import ChainOptions, bezier_path

CONFIG = MarionetConfig.tiny(max_frames=40)


def test_the_written_list_becomes_a_program():
    program = parse_actions("stand up 1s, Walk 1.5s along 0,0 2,1 4,0, sit + ARM movement 12f; kick 0.5s",
                            TAG_NAMES, 30.0, 120)
    assert [a.tags for a in program.actions] == [("Stand Up",), ("Walk",), ("Sit", "Arm Movement"), ("Kick",)]
    assert [a.duration for a in program.actions] == [30, 45, 12, 15]
    assert [a.path is None for a in program.actions] == [True, False, True, True]
    walk = np.array(program.actions[1].path)
    assert walk.shape == (45, 2) and np.allclose(walk[-1], [4.0, 0.0]) and np.abs(walk[0]).max() < 0.2
    assert parse_actions("Walk Upward/Downward 2s", TAG_NAMES, 30.0, 120).actions[0].tags == ("Walk Upward/Downward",)


def test_bad_text_names_the_action_and_the_field():
    with pytest.raises(ValueError, match=r"action 2 \('dance 2s'\): tags: unknown tag 'dance'; the model knows: Walk"):
        parse_actions("walk 1s, dance 2s", TAG_NAMES, 30.0, 120)
    with pytest.raises(ValueError, match=r"action 1 \('walk 5s'\): duration: expected 1 to 120 frames \(4 s"):
        parse_actions("walk 5s", TAG_NAMES, 30.0, 120)
    with pytest.raises(ValueError, match=r"action 1 .*: path: expected two or more ground points 'x,z'"):
        parse_actions("walk 2s along 0,0", TAG_NAMES, 30.0, 120)
    with pytest.raises(ValueError, match=r"action 1 \('walk'\): expected '<tags> <duration>s\|f"):
        parse_actions("walk", TAG_NAMES, 30.0, 120)
    with pytest.raises(ValueError, match="actions: expected at least one action"):
        parse_actions("  ", TAG_NAMES, 30.0, 120)


def test_bezier_paths_are_the_supplements_curves_sampled_at_n_over_t():
    line = bezier_path(np.array([[0.0, 0.0], [3.0, -6.0]]), 3)
    np.testing.assert_allclose(line, [[1, -2], [2, -4], [3, -6]], atol=1e-6)
    p = np.array([[0.0, 0.0], [1.0, 2.0], [3.0, 2.0], [4.0, 0.0]])
    t = np.arange(1, 5)[:, None] / 4
    cubic = (1 - t) ** 3 * p[0] + 3 * (1 - t) ** 2 * t * p[1] + 3 * (1 - t) * t ** 2 * p[2] + t ** 3 * p[3]
    np.testing.assert_allclose(bezier_path(p, 4), cubic, atol=1e-6)


@pytest.fixture(scope="module")
def generator():
    takes = synthetic.generate("synth-mag", "test", seed=0, count=4, progress=False)
    params = jax.jit(init_marionet, static_argnums=1)(jax.random.key(0), CONFIG)
    return ContextGenerator(CONFIG, params, DataFacts.of(takes), start_bank(takes, per_tag=2), max_frames=40)


def test_composed_actions_follow_one_another_with_their_segment_table(generator):
    program = parse_actions("walk 20f along 0,0 1,0, wave hand 10f, run 15f", generator.class_names, 30.0, 40)
    motion = compose(generator, program, jax.random.key(0), options=ChainOptions("always"))
    assert motion["joints"].shape == (45, 24, 3) and np.isfinite(motion["joints"]).all()
    assert [(s["start"], s["end"]) for s in motion["segments"]] == [(0, 20), (20, 30), (30, 45)]
    assert [s["tags"] for s in motion["segments"]] == [["Walk"], ["Wave Hand"], ["Run"]]
    assert all(s["shadowed"] and not s["revised"] for s in motion["segments"])
    again = compose(generator, program, jax.random.key(0), options=ChainOptions("always"))
    np.testing.assert_array_equal(again["joints"], motion["joints"])  # deterministic from the key


@pytest.mark.filterwarnings(r"ignore:os\.fork\(\) was called:RuntimeWarning")  # ffmpeg decodes in a subprocess
def test_the_command_writes_the_motion_and_its_segments(generator, tmp_path, capsys):
    folder = generator.save(tmp_path / "generator")
    out = tmp_path / "out" / "motion.bvh"
    written = main([str(folder), "walk 15f, stand up 20f along 0,0 0.5,1", "--out", str(out), "--mean", "--gif",
                    "--rig", "mixamo", "--clean-feet", "--video"])
    assert written == out and load_bvh(out).rotations.shape[0] == 35 and load_bvh(out).names[0] == "mixamorig:Hips"
    table = json.loads((tmp_path / "out" / "motion.segments.json").read_text())
    assert table["frames"] == 35 and [s["end"] for s in table["segments"]] == [15, 35]
    picture = plt.imread(tmp_path / "out" / "motion.png")  # poses above the tag timeline
    assert picture.shape[1] > 2 * picture.shape[0] and picture[..., :3].std() > 0.01
    with Image.open(tmp_path / "out" / "motion.gif") as animation:  # one picture per frame, the body moving
        assert animation.n_frames == 35
        first = np.asarray(animation.convert("RGB"))
        animation.seek(34)
        assert np.abs(np.asarray(animation.convert("RGB"), float) - first).mean() > 0.1
    reader = imageio_ffmpeg.read_frames(str(tmp_path / "out" / "motion.mp4"))  # --video: the same, as a video
    next(reader)
    assert sum(1 for _ in reader) == 35
    seen = generator.starts.transitions[TAG_NAMES.index("Walk"), TAG_NAMES.index("Stand Up")] > 0
    assert ("never saw 'Walk' followed by 'Stand Up'" in capsys.readouterr().err) == (not seen)
    for bad, message in ((["dance 1s"], "unknown tag 'dance'"), (["walk 1s", "--out", str(tmp_path / "m.txt")],
                                                                  "--out: expected a .bvh, .npz or .npy file"),
                         (["walk 1s", "--smoothing", "-1"], "ChainOptions.smoothing: expected >= 0"),
                         (["walk 1s", "--gender", "female"], "they say what npz files hold; the formats written are"),
                         (["walk 1s", "--rig", "mixamo", "--out", str(tmp_path / "m.npz")], "--rig: it names a BVH"),
                         (["walk 1s", "--betas", "1,x", "--out", str(tmp_path / "m.npz")],
                          "--betas: expected comma-separated numbers, got '1,x'")):
        argv = [str(folder), *bad] + ([] if "--out" in bad else ["--out", str(out)])
        with pytest.raises(SystemExit) as exit_:
            main(argv)
        assert exit_.value.code == 2 and message in capsys.readouterr().err


def test_tag_pairs_never_seen_in_training_are_named(generator):
    seen = generator.starts.transitions
    before, after = np.argwhere(seen > 0)[0]
    never = np.argwhere(seen == 0)[0]
    names = generator.class_names
    text = f"{names[before]} 10f, {names[after]} 10f, {names[never[0]]} 10f, {names[never[1]]} 10f"
    warnings = unseen_pairs(generator, parse_actions(text, names, 30.0, 40))
    expected = [a for a, (x, y) in enumerate([(before, after), (after, never[0]), (never[0], never[1])], 2)
                if not seen[x, y]]
    assert [int(w.split()[1]) for w in warnings] == expected and 4 in expected
