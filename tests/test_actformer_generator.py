"""ActFormer's generator: parameter counts at the authors' configs, shapes and output constraints for one and
several persons, spectral normalisation in training, person structure (shared z, the I-Former's symmetry), and
the ablation switches."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from jaxmotion.models.actformer import GeneratorConfig, generate, init_generator
from jaxmotion.nn.core import count_parameters
from jaxmotion.nn.gp_prior import gp_factors, sample_gp


def _z(config, batch=3, key=0, per_person=False):
    factors = jnp.asarray(gp_factors(config.frames))
    if per_person:
        return sample_gp(jax.random.key(key), factors, batch * config.persons).reshape(
            batch, config.persons, config.frames, config.latent)
    return sample_gp(jax.random.key(key), factors, batch)


def _ready(config, key=0):
    """Fresh parameters whose power-iteration vectors have had the ten training calls' steps (PyTorch's, like
    these, start random, so an untrained evaluation call divides by a meaningless sigma)."""
    params, spectral = init_generator(jax.random.key(key), config)
    z, y = _z(config, 1), jnp.zeros(1, int)
    for _ in range(10):
        _, spectral = generate(config, params, spectral, z, y, train=True)
    return params, spectral


def test_parameter_counts_match_the_authors_code():
    """NTU-2P (config/generator/ntu120_2p): 1 358 075, counted by running the authors' code (FACTS 5; the
    paper's Table 6 says 1 359 675). NTU-1P (94 classes, 2 T-Formers) by the same arithmetic: 715 075."""
    def shapes(config):  # initialising the full generator eagerly takes seconds
        return jax.eval_shape(lambda: init_generator(jax.random.key(0), config))[0]

    assert count_parameters(shapes(GeneratorConfig(num_classes=26, persons=2))) == 1_358_075
    assert count_parameters(shapes(GeneratorConfig(num_classes=94))) == 715_075


@pytest.mark.parametrize("persons", [1, 2])
def test_skeleton_output_is_a_root_and_unit_limb_vectors(persons):
    config = GeneratorConfig(num_classes=5, persons=persons, frames=16)
    params, spectral = _ready(config)
    motion, same = generate(config, params, spectral, _z(config), jnp.array([0, 1, 4]))
    assert motion.shape == ((3, 16, 25, 3) if persons == 1 else (3, 2, 16, 25, 3)) and same is spectral
    norms = np.linalg.norm(np.asarray(motion)[..., 1:, :], axis=-1)  # |tanh| / (|tanh| + 1e-4): just under 1
    assert np.all(norms <= 1.0) and np.median(norms) > 0.99
    assert np.isfinite(np.asarray(motion)).all()


def test_smpl_output_is_orthonormal_rot6d_and_a_raw_translation():
    config = GeneratorConfig(num_classes=3, joints=25, channels=6, output="smpl", frames=8)
    params, spectral = _ready(config, 1)
    motion = np.asarray(generate(config, params, spectral, _z(config), jnp.array([0, 1, 2]))[0])
    b1, b2 = motion[..., :24, :3], motion[..., :24, 3:]
    np.testing.assert_allclose(np.linalg.norm(b1, axis=-1), 1.0, atol=1e-5)
    np.testing.assert_allclose(np.linalg.norm(b2, axis=-1), 1.0, atol=1e-5)
    np.testing.assert_allclose((b1 * b2).sum(-1), 0.0, atol=1e-5)
    assert motion.shape == (3, 8, 25, 6)


def test_training_calls_move_the_power_iteration_and_sigma_tends_to_the_top_singular_value():
    config = GeneratorConfig(num_classes=2, frames=4, joints=5, width_per_joint=8)
    params, spectral = init_generator(jax.random.key(2), config)
    z, y = _z(config, 2), jnp.array([0, 1])
    step = jax.jit(lambda s: generate(config, params, s, z, y, train=True))
    _, moved = step(spectral)
    assert not np.allclose(np.asarray(moved.head.u), np.asarray(spectral.head.u))
    for _ in range(40):
        _, moved = step(moved)
    w = np.asarray(params.blocks.linear1.weight[1], np.float64)
    sigma = float(moved.blocks.fc1.u[1] @ w @ moved.blocks.fc1.v[1])
    assert sigma == pytest.approx(np.linalg.svd(w, compute_uv=False)[0], rel=1e-3)
    # evaluation reads the stored vectors: deterministic, and the same as the training call's output from them
    a, _ = generate(config, params, moved, z, y)
    b, _ = generate(config, params, moved, z, y)
    np.testing.assert_array_equal(np.asarray(a), np.asarray(b))


def test_persons_from_one_shared_z_differ_only_through_their_positional_codes():
    """With a shared z and the same positional code for both persons, the I-Former sees two identical
    tokens, so the persons come out identical; the trained code's person part is what tells them apart."""
    config = GeneratorConfig(num_classes=3, persons=2, frames=8)
    params, spectral = _ready(config, 3)
    z, y = _z(config), jnp.array([0, 1, 2])
    motion = np.asarray(generate(config, params, spectral, z, y)[0])
    assert not np.allclose(motion[:, 0], motion[:, 1], atol=1e-3)
    same_code = params._replace(positions=jnp.broadcast_to(params.positions[:, :1], params.positions.shape))
    twins = np.asarray(generate(config, same_code, spectral, z, y)[0])
    np.testing.assert_allclose(twins[:, 0], twins[:, 1], atol=1e-5)
    # swapping the persons' codes swaps the persons (the I-Former is order-free)
    swapped = params._replace(positions=params.positions[:, ::-1])
    np.testing.assert_allclose(np.asarray(generate(config, swapped, spectral, z, y)[0]), motion[:, ::-1], atol=2e-5)


def test_ablation_switches_build_and_run():
    for config in (GeneratorConfig(num_classes=2, persons=2, frames=8, positions="fixed"),
                   GeneratorConfig(num_classes=2, persons=2, frames=8, positions="independent"),
                   GeneratorConfig(num_classes=2, frames=8, positions="fixed", spectral_norm=False)):
        params, spectral = init_generator(jax.random.key(4), config)
        assert (spectral is None) == (not config.spectral_norm)
        assert (params.positions is None) == (config.positions == "fixed")
        per_person = config.persons > 1
        motion, _ = generate(config, params, spectral, _z(config, 2, per_person=per_person), jnp.array([0, 1]))
        assert np.isfinite(np.asarray(motion)).all()
    # split positional codes start as one temporal half shared by the persons and one person half shared in time
    params, _ = init_generator(jax.random.key(5), GeneratorConfig(num_classes=2, persons=3, frames=8))
    pe = np.asarray(params.positions)
    np.testing.assert_array_equal(pe[:, 0, :100], pe[:, 2, :100])
    np.testing.assert_array_equal(pe[0, :, 100:], pe[5, :, 100:])


def test_bad_inputs_name_the_field():
    config = GeneratorConfig(num_classes=2, frames=8)
    params, spectral = init_generator(jax.random.key(0), config)
    with pytest.raises(ValueError, match=r"z: expected \[B, 8, 120\]"):
        generate(config, params, spectral, jnp.zeros((2, 9, 120)), jnp.zeros(2, int))
    with pytest.raises(ValueError, match=r"labels: expected \[B\] = \[2\]"):
        generate(config, params, spectral, jnp.zeros((2, 8, 120)), jnp.zeros(3, int))
    with pytest.raises(ValueError, match="GeneratorConfig.output"):
        GeneratorConfig(num_classes=2, output="smpl")


def test_interaction_by_concatenation_is_the_one_person_network_with_every_person_in_its_head():
    config = GeneratorConfig(num_classes=3, persons=2, frames=8, interaction="concat")
    params, spectral = _ready(config, 6)
    assert config.num_blocks == config.depth and params.positions.shape == (9, config.width)
    assert params.head.weight.shape == (25 * 2 * 3, config.width)
    motion = np.asarray(generate(config, params, spectral, _z(config), jnp.array([0, 1, 2]))[0])
    assert motion.shape == (3, 2, 8, 25, 3)
    assert np.median(np.linalg.norm(motion[..., 1:, :], axis=-1)) > 0.99
    with pytest.raises(ValueError, match="one latent sequence per person needs interaction='iformer'"):
        generate(config, params, spectral, _z(config, per_person=True), jnp.array([0, 1, 2]))
