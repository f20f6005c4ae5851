"""The batching pipeline: windows, padding, masks, sampling schemes, canonical frame, model inputs."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from jaxmotion.data import Motion, pack
from jaxmotion.data.pipeline import (
    BatchSpec,
    BucketedEpochOrder,
    EpochOrder,
    PairSpec,
    class_members,
    draw_partners,
    canonicalize_motion,
    length_buckets,
    make_batch_fn,
    random_lengths,
    sequence_weights,
    window_frames,
)
from jaxmotion.geometry import SMPL24, axis_angle_to_matrix, forward_kinematics
from jaxmotion.models.actor import from_features, to_features

LENGTHS = (30, 12, 50, 7, 41, 25)
ACTIONS = (0, 0, 0, 1, 1, 2)


def _fk(rotations, translation):
    return np.asarray(forward_kinematics(axis_angle_to_matrix(jnp.asarray(rotations)), jnp.asarray(translation),
                                         SMPL24.offsets, SMPL24.parents))


@pytest.fixture(scope="module")
def dataset():
    rng = np.random.default_rng(0)
    n, longest = len(LENGTHS), max(LENGTHS)
    rot = (0.3 * rng.normal(size=(n, longest, 24, 3))).astype(np.float32)
    rot[:, :, 0, 1] += rng.uniform(-3, 3, size=(n, 1))  # an arbitrary heading per sequence
    trans = (np.cumsum(0.02 * rng.normal(size=(n, longest, 3)), axis=1) + rng.normal(size=(n, 1, 3)))
    trans = trans.astype(np.float32)
    joints = _fk(rot, trans)  # one FK call for all sequences, then cut each to its length
    motions = [Motion(joints[i, :t], trans[i, :t], rot[i, :t], action=a, mode=i % 2, subject=i, name=str(i))
               for i, (t, a) in enumerate(zip(LENGTHS, ACTIONS, strict=True))]
    return pack(motions, name="toy", split="train", class_names=("a", "b", "c"), skeleton=SMPL24, fps=20)


def test_last_frame_padding_repeats_the_final_frame():
    frames, mask = window_frames(jnp.array([100]), jnp.array([4]), 7, "last")
    assert frames.tolist() == [[100, 101, 102, 103, 103, 103, 103]]
    assert mask.tolist() == [[True] * 4 + [False] * 3]


def test_snake_padding_runs_back_and_forth():
    frames, _ = window_frames(jnp.array([0, 10]), jnp.array([4, 1]), 10, "snake")
    assert frames.tolist() == [[0, 1, 2, 3, 2, 1, 0, 1, 2, 3], [10] * 10]


def test_random_lengths_stay_in_range():
    n = jnp.array([5, 60, 80, 200] * 50)
    got = np.asarray(random_lengths(jax.random.key(0), n, 60, 100))
    assert np.all(got[n == 5] == 5)  # too short: kept whole, never dropped
    assert np.all(got[n == 60] == 60)
    assert np.all((got[n == 80] >= 60) & (got[n == 80] <= 80))
    assert np.all((got[n == 200] >= 60) & (got[n == 200] <= 100)) and len(set(got[n == 200])) > 10


def test_sequence_weights_follow_each_scheme():
    actions = jnp.array([0, 0, 0, 0, 1, 2, 2, 2, 2, 2, 2, 2, 2, 2])  # class counts 4, 1, 9
    class_mass = lambda w: np.bincount(np.asarray(actions), weights=np.asarray(w))  # noqa: E731
    np.testing.assert_allclose(class_mass(sequence_weights(actions, 3, "uniform")), np.array([4, 1, 9]) / 14,
                               rtol=1e-6)
    np.testing.assert_allclose(class_mass(sequence_weights(actions, 3, "balanced")), [1 / 3] * 3, rtol=1e-6)
    np.testing.assert_allclose(class_mass(sequence_weights(actions, 3, "sqrt")), np.array([2, 1, 3]) / 6, rtol=1e-6)


@pytest.mark.parametrize("batch_size", [3, 4])
def test_epoch_sampling_visits_every_sequence_once_per_epoch(batch_size):
    n, epochs = 12, 3
    steps = n * epochs // batch_size
    order = EpochOrder(jax.random.key(1), n, batch_size)
    ids = np.concatenate([order(s) for s in range(steps)])
    for e in range(epochs):
        assert sorted(ids[e * n:(e + 1) * n]) == list(range(n))
    assert not np.array_equal(ids[:n], ids[n:2 * n])  # a fresh order each epoch
    again = EpochOrder(jax.random.key(1), n, batch_size)
    np.testing.assert_array_equal(again(steps - 1), order(steps - 1))  # a function of (key, step) only


def test_length_buckets_split_at_quantiles_and_never_split_equal_lengths():
    bucket_of, longest = length_buckets(np.array([5, 1, 9, 3, 7, 3, 2, 8]), 4)
    np.testing.assert_array_equal(longest, [2, 3, 7, 9])
    np.testing.assert_array_equal(bucket_of, [2, 0, 3, 1, 2, 1, 0, 3])
    np.testing.assert_array_equal(length_buckets(np.array([4, 4, 4, 6]), 3)[1], [4, 6])  # ties: fewer buckets


def test_bucketed_epochs_visit_every_sequence_with_one_bucket_per_batch():
    bucket_of = np.array([0, 1, 0, 2, 1, 0, 2, 0, 1, 0])  # buckets of 5, 3 and 2 sequences
    order = BucketedEpochOrder(jax.random.key(4), bucket_of, batch_size=2)
    assert order.per_epoch == 3 + 2 + 1
    epochs = [[order(e * order.per_epoch + i) for i in range(order.per_epoch)] for e in range(2)]
    for batches in epochs:
        ids = np.concatenate([batch for batch, _ in batches])
        assert set(ids) == set(range(10)) and len(ids) == 12  # the last batches of buckets 0 and 1 are filled up
        assert all((bucket_of[batch] == bucket).all() for batch, bucket in batches)
    assert any(not np.array_equal(x, y) for (x, _), (y, _) in zip(*epochs))  # a fresh order each epoch
    again = BucketedEpochOrder(jax.random.key(4), bucket_of, batch_size=2)
    np.testing.assert_array_equal(again(7)[0], order(7)[0])  # a function of (key, step) only


def test_bucketed_batches_are_padded_to_their_buckets_longest(dataset):
    """LENGTHS 30 12 50 7 41 25 in 3 buckets: (7, 12), (25, 30), (41, 50 cropped to the window 45)."""
    spec = BatchSpec(batch_size=2, window=45, canonical=False, buckets=3)
    batch_fn = make_batch_fn(dataset, jax.random.key(0), spec)
    plain = make_batch_fn(dataset, jax.random.key(0), BatchSpec(batch_size=2, window=45, canonical=False))
    windows = {}
    for step in range(6):
        batch = batch_fn(step)
        lengths = tuple(sorted(np.asarray(batch["lengths"]).tolist()))
        windows[lengths] = batch["mask"].shape[1]
        for b in range(2):  # the sequence itself up to its length, then its last frame
            seq = dataset[int(batch["subjects"][b])]
            real = int(batch["lengths"][b])
            assert int(batch["mask"][b].sum()) == real == min(seq.num_frames, 45)
        assert batch.keys() == plain(step).keys()
    assert windows == {(7, 12): 12, (25, 30): 30, (41, 45): 45}
    with pytest.raises(ValueError, match="buckets: 3 length buckets batch whole sequences by epoch"):
        BatchSpec(batch_size=2, window=45, buckets=3, min_length=10)
    with pytest.raises(ValueError, match="PairSpec.batch.buckets"):
        make_batch_fn(dataset, jax.random.key(0), PairSpec(BatchSpec(batch_size=2, window=45, buckets=3)))


def test_batches_have_static_shapes_and_are_deterministic(dataset):
    spec = BatchSpec(batch_size=4, window=20)
    a = make_batch_fn(dataset, jax.random.key(0), spec)
    b = make_batch_fn(dataset, jax.random.key(0), spec)
    first, again = a(5), b(5)
    assert first["joints"].shape == (4, 20, 24, 3) and first["rotations"].shape == (4, 20, 24, 3)
    assert first["translation"].shape == (4, 20, 3) and first["mask"].shape == (4, 20)
    jax.tree.map(lambda x, y: np.testing.assert_array_equal(np.asarray(x), np.asarray(y)), first, again)
    assert not np.array_equal(np.asarray(a(6)["joints"]), np.asarray(first["joints"]))


def test_window_is_a_crop_of_its_sequence_padded_with_the_last_frame(dataset):
    batch = make_batch_fn(dataset, jax.random.key(3), BatchSpec(batch_size=6, window=40, canonical=False))(0)
    for b in range(6):
        seq = dataset[int(batch["subjects"][b])]  # subject i is sequence i in this fixture
        n, real = seq.num_frames, int(batch["lengths"][b])
        assert real == min(n, 40) and int(batch["mask"][b].sum()) == real
        window = np.asarray(batch["joints"][b])
        np.testing.assert_allclose(window[0, 0], 0.0, atol=1e-6)  # root of frame 0 moved to the origin
        crops = [s for s in range(n - real + 1)
                 if np.allclose(seq.joints[s:s + real] - seq.joints[s, 0], window[:real], atol=1e-5)]
        assert crops, f"window {b} is not a crop of its sequence"
        np.testing.assert_array_equal(window[real:], np.broadcast_to(window[real - 1], window[real:].shape))


def test_canonical_batches_start_at_the_origin_facing_forward_and_stay_fk_consistent(dataset):
    batch = make_batch_fn(dataset, jax.random.key(4), BatchSpec(batch_size=6, window=16))(2)
    joints = np.asarray(batch["joints"])
    np.testing.assert_allclose(joints[:, 0, 0], 0.0, atol=1e-5)
    left = joints[:, 0, SMPL24.index("left_hip")] - joints[:, 0, SMPL24.index("right_hip")]
    facing = np.cross(left, [0.0, 1.0, 0.0])
    np.testing.assert_allclose(facing[:, 0], 0.0, atol=1e-5)
    assert np.all(facing[:, 2] > 0)
    np.testing.assert_allclose(_fk(batch["rotations"], batch["translation"]), joints, atol=2e-5)


def test_variable_length_batches_mask_after_the_sampled_length(dataset):
    spec = BatchSpec(batch_size=6, window=45, sampling="uniform", min_length=10)
    batch = make_batch_fn(dataset, jax.random.key(5), spec)(0)
    lengths, mask = np.asarray(batch["lengths"]), np.asarray(batch["mask"])
    n = np.array([LENGTHS[int(s)] for s in np.asarray(batch["subjects"])])
    assert np.all(lengths <= np.minimum(n, 45)) and np.all(lengths >= np.minimum(n, 10))
    np.testing.assert_array_equal(mask, np.arange(45)[None] < lengths[:, None])


def test_canonicalize_motion_keeps_joints_equal_to_fk(dataset):
    m = dataset[2]
    j, t, r = jax.jit(canonicalize_motion, static_argnums=(3, 4))(jnp.asarray(m.joints)[None], jnp.asarray(m.translation)[None],
                                  jnp.asarray(m.rotations)[None], SMPL24.index("left_hip"), SMPL24.index("right_hip"))
    np.testing.assert_allclose(_fk(r, t), np.asarray(j), atol=2e-5)


@pytest.mark.parametrize("rep, channels", [("rot6d", 6), ("quaternion", 4), ("axis_angle", 3), ("matrix", 9)])
def test_actor_features_round_trip(dataset, rep, channels):
    m = dataset[0]
    rot, trans = jnp.asarray(m.rotations)[None], jnp.asarray(m.translation)[None]
    feats = jax.jit(to_features, static_argnums=2)(rot, trans, rep)
    assert feats.shape == (1, m.num_frames, 25, channels)
    np.testing.assert_allclose(np.asarray(feats[0, 0, 24]), 0.0, atol=1e-6)  # translation relative to frame 0
    back_rot, back_trans = jax.jit(from_features, static_argnums=1)(feats, rep)
    np.testing.assert_allclose(np.asarray(axis_angle_to_matrix(back_rot)), np.asarray(axis_angle_to_matrix(rot)),
                               atol=1e-5)
    np.testing.assert_allclose(np.asarray(back_trans), np.asarray(trans - trans[:, :1]), atol=1e-5)


def test_bad_specs_are_rejected(dataset):
    with pytest.raises(ValueError, match="min_length must be in"):
        BatchSpec(batch_size=2, window=10, min_length=11)
    with pytest.raises(ValueError, match="exceeds the 6 sequences"):
        make_batch_fn(dataset, jax.random.key(0), BatchSpec(batch_size=7, window=10))
    make_batch_fn(dataset, jax.random.key(0), BatchSpec(batch_size=2, window=50))  # the longest clip: accepted
    with pytest.raises(ValueError, match=r"window: 51 frames is longer than every clip of toy/train \(the longest has "
                                         r"50\): every training window would be mostly padding; choose at most 50"):
        make_batch_fn(dataset, jax.random.key(0), BatchSpec(batch_size=2, window=51))


# --- pairs (ODMO) -----------------------------------------------------------------------------------


@pytest.mark.parametrize("other", ["uniform", "balanced"])
def test_partners_share_the_class_half_of_the_time_and_are_never_the_sequence_itself(other):
    actions = np.array([0] * 30 + [1] * 10 + [2] * 60)
    table = class_members(actions, 3)
    ids = jnp.asarray(np.tile(np.arange(100), 40))
    partners, same = map(np.asarray, draw_partners(jax.random.key(0), ids, table, other, 0.5))
    ids = np.asarray(ids)
    np.testing.assert_array_equal(actions[partners] == actions[ids], same)
    assert abs(same.mean() - 0.5) < 0.03
    assert not np.any(partners[same] == ids[same])
    # a same-class partner is uniform over the other members of the class
    zeros = jnp.zeros(2000, jnp.int32)
    of_first, _ = draw_partners(jax.random.key(1), zeros, table, other, 1.0)
    counts = np.bincount(np.asarray(of_first), minlength=30)
    assert counts[0] == 0 and np.all(counts[1:30] > 35) and counts[30:].sum() == 0
    # another-class partner: by class size (uniform over sequences) or every other class alike
    from_class_0 = actions[partners[~same & (actions[ids] == 0)]]
    share_of_class_2 = np.mean(from_class_0 == 2)
    assert abs(share_of_class_2 - (60 / 70 if other == "uniform" else 0.5)) < 0.05


def test_a_lone_class_member_is_its_own_partner_and_a_single_class_always_pairs_within():
    table = class_members(np.array([0, 1, 1]), 2)
    partners, same = draw_partners(jax.random.key(1), jnp.zeros(200, jnp.int32), table, "uniform", 1.0)
    assert np.all(np.asarray(partners) == 0) and np.all(np.asarray(same))
    table = class_members(np.array([0, 0, 0]), 1)
    partners, same = draw_partners(jax.random.key(2), jnp.zeros(200, jnp.int32), table, "uniform", 0.0)
    assert np.all(np.asarray(same)) and set(np.asarray(partners).tolist()) == {1, 2}


def test_pair_batches_are_deterministic_with_class_labels_matching_same(dataset):
    spec = PairSpec(BatchSpec(batch_size=8, window=20, sampling="balanced", canonical=False))
    a, b = make_batch_fn(dataset, jax.random.key(0), spec), make_batch_fn(dataset, jax.random.key(0), spec)
    first, second = a(3), b(3)
    for half in ("first", "second"):
        for k, v in first[half].items():
            np.testing.assert_array_equal(v, second[half][k])
        assert first[half]["joints"].shape == (8, 20, 24, 3)
        np.testing.assert_allclose(first[half]["joints"][:, 0, 0], 0, atol=1e-6)  # root of frame 0 at the origin
    np.testing.assert_array_equal(first["same"], first["first"]["actions"] == first["second"]["actions"])
    # the unpaired batch of the same spec and key is the pair batch's first half
    plain = make_batch_fn(dataset, jax.random.key(0), spec.batch)(3)
    np.testing.assert_array_equal(plain["joints"], first["first"]["joints"])


def test_pair_spec_rejects_unknown_partner_draws():
    with pytest.raises(ValueError, match="PairSpec.other"):
        PairSpec(BatchSpec(batch_size=2, window=4), other="nearest")
    with pytest.raises(ValueError, match="PairSpec.same_probability"):
        PairSpec(BatchSpec(batch_size=2, window=4), same_probability=1.5)


def test_tiled_windows_cut_each_clip_as_actformers_reference_set():
    from jaxmotion.data import synthetic
    from jaxmotion.data.pipeline import tiled_windows

    data = synthetic.generate("synth-humanact12", count=24)
    out = tiled_windows(data, 30)
    expected = [len(range(0, max(int(n) - 30, 0), 30)) for n in data.lengths]
    np.testing.assert_array_equal(np.bincount(out["sequence"], minlength=len(data)), expected)
    assert out["joints"].shape == (sum(expected), 30, 24, 3) and out["mask"].all()
    k = int(np.flatnonzero(out["sequence"] == 0)[1])  # the clip's second window starts at frame 30
    np.testing.assert_array_equal(out["joints"][k], data[0].joints[30:60])
    np.testing.assert_array_equal(out["actions"], data.actions[out["sequence"]])
    with pytest.raises(ValueError, match="no clip .* is longer than 1000 frames"):
        tiled_windows(data, 1000)
