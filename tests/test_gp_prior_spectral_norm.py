"""ActFormer's layers: the Gaussian-process latent prior (kernel, factors, samples) and spectral normalisation
(power iteration to the top singular value, PyTorch's algorithm step by step, gradients)."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from jaxmotion.nn.gp_prior import CHANNELS, STEPS, gp_factors, length_scales, rbf_kernel, sample_gp, white_factors
from jaxmotion.nn.spectral_norm import SpectralState, init_spectral_state, spectral_normalize


# --- GP prior --------------------------------------------------------------------------------------------

def test_length_scales_and_kernel_are_actformers():
    scales = length_scales()
    assert scales.shape == (CHANNELS,) and scales[0] == pytest.approx(100 / 120) and scales[-1] == 100.0
    k = rbf_kernel(STEPS, scales[[0, 59]])
    assert k.shape == (2, STEPS, STEPS)
    np.testing.assert_allclose(np.diagonal(k, axis1=1, axis2=2), 1.0)
    assert k[0, 0, 1] == pytest.approx(np.exp(-(1.2 ** 2)))  # l = 5/6: one step apart
    assert k[1, 3, 53] == pytest.approx(np.exp(-1.0))  # l = 50: 50 steps apart, no factor 2


def test_factors_reproduce_the_near_singular_kernels():
    """The slow channels' kernels have no Cholesky factor (numerically rank-deficient); the factors still
    give K back to float32 rounding."""
    scales = length_scales()
    k = rbf_kernel(STEPS, scales)
    with pytest.raises(np.linalg.LinAlgError):
        np.linalg.cholesky(k[-1])
    f = gp_factors().astype(np.float64)
    np.testing.assert_allclose(f @ np.swapaxes(f, 1, 2), k, atol=2e-5)


def test_sample_covariance_matches_the_kernel():
    factors = jnp.asarray(gp_factors(scales=np.array([2.0, 10.0, 100.0])))
    x = np.asarray(sample_gp(jax.random.key(0), factors, 20000), np.float64)  # [B, T, Z]
    assert x.shape == (20000, STEPS, 3)
    k = rbf_kernel(STEPS, np.array([2.0, 10.0, 100.0]))
    for z in range(3):
        np.testing.assert_allclose(np.cov(x[:, :, z], rowvar=False), k[z], atol=0.04)
    np.testing.assert_allclose(x.mean(0), 0.0, atol=0.04)


def test_samples_are_keyed_and_the_white_prior_is_independent_steps():
    factors = jnp.asarray(gp_factors())
    a, b = sample_gp(jax.random.key(1), factors, 4), sample_gp(jax.random.key(1), factors, 4)
    np.testing.assert_array_equal(np.asarray(a), np.asarray(b))
    assert not np.allclose(np.asarray(a), np.asarray(sample_gp(jax.random.key(2), factors, 4)))
    white = np.asarray(sample_gp(jax.random.key(0), jnp.asarray(white_factors(STEPS, 2)), 20000), np.float64)
    np.testing.assert_allclose(np.cov(white[:, :, 0], rowvar=False), np.eye(STEPS), atol=0.04)
    # the slowest GP channel barely moves over a clip; the fastest one decorrelates within two steps
    x = np.asarray(a)
    assert np.abs(np.diff(x[:, :, -1], axis=1)).max() < 0.1 < np.abs(np.diff(x[:, :, 0], axis=1)).mean()


def test_bad_factors_are_refused():
    with pytest.raises(ValueError, match=r"factors: expected \[Z, T, T\]"):
        sample_gp(jax.random.key(0), jnp.zeros((3, 60, 59)), 2)
    with pytest.raises(ValueError, match="scales"):
        rbf_kernel(60, np.array([1.0, -2.0]))


# --- spectral normalisation -------------------------------------------------------------------------------

def _torch_like_step(w, u):
    """One training call of torch.nn.utils.spectral_norm, in numpy float64."""
    m = w.reshape(w.shape[0], -1)
    v = m.T @ u
    v /= max(np.linalg.norm(v), 1e-12)
    u = m @ v
    u /= max(np.linalg.norm(u), 1e-12)
    return w / (u @ m @ v), u, v


@pytest.mark.parametrize("shape", [(6, 4), (8, 3, 5), (5,)], ids=["linear", "conv", "gain"])
def test_power_iteration_drives_the_top_singular_value_to_one(shape):
    w = jax.random.normal(jax.random.key(0), shape)
    state = init_spectral_state(jax.random.key(1), w)
    step = jax.jit(lambda w, s: spectral_normalize(w, s, train=True))
    u_ref = np.asarray(state.u, np.float64)
    for i in range(30):
        normalized, state = step(w, state)
        if i < 3:  # the same arithmetic as PyTorch's, call by call
            expected, u_ref, _ = _torch_like_step(np.asarray(w, np.float64), u_ref)
            np.testing.assert_allclose(np.asarray(normalized), expected, rtol=1e-5)
    top = np.linalg.svd(np.asarray(normalized, np.float64).reshape(shape[0], -1), compute_uv=False)[0]
    assert top == pytest.approx(1.0, abs=1e-4)
    if len(shape) == 1:  # a gain vector is divided by its norm
        np.testing.assert_allclose(np.linalg.norm(np.asarray(normalized)), 1.0, rtol=1e-5)


def test_evaluation_uses_the_stored_vectors_and_gradients_flow_through_the_weight():
    w = jax.random.normal(jax.random.key(0), (4, 3))
    state = init_spectral_state(jax.random.key(1), w)
    out, same = spectral_normalize(w, state, train=False)
    assert same is state
    np.testing.assert_allclose(np.asarray(out), np.asarray(w / (state.u @ w @ state.v)), rtol=1e-6)
    grad = jax.grad(lambda w: spectral_normalize(w, state, train=True)[0].sum())(w)
    assert np.isfinite(np.asarray(grad)).all() and np.abs(np.asarray(grad)).max() > 0
    # scaling the weight leaves the normalised weight unchanged (sigma scales with it)
    np.testing.assert_allclose(np.asarray(spectral_normalize(3.0 * w, state, train=True)[0]),
                               np.asarray(spectral_normalize(w, state, train=True)[0]), rtol=1e-5)


def test_a_state_of_the_wrong_size_is_refused():
    with pytest.raises(ValueError, match=r"state: expected u \[4\] and v \[3\]"):
        spectral_normalize(jnp.ones((4, 3)), SpectralState(jnp.ones(3), jnp.ones(4)), train=True)
