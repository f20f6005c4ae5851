"""Neural Marionette's multi-action protocol: candidates are the confidently recognised test actions; programs follow
the training transitions (overall) or the few most frequent ones (sufficient), deterministically; paths are replayed
from each action's start; replaying the real candidates scores a perfect accuracy, FID 0 and QR 1."""

import jax
import numpy as np
import pytest

from jaxmotion.data import synthetic
from jaxmotion.data.segments import label_transitions
from jaxmotion.evaluation.actions import action_set
from jaxmotion.evaluation.multi_action import (MultiActionProtocol, candidate_actions, evaluate_programs, real_windows,
                                               test_programs as make_programs)
from jaxmotion.pipelines.multi_action import joined


class _Oracle:
    """A recogniser that knows every real test action by its first frame (its label, with certainty) and calls
    anything else class 0; its features are each clip's mean root position on the ground."""

    num_classes = 31

    def __init__(self, actions, unsure=()):
        self.known = {self._key(j): int(a) for j, a in zip(actions.real["joints"], actions.real["actions"])}
        self.unsure = {self._key(actions.real["joints"][i]) for i in unsure}

    @staticmethod
    def _key(joints):
        return np.asarray(joints[0], np.float32).round(5).tobytes()

    def __call__(self, motions, on_chunk=None):
        joints = np.asarray(motions["joints"])
        logits = np.zeros((len(joints), self.num_classes), np.float32)
        for n, clip in enumerate(joints):
            key = self._key(clip)
            logits[n, self.known.get(key, 0)] = 0.0 if key in self.unsure else 10.0
        mask = np.arange(joints.shape[1])[None] < np.asarray(motions["lengths"])[:, None]
        roots = joints[:, :, 0, [0, 2]]  # two features: a covariance that few samples determine
        features = (roots * mask[..., None]).sum(axis=1) / mask.sum(1)[:, None]
        return logits, features


@pytest.fixture(scope="module")
def data():
    train = synthetic.generate("synth-mag", "train", seed=0, count=30, progress=False)
    takes = synthetic.generate("synth-mag", "test", seed=0, count=8, progress=False)
    return train, takes, action_set(takes)


def test_candidates_are_the_actions_recognised_with_enough_confidence(data):
    _, _, actions = data
    oracle = _Oracle(actions, unsure=[0, 3])
    picked = candidate_actions(oracle, actions, 0.5)
    assert picked.tolist() == [i for i in range(len(actions)) if i not in (0, 3)]


@pytest.mark.parametrize("kind", ["overall", "sufficient"])
def test_programs_follow_the_training_transitions_from_every_candidate(data, kind):
    train, _, actions = data
    transitions = label_transitions(train.segments)
    candidates = np.arange(len(actions))
    protocol = MultiActionProtocol(actions=6)
    programs = make_programs(jax.random.key(0), actions, candidates, transitions, kind, protocol)
    again = make_programs(jax.random.key(0), actions, candidates, transitions, kind, protocol)
    np.testing.assert_array_equal(programs.picks, again.picks)
    assert programs.picks.shape == (len(candidates), 6) and programs.picks[:, 0].tolist() == candidates.tolist()
    labels = actions.real["actions"]
    top = np.argsort(-transitions, axis=1, kind="stable")[:, :4]
    real_next = np.argmax(actions.conditions["next_tags"], axis=-1)
    present = set(labels.tolist())
    for row in programs.picks:
        for before, after in zip(row[:-1], row[1:]):
            tag, nxt = labels[before], labels[after]
            followers = {t for t in np.flatnonzero(transitions[tag] > 0) if t in present}
            if kind == "overall":
                assert nxt in followers or (not followers and nxt == tag)
            else:
                allowed = {t for t in top[tag] if transitions[tag, t] > 0} | {tag, real_next[before]}
                assert nxt in allowed & present
    c = programs.conditions
    np.testing.assert_array_equal(c["next_tags"][:, :-1], c["tags"][:, 1:])
    np.testing.assert_array_equal(c["next_tags"][:, -1], c["tags"][:, -1])  # the last: its own tags
    np.testing.assert_array_equal(c["durations"], actions.conditions["durations"][programs.picks])
    # each path in its action's start frame: it begins beside the origin, wherever the take stood
    starts = c["paths"][:, :, 0][c["follow"]]
    assert np.abs(starts).max() < 0.2
    other = make_programs(jax.random.key(1), actions, candidates, transitions, kind, protocol)
    assert (other.picks != programs.picks).any()


def test_replaying_the_real_candidates_scores_perfect_accuracy_and_no_distance(data):
    train, takes, actions = data
    transitions = label_transitions(train.segments)
    protocol = MultiActionProtocol(actions=4, count=5, window=10)
    programs = make_programs(jax.random.key(2), actions, np.arange(len(actions)), transitions, "overall", protocol)
    real = actions.real

    def replay(key, conditions):
        picks = programs.picks[:len(conditions["durations"])]
        frames = real["joints"].shape[1]
        mask = (np.arange(frames) < real["lengths"][picks][..., None])
        return {**{k: real[k][picks] * mask.reshape(*mask.shape, *([1] * (real[k].ndim - 2)))
                   for k in ("joints", "rotations", "translation")}, "lengths": real["lengths"][picks]}

    rows, curves = evaluate_programs(jax.random.key(0), {"replay": replay}, joined, _Oracle(actions), programs, takes,
                                     protocol)
    row = rows["replay"]
    assert row["accuracy"] == [1.0] and row["motion_qr"] == [1.0] and "action_qr" not in row
    assert row["FID"][0] == pytest.approx(0.0, abs=1e-3)
    np.testing.assert_allclose(curves["replay"]["FID"], 0.0, atol=1e-3)
    np.testing.assert_array_equal(curves["replay"]["motion_qr"], 1.0)
    np.testing.assert_array_equal(curves["replay"]["action_qr"], 1.0)
    assert all(np.isfinite(v[0]) for v in row.values()) and row["pose_gap"][0] > 0  # real clips do not meet
    with pytest.raises(ValueError, match="kind: expected 'overall' or 'sufficient'"):
        make_programs(jax.random.key(2), actions, np.arange(3), transitions, "some", protocol)
    with pytest.raises(ValueError, match="candidates: none"):
        make_programs(jax.random.key(2), actions, np.arange(0), transitions, "overall", protocol)


def test_transition_fids_reference_windows_are_crops_of_the_real_takes(data):
    _, takes, _ = data
    windows = real_windows(jax.random.key(2), takes, 30, 6)
    assert windows["joints"].shape == (6, 30, 24, 3) and windows["lengths"].tolist() == [30] * 6
    for joints in windows["joints"]:  # 30 consecutive frames of one take, where they are
        starts = [s for t in range(len(takes)) for s in range(takes.starts[t], takes.starts[t] + takes.lengths[t] - 29)
                  if np.allclose(takes.joints[s], joints[0], atol=1e-6)]
        assert any(np.allclose(takes.joints[s:s + 30], joints, atol=1e-6) for s in starts)


def test_label_transitions_count_first_tags_within_takes(data):
    train, _, _ = data
    counts = label_transitions(train.segments)
    seg = train.segments
    pairs = [(seg.primary[i], seg.primary[i + 1]) for i in range(len(seg.start) - 1)
             if seg.sequence[i] == seg.sequence[i + 1]]
    assert counts.sum() == len(pairs) and all(counts[a, b] > 0 for a, b in pairs)
