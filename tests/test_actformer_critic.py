"""ActFormer's critic: parameter count at the authors' NTU-2P config, the node-specific graph convolution
against a direct loop, persons stacked on the channels, the projection conditioning, spectral norm in training."""

import dataclasses

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from jaxmotion.models.actformer_critic import (
    CriticConfig,
    CriticGraphs,
    GraphConvParams,
    critic,
    graph_conv,
    init_critic,
    time_windows,
)
from jaxmotion.nn.core import count_parameters


def _graphs(rng, sizes=(25, 11, 5)):
    """Random non-negative adjacencies with the NTU pyramid's shapes (the values do not matter here)."""
    v, l1, l2 = sizes
    return CriticGraphs(*(rng.uniform(0, 1, (2, w, n)) for w, n in ((v, v), (l1, v), (l2, l1), (l2, l2))))


def test_parameter_count_matches_the_authors_code_at_the_ntu_2p_config():
    """config/generator/ntu120_2p: C 6 (2 persons x 3), base 32, 26 classes: 5 174 593 (P-AF Table 6, FACTS 5)."""
    graphs = _graphs(np.random.default_rng(0))  # shapes only: initialising the full critic eagerly takes seconds
    params, spectral = jax.eval_shape(lambda: init_critic(jax.random.key(0), CriticConfig(num_classes=26, channels=6),
                                                          graphs))
    assert count_parameters(params) == 5_174_593
    assert spectral is not None


def test_node_specific_graph_conv_equals_a_direct_loop():
    rng = np.random.default_rng(1)
    a = rng.uniform(0, 1, (2, 3, 4))  # K=2 hops, W=3 out nodes, V=4 in nodes
    c_in, c, kt = 2, 3, 4
    p = GraphConvParams(jnp.asarray(rng.normal(size=(4 * c * 2, c_in, kt)), jnp.float32),
                        jnp.asarray(rng.normal(size=(4 * c * 2,)), jnp.float32))
    x = rng.normal(size=(2, 10, 4, c_in)).astype(np.float32)
    out = np.asarray(graph_conv(p, a, jnp.asarray(x), stride=2, padding=1))
    w, b = np.asarray(p.weight, np.float64).reshape(4, c, 2, c_in, kt), np.asarray(p.bias).reshape(4, c, 2)
    padded = np.pad(x.astype(np.float64), ((0, 0), (1, 1), (0, 0), (0, 0)))
    frames = (10 + 2 - kt) // 2 + 1
    expected = np.zeros((2, frames, 3, c))
    for t in range(frames):
        window = padded[:, 2 * t:2 * t + kt]  # [B, kt, V, C_in]
        f = np.einsum("bsvi,vckis->bvck", window, w) + b  # node v's own conv into (c, k)
        expected[:, t] = np.einsum("kwv,bvck->bwc", a, f)
    assert out.shape == (2, frames, 3, c)
    np.testing.assert_allclose(out, expected, rtol=1e-4, atol=1e-4)


@pytest.mark.parametrize("kernel, stride, padding", [(5, 1, 2), (4, 2, 1), (3, 2, 0)])
def test_frame_windows_turn_conv4_into_a_matmul(kernel, stride, padding):
    """conv4 spans every node: as a matmul over the frame windows it equals the 2-D convolution the code runs."""
    rng = np.random.default_rng(4)
    x = rng.normal(size=(2, 11, 3, 5)).astype(np.float32)  # [B, T, W, C]
    w = rng.normal(size=(7, 5, 3, kernel)).astype(np.float32)  # [O, C, W, kernel]
    expected = jax.lax.conv_general_dilated(jnp.transpose(x, (0, 3, 2, 1)), w, (1, stride), [(0, 0), (padding, padding)],
                                            dimension_numbers=("NCHW", "OIHW", "NCHW"),
                                            precision=jax.lax.Precision.HIGHEST)[:, :, 0]  # [B, O, T']
    got = jnp.einsum("btjwc,ocwj->bot", time_windows(jnp.asarray(x), kernel, stride, padding), w,
                     precision=jax.lax.Precision.HIGHEST)
    np.testing.assert_allclose(np.asarray(got), np.asarray(expected), rtol=1e-5, atol=1e-5)
    with pytest.raises(ValueError, match="too few"):
        time_windows(jnp.asarray(x[:, :2]), kernel + 3, stride, 0)


def test_scores_read_persons_stacked_on_channels_and_project_the_label():
    config = CriticConfig(num_classes=4, channels=6)
    graphs = _graphs(np.random.default_rng(2))
    params, spectral = init_critic(jax.random.key(1), config, graphs)
    for _ in range(5):
        _, spectral = critic(config, graphs, params, spectral, jnp.zeros((1, 60, 25, 6)), jnp.zeros(1, int),
                             train=True)
    motion = jax.random.normal(jax.random.key(2), (3, 2, 60, 25, 3))
    stacked = jnp.concatenate([motion[:, 0], motion[:, 1]], -1)  # person-major channels
    scores, same = critic(config, graphs, params, spectral, motion, jnp.array([0, 1, 2]))
    assert scores.shape == (3,) and same is spectral
    np.testing.assert_allclose(np.asarray(critic(config, graphs, params, spectral, stacked, jnp.array([0, 1, 2]))[0]),
                               np.asarray(scores), rtol=1e-6)
    # the label enters only through <E[y], h>: the same motions under two labels differ by a linear form of h
    other = critic(config, graphs, params, spectral, motion, jnp.array([3, 3, 3]))[0]
    assert not np.allclose(np.asarray(other), np.asarray(scores))


def test_bad_shapes_name_the_field():
    config = CriticConfig(num_classes=2)
    graphs = _graphs(np.random.default_rng(3))
    params, spectral = init_critic(jax.random.key(0), config, graphs)
    with pytest.raises(ValueError, match=r"motion: expected \[B, T, 25, 3\]"):
        critic(config, graphs, params, spectral, jnp.zeros((2, 60, 24, 3)), jnp.zeros(2, int))
    with pytest.raises(ValueError, match=r"graphs.down2: expected \[K, W, 11\]"):
        init_critic(jax.random.key(0), config, graphs._replace(down2=np.ones((2, 5, 10))))


@pytest.mark.parametrize("pooling", ["avg", "max", "attention"])
def test_pooled_critics_score_persons_alone_and_ignore_their_order(pooling):
    """Table 4's alternatives: the critic body on each person (C channels), features pooled symmetrically."""
    config = CriticConfig(num_classes=4, channels=3, base_channels=8, pooling=pooling)
    graphs = _graphs(np.random.default_rng(4))
    params, spectral = init_critic(jax.random.key(3), config, graphs)
    assert (params.attention is not None) == (pooling == "attention")
    motion = jax.random.normal(jax.random.key(4), (3, 2, 60, 25, 3))
    labels = jnp.array([0, 1, 2])
    scores, moved = critic(config, graphs, params, spectral, motion, labels, train=True)
    swapped, _ = critic(config, graphs, params, spectral, motion[:, ::-1], labels, train=True)
    assert scores.shape == (3,)
    np.testing.assert_allclose(np.asarray(swapped), np.asarray(scores), rtol=1e-5, atol=1e-5)
    if pooling == "attention":  # its layers are normalised like the rest: their vectors move in training
        assert not np.allclose(np.asarray(moved.attention[0].u), np.asarray(spectral.attention[0].u))
    # one person's features decide a max-pooled score where they dominate; the mean mixes both
    single, _ = critic(dataclasses.replace(config, pooling="concat"), graphs, params._replace(attention=None),
                       spectral._replace(attention=None), motion[:, 0], labels)
    double, _ = critic(config, graphs, params, spectral, jnp.stack([motion[:, 0], motion[:, 0]], 1), labels)
    if pooling in ("avg", "max"):  # pooling two copies of one person gives that person's own score
        np.testing.assert_allclose(np.asarray(double), np.asarray(single), rtol=1e-5, atol=1e-5)
    with pytest.raises(ValueError, match="scores persons one by one"):
        critic(config, graphs, params, spectral, motion[:, 0], labels)
