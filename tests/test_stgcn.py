"""ST-GCN recogniser: the reference's spatial graph, its exact architecture (parameter count, state-dict shapes),
a block and the whole net against a float64 numpy reference, shapes, person pooling, BatchNorm modes, dropout and
that it learns."""

import math

import jax
import jax.numpy as jnp
import numpy as np
import optax
import pytest
from hypothesis import given
from hypothesis import strategies as st

from jaxmotion.geometry.skeletons import SMPL24
from jaxmotion.nn.core import BatchNormStats
from jaxmotion.nn.stgcn import (
    REFERENCE_CHANNELS,
    REFERENCE_STRIDES,
    graph_aggregate,
    init_stgcn,
    init_stgcn_block,
    spatial_partition,
    stgcn,
    stgcn_block,
)

TINY = {"channels": (8, 8, 16), "strides": (1, 2, 1)}
CHAIN = (-1, 0, 1, 2)
SMPL_GRAPH = spatial_partition(SMPL24.parents, center=0)


@st.composite
def trees(draw):
    """A random tree rooted at joint 0 (each joint hangs off an earlier one) and a random centre."""
    num_joints = draw(st.integers(2, 12))
    parents = (-1, *(draw(st.integers(0, j - 1)) for j in range(1, num_joints)))
    return parents, draw(st.integers(0, num_joints - 1))


# -------------------------------------------------------------------------------------------------- graph


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
    # The "nearer the centre" subset: pelvis -> hips/spine1, and hips/spine1 -> knees/spine2 (module docstring).
    assert sorted(zip(*np.nonzero(SMPL_GRAPH[2]), strict=True)) == [(0, 1), (0, 2), (0, 3), (1, 4), (2, 5), (3, 6)]


def test_graph_aggregate_sums_each_subset_over_source_joints():
    y = np.random.default_rng(0).normal(size=(2, 3, 4, 3, 5))  # [N, T, V, K, C]
    graph = spatial_partition(CHAIN, center=1)
    expected = sum(graph[k, v, :, None] * y[:, :, v, k, None, :] for k in range(3) for v in range(4))
    np.testing.assert_allclose(graph_aggregate(y, graph), expected, rtol=1e-5, atol=1e-6)


# ----------------------------------------------------------------------------------------- architecture


def _reference_shapes():
    return jax.eval_shape(lambda key: init_stgcn(key, SMPL_GRAPH, 6, 40), jax.random.key(0))


def test_parameter_count_matches_the_actor_uestc_reference():
    params, stats = _reference_shapes()
    count = sum(math.prod(p.shape) for p in jax.tree.leaves(params))

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
    assert stats.data_bn.running_mean.shape == stats.data_bn.running_var.shape == (24, 6)
    # BatchNorms: data_bn, two per block, one per residual conv (blocks 5 and 8)
    assert len(jax.tree.leaves(stats)) == 2 * (1 + 2 * 10 + 2)


def test_parameters_have_the_reference_state_dict_shapes_less_unit_kernel_axes():
    params, stats = _reference_shapes()
    # torch shapes of the reference (yysijie/st-gcn, ACTOR's copy) for data_bn, block 5 (64 -> 128, stride 2),
    # block 6 (identity residual) and fcn, mapped as the module docstring says
    reference = {
        "data_bn.weight": (params.data_bn.weight, (144,)),
        "data_bn.running_var": (stats.data_bn.running_var, (144,)),
        "st_gcn_networks.4.gcn.conv.weight": (params.blocks[4].gcn.weight, (384, 64, 1, 1)),
        "st_gcn_networks.4.gcn.conv.bias": (params.blocks[4].gcn.bias, (384,)),
        "st_gcn_networks.4.tcn.0.weight": (params.blocks[4].tcn_bn_in.weight, (128,)),
        "st_gcn_networks.4.tcn.2.weight": (params.blocks[4].tcn_conv.weight, (128, 128, 9, 1)),
        "st_gcn_networks.4.tcn.3.running_mean": (stats.blocks[4].tcn_bn_out.running_mean, (128,)),
        "st_gcn_networks.4.residual.0.weight": (params.blocks[4].residual_conv.weight, (128, 64, 1, 1)),
        "st_gcn_networks.4.residual.1.bias": (params.blocks[4].residual_bn.bias, (128,)),
        "edge_importance.4": (params.blocks[4].edge_importance, (3, 24, 24)),
        "fcn.weight": (params.fcn.weight, (40, 256, 1, 1)),
    }
    for name, (ours, torch_shape) in reference.items():
        if name.startswith("data_bn"):  # the reference's V·C joint-major channels as [V, C]
            assert ours.shape == (24, 6) and math.prod(torch_shape) == 24 * 6, name
        else:  # conv kernels lose their unit axes: 1x1 -> [out, in], (9, 1) -> [out, in, 9]
            assert ours.shape == torch_shape[:2] + tuple(d for d in torch_shape[2:] if d != 1), name
    assert params.blocks[5].residual_conv is None and stats.blocks[5].residual_bn is None  # identity
    assert params.blocks[0].residual_conv is None  # no residual in the first block


def test_initialisation_is_torchs_default():
    params, stats = init_stgcn(jax.random.key(0, impl="rbg"), SMPL_GRAPH, 6, 40, channels=(64, 128),
                               strides=(1, 2))
    block = params.blocks[1]
    for leaf, fan_in in [(block.gcn.weight, 64), (block.gcn.bias, 64), (block.tcn_conv.weight, 128 * 9),
                         (block.tcn_conv.bias, 128 * 9), (block.residual_conv.weight, 64), (params.fcn.weight, 128)]:
        assert 0.9 / math.sqrt(fan_in) < np.abs(leaf).max() <= 1 / math.sqrt(fan_in)
    np.testing.assert_array_equal(block.edge_importance, 1.0)
    np.testing.assert_array_equal(block.tcn_bn_in.weight, 1.0)
    np.testing.assert_array_equal(block.residual_bn.bias, 0.0)
    np.testing.assert_array_equal(stats.blocks[1].tcn_bn_out.running_var, 1.0)
    np.testing.assert_array_equal(stats.data_bn.running_mean, 0.0)
    # every leaf its own buffer: a train state holding parameters and statistics can be donated
    jax.jit(lambda v: jax.tree.map(lambda a: a + 1, v), donate_argnums=0)((params, stats))


@pytest.mark.parametrize("frames, stride", [(1, 2), (7, 2), (8, 2), (9, 3), (7, 1)])
def test_block_output_length_is_ceil_frames_over_stride(frames, stride):
    graph = spatial_partition(CHAIN, 0)

    def run(key):
        p, s = init_stgcn_block(key, graph, 3, 4, stride=stride)
        return stgcn_block(p, s, jnp.zeros((2, frames, 4, 3)), graph, stride=stride, train=True)

    out, _ = jax.eval_shape(run, jax.random.key(0))
    assert out.shape == (2, -(-frames // stride), 4, 4)


# ---------------------------------------------------------------------------- float64 numpy reference


def _np(tree):
    return jax.tree.map(lambda a: np.asarray(a, np.float64), tree)


def ref_batch_norm(p, s, x, train):
    """torch BatchNorm in train (batch statistics; running ones moved by 0.1 to the unbiased estimates) or
    eval mode, over the features of ``p.weight``'s shape."""
    flat = x.reshape(-1, *p.weight.shape)
    mean, var = (flat.mean(0), flat.var(0)) if train else (s.running_mean, s.running_var)
    if train:
        s = BatchNormStats(0.9 * s.running_mean + 0.1 * mean, 0.9 * s.running_var + 0.1 * flat.var(0, ddof=1))
    return (x - mean) / np.sqrt(var + 1e-5) * p.weight + p.bias, s


def ref_block(p, s, x, graph, stride, residual, train):
    """One reference block on ``x [N, T, V, C_in]``, written with loops over subsets and output frames."""
    relu = lambda a: np.maximum(a, 0.0)
    subsets, features = graph.shape[0], p.tcn_bn_in.weight.shape[0]
    adjacency = graph * (1.0 if p.edge_importance is None else p.edge_importance)
    weight = p.gcn.weight.reshape(subsets, features, -1)  # torch's view(n, K, C, t, v): subset-major
    bias = p.gcn.bias.reshape(subsets, features)
    y = sum(np.einsum("ntvc,vw->ntwc", x @ weight[k].T + bias[k], adjacency[k]) for k in range(subsets))
    y, s_in = ref_batch_norm(p.tcn_bn_in, s.tcn_bn_in, y, train)
    y = relu(y)
    kernel = p.tcn_conv.weight.shape[-1]
    pad = (kernel - 1) // 2
    padded = np.pad(y, ((0, 0), (pad, pad), (0, 0), (0, 0)))
    y = np.stack([sum(padded[:, t * stride + j] @ p.tcn_conv.weight[:, :, j].T for j in range(kernel))
                  for t in range(-(-x.shape[1] // stride))], axis=1) + p.tcn_conv.bias
    y, s_out = ref_batch_norm(p.tcn_bn_out, s.tcn_bn_out, y, train)
    s_res = None
    if not residual:
        res = 0.0
    elif p.residual_conv is None:
        res = x
    else:
        res, s_res = ref_batch_norm(p.residual_bn, s.residual_bn,
                                    x[:, ::stride] @ p.residual_conv.weight.T + p.residual_conv.bias, train)
    return relu(y + res), (s_in, s_out, s_res)


def ref_stgcn(params, stats, x, graph, strides, train):
    """The reference net on ``x [B, M, T, V, C]``: logits, features and the new running statistics."""
    batch, persons = x.shape[:2]
    h, data_stats = ref_batch_norm(params.data_bn, stats.data_bn, x.reshape(-1, *x.shape[2:]), train)
    block_stats = []
    for i, (p, s, stride) in enumerate(zip(params.blocks, stats.blocks, strides, strict=True)):
        h, s = ref_block(p, s, h, graph, stride, i > 0, train)
        block_stats.append(s)
    features = h.mean(axis=(1, 2)).reshape(batch, persons, -1).mean(axis=1)
    return features @ params.fcn.weight.T + params.fcn.bias, features, (data_stats, block_stats)


def _random_variables(seed, graph, in_features, num_classes, channels, strides):
    """``init_stgcn``'s structure with random values (numpy-drawn, so nothing is compiled): scales and edge
    importances near 1, running variances in [0.5, 1.5], everything else N(0, 0.3²)."""
    rng = np.random.default_rng(seed)

    def draw(path, leaf):
        name = jax.tree_util.keystr(path)
        value = 0.3 * rng.standard_normal(leaf.shape)
        if name.endswith("running_var"):
            value = rng.uniform(0.5, 1.5, leaf.shape)
        elif name.endswith("edge_importance") or ("bn" in name and name.endswith(".weight")):
            value += 1.0
        return jnp.asarray(value, jnp.float32)

    shapes = jax.eval_shape(lambda key: init_stgcn(key, graph, in_features, num_classes, channels=channels,
                                                   strides=strides, temporal_kernel=5), jax.random.key(0))
    return jax.tree_util.tree_map_with_path(draw, shapes)


def _assert_tree_close(got, want, **tolerance):
    assert jax.tree.structure(got) == jax.tree.structure(want)
    for a, b in zip(jax.tree.leaves(got), jax.tree.leaves(want), strict=True):
        np.testing.assert_allclose(a, b, **tolerance)


@pytest.mark.parametrize("train", [True, False], ids=["train", "eval"])
@pytest.mark.parametrize("stride", [1, 2])
def test_block_matches_numpy_reference(train, stride):
    graph = spatial_partition(CHAIN, center=1)
    channels = (5, 6) if stride == 1 else (5, 5)  # the second block: conv residual (stride 1) or strided
    params, stats = _random_variables(1, graph, 3, 2, channels, (1, stride))
    p, s = params.blocks[1], stats.blocks[1]
    x = jnp.asarray(np.random.default_rng(2).normal(size=(3, 7, 4, channels[0])), jnp.float32)
    run = jax.jit(lambda p, s, x: stgcn_block(p, s, x, graph, stride=stride, train=train))
    out, new = run(p, s, x)
    ref_out, ref_stats = ref_block(_np(p), _np(s), np.asarray(x, np.float64), graph, stride, True, train)
    np.testing.assert_allclose(out, ref_out, rtol=1e-4, atol=1e-4)
    _assert_tree_close(tuple(new), ref_stats, rtol=1e-5, atol=1e-5)


@pytest.mark.parametrize("train", [True, False], ids=["train", "eval"])
def test_network_matches_numpy_reference(train):
    channels, strides = (6, 6, 8, 8), (1, 1, 2, 1)  # no, identity, strided conv and identity residuals
    params, stats = _random_variables(3, SMPL_GRAPH, 6, 5, channels, strides)
    assert params.blocks[1].residual_conv is None and params.blocks[2].residual_conv is not None
    x = jnp.asarray(np.random.default_rng(4).normal(size=(3, 2, 9, 24, 6)), jnp.float32)
    run = jax.jit(lambda p, s, x: stgcn(p, s, x, SMPL_GRAPH, strides=strides, train=train))
    (logits, features), new = run(params, stats, x)
    ref_logits, ref_features, (ref_data, ref_blocks) = ref_stgcn(_np(params), _np(stats), np.asarray(x, np.float64),
                                                                 SMPL_GRAPH, strides, train)
    np.testing.assert_allclose(features, ref_features, rtol=1e-4, atol=1e-4)
    np.testing.assert_allclose(logits, ref_logits, rtol=1e-4, atol=1e-4)
    _assert_tree_close((tuple(new.data_bn), [tuple(b) for b in new.blocks]),
                       (tuple(ref_data), [tuple(b) for b in ref_blocks]), rtol=1e-4, atol=1e-5)


# ------------------------------------------------------------------------------------------- behaviour


@pytest.fixture(scope="module")
def tiny():
    """Tiny SMPL-tree variables after one train step (non-trivial running stats), jitted eval- and train-mode
    forwards ``(params, stats, x[, key]) -> ((logits, features), stats)`` and a two-person input of odd length
    ``[4, 2, 11, 24, 6]``.

    Shared by the tests below, and keyed with "rbg" rather than threefry, because XLA on CPU takes seconds
    to compile threefry's random draws."""
    x = jnp.asarray(np.random.default_rng(0).normal(size=(4, 2, 11, 24, 6)), jnp.float32)
    params, stats = jax.jit(lambda key: init_stgcn(key, SMPL_GRAPH, 6, 3, **TINY))(jax.random.key(0, impl="rbg"))

    def forward(train):
        return jax.jit(lambda p, s, x, key=None, rate=0.0: stgcn(p, s, x, SMPL_GRAPH, strides=TINY["strides"],
                                                                  train=train, dropout_rate=rate, dropout_key=key),
                       static_argnames="rate")

    apply, train_apply = forward(False), forward(True)
    stats = train_apply(params, stats, x * 2 + 1)[1]
    return params, stats, apply, train_apply, x


def test_output_shapes_for_single_and_multi_person_inputs_of_odd_length(tiny):
    params, stats, apply, _, x = tiny
    for persons in (x, x[:, 0]):
        (logits, features), _ = apply(params, stats, persons)
        assert logits.shape == (4, 3) and features.shape == (4, 16)


def test_persons_are_pooled_by_mean(tiny):
    params, stats, apply, _, x = tiny
    logits, features = apply(params, stats, x)[0]
    swapped = apply(params, stats, x[:, ::-1])[0]
    np.testing.assert_allclose(swapped[0], logits, rtol=1e-5, atol=1e-5)
    np.testing.assert_allclose(swapped[1], features, rtol=1e-5, atol=1e-5)
    single = apply(params, stats, x[:, 0])[0]
    copies = apply(params, stats, jnp.stack([x[:, 0]] * 3, axis=1))[0]
    np.testing.assert_allclose(copies[0], single[0], rtol=1e-5, atol=1e-5)
    np.testing.assert_allclose(copies[1], single[1], rtol=1e-5, atol=1e-5)


def test_eval_mode_is_deterministic_and_uses_running_averages(tiny):
    params, stats, apply, train_apply, x = tiny
    (first, _), kept = apply(params, stats, x)
    np.testing.assert_array_equal(apply(params, stats, x)[0][0], first)
    jax.tree.map(np.testing.assert_array_equal, kept, stats)
    # Running averages make each sample's output independent of the rest of the batch.
    other_batch = x.at[2:].set(0.0)
    np.testing.assert_allclose(apply(params, stats, other_batch)[0][0][:2], first[:2], rtol=1e-5, atol=1e-5)
    # Train mode normalises with batch statistics instead, and moves the running averages.
    assert not np.allclose(train_apply(params, stats, other_batch)[0][0][:2], first[:2], atol=1e-3)
    (train_logits, _), moved = train_apply(params, stats, x)
    assert not np.allclose(train_logits, first, atol=1e-3)
    assert all(not np.allclose(a, b) for a, b in zip(jax.tree.leaves(moved), jax.tree.leaves(stats), strict=True))


def test_edge_importance_starts_at_ones_and_can_be_left_out(tiny):
    params, stats, apply, _, x = tiny
    for block in params.blocks:
        np.testing.assert_array_equal(block.edge_importance, np.ones((3, 24, 24)))
    plain = jax.eval_shape(lambda key: init_stgcn(key, SMPL_GRAPH, 6, 3, edge_importance=False, **TINY),
                           jax.random.key(0))[0]
    assert all(block.edge_importance is None for block in plain.blocks)
    # edge importances of ones weigh the graph as leaving them out does
    without = params._replace(blocks=tuple(b._replace(edge_importance=None) for b in params.blocks))
    np.testing.assert_allclose(apply(without, stats, x)[0][0], apply(params, stats, x)[0][0], rtol=1e-6)


def test_dropout_is_random_in_train_mode_only(tiny):
    params, stats, apply, train_apply, x = tiny
    key_a, key_b = jax.random.key(0, impl="rbg"), jax.random.key(1, impl="rbg")
    train_a = train_apply(params, stats, x, key_a, rate=0.5)[0][0]
    assert not np.allclose(train_a, train_apply(params, stats, x, key_b, rate=0.5)[0][0])
    np.testing.assert_array_equal(train_a, train_apply(params, stats, x, key_a, rate=0.5)[0][0])
    np.testing.assert_array_equal(train_apply(params, stats, x, None, rate=0.5)[0][0],
                                  train_apply(params, stats, x)[0][0])
    np.testing.assert_array_equal(apply(params, stats, x, key_a, rate=0.5)[0][0], apply(params, stats, x)[0][0])


def test_tiny_model_overfits_a_small_random_problem(tiny):
    params, stats, _, _, _ = tiny
    x = jnp.asarray(np.random.default_rng(1).normal(size=(12, 16, 24, 6)), jnp.float32)
    labels = jnp.arange(12) % 3
    optimizer = optax.adam(1e-2)

    @jax.jit
    def step(params, stats, opt_state):
        def loss_fn(p):
            (logits, _), new_stats = stgcn(p, stats, x, SMPL_GRAPH, strides=TINY["strides"], train=True)
            return optax.softmax_cross_entropy_with_integer_labels(logits, labels).mean(), new_stats

        (loss, stats), grads = jax.value_and_grad(loss_fn, has_aux=True)(params)
        updates, opt_state = optimizer.update(grads, opt_state, params)
        return optax.apply_updates(params, updates), stats, opt_state, loss

    opt_state = optimizer.init(params)
    losses = []
    for _ in range(25):
        params, stats, opt_state, loss = step(params, stats, opt_state)
        losses.append(float(loss))
    # From about ln 3 to under 0.1: every training clip's own class gets most of the probability.
    assert losses[-1] < 0.1 < 0.5 * losses[0]


def test_bad_shapes_and_settings_name_the_problem():
    graph = spatial_partition(CHAIN, 0)
    params, stats = jax.eval_shape(lambda key: init_stgcn(key, graph, 3, 3, **TINY), jax.random.key(0))

    def run(x, strides=TINY["strides"]):
        jax.eval_shape(lambda p, s, x: stgcn(p, s, x, graph, strides=strides, train=False), params, stats, x)

    with pytest.raises(ValueError, match=r"x: expected shape \[B, T, V, C\].*V = 4 joints, got \(2, 6, 5, 3\)"):
        run(jnp.zeros((2, 6, 5, 3)))
    with pytest.raises(ValueError, match=r"x: expected shape \[B, T, V, C\]"):
        run(jnp.zeros((6, 4, 3)))
    with pytest.raises(ValueError, match=r"x: expected trailing feature axes \(4, 3\)"):
        run(jnp.zeros((2, 6, 4, 6)))
    with pytest.raises(ValueError, match="strides: expected one per block"):
        run(jnp.zeros((2, 6, 4, 3)), strides=(1, 2))
    identity = jax.eval_shape(lambda key: init_stgcn(key, graph, 3, 3, channels=(8, 8), strides=(1, 1)),
                              jax.random.key(0))
    with pytest.raises(ValueError, match="no residual conv, so needs stride 1"):  # block 2 was made for stride 1
        jax.eval_shape(lambda p, s, x: stgcn(p, s, x, graph, strides=(1, 2), train=False), *identity,
                       jnp.zeros((2, 6, 4, 3)))
    with pytest.raises(ValueError, match="channels, strides"):
        init_stgcn(jax.random.key(0), graph, 3, 3, channels=(8, 8), strides=(1,))
    with pytest.raises(ValueError, match="temporal_kernel: expected an odd size, got 4"):
        init_stgcn(jax.random.key(0), graph, 3, 3, temporal_kernel=4, **TINY)
    with pytest.raises(ValueError, match=r"graph: expected shape \[K, V, V\]"):
        init_stgcn(jax.random.key(0), graph[0], 3, 3, **TINY)
    with pytest.raises(ValueError, match="center: expected a joint index in \\[0, 4\\), got 4"):
        spatial_partition(CHAIN, center=4)
    with pytest.raises(ValueError, match="parents"):
        spatial_partition((-1, 2, 1), center=0)


def test_reference_defaults_are_actors_architecture():
    assert REFERENCE_CHANNELS == (64, 64, 64, 64, 128, 128, 128, 256, 256, 256)
    assert REFERENCE_STRIDES == (1, 1, 1, 1, 2, 1, 1, 2, 1, 1)
