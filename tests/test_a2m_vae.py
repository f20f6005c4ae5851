"""Action2Motion GRU VAE: shapes and argument checks, the Gaussian KL, the loss normalisation, causality, the
own-output feedback quirk, masking of padded frames, a short training run and the paper-size parameter count."""

import math

import jax
import jax.numpy as jnp
import numpy as np
import optax
import pytest

from jaxmotion.models.a2m import (
    A2MOptimizer,
    A2MVAEConfig,
    _feedback_draws,
    a2m_generate,
    a2m_optimizer,
    a2m_vae_forward,
    a2m_vae_loss,
    gaussian_kl,
    init_a2m_vae,
)
from jaxmotion.nn.core import count_parameters
from jaxmotion.train.a2m import a2m_step
from jaxmotion.train.state import TrainState

F, C, B, T = 6, 2, 3, 7
# One configuration (and one set of parameters) for almost every test: compilation dominates their time.
CFG = A2MVAEConfig(pose_dim=F, num_classes=C, kl_weight=1e-2, hidden=8, latent=4)
LOSS = jax.jit(a2m_vae_loss, static_argnums=0)  # compiled once per input shape, shared by the tests
FORWARD = jax.jit(a2m_vae_forward, static_argnums=0)


def _data(seed=0, b=B, t=T):
    rng = np.random.default_rng(seed)
    return jnp.asarray(rng.standard_normal((b, t, F)), jnp.float32), jnp.asarray(rng.integers(0, C, b), jnp.int32)


@pytest.fixture(scope="module")
def params():
    return init_a2m_vae(jax.random.key(0), CFG)


def test_shapes_and_generation_keys(params):
    poses, actions = _data()
    loss, metrics = LOSS(CFG, params, poses, actions, key=jax.random.key(1))
    assert loss.shape == () and np.isfinite(float(loss))
    assert set(metrics) >= {"loss", "recon", "kl", "loss_per_frame"}
    out = FORWARD(CFG, params, poses, actions, key=jax.random.key(1))
    assert out["recon"].shape == (B, T, F) and out["mu_p"].shape == (B, T, CFG.latent)

    gen = jax.jit(a2m_generate, static_argnums=(0, 3))
    a = gen(CFG, params, actions, 5, key=jax.random.key(2))
    assert a.shape == (B, 5, F)
    np.testing.assert_array_equal(a, gen(CFG, params, actions, 5, key=jax.random.key(2)))
    assert not np.allclose(a, gen(CFG, params, actions, 5, key=jax.random.key(3)))
    assert a2m_generate(CFG, params, actions[:1], 1, key=jax.random.key(2)).shape == (1, 1, F)


def test_bad_shapes_raise(params):
    poses, actions = _data()
    with pytest.raises(ValueError, match="poses"):
        a2m_vae_loss(CFG, params, poses[..., :4], actions, key=jax.random.key(0))
    with pytest.raises(ValueError, match="poses"):
        a2m_vae_loss(CFG, params, poses[0], actions, key=jax.random.key(0))
    with pytest.raises(ValueError, match="actions"):
        a2m_vae_loss(CFG, params, poses, actions[:2], key=jax.random.key(0))
    with pytest.raises(ValueError, match="mask"):
        a2m_vae_loss(CFG, params, poses, actions, key=jax.random.key(0), mask=jnp.ones((B, T + 1), bool))
    with pytest.raises(ValueError, match="actions"):
        a2m_generate(CFG, params, actions[:, None], 4, key=jax.random.key(0))
    with pytest.raises(ValueError, match="num_frames"):
        a2m_generate(CFG, params, actions, 0, key=jax.random.key(0))
    with pytest.raises(ValueError, match="own_output_feedback"):
        A2MVAEConfig(pose_dim=F, num_classes=C, kl_weight=0.0, own_output_feedback=1.5)


def test_gaussian_kl_hand_values_and_zero_when_posterior_is_prior(params):
    # KL(N(1, 4) || N(0, 1)) = ½ log(1/4) + (4 + 1)/2 − ½ = 2 − ln 2
    kl = gaussian_kl(jnp.float32(1.0), jnp.float32(math.log(4.0)), jnp.float32(0.0), jnp.float32(0.0))
    np.testing.assert_allclose(kl, 2.0 - math.log(2.0), rtol=1e-6)
    # KL(N(0, 1) || N(2, e)) = ½ (1 − 0) + (1 + 4) / (2e) − ½
    kl = gaussian_kl(jnp.float32(0.0), jnp.float32(0.0), jnp.float32(2.0), jnp.float32(1.0))
    np.testing.assert_allclose(kl, 5.0 / (2.0 * math.e), rtol=1e-6)

    # Identical nets that ignore their pose input (previous pose for the prior, current pose for the
    # posterior): the two Gaussians coincide at every frame, so the KL term vanishes.
    prior = params.prior_net
    prior = prior._replace(embed=prior.embed._replace(weight=prior.embed.weight.at[:, :F].set(0.0)))
    same = params._replace(prior_net=prior, posterior_net=prior)
    poses, actions = _data()
    _, metrics = LOSS(CFG, same, poses, actions, key=jax.random.key(4))
    assert float(metrics["kl"]) == pytest.approx(0.0, abs=1e-6)
    assert float(metrics["recon"]) > 0


def test_loss_normalisation_matches_the_reference_formula(params):
    """Σ_t [MSE averaged over batch and features] + λ Σ_t [KL summed over batch and latents / B]."""
    poses, actions = _data(5)
    key = jax.random.key(6)
    loss, metrics = LOSS(CFG, params, poses, actions, key=key)
    out = {k: np.asarray(v, np.float64) for k, v in FORWARD(CFG, params, poses, actions, key=key).items()}
    x = np.asarray(poses, np.float64)
    mse = sum(np.mean((out["recon"][:, t] - x[:, t]) ** 2) for t in range(T))
    var_q, var_p = np.exp(out["logvar_q"]), np.exp(out["logvar_p"])
    kl_el = 0.5 * np.log(var_p / var_q) + (var_q + (out["mu_q"] - out["mu_p"]) ** 2) / (2 * var_p) - 0.5
    kld = sum(kl_el[:, t].sum() / B for t in range(T))
    np.testing.assert_allclose(metrics["recon"], mse, rtol=1e-5)
    np.testing.assert_allclose(metrics["kl"], kld, rtol=1e-5)
    np.testing.assert_allclose(loss, mse + CFG.kl_weight * kld, rtol=1e-5)
    np.testing.assert_allclose(metrics["loss_per_frame"], (mse + CFG.kl_weight * kld) / T, rtol=1e-5)


def test_causality_with_ground_truth_feedback(params):
    """own_output_feedback = 0 (x_prev is always the ground truth): decoded frame t depends on poses ≤ t only
    (t − 1 through x_prev, t through the posterior sample); the prior at t on poses < t only."""
    cfg = A2MVAEConfig(pose_dim=F, num_classes=C, kl_weight=1e-2, hidden=8, latent=4, own_output_feedback=0.0)
    poses, actions = _data(7, b=1, t=5)

    def outputs(p):
        out = a2m_vae_forward(cfg, params, p, actions, key=jax.random.key(8))
        return out["recon"][0], out["mu_p"][0]

    d_recon, d_prior = jax.jacobian(outputs)(poses)  # [T, F|Z, 1, T, F]
    d_recon = np.abs(np.asarray(d_recon[:, :, 0])).sum((1, 3))  # [t, s]
    d_prior = np.abs(np.asarray(d_prior[:, :, 0])).sum((1, 3))
    t_len = poses.shape[1]
    for t in range(t_len):
        for s in range(t_len):
            if s > t:
                assert d_recon[t, s] == 0.0, (t, s)
            if s >= t:
                assert d_prior[t, s] == 0.0, (t, s)
        assert d_recon[t, t] > 0
        if t:
            assert d_recon[t, t - 1] > 0 and d_prior[t, t - 1] > 0


def test_feedback_quirk(params):
    # The draw: own_output_feedback is the probability of feeding back the model's OWN output. "sequence" (the
    # authors' code) is one draw per call for all frames; "step" draws per frame.
    keys = jax.random.split(jax.random.key(9), 400)
    seq = np.asarray(jax.vmap(lambda k: _feedback_draws(k, CFG, 6))(keys))
    assert (seq.all(1) | ~seq.any(1)).all()
    assert abs(seq[:, 0].mean() - 0.6) < 0.08
    step_cfg = A2MVAEConfig(pose_dim=F, num_classes=C, kl_weight=1e-2, feedback_scope="step")
    step = np.asarray(jax.vmap(lambda k: _feedback_draws(k, step_cfg, 6))(keys))
    assert (step.any(1) & ~step.all(1)).any() and abs(step.mean() - 0.6) < 0.05

    # With own-output feedback always on and a posterior blind to its pose input, nothing the decoder sees
    # depends on the ground truth; with ground-truth feedback it does (through x_prev).
    post = params.posterior_net
    blind = params._replace(posterior_net=post._replace(
        embed=post.embed._replace(weight=post.embed.weight.at[:, :F].set(0.0))))
    poses, actions = _data(10, b=1, t=4)
    for ratio, depends in ((1.0, False), (0.0, True)):
        cfg = A2MVAEConfig(pose_dim=F, num_classes=C, kl_weight=1e-2, hidden=8, latent=4, own_output_feedback=ratio)
        grad = jax.grad(lambda p: a2m_vae_forward(cfg, blind, p, actions, key=jax.random.key(11))["recon"].sum())(poses)
        assert (np.abs(np.asarray(grad)).max() > 0) == depends, ratio


def test_masked_frames_do_not_change_the_loss(params):
    poses, actions = _data(12)
    key = jax.random.key(13)
    lengths = np.array([4, T, 2])
    mask = jnp.asarray(np.arange(T)[None] < lengths[:, None])
    base, _ = LOSS(CFG, params, poses, actions, key=key, mask=mask)
    noisy = jnp.where(mask[..., None], poses, 100.0 * jax.random.normal(jax.random.key(14), poses.shape))
    np.testing.assert_allclose(LOSS(CFG, params, noisy, actions, key=key, mask=mask)[0], base, rtol=1e-6)

    # Padding every sequence of a batch to T by repeating its last frame gives the loss of the unpadded batch.
    short = poses[:, :4]
    padded = jnp.concatenate([short, jnp.repeat(short[:, -1:], T - 4, axis=1)], axis=1)
    mask4 = jnp.asarray(np.arange(T)[None] < np.full((B, 1), 4))
    np.testing.assert_allclose(LOSS(CFG, params, padded, actions, key=key, mask=mask4)[0],
                               LOSS(CFG, params, short, actions, key=key)[0], rtol=1e-5)


def test_short_training_reduces_the_loss(params):
    """150 Adam steps (one compiled step; the steps themselves take a fraction of a second) on 4 sequences of
    2 classes, with the feedback quirk and the KL on."""
    t = np.linspace(0.0, 1.0, 8)[None, :, None]
    phase = np.arange(F)[None, None, :] / F
    motions = np.concatenate([np.sin(2 * np.pi * (t + phase)), 0.5 * np.cos(4 * np.pi * (t - phase))])
    poses, actions = jnp.asarray(np.concatenate([motions, motions]), jnp.float32), jnp.asarray([0, 1, 0, 1])
    state = TrainState.create(params, optax.adam(1e-2))
    step = jax.jit(a2m_step(CFG))  # the library's step, on a batch of poses laid out as joints [B, T, J, 3]
    batch = {"joints": poses.reshape(*poses.shape[:2], -1, 3), "actions": actions}
    losses = []
    for key in jax.random.split(jax.random.key(16), 150):
        state, metrics = step(state, batch, key)
        losses.append(float(metrics["loss"]))
    assert np.mean(losses[-10:]) < 0.1 * np.mean(losses[:3]), losses[::10]


def test_paper_parameter_count_and_optimizer():
    """HumanAct12 xyz, paper sizes: F = 72, C = 12, time counter on -> condition width 85; H = 128, Z = 30."""
    cfg = A2MVAEConfig(pose_dim=72, num_classes=12, kl_weight=1e-3)
    d_in, h, z = 72 + 12 + 1, 128, 30
    gru_cell = 3 * h * h + 3 * h * h + 3 * h + 3 * h  # weight_ih, weight_hh, bias_ih, bias_hh
    gaussian = (d_in * h + h) + gru_cell + 2 * (h * z + z)  # embed, 1 cell, mu_net, logvar_net
    decoder = ((d_in + z) * h + h) + 2 * gru_cell + (h * 72 + 72)  # embed, 2 cells, output
    expected = 2 * gaussian + decoder
    assert expected == 457_920
    shapes = jax.eval_shape(lambda k: init_a2m_vae(k, cfg), jax.random.key(0))
    assert count_parameters(shapes) == expected
    assert shapes.decoder.embed.weight.shape == (h, d_in + z) and len(shapes.decoder.gru) == 2

    # torch Adam(weight_decay) = L2 on the gradient before the moments: on a zero gradient the first step
    # still moves a parameter by ≈ lr (Adam normalises the decay term), against the sign of the parameter.
    tc = A2MOptimizer()
    assert (tc.learning_rate, tc.weight_decay) == (2e-4, 1e-5)
    opt = a2m_optimizer(tc)
    p = {"w": jnp.asarray([2.0, -3.0])}
    updates, _ = opt.update({"w": jnp.zeros(2)}, opt.init(p), p)
    np.testing.assert_allclose(updates["w"], [-2e-4, 2e-4], rtol=1e-3)
