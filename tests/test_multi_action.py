"""Neural Marionette's chain: each action continues the last frames of the one before, as one call per action would;
the whole chain turns and moves with its first context; Shadow Start's projection on known cases; Action Revision
regenerates exactly the rejected actions; the joined motion's segment table; bad conditions named."""

import jax
import numpy as np
import pytest

from jaxmotion.data import synthetic
from jaxmotion.geometry import axis_angle_to_matrix
from jaxmotion.geometry.rotations import matrix_to_axis_angle
from jaxmotion.models.mann import MannConfig, init_mann
from jaxmotion.models.marionet import MarionetConfig, embed_poses, init_marionet
from jaxmotion.pipelines.artefacts import DataFacts
from jaxmotion.pipelines.marionette import ContextGenerator, StartBank, generate_actions, start_bank
from jaxmotion.pipelines.multi_action import ChainOptions, chain_actions, heading_ranges, joined, shadow_start

CONFIG = MarionetConfig.tiny(max_frames=10)
ACTIONS, FRAMES = 3, 9


@pytest.fixture(scope="module")
def generator():
    takes = synthetic.generate("synth-mag", "test", seed=0, count=4, progress=False)
    params = jax.jit(init_marionet, static_argnums=1)(jax.random.key(0), CONFIG)
    return ContextGenerator(CONFIG, params, DataFacts.of(takes), start_bank(takes, per_tag=2), max_frames=10)


def _conditions(seed, programs=2):
    rng = np.random.default_rng(seed)
    tags = np.zeros((programs, ACTIONS, 31), bool)
    tags[np.arange(programs)[:, None], np.arange(ACTIONS), rng.integers(0, 31, (programs, ACTIONS))] = True
    next_tags = np.concatenate([tags[:, 1:], tags[:, -1:]], axis=1)
    steps = np.cumsum(np.full((programs, ACTIONS, FRAMES, 2), 0.04), axis=2)
    return {"context_rotations": (0.2 * rng.normal(size=(programs, 6, 24, 3))).astype(np.float32),
            "context_translation": (np.cumsum(0.03 * rng.normal(size=(programs, 6, 3)), axis=1)
                                    + [0.3, 0.9, -0.5]).astype(np.float32),
            "tags": tags, "next_tags": next_tags, "durations": rng.integers(4, FRAMES + 1, (programs, ACTIONS)),
            "paths": steps.astype(np.float32), "follow": rng.random((programs, ACTIONS)) < 0.5}


def test_each_action_continues_the_last_six_frames_of_the_one_before(generator):
    c = _conditions(0)
    out = chain_actions(generator, None, c, local_paths=False)
    rotations, translation = c["context_rotations"], c["context_translation"]
    for a in range(ACTIONS):
        alone = generate_actions(generator.params, CONFIG, rotations, translation, c["tags"][:, a],
                                 c["next_tags"][:, a], c["durations"][:, a], c["paths"][:, a], c["follow"][:, a])
        np.testing.assert_allclose(out["joints"][:, a], alone["joints"], atol=1e-5)
        whole_r = np.concatenate([rotations, alone["rotations"]], axis=1)
        whole_t = np.concatenate([translation, alone["translation"]], axis=1)
        index = c["durations"][:, a, None] + np.arange(6)
        rotations = np.take_along_axis(whole_r, index[..., None, None], axis=1)
        translation = np.take_along_axis(whole_t, index[..., None], axis=1)
    assert out["lengths"].tolist() == c["durations"].tolist() and not out["shadowed"].any()


def test_local_paths_make_the_chain_follow_its_first_context_wherever_it_stands(generator):
    c = _conditions(1)
    out = chain_actions(generator, jax.random.key(3), c, local_paths=True)
    angle, shift = 0.9, np.array([1.5, 0.0, -2.0], np.float32)
    turn = np.array([[np.cos(angle), 0, np.sin(angle)], [0, 1, 0], [-np.sin(angle), 0, np.cos(angle)]], np.float32)
    moved = dict(c)
    roots = jax.vmap(jax.vmap(lambda r: turn @ r))(axis_angle_to_matrix(c["context_rotations"][:, :, 0]))
    moved["context_rotations"] = c["context_rotations"].copy()
    moved["context_rotations"][:, :, 0] = np.asarray(matrix_to_axis_angle(roots))
    moved["context_translation"] = c["context_translation"] @ turn.T + shift
    again = chain_actions(generator, jax.random.key(3), moved, local_paths=True)
    mask = np.arange(FRAMES) < c["durations"][..., None]
    np.testing.assert_allclose(again["joints"][mask], (out["joints"] @ turn.T + shift)[mask], atol=5e-4)


def test_shadow_start_projects_onto_the_nearest_begin_poses_of_the_tag(generator):
    params = generator.params
    rng = np.random.default_rng(2)
    bank = rng.normal(size=(6, 135)).astype(np.float32)
    labels = np.array([0, 0, 1, 1, 1, 2])
    begin = bank[[2]] + 0.01 * rng.normal(size=(1, 135)).astype(np.float32)
    f0, basis = np.asarray(embed_poses(params, begin))[0], np.asarray(embed_poses(params, bank))
    # one neighbour: the projection onto the nearest begin pose of tag 1 (by embedding distance)
    nearest = 2 + np.argmin(np.sum((basis[2:5] - f0) ** 2, axis=1))
    alone = basis[nearest] * (f0 @ basis[nearest]) / (basis[nearest] @ basis[nearest])
    got = shadow_start(params, begin, np.array([1]), basis, labels, neighbours=1, normalise=False)
    np.testing.assert_allclose(np.asarray(got)[0], alone, rtol=1e-4, atol=1e-5)
    # all three of tag 1: the least-squares projection onto their span, then on their mean norm
    span = basis[2:5]
    projection = span.T @ np.linalg.lstsq(span.T, f0, rcond=None)[0]
    got = shadow_start(params, begin, np.array([1]), basis, labels, neighbours=5, normalise=False)
    np.testing.assert_allclose(np.asarray(got)[0], projection, rtol=1e-3, atol=1e-4)
    normalised = shadow_start(params, begin, np.array([1]), basis, labels, neighbours=5, normalise=True)
    np.testing.assert_allclose(np.linalg.norm(np.asarray(normalised)[0]), np.linalg.norm(span, axis=1).mean(),
                               rtol=1e-5)
    direction = np.asarray(normalised)[0] / np.linalg.norm(np.asarray(normalised)[0])
    np.testing.assert_allclose(direction, projection / np.linalg.norm(projection), atol=1e-3)  # only its length
    unknown = shadow_start(params, begin, np.array([7]), basis, labels, neighbours=2, normalise=True)
    np.testing.assert_allclose(np.asarray(unknown)[0], f0, rtol=1e-6)  # no begin pose of the tag: f_0 stays


class _Reviser:
    """A classifier that answers ``answer(tags)``, for Action Revision's decisions."""

    def __init__(self, answer):
        self.answer, self.calls = answer, []

    def __call__(self, motions, on_chunk=None):
        self.calls.append(motions["lengths"])
        return self.answer(len(motions["lengths"])), None


def test_action_revision_regenerates_exactly_the_rejected_actions_from_their_shadow(generator):
    c = _conditions(3)
    labels = np.argmax(c["tags"], axis=-1)
    pure = chain_actions(generator, None, c)
    always = chain_actions(generator, None, c, options=ChainOptions("always"))
    assert always["shadowed"].all() and "revised" not in always
    assert np.abs(always["joints"] - pure["joints"]).max() > 1e-4  # the shadow changes the start
    right = iter(labels.T)  # the classifier agrees with every action: the pure chain
    accepting = chain_actions(generator, None, c, options=ChainOptions("revision"),
                              reviser=_Reviser(lambda n: np.eye(31)[next(right)]))
    np.testing.assert_array_equal(accepting["joints"], pure["joints"])
    assert not accepting["revised"].any()
    wrong = iter((labels.T + 1) % 31)  # it rejects every action: each one regenerated from its shadow (Z = mu)
    rejecting = chain_actions(generator, None, c, options=ChainOptions("revision"),
                              reviser=_Reviser(lambda n: np.eye(31)[next(wrong)]))
    np.testing.assert_allclose(rejecting["joints"], always["joints"], atol=1e-5)
    assert rejecting["revised"].all() and rejecting["shadowed"].all()


def test_joined_actions_lie_end_to_end_with_their_segment_table(generator):
    c = _conditions(4)
    out = chain_actions(generator, jax.random.key(0), c)
    motion = joined(out)
    for b in range(2):
        pieces = [out["joints"][b, a, :c["durations"][b, a]] for a in range(ACTIONS)]
        whole = np.concatenate(pieces)
        assert motion["lengths"][b] == len(whole)
        np.testing.assert_array_equal(motion["joints"][b, :len(whole)], whole)
        np.testing.assert_array_equal(motion["joints"][b, len(whole):], whole[-1:].repeat(
            motion["joints"].shape[1] - len(whole), axis=0))
        np.testing.assert_array_equal(motion["starts"][b], np.cumsum([0, *c["durations"][b, :-1]]))
    np.testing.assert_array_equal(motion["boundaries"], motion["starts"][:, 1:])


def test_bad_conditions_name_the_field(generator):
    c = _conditions(5)
    with pytest.raises(ValueError, match=r"conditions.durations: expected frames from 1 to 10"):
        chain_actions(generator, None, {**c, "durations": c["durations"] + 10})
    with pytest.raises(ValueError, match=r"conditions.paths: expected \[B, A, T, 2\] = \(2, 3, T >= "):
        chain_actions(generator, None, {**c, "paths": c["paths"][:, :, :2]})
    with pytest.raises(ValueError, match=r"conditions.next_tags: expected \[2, 3, 31\]"):
        chain_actions(generator, None, {**c, "next_tags": c["next_tags"][:, :2]})
    with pytest.raises(ValueError, match=r"conditions.context: expected rotations \[2, 6, 24, 3\]"):
        chain_actions(generator, None, {**c, "context_rotations": c["context_rotations"][:, :5]})
    with pytest.raises(ValueError, match="reviser: Action Revision needs a classifier"):
        chain_actions(generator, None, c, options=ChainOptions("revision"))
    mann = ContextGenerator(MannConfig.tiny(), init_mann(jax.random.key(0), MannConfig.tiny()), generator.facts,
                            generator.starts, max_frames=10)
    with pytest.raises(ValueError, match="Shadow Start acts on MARIONET's pose embedding; the generator is mann"):
        chain_actions(mann, None, c, options=ChainOptions("always"))
    assert chain_actions(mann, None, c)["joints"].shape == (2, ACTIONS, FRAMES, 24, 3)  # MANN chains as well
    with pytest.raises(ValueError, match="ChainOptions.shadow_start: expected"):
        ChainOptions("sometimes")


def test_smoothing_blends_shadowed_actions_in_from_the_pose_before(generator):
    c = _conditions(6)
    plain = chain_actions(generator, None, c, options=ChainOptions("always"))
    smooth = chain_actions(generator, None, c, options=ChainOptions("always", smoothing=3))
    first = smooth["rotations"][:, 0]
    last = c["context_rotations"][:, -1]
    # frame 0 lies a quarter of the way from the pose before to the action's own (weights 1/4, 2/4, 3/4, then 1)
    np.testing.assert_allclose(smooth["translation"][:, 0, 0], 0.75 * c["context_translation"][:, -1]
                               + 0.25 * plain["translation"][:, 0, 0], atol=1e-5)
    assert np.abs(first[:, 0] - last).max() < np.abs(plain["rotations"][:, 0, 0] - last).max()
    np.testing.assert_allclose(smooth["joints"][:, 0, 3:], plain["joints"][:, 0, 3:], atol=1e-5)  # frame 3 on
    pure = chain_actions(generator, None, c, options=ChainOptions("never", smoothing=3))
    np.testing.assert_array_equal(pure["joints"], chain_actions(generator, None, c)["joints"])  # no shadow, no blend


def test_heading_ranges_are_the_directions_training_starts_took_plus_a_margin():
    angles = np.deg2rad([10.0, 30.0])
    paths = np.zeros((2, 3, 8, 2), np.float32)  # tag 0: two starts heading 10 and 30 degrees, one standing still
    paths[0, :2, :, 0] = np.sin(angles)[:, None] * np.arange(1, 9) * 0.05
    paths[0, :2, :, 1] = np.cos(angles)[:, None] * np.arange(1, 9) * 0.05
    bank = _bank(paths, counts=[3, 2])
    ranges = np.rad2deg(heading_ranges(bank, margin=np.deg2rad(15.0)))
    np.testing.assert_allclose(ranges[0], [20.0, -25.0, 25.0], atol=1e-4)
    np.testing.assert_allclose(ranges[1], [0.0, -180.0, 180.0], atol=1e-4)  # tag 1 never moves: no check


def _bank(paths, counts):
    tags, per_tag, frames, _ = paths.shape
    zeros = np.zeros((tags, per_tag, 6), np.float32)
    return StartBank(np.zeros((tags, per_tag, 6, 24, 3), np.float32), zeros[..., None].repeat(3, -1), paths,
                     np.full((tags, per_tag), frames, np.int32), np.array(counts, np.int32),
                     np.zeros((1, 135), np.float32), np.zeros(1, np.int32), np.zeros((tags, tags)))


def test_the_orientation_check_turns_a_context_towards_a_path_no_start_of_its_tag_took(generator):
    """A path 2.5 rad off the tag's usual direction: the context turns about its last root until the path lies at
    the edge of the range, and the action is what the model makes from that turned context; a path within the range
    changes nothing."""
    ranges = heading_ranges(generator.starts)
    tag = int(np.argmin(np.where(ranges[:, 2] - ranges[:, 1] < 6.0, ranges[:, 2], np.inf)))  # a tag with a range
    mean, _, high = ranges[tag]
    c = {k: v[:1, :1] if k in ("tags", "next_tags", "durations", "paths", "follow") else v[:1]
         for k, v in _conditions(7, programs=1).items()}
    c["tags"] = c["next_tags"] = np.eye(31, dtype=bool)[None, None, tag]
    c["follow"], c["durations"] = np.ones((1, 1), bool), np.full((1, 1), FRAMES)
    last_root = axis_angle_to_matrix(c["context_rotations"][0, -1, 0])
    facing = np.arctan2(*np.asarray(last_root)[[0, 2], 2])  # the root's forward axis on the ground

    def path(offset):  # straight from the last root, `offset` from the tag's usual direction
        heading = facing + mean + offset
        steps = 0.05 * np.arange(1, FRAMES + 1)[:, None] * [np.sin(heading), np.cos(heading)]
        return (c["context_translation"][0, -1, [0, 2]] + steps).astype(np.float32)[None, None]

    options = ChainOptions(orientation=True)
    out = chain_actions(generator, None, {**c, "paths": path(2.5)}, options=options)
    np.testing.assert_allclose(out["turned"][0, 0], 2.5 - high, atol=1e-4)
    turn = float(out["turned"][0, 0])
    about_y = np.array([[np.cos(turn), 0, np.sin(turn)], [0, 1, 0], [-np.sin(turn), 0, np.cos(turn)]], np.float32)
    pivot = c["context_translation"][0, -1] * [1, 0, 1]
    roots = np.asarray(matrix_to_axis_angle(about_y @ axis_angle_to_matrix(c["context_rotations"][0, :, 0])))
    turned = c["context_rotations"].copy()
    turned[0, :, 0] = roots
    alone = generate_actions(generator.params, CONFIG, turned, (c["context_translation"] - pivot) @ about_y.T + pivot,
                             c["tags"][:, 0], c["next_tags"][:, 0], c["durations"][:, 0], path(2.5)[:, 0],
                             c["follow"][:, 0])
    np.testing.assert_allclose(out["joints"][:, 0], alone["joints"], atol=1e-4)
    within = {**c, "paths": path(0.0)}
    kept = chain_actions(generator, None, within, options=options)
    assert kept["turned"][0, 0] == 0
    np.testing.assert_array_equal(kept["joints"], chain_actions(generator, None, within)["joints"])
    with pytest.raises(ValueError, match="options.orientation: the check turns a context towards a world path"):
        chain_actions(generator, None, within, options=options, local_paths=True)
