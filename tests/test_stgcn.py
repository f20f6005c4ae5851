"""ST-GCN recogniser: the reference's spatial graph, its exact architecture (parameter count), shapes, person
pooling, BatchNorm modes and that it learns."""

import functools

import jax
import jax.numpy as jnp
import numpy as np
import optax
import pytest
from hypothesis import given
from hypothesis import strategies as st

from jaxmotion.geometry.skeletons import SMPL24
from jaxmotion.nn.stgcn import STGCN, STGCNBlock, graph_aggregate, spatial_partition

TINY = {"channels": (8, 8, 16), "strides": (1, 2, 1)}
CHAIN = (-1, 0, 1, 2)


@st.composite
def trees(draw):
    """A random tree rooted at joint 0 (each joint hangs off an earlier one) and a random centre."""
    num_joints = draw(st.integers(2, 12))
    parents = (-1, *(draw(st.integers(0, j - 1)) for j in range(1, num_joints)))
    return parents, draw(st.integers(0, num_joints - 1))


def test_partition_hand_computed_on_a_chain_with_centre_at_one_end():
    # Chain 0-1-2-3, centre 0. deg = |{self} ∪ neighbours|: 2, 3, 3, 2. Entry [v, w] = 1/deg(w).
    # Distances to the centre are cut at max_hop = 1: joints 2 and 3 are both "inf", so the edge 2-3 lands
    # in subset 1 in both directions (the reference's behaviour), while 0-1 and 1-2 split by direction.
    third, half = 1 / 3, 1 / 2
    expected = np.zeros((3, 4, 4))
    expected[0] = np.diag([half, third, third, half])
    expected[1, 1, 0] = half   # joint 0 gathers from 1, farther from the centre
    expected[1, 2, 1] = third  # joint 1 gathers from 2 (inf > 1)
    expected[1, 3, 2] = third  # joint 2 gathers from 3 (inf == inf)
    expected[1, 2, 3] = half   # joint 3 gathers from 2 (inf == inf)
    expected[2, 0, 1] = third  # joint 1 gathers from 0, nearer the centre
    expected[2, 1, 2] = third  # joint 2 gathers from 1 (1 < inf)
    np.testing.assert_allclose(spatial_partition(CHAIN, center=0), expected, rtol=1e-6)


@given(trees(), st.integers(1, 3))
def test_partition_subsets_split_the_column_normalised_neighbourhood(tree, max_hop):
    parents, center = tree
    graph = spatial_partition(parents, center, max_hop)
    assert graph.shape == (1 + 2 * max_hop, len(parents), len(parents))
    # Independent neighbourhood: joints within max_hop steps of each other (self included).
    linked = np.eye(len(parents), dtype=int)
    for child, parent in enumerate(parents[1:], start=1):
        linked[child, parent] = linked[parent, child] = 1
    within = np.linalg.matrix_power(linked, max_hop) > 0
    degree = within.sum(axis=0)
    np.testing.assert_allclose(graph.sum(axis=0), within / degree, rtol=1e-6)
    np.testing.assert_allclose(graph.sum(axis=(0, 1)), 1.0, rtol=1e-6)  # A·D⁻¹: every column sums to 1
    # Subsets are disjoint and each keeps the normalised weight 1/deg(w) of the pairs it takes.
    assert ((graph != 0).sum(axis=0) == within).all()
    np.testing.assert_allclose(graph, np.where(graph != 0, 1 / degree, 0.0), rtol=1e-6)
    np.testing.assert_allclose(np.diag(graph[0]), 1 / degree, rtol=1e-6)


def test_partition_of_smpl_only_splits_edges_near_the_centre():
    graph = spatial_partition(SMPL24.parents, center=0)
    # The "nearer the centre" subset: pelvis -> hips/spine1, and hips/spine1 -> knees/spine2 (module docstring).
    assert sorted(zip(*np.nonzero(graph[2]), strict=True)) == [(0, 1), (0, 2), (0, 3), (1, 4), (2, 5), (3, 6)]


def test_graph_aggregate_sums_each_subset_over_source_joints():
    y = np.random.default_rng(0).normal(size=(2, 3, 4, 3, 5))  # [N, T, V, K, C]
    graph = spatial_partition(CHAIN, center=1)
    expected = sum(graph[k, v, :, None] * y[:, :, v, k, None, :] for k in range(3) for v in range(4))
    np.testing.assert_allclose(graph_aggregate(y, graph), expected, rtol=1e-5, atol=1e-6)


def test_parameter_count_matches_the_actor_uestc_reference():
    model = STGCN(num_classes=40, parents=SMPL24.parents, center=0)
    variables = jax.eval_shape(lambda: model.init(jax.random.key(0), jnp.zeros((1, 60, 24, 6)), train=False))
    count = sum(int(np.prod(p.shape)) for p in jax.tree.leaves(variables["params"]))

    k, v, t = 3, 24, 9  # spatial subsets, joints, temporal kernel

    def block(c_in, c_out, residual):
        gcn = c_in * k * c_out + k * c_out             # 1x1 conv to K·C_out channels, with bias
        tcn = 2 * c_out + (c_out * c_out * t + c_out) + 2 * c_out  # BN, 9x1 conv, BN
        res = (c_in * c_out + c_out + 2 * c_out) if residual == "conv" else 0  # 1x1 conv + BN
        return gcn + tcn + res + k * v * v               # + edge importance

    expected = (
        2 * v * 6                                          # data_bn over V·C = 144 channels
        + block(6, 64, None)                               # 38,528 + 1,728: no residual in block 1
        + 3 * block(64, 64, "identity")
        + block(64, 128, "conv")                           # stride 2
        + 2 * block(128, 128, "identity")
        + block(128, 256, "conv")                          # stride 2
        + 2 * block(256, 256, "identity")
        + (256 * 40 + 40)                                  # fcn
    )
    assert expected == 3_092_936
    assert count == expected
    assert variables["batch_stats"]["data_bn"]["mean"].shape == (24, 6)


@pytest.mark.parametrize("frames, stride", [(1, 2), (7, 2), (8, 2), (9, 3), (7, 1)])
def test_block_output_length_is_ceil_frames_over_stride(frames, stride):
    block = STGCNBlock(features=4, stride=stride)
    x = jnp.zeros((2, frames, 4, 3))
    out, _ = jax.eval_shape(lambda: block.init_with_output(jax.random.key(0), x, spatial_partition(CHAIN, 0),
                                                          train=False))
    assert out.shape == (2, -(-frames // stride), 4, 4)


@pytest.fixture(scope="module")
def tiny():
    """A tiny SMPL-tree model, its variables after one train step (non-trivial running stats), jitted eval-
    and train-mode applies, and a two-person input of odd length ``[4, 2, 11, 24, 6]``.

    Shared by the tests below, and keyed with "rbg" rather than threefry, because XLA on CPU takes seconds
    to compile threefry's random draws."""
    model = STGCN(num_classes=3, parents=SMPL24.parents, center=0, **TINY)
    x = jnp.asarray(np.random.default_rng(0).normal(size=(4, 2, 11, 24, 6)), jnp.float32)
    variables = jax.jit(functools.partial(model.init, train=False))(jax.random.key(0, impl="rbg"), x)
    train_apply = jax.jit(functools.partial(model.apply, train=True, mutable=["batch_stats"]))
    variables = {"params": variables["params"], **train_apply(variables, x * 2 + 1)[1]}
    apply = jax.jit(functools.partial(model.apply, train=False))
    return model, variables, apply, train_apply, x


def test_output_shapes_for_single_and_multi_person_inputs_of_odd_length(tiny):
    _, variables, apply, _, x = tiny
    for persons in (x, x[:, 0]):
        logits, features = apply(variables, persons)
        assert logits.shape == (4, 3) and features.shape == (4, 16)


def test_persons_are_pooled_by_mean(tiny):
    _, variables, apply, _, x = tiny
    logits, features = apply(variables, x)
    swapped = apply(variables, x[:, ::-1])
    np.testing.assert_allclose(swapped[0], logits, rtol=1e-5, atol=1e-5)
    np.testing.assert_allclose(swapped[1], features, rtol=1e-5, atol=1e-5)
    single = apply(variables, x[:, 0])
    copies = apply(variables, jnp.stack([x[:, 0]] * 3, axis=1))
    np.testing.assert_allclose(copies[0], single[0], rtol=1e-5, atol=1e-5)
    np.testing.assert_allclose(copies[1], single[1], rtol=1e-5, atol=1e-5)


def test_eval_mode_is_deterministic_and_uses_running_averages(tiny):
    _, variables, apply, train_apply, x = tiny
    first, second = apply(variables, x), apply(variables, x)
    np.testing.assert_array_equal(first[0], second[0])
    # Running averages make each sample's output independent of the rest of the batch.
    other_batch = x.at[2:].set(0.0)
    np.testing.assert_allclose(apply(variables, other_batch)[0][:2], first[0][:2], rtol=1e-5, atol=1e-5)
    # Train mode normalises with batch statistics instead, and moves the running averages.
    assert not np.allclose(train_apply(variables, other_batch)[0][0][:2], first[0][:2], atol=1e-3)
    (train_logits, _), updates = train_apply(variables, x)
    assert not np.allclose(train_logits, first[0], atol=1e-3)
    moved = jax.tree.map(lambda a, b: not np.allclose(a, b), updates["batch_stats"], variables["batch_stats"])
    assert all(jax.tree.leaves(moved))


def test_graph_is_constant_and_edge_importance_starts_at_ones(tiny):
    _, variables, _, _, _ = tiny
    for i in range(3):
        np.testing.assert_array_equal(variables["params"][f"block{i}"]["edge_importance"], np.ones((3, 24, 24)))
    plain = STGCN(num_classes=3, parents=SMPL24.parents, center=0, edge_importance=False, **TINY)
    shapes = jax.eval_shape(lambda: plain.init(jax.random.key(0), jnp.zeros((1, 5, 24, 6)), train=False))
    assert "edge_importance" not in shapes["params"]["block0"]


def test_dropout_is_random_in_train_mode_only(tiny):
    model, variables, _, _, x = tiny
    model = model.clone(dropout=0.5)

    @jax.jit
    def logits(key):
        train = model.apply(variables, x, train=True, mutable=["batch_stats"], rngs={"dropout": key})[0][0]
        return train, model.apply(variables, x, train=False)[0]

    (train_a, eval_a), (train_b, eval_b) = (logits(jax.random.key(seed, impl="rbg")) for seed in (0, 1))
    assert not np.allclose(train_a, train_b)
    np.testing.assert_array_equal(eval_a, eval_b)


def test_tiny_model_overfits_a_small_random_problem(tiny):
    model, variables, _, _, _ = tiny
    x = jnp.asarray(np.random.default_rng(1).normal(size=(12, 16, 24, 6)), jnp.float32)
    labels = jnp.arange(12) % 3
    optimizer = optax.adam(1e-2)

    @jax.jit
    def step(params, batch_stats, opt_state):
        def loss_fn(p):
            (logits, _), updates = model.apply({"params": p, "batch_stats": batch_stats}, x, train=True,
                                               mutable=["batch_stats"])
            return optax.softmax_cross_entropy_with_integer_labels(logits, labels).mean(), updates["batch_stats"]

        (loss, batch_stats), grads = jax.value_and_grad(loss_fn, has_aux=True)(params)
        updates, opt_state = optimizer.update(grads, opt_state, params)
        return optax.apply_updates(params, updates), batch_stats, opt_state, loss

    params, batch_stats = variables["params"], variables["batch_stats"]
    opt_state = optimizer.init(params)
    losses = []
    for _ in range(25):
        params, batch_stats, opt_state, loss = step(params, batch_stats, opt_state)
        losses.append(float(loss))
    # From about ln 3 to under 0.1: every training clip's own class gets most of the probability.
    assert losses[-1] < 0.1 < 0.5 * losses[0]


def test_bad_shapes_and_settings_name_the_problem():
    model = STGCN(num_classes=3, parents=CHAIN, center=0, **TINY)
    with pytest.raises(ValueError, match=r"x: expected shape \[B, T, V, C\].*V = 4 joints, got \(2, 6, 5, 3\)"):
        model.init(jax.random.key(0), jnp.zeros((2, 6, 5, 3)), train=False)
    with pytest.raises(ValueError, match=r"x: expected shape \[B, T, V, C\]"):
        model.init(jax.random.key(0), jnp.zeros((6, 4, 3)), train=False)
    with pytest.raises(ValueError, match="channels, strides"):
        STGCN(3, CHAIN, 0, channels=(8, 8), strides=(1,)).init(jax.random.key(0), jnp.zeros((1, 6, 4, 3)), train=False)
    with pytest.raises(ValueError, match="center: expected a joint index in \\[0, 4\\), got 4"):
        spatial_partition(CHAIN, center=4)
    with pytest.raises(ValueError, match="parents"):
        spatial_partition((-1, 2, 1), center=0)
