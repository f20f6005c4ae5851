"""ACTOR's use cases: variable-length generation, denoising, latent interpolation, noise, the picture grid."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from jaxmotion.data.pipeline import BatchSpec, gather_windows
from jaxmotion.geometry.skeletons import SMPL24
from jaxmotion.metrics.smoothness import mean_acceleration
from jaxmotion.models.actor import init_actor
from jaxmotion.pipelines.actor import (
    actor_sampler,
    denoise,
    generate_motions,
    interpolate,
    noisy,
)
from jaxmotion.pipelines.pictures import generation_grid
from smooth_motions import MODEL, WINDOW, fk, smooth_dataset


@pytest.fixture(scope="module")
def setup():
    data = smooth_dataset()
    params = jax.jit(init_actor, static_argnums=1)(jax.random.key(0), MODEL)
    windows = gather_windows(data, np.arange(len(data)), jax.random.key(1), BatchSpec(batch_size=1, window=WINDOW))
    return data, params, windows, denoise(params, MODEL, windows, SMPL24)


def test_generated_motions_have_their_own_lengths_and_joints_are_fk(setup):
    _, params, _, _ = setup
    actions, durations = np.array([0, 1, 1, 0, 1]), np.array([5, 12, 9, 12, 3])
    out = generate_motions(params, MODEL, jax.random.key(2), actions, durations, SMPL24, chunk=2)
    np.testing.assert_array_equal(out.lengths, durations)
    np.testing.assert_array_equal(out.actions, actions)
    assert out.joints.shape == (durations.sum(), 24, 3) and out.class_names == ("0", "1")
    np.testing.assert_allclose(out.joints, fk(out.rotations, out.translation), atol=1e-4)
    # row n's noise comes from fold_in(key, n): neither the chunk size nor the row count changes a row
    prefix = generate_motions(params, MODEL, jax.random.key(2), actions[:2], durations[:2], SMPL24, chunk=2)
    np.testing.assert_allclose(prefix.rotations, out.rotations[:prefix.joints.shape[0]], atol=1e-5)
    with pytest.raises(ValueError, match="durations: expected"):
        generate_motions(params, MODEL, jax.random.key(2), actions, durations[:3], SMPL24)
    with pytest.raises(ValueError, match="actions: expected class ids in \\[0, 2\\)"):
        generate_motions(params, MODEL, jax.random.key(2), actions + 1, durations, SMPL24)


def test_denoise_is_deterministic_without_a_key_and_keeps_lengths_and_padding(setup):
    _, params, windows, first = setup
    second = denoise(params, MODEL, windows, SMPL24, chunk=6)
    np.testing.assert_array_equal(first["joints"], second["joints"])
    np.testing.assert_array_equal(first["lengths"], windows["lengths"])
    np.testing.assert_array_equal(first["mask"], windows["mask"])
    np.testing.assert_array_equal(first["actions"], windows["actions"])
    assert first["joints"].shape == windows["joints"].shape
    n = int(windows["lengths"][0])
    assert n < WINDOW  # padded like the input: the last real frame repeated
    np.testing.assert_array_equal(first["joints"][0, n:], np.broadcast_to(first["joints"][0, n - 1], (WINDOW - n, 24, 3)))
    np.testing.assert_allclose(first["joints"], fk(first["rotations"], first["translation"]), atol=1e-4)
    sampled = denoise(params, MODEL, windows, SMPL24, key=jax.random.key(3))
    assert not np.allclose(sampled["rotations"], first["rotations"], atol=1e-4)
    with pytest.raises(ValueError, match=r"motions\['rotations'\]: expected \[B, T, 24, 3\]"):
        denoise(params, MODEL, {**windows, "rotations": windows["rotations"][:, :, :5]}, SMPL24)


def test_interpolation_endpoints_decode_the_endpoints_posterior_means(setup):
    data, params, _, denoised = setup
    a, b = 0, 2  # same action; both shorter than the window, so their windows are the whole motions
    out = interpolate(params, MODEL, data[a], data[b], steps=5, skeleton=SMPL24, window=WINDOW)
    ends = {k: v[[a, b]] for k, v in denoised.items()}
    n_a, n_b = data.lengths[[a, b]]
    np.testing.assert_array_equal(out["lengths"], np.round(np.linspace(n_a, n_b, 5)))
    np.testing.assert_allclose(out["weights"], np.linspace(0, 1, 5))
    for row, end, n in ((0, 0, n_a), (-1, 1, n_b)):
        np.testing.assert_allclose(out["rotations"][row, :n], ends["rotations"][end, :n], atol=1e-4)
        np.testing.assert_allclose(out["joints"][row, :n], ends["joints"][end, :n], atol=1e-4)
    assert not np.allclose(out["rotations"][2, :n_a], out["rotations"][0, :n_a], atol=1e-3)


def test_noisy_perturbs_rotations_only_on_demand_and_raises_jitter(setup):
    _, _, windows, _ = setup
    clean = noisy(jax.random.key(4), windows, 0.0, SMPL24)
    np.testing.assert_allclose(clean["joints"], fk(windows["rotations"], windows["translation"]), atol=1e-5)
    rough = noisy(jax.random.key(4), windows, 0.05, SMPL24)
    again = noisy(jax.random.key(4), windows, 0.05, SMPL24)
    np.testing.assert_array_equal(rough["rotations"], again["rotations"])
    mask = jnp.asarray(windows["mask"])
    assert mean_acceleration(jnp.asarray(rough["joints"]), mask) > 2 * mean_acceleration(jnp.asarray(clean["joints"]), mask)
    n = int(windows["lengths"][0])
    np.testing.assert_array_equal(rough["joints"][0, n:], np.broadcast_to(rough["joints"][0, n - 1], (WINDOW - n, 24, 3)))


def test_generation_grid_draws_the_samplers_motions(setup, tmp_path):
    _, params, _, _ = setup
    path = tmp_path / "generated.gif"
    sampler = actor_sampler(params, MODEL, SMPL24)
    data = generation_grid(sampler, jax.random.key(5), SMPL24, ("a", "b"), 20.0, 2, path, per_action=2, duration=4,
                           video=True)
    assert path.stat().st_size > 0 and path.read_bytes()[:3] == b"GIF"
    assert path.with_suffix(".mp4").read_bytes()[4:8] == b"ftyp"  # the same grid as an MP4 (an ISO media file)
    np.testing.assert_array_equal(data.actions, [0, 0, 1, 1])
    np.testing.assert_array_equal(data.modes, [0, 1, 0, 1])
    direct = np.asarray(sampler(jax.random.key(5), np.array([0, 0, 1, 1]), np.full(4, 4))["joints"])
    lift = data.joints.reshape(direct.shape) - direct  # the sampler's motions, each lifted onto the floor as a whole
    np.testing.assert_allclose(lift, np.broadcast_to(lift[:, :1, :1], lift.shape), atol=1e-6)
    np.testing.assert_allclose(lift[..., [0, 2]], 0.0)
    np.testing.assert_allclose(data.joints[data.starts[:-1], :, 1].min(axis=1), 0.0, atol=1e-6)
    with pytest.raises(ValueError, match="actions"):
        generation_grid(sampler, jax.random.key(5), SMPL24, ("a", "b"), 20.0, [2], path)


def test_frame_noise_reaches_the_denoised_output_only_through_the_latent(setup):
    """ACTOR's denoising rests on its sequence-level bottleneck: the decoder sees the input only through
    one latent vector, so per-frame noise cannot come out as per-frame jitter, trained or not. (Whether a
    trained model's output is as smooth as the clean motion is the denoising experiment's claim, not this
    test's: an untrained decoder is smooth-independent of the input but not smooth.)"""
    _, params, windows, _ = setup
    mask = jnp.asarray(windows["mask"])
    jitter = {}
    for sigma in (0.0, 0.2):
        rough = noisy(jax.random.key(6), windows, sigma, SMPL24)
        out = denoise(params, MODEL, rough, SMPL24)
        jitter[sigma] = [float(mean_acceleration(jnp.asarray(m["joints"]), mask)) for m in (rough, out)]
    added_in, added_out = jitter[0.2][0] - jitter[0.0][0], abs(jitter[0.2][1] - jitter[0.0][1])
    assert added_in > 0.1  # metres per frame²: the noise is large
    assert added_out < 0.01 * added_in
