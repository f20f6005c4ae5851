"""The CSGN-style generator (jaxmotion.models.csgn): shapes and output constraints for NTU-25 and SMPL-25, one and
two persons, both temporal modes; BatchNorm's train / eval behaviour (running statistics by hand, row
independence in eval); graph upsampling as the adjoint of the critic's downsampling; conditional BatchNorm;
temporal receptive fields; gradients reaching every parameter; spectral normalisation; input checks."""

import dataclasses
import functools

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from jaxmotion.geometry.skeletons import NTU25, SMPL24
from jaxmotion.models.actformer_critic import GraphConvParams, graph_conv
from jaxmotion.models.csgn import (
    CondBatchNormParams,
    CSGNBuffers,
    CSGNConfig,
    conditional_batch_norm,
    generate,
    generator_graphs,
    graph_upsample,
    init_generator,
)
from jaxmotion.nn.core import BatchNormStats, count_parameters
from jaxmotion.nn.gp_prior import gp_factors, sample_gp

SMPL25 = SMPL24.parents + (0,)
_generate = jax.jit(generate, static_argnums=0, static_argnames="train")


def _config(**overrides):
    """A small generator: 8 frames, narrow layers (the structure is the default one)."""
    fields = {"num_classes": 4, "frames": 8, "widths": (16, 16, 8, 8), "heads": 2}
    return CSGNConfig(**{**fields, **overrides})


def _z(config, batch=3, key=0):
    return sample_gp(jax.random.key(key), jnp.asarray(gp_factors(config.frames)), batch)


def _perturbed(params, key=1, scale=0.5):
    """The parameters with random class embeddings in every conditional BatchNorm (they start at zero)."""
    keys = iter(jax.random.split(jax.random.key(key), 8))

    def perturb(norm):
        return CondBatchNormParams(scale * jax.random.normal(next(keys), norm.gain.shape),
                                   scale * jax.random.normal(next(keys), norm.bias.shape))

    return params._replace(input_norm=perturb(params.input_norm),
                           stages=tuple(s._replace(norm=perturb(s.norm)) for s in params.stages))


def _assert_same_tree(a, b):
    assert jax.tree.structure(a) == jax.tree.structure(b)
    for x, y in zip(jax.tree.leaves(a), jax.tree.leaves(b)):
        np.testing.assert_array_equal(np.asarray(x), np.asarray(y))


def _trained_buffers(config, params, buffers, steps=2):
    """Buffers whose running statistics have moved away from (0, 1)."""
    for i in range(steps):
        _, buffers = _generate(config, params, buffers, _z(config, 3, key=10 + i), jnp.array([0, 1, 3]), train=True)
    return buffers


# --- shapes and output constraints ---------------------------------------------------------------------------


@pytest.mark.parametrize("temporal", ["conv", "transformer"])
@pytest.mark.parametrize("persons", [1, 2])
def test_ntu25_skeleton_output_shapes_and_unit_limbs(persons, temporal):
    # two persons with T-Formers also with spectral norm (test_spectral_vectors_move_in_training_only's config)
    config = _config(persons=persons, temporal=temporal, spectral_norm=persons == 2 and temporal == "transformer")
    params, buffers = init_generator(jax.random.key(0), config)
    for train in (True, False):
        motion, _ = _generate(config, params, buffers, _z(config), jnp.array([0, 1, 3]), train=train)
        assert motion.shape == ((3, 8, 25, 3) if persons == 1 else (3, 2, 8, 25, 3))
        motion = np.asarray(motion)
        assert np.isfinite(motion).all()
        norms = np.linalg.norm(motion[..., 1:, :], axis=-1)  # |tanh| / (|tanh| + 1e-4): just under 1
        assert np.all(norms <= 1.0) and np.median(norms) > 0.99
        assert np.abs(motion[..., 0, :]).max() > 0.0  # the raw root


@pytest.mark.parametrize("persons, temporal", [(1, "conv"), (2, "transformer")])
def test_smpl25_output_is_orthonormal_rot6d_and_a_raw_translation(persons, temporal):
    config = _config(persons=persons, temporal=temporal, parents=SMPL25, channels=6, output="smpl")
    params, buffers = init_generator(jax.random.key(2), config)
    motion = np.asarray(_generate(config, params, buffers, _z(config), jnp.array([0, 1, 2]), train=True)[0])
    assert motion.shape == ((3, 8, 25, 6) if persons == 1 else (3, 2, 8, 25, 6))
    b1, b2 = motion[..., :24, :3], motion[..., :24, 3:]
    np.testing.assert_allclose(np.linalg.norm(b1, axis=-1), 1.0, atol=1e-5)
    np.testing.assert_allclose(np.linalg.norm(b2, axis=-1), 1.0, atol=1e-5)
    np.testing.assert_allclose((b1 * b2).sum(-1), 0.0, atol=1e-5)
    assert not np.allclose(np.linalg.norm(motion[..., 24, :3], axis=-1), 1.0, atol=1e-3)  # raw, not normalised


def test_parameter_count_follows_the_layer_arithmetic():
    """Default widths at NTU-25 (L2 = 5, L1 = 11 nodes), one person, 94 classes, node-specific layers with two
    hop kernels: every term written out, so a changed layer shows here."""
    k, z, (w0, w1, w2, w3), v, l1, l2, hops = 94, 120, (128, 128, 64, 32), 25, 11, 5, 2
    for temporal, kt in (("conv", 3), ("transformer", 1)):
        config = CSGNConfig(num_classes=k, temporal=temporal)
        params, buffers = jax.eval_shape(lambda key, c=config: init_generator(key, c), jax.random.key(0))
        expected = ((z + 1) * l2 * w0 + 2 * k * (w0 + w1 + w2 + w3)  # input Linear, CBN embeddings
                    + hops * kt * (l2 * w1 * w0 + l2 * w2 * w1 + l1 * w3 * w2)  # up3, up2, up1 (no bias)
                    + v * 3 * hops * (w3 * kt + 1))  # output layer with bias
        if temporal == "transformer":  # positions [T, w], qkv, out, MLP (ratio 2), two LayerNorms
            expected += sum(60 * w + (3 * w * w + 3 * w) + (w * w + w) + (2 * w * w + 2 * w) + (2 * w * w + w) + 4 * w
                            for w in (w1, w2, w3))
        assert count_parameters(params) == expected
        assert 5e5 < expected < 1.4e6
        assert buffers.spectral is None and [s.running_mean.shape for s in buffers.stages] == [(w1,), (w2,), (w3,)]


# --- BatchNorm: eval mode, train mode -----------------------------------------------------------------------


@pytest.mark.parametrize("temporal", ["conv", "transformer"])
def test_eval_mode_rows_do_not_depend_on_the_batch(temporal):
    config = _config(temporal=temporal)
    params, buffers = init_generator(jax.random.key(3), config)
    params = _perturbed(params)
    buffers = _trained_buffers(config, params, buffers)
    z, labels = _z(config, 3, key=5), jnp.array([3, 0, 2])
    full, same = _generate(config, params, buffers, z, labels)
    _assert_same_tree(same, buffers)
    alone, _ = _generate(config, params, buffers, z[2:3], labels[2:3])
    other, _ = _generate(config, params, buffers, jnp.concatenate([_z(config, 2, key=6), z[2:3]]),
                         jnp.array([1, 1, 2]))
    np.testing.assert_allclose(np.asarray(alone[0]), np.asarray(full[2]), rtol=1e-5, atol=1e-5)
    np.testing.assert_allclose(np.asarray(other[2]), np.asarray(full[2]), rtol=1e-5, atol=1e-5)
    # training mode normalises with the batch's statistics: the same row changes with its batch
    a = _generate(config, params, buffers, z, labels, train=True)[0][2]
    b = _generate(config, params, buffers, jnp.concatenate([_z(config, 2, key=6), z[2:3]]), jnp.array([1, 1, 2]),
                  train=True)[0][2]
    assert np.abs(np.asarray(a) - np.asarray(b)).max() > 1e-3


def test_train_mode_moves_running_statistics_by_momentum_0_1():
    config = _config()
    params, buffers = init_generator(jax.random.key(4), config)
    start = CSGNBuffers(BatchNormStats(jnp.full((16,), 0.5), jnp.full((16,), 2.0)), buffers.stages, None)
    z, labels = _z(config, 3, key=7), jnp.array([0, 1, 2])
    _, moved = _generate(config, params, start, z, labels, train=True)
    # the first BatchNorm's input by hand: the per-frame Linear, nodes x channels, node-major
    h = np.asarray(z, np.float64) @ np.asarray(params.input.weight, np.float64).T + np.asarray(params.input.bias)
    h = h.reshape(3, 8, 5, 16)  # [B, T, L2, w0]
    mean, var = h.mean((0, 1, 2)), h.var((0, 1, 2), ddof=1)
    np.testing.assert_allclose(moved.input_norm.running_mean, 0.9 * 0.5 + 0.1 * mean, rtol=1e-4, atol=1e-5)
    np.testing.assert_allclose(moved.input_norm.running_var, 0.9 * 2.0 + 0.1 * var, rtol=1e-4, atol=1e-5)
    for before, after in zip(buffers.stages, moved.stages):  # every stage's statistics moved
        assert np.abs(np.asarray(after.running_mean) - np.asarray(before.running_mean)).max() > 1e-4
        assert np.abs(np.asarray(after.running_var) - np.asarray(before.running_var)).max() > 1e-4


# --- graph upsampling ---------------------------------------------------------------------------------------


def _shared_weights(m, nodes):
    """Graph-layer weight ``[N·c·K, C_in, 1]`` with the same ``m [c, K, C_in]`` at every input node."""
    return jnp.asarray(np.tile(m.reshape(1, -1, m.shape[-1]), (nodes, 1, 1)).reshape(-1, m.shape[-1], 1),
                       jnp.float32)


@pytest.mark.parametrize("layer", ["up1", "up2", "up3", "out"])
def test_upsampling_is_the_adjoint_of_the_matching_downsampling(layer):
    """With node-shared weights and unit temporal kernels: <down(x), y> = <x, up(y)>, for the critic's
    adjacency (NTU-25) and the weight transposed between the two."""
    rng = np.random.default_rng(0)
    a = getattr(generator_graphs(NTU25.parents), layer)  # [K, W, V] the downsampling's
    hops, coarse, fine = a.shape
    c_fine, c_coarse = 3, 4
    m = rng.normal(size=(c_coarse, hops, c_fine))  # down: fine channels -> coarse channels
    down = GraphConvParams(_shared_weights(m, fine), None)
    up = GraphConvParams(_shared_weights(np.transpose(m, (2, 1, 0)), coarse), None)
    x = rng.normal(size=(2, 5, fine, c_fine)).astype(np.float32)
    y = rng.normal(size=(2, 5, coarse, c_coarse)).astype(np.float32)
    down_x = np.asarray(graph_conv(down, a, jnp.asarray(x), stride=1, padding=0), np.float64)
    up_y = np.asarray(graph_upsample(up, a, jnp.asarray(y), padding=0), np.float64)
    assert down_x.shape == y.shape and up_y.shape == x.shape
    np.testing.assert_allclose((down_x * y).sum(), (x * up_y).sum(), rtol=1e-4)


def test_upsampling_spreads_a_coarse_node_to_itself_and_its_neighbours():
    """NTU-25, L1 -> V: a unit impulse on coarse node w (one channel, unit weights per hop kernel) lands on the
    fine node it was kept from (weight A[0, w, kept]) and that node's skeleton neighbours (A[1, w, v]), nowhere
    else."""
    a = generator_graphs(NTU25.parents).up1  # [2, 11, 25]
    kept = [0, 3, 5, 7, 9, 11, 13, 15, 17, 19, 20]  # graph_coarsening's NTU-25 first level
    ones = GraphConvParams(jnp.ones((11 * 2, 1, 1)), None)
    for w in (0, 4, 10):
        y = np.zeros((1, 1, 11, 1), np.float32)
        y[0, 0, w, 0] = 1.0
        out = np.asarray(graph_upsample(ones, a, jnp.asarray(y), padding=0))[0, 0, :, 0]
        neighbours = {c for c, p in enumerate(NTU25.parents) if p == kept[w]} | {NTU25.parents[kept[w]]} - {-1}
        assert set(np.flatnonzero(out)) == {kept[w]} | neighbours
        np.testing.assert_allclose(out[kept[w]], a[0, w, kept[w]], rtol=1e-6)


# --- conditional BatchNorm ----------------------------------------------------------------------------------


def test_conditional_batch_norm_starts_as_plain_batch_norm_and_then_depends_on_the_label():
    rng = np.random.default_rng(1)
    x = rng.normal(2.0, 3.0, size=(3, 4, 5, 6)).astype(np.float32)  # [B, T, N, C]
    labels = jnp.array([0, 2, 2])
    stats = BatchNormStats(jnp.zeros(6), jnp.ones(6))
    zero = CondBatchNormParams(jnp.zeros((3, 6)), jnp.zeros((3, 6)))
    plain = (x - x.mean((0, 1, 2))) / np.sqrt(x.var((0, 1, 2)) + 1e-5)
    y, _ = conditional_batch_norm(zero, stats, jnp.asarray(x), labels, train=True)
    np.testing.assert_allclose(np.asarray(y), plain, rtol=1e-4, atol=1e-4)
    y_eval, same = conditional_batch_norm(zero, stats, jnp.asarray(x), labels, train=False)
    np.testing.assert_allclose(np.asarray(y_eval), x / np.sqrt(1 + 1e-5), rtol=1e-5)
    assert same is stats
    g, b = rng.normal(size=(3, 6)).astype(np.float32), rng.normal(size=(3, 6)).astype(np.float32)
    y, _ = conditional_batch_norm(CondBatchNormParams(jnp.asarray(g), jnp.asarray(b)), stats, jnp.asarray(x),
                                  labels, train=True)
    expected = plain * (1 + g[[0, 2, 2]])[:, None, None] + b[[0, 2, 2]][:, None, None]
    np.testing.assert_allclose(np.asarray(y), expected, rtol=1e-4, atol=1e-4)


@pytest.mark.parametrize("temporal", ["conv", "transformer"])
def test_generator_ignores_the_label_at_init_and_uses_it_once_embeddings_move(temporal):
    config = _config(temporal=temporal)
    params, buffers = init_generator(jax.random.key(5), config)
    z = jnp.broadcast_to(_z(config, 1, key=8), (3, 8, 120))  # one latent, three labels
    same, _ = _generate(config, params, buffers, z, jnp.array([0, 3, 1]))
    np.testing.assert_array_equal(np.asarray(same[0]), np.asarray(same[1]))
    np.testing.assert_array_equal(np.asarray(same[0]), np.asarray(same[2]))
    moved, _ = _generate(config, _perturbed(params), buffers, z, jnp.array([0, 3, 1]))
    assert np.abs(np.asarray(moved[0]) - np.asarray(moved[1])).max() > 1e-2
    assert np.abs(np.asarray(moved[1]) - np.asarray(moved[2])).max() > 1e-2


# --- temporal modelling -------------------------------------------------------------------------------------


def test_conv_mode_is_local_in_time_and_the_t_former_is_global():
    """Four graph layers with temporal kernel 3 reach 4 frames either way (a change at frame 0 of 8 leaves
    frames 5..7 as they were); with T-Formers every frame sees every frame (eval mode, so the batch statistics do
    not mix the frames)."""
    for temporal, unchanged in (("conv", slice(5, None)), ("transformer", slice(0, 0))):
        config = _config(temporal=temporal)
        params, buffers = init_generator(jax.random.key(6), config)
        z, labels = _z(config, 3, key=9), jnp.array([1, 2, 3])
        a, _ = _generate(config, params, buffers, z, labels)
        b, _ = _generate(config, params, buffers, z.at[:, 0].add(1.0), labels)
        diff = np.abs(np.asarray(a) - np.asarray(b)).max(axis=(0, 2, 3))  # per frame
        np.testing.assert_array_equal(diff[unchanged], 0.0)
        assert diff[0] > 0 and (temporal == "conv" or diff.min() > 0)
        if temporal == "conv":
            assert diff[4] > 0


# --- gradients, spectral normalisation ---------------------------------------------------------------------


@pytest.mark.parametrize("temporal, spectral_norm, persons", [("conv", True, 2), ("transformer", False, 1)])
def test_gradients_reach_every_parameter(temporal, spectral_norm, persons):
    config = _config(temporal=temporal, spectral_norm=spectral_norm, persons=persons)
    params, buffers = init_generator(jax.random.key(7), config)
    z, labels = _z(config, 3, key=11), jnp.array([0, 1, 3])
    target = jax.random.normal(jax.random.key(12), (3,) + ((persons,) if persons > 1 else ()) + (8, 25, 3))

    @jax.jit
    def loss(p):
        motion, _ = generate(config, p, buffers, z, labels, train=True)
        return jnp.sum(motion * target)

    grads = jax.grad(loss)(params)
    leaves = jax.tree_util.tree_leaves_with_path(grads)
    assert len(leaves) == len(jax.tree.leaves(params))
    dead = [jax.tree_util.keystr(path) for path, g in leaves if not np.any(np.asarray(g) != 0)]
    assert not dead, dead
    assert all(np.isfinite(np.asarray(g)).all() for _, g in leaves)


def test_spectral_vectors_move_in_training_only():
    config = _config(spectral_norm=True, temporal="transformer", persons=2)
    params, buffers = init_generator(jax.random.key(8), config)
    assert buffers.spectral is not None and buffers.spectral.stages[0].block is not None
    z, labels = _z(config), jnp.array([0, 1, 3])
    _, same = _generate(config, params, buffers, z, labels)
    _assert_same_tree(same, buffers)
    _, moved = _generate(config, params, buffers, z, labels, train=True)
    before, after = jax.tree.leaves(buffers.spectral), jax.tree.leaves(moved.spectral)
    assert len(before) == len(after) == 2 * (2 + 3 * 5)  # (u, v) of input, output, 3 x (graph layer + 4 in a block)
    assert all(np.abs(np.asarray(a) - np.asarray(b)).max() > 0 for a, b in zip(before, after))


# --- input checks -------------------------------------------------------------------------------------------


def test_bad_latents_labels_and_buffers_are_refused_with_the_expected_shape():
    config = _config()
    params, buffers = init_generator(jax.random.key(10), config)
    run = functools.partial(generate, config, params, buffers)
    z = _z(config, 2)
    with pytest.raises(ValueError, match=r"z: expected \[B, 8, 120\]"):
        run(z[0], jnp.array([0, 1]))
    with pytest.raises(ValueError, match=r"z: expected \[B, 8, 120\]"):
        run(z[:, :7], jnp.array([0, 1]))
    with pytest.raises(ValueError, match=r"z: expected \[B, 8, 120\]"):
        run(jnp.stack([z, z], 1), jnp.array([0, 1]))  # one latent per person: not this generator
    with pytest.raises(ValueError, match=r"labels: expected \[B\] = \[2\]"):
        run(z, jnp.array([0, 1, 2]))
    with pytest.raises(ValueError, match=r"labels: expected \[B\] = \[2\] integer"):
        run(z, jnp.array([0.0, 1.0]))
    with pytest.raises(ValueError, match="buffers: expected the CSGNBuffers"):
        generate(dataclasses.replace(config, spectral_norm=True), params, buffers, z, jnp.array([0, 1]))


@pytest.mark.parametrize("overrides, field", [
    ({"num_classes": 0}, "num_classes"),
    ({"frames": -1}, "frames"),
    ({"joints": 24}, "parents"),  # 25 NTU parents for 24 nodes
    ({"parents": (-1, 0, 3, 2), "joints": 4}, "parents"),  # a cycle
    ({"parents": [-1, 0]}, "parents"),
    ({"widths": (16, 16, 8)}, "widths"),
    ({"widths": (16, 16, 8, 0)}, "widths"),
    ({"time_kernel": 4}, "time_kernel"),
    ({"temporal": "lstm"}, "temporal"),
    ({"temporal": "transformer", "heads": 3}, "heads"),
    ({"output": "skeleton", "channels": 6}, "output"),
    ({"output": "smpl", "channels": 3}, "output"),
    ({"output": "quat"}, "output"),
    ({"negative_slope": -0.1}, "negative_slope"),
])
def test_bad_config_fields_are_named(overrides, field):
    with pytest.raises(ValueError, match=rf"CSGNConfig\.{field}"):
        _config(**overrides)
