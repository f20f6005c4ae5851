"""Recurrent layers: GRU and LSTM cells and stacks against float64 numpy references of PyTorch's equations
(with zero and with given initial states), the stacked step against the scanned stack, and PyTorch's
default initialisation."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from jaxmotion.nn.recurrent import (
    LSTMState,
    gru_stack,
    gru_stack_step,
    init_gru,
    init_lstm,
    init_lstm_stack,
    lstm_stack,
    lstm_stack_step,
    lstm_zero_state,
)


def _sigmoid(x):
    return 1.0 / (1.0 + np.exp(-x))


def _ref_lstm(layers, xs, h0, c0):
    """torch.nn.LSTM in float64, layer by layer: xs [T, B, D], h0/c0 [L, B, H] -> outputs, (h_n, c_n)."""
    out = np.asarray(xs, np.float64)
    hs, cs = [], []
    for layer, p in enumerate(layers):
        w_ih, w_hh, b_ih, b_hh = (np.asarray(a, np.float64) for a in p)
        h, c = np.asarray(h0[layer], np.float64), np.asarray(c0[layer], np.float64)
        steps = []
        for x in out:
            gates = x @ w_ih.T + b_ih + h @ w_hh.T + b_hh
            i, f, g, o = np.split(gates, 4, axis=-1)
            c = _sigmoid(f) * c + _sigmoid(i) * np.tanh(g)
            h = _sigmoid(o) * np.tanh(c)
            steps.append(h)
        out = np.stack(steps)
        hs.append(h)
        cs.append(c)
    return out, np.stack(hs), np.stack(cs)


def _ref_gru(layers, xs, h0):
    out = np.asarray(xs, np.float64)
    for layer, p in enumerate(layers):
        w_ih, w_hh, b_ih, b_hh = (np.asarray(a, np.float64) for a in p)
        h = np.asarray(h0[layer], np.float64)
        steps = []
        for x in out:
            i_r, i_z, i_n = np.split(x @ w_ih.T + b_ih, 3, axis=-1)
            h_r, h_z, h_n = np.split(h @ w_hh.T + b_hh, 3, axis=-1)
            r, z = _sigmoid(i_r + h_r), _sigmoid(i_z + h_z)
            h = (1 - z) * np.tanh(i_n + r * h_n) + z * h
            steps.append(h)
        out = np.stack(steps)
    return out


def _normal(seed, *shape, scale=1.0):
    return jnp.asarray(scale * np.random.default_rng(seed).standard_normal(shape), jnp.float32)


@pytest.mark.parametrize("layers,given_state", [(1, False), (2, False), (2, True), (3, True)])
def test_lstm_stack_matches_float64_reference(layers, given_state):
    t, b, d, h = 7, 3, 5, 6
    params = init_lstm_stack(jax.random.key(layers), d, h, layers)
    xs = _normal(0, t, b, d)
    state = LSTMState(_normal(1, layers, b, h), _normal(2, layers, b, h)) if given_state else None
    outputs, final = jax.jit(lstm_stack)(params, xs, state)
    zeros = np.zeros((layers, b, h))
    ref_out, ref_h, ref_c = _ref_lstm(params, xs, *(state if given_state else (zeros, zeros)))
    np.testing.assert_allclose(outputs, ref_out, rtol=1e-5, atol=1e-6)
    np.testing.assert_allclose(final.h, ref_h, rtol=1e-5, atol=1e-6)
    np.testing.assert_allclose(final.c, ref_c, rtol=1e-5, atol=1e-6)
    np.testing.assert_array_equal(final.h[-1], outputs[-1])  # the top layer's last output is its final state


def test_lstm_gate_order_is_input_forget_cell_output():
    # one unit, one input: only the forget gate's rows saturate to 1, so c' = c and h' = σ(o)·tanh(c)
    p = init_lstm(jax.random.key(0), 1, 1)
    big = jnp.array([[-30.0], [30.0], [0.0], [30.0]])  # i, f, g, o pre-activations per unit input 1
    p = p._replace(w_ih=big, w_hh=jnp.zeros((4, 1)), b_ih=jnp.zeros(4), b_hh=jnp.zeros(4))
    state = LSTMState(jnp.zeros((1, 1, 1)), jnp.full((1, 1, 1), 0.7))
    new, top = lstm_stack_step((p,), state, jnp.ones((1, 1)))
    np.testing.assert_allclose(new.c[0, 0, 0], 0.7, rtol=1e-6)
    np.testing.assert_allclose(top[0, 0], np.tanh(0.7), rtol=1e-6)


def test_lstm_stack_step_repeated_equals_the_scanned_stack():
    params = init_lstm_stack(jax.random.key(3), 4, 5, 2)
    xs = _normal(4, 6, 2, 4)
    state = lstm_zero_state(params, 2)
    tops = []
    for x in xs:
        state, top = lstm_stack_step(params, state, x)
        tops.append(top)
    outputs, final = lstm_stack(params, xs)
    np.testing.assert_allclose(np.stack(tops), outputs, rtol=1e-6, atol=1e-7)
    np.testing.assert_allclose(state.c, final.c, rtol=1e-6, atol=1e-7)


def test_lstm_stack_gradients_equal_the_unrolled_steps_with_the_step_recomputed():
    # On a CPU the scanned step is rematerialised in the backward pass: same gradients, fewer stored activations.
    params = init_lstm_stack(jax.random.key(5), 4, 5, 2)
    xs = _normal(6, 7, 3, 4)

    def unrolled(params, xs):
        state, tops = lstm_zero_state(params, 3), []
        for x in xs:
            state, top = lstm_stack_step(params, state, x)
            tops.append(top)
        return jnp.sum(jnp.stack(tops) ** 2)

    def scanned(params, xs):
        return jnp.sum(lstm_stack(params, xs)[0] ** 2)

    for a, b in zip(jax.tree.leaves(jax.grad(unrolled, (0, 1))(params, xs)),
                    jax.tree.leaves(jax.grad(scanned, (0, 1))(params, xs)), strict=True):
        np.testing.assert_allclose(b, a, rtol=1e-5, atol=1e-6)
    assert ("remat" in str(jax.make_jaxpr(scanned)(params, xs))) == (jax.default_backend() == "cpu")


def test_gru_stack_matches_float64_reference_with_given_states():
    params = tuple(init_gru(k, 4 if i == 0 else 6, 6) for i, k in enumerate(jax.random.split(jax.random.key(5), 2)))
    xs, h0 = _normal(6, 5, 3, 4), (_normal(7, 3, 6), _normal(8, 3, 6))
    np.testing.assert_allclose(jax.jit(gru_stack)(params, xs, h0), _ref_gru(params, xs, h0), rtol=1e-5, atol=1e-6)
    hs, top = gru_stack_step(params, h0, xs[0])
    np.testing.assert_allclose(top, _ref_gru(params, xs[:1], h0)[0], rtol=1e-5, atol=1e-6)
    assert len(hs) == 2


def test_init_lstm_has_torchs_shapes_and_bound():
    layers = init_lstm_stack(jax.random.key(0), 10, 64, 2)
    assert [tuple(a.shape) for a in layers[0]] == [(256, 10), (256, 64), (256,), (256,)]
    assert layers[1].w_ih.shape == (256, 64)
    for p in layers:
        for leaf in p:
            assert 0.9 / 8 < np.abs(leaf).max() <= 1 / 8
    assert not np.allclose(layers[0].w_hh, layers[1].w_hh)


def test_lstm_stack_names_the_field_of_a_bad_shape():
    params = init_lstm_stack(jax.random.key(0), 4, 5, 2)
    with pytest.raises(ValueError, match=r"xs: expected \[T, B, 4\]"):
        lstm_stack(params, jnp.zeros((3, 2, 5)))
    with pytest.raises(ValueError, match=r"state: expected h and c of shape \[2, 2, 5\]"):
        lstm_stack(params, jnp.zeros((3, 2, 4)), LSTMState(jnp.zeros((1, 2, 5)), jnp.zeros((1, 2, 5))))
