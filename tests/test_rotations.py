"""Properties of jaxmotion.geometry.rotations: round trips, rotation validity, finiteness at 0 and pi,
analytical cases, input validation, eager/jit agreement and dtype preservation."""

import functools
import re

import jax
import jax.numpy as jnp
import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from jaxmotion.geometry import rotations as rot

ATOL = 1e-5
# Few fixed batch shapes (one with two leading axes) so compiled kernels are reused across examples.
batch_shapes = st.sampled_from([(1,), (5,), (2, 3)])
seeds = st.integers(0, 2**31 - 1)
# jax.jit cached per function so hypothesis examples reuse one compiled kernel.
TRANSFORMS = [
    pytest.param(lambda f: f, id="eager"),
    pytest.param(functools.cache(jax.jit), id="jit"),
]
REPS = list(rot.REPRESENTATIONS)
NEAR_PI = [np.pi, np.pi - 1e-7, np.pi - 1e-4]
PI_AXES = [(1, 0, 0), (0, 1, 0), (0, 0, 1), (1, 1, 1), (1, -2, 0.5)]


# ---------------------------------------------------------------- input generators


def random_rotvec(key, shape, max_angle):
    """Rotation vectors with uniform random axis and angle in [0, max_angle)."""
    k_axis, k_angle = jax.random.split(key)
    axis = jax.random.normal(k_axis, shape + (3,))
    axis = axis / jnp.linalg.norm(axis, axis=-1, keepdims=True)
    return axis * jax.random.uniform(k_angle, shape + (1,), maxval=max_angle)


def random_rotation(key, shape):
    """Uniform rotations on SO(3) (normalised Gaussian quaternions)."""
    return rot.quaternion_to_matrix(jax.random.normal(key, shape + (4,)))


def random_input(key, rep, shape):
    """Arbitrary valid input of a representation: any vector, or a rotation matrix for "matrix"."""
    if rep == "matrix":
        return random_rotation(key, shape)
    return jax.random.normal(key, shape + rot.REPRESENTATIONS[rep])


def unit(v):
    return v / jnp.linalg.norm(v, axis=-1, keepdims=True)


def assert_close(actual, expected, atol=ATOL):
    np.testing.assert_allclose(np.asarray(actual), np.asarray(expected), rtol=0, atol=atol)


def assert_rotation(m):
    m = np.asarray(m, dtype=np.float64)
    eye = np.broadcast_to(np.eye(3), m.shape)
    assert_close(m @ np.swapaxes(m, -1, -2), eye)
    assert_close(np.linalg.det(m), np.ones(m.shape[:-2]))


def assert_finite_value_and_jacobian(fn, x):
    x = jnp.asarray(x, jnp.float32)
    assert np.isfinite(np.asarray(fn(x))).all()
    assert np.isfinite(np.asarray(jax.jacrev(fn)(x))).all()


# Composites as module-level functions so the jit cache hits across hypothesis examples.
def aa_mat_aa(v):
    return rot.matrix_to_axis_angle(rot.axis_angle_to_matrix(v))


def aa_quat_aa(v):
    return rot.quaternion_to_axis_angle(rot.axis_angle_to_quaternion(v))


def quat_mat_quat(q):
    return rot.matrix_to_quaternion(rot.quaternion_to_matrix(q))


def mat_6d_mat(m):
    return rot.rot6d_to_matrix(rot.matrix_to_rot6d(m))


# ---------------------------------------------------------------- round trips


@pytest.mark.parametrize("transform", TRANSFORMS)
@given(seed=seeds, shape=batch_shapes)
def test_axis_angle_to_matrix_round_trip_recovers_rotvec(transform, seed, shape):
    # Angles stop short of pi, where v and -v are the same rotation.
    v = random_rotvec(jax.random.PRNGKey(seed), shape, np.pi - 1e-3)
    assert_close(transform(aa_mat_aa)(v), v)


@pytest.mark.parametrize("transform", TRANSFORMS)
@given(seed=seeds, shape=batch_shapes)
def test_axis_angle_to_quaternion_round_trip_recovers_rotvec(transform, seed, shape):
    v = random_rotvec(jax.random.PRNGKey(seed), shape, np.pi - 1e-3)
    assert_close(transform(aa_quat_aa)(v), v)


@pytest.mark.parametrize("transform", TRANSFORMS)
@given(seed=seeds, shape=batch_shapes)
def test_quaternion_to_matrix_round_trip_recovers_unit_quaternion_up_to_sign(transform, seed, shape):
    q = jax.random.normal(jax.random.PRNGKey(seed), shape + (4,))  # non-unit on purpose
    out, expected = transform(quat_mat_quat)(q), unit(q)
    sign = jnp.sign(jnp.sum(out * expected, axis=-1, keepdims=True))  # q and -q are one rotation
    assert_close(out, sign * expected)


@pytest.mark.parametrize("transform", TRANSFORMS)
@given(seed=seeds, shape=batch_shapes)
def test_matrix_to_rot6d_round_trip_recovers_matrix(transform, seed, shape):
    m = random_rotation(jax.random.PRNGKey(seed), shape)
    assert_close(transform(mat_6d_mat)(m), m)


@pytest.mark.parametrize("rep", REPS)
@given(seed=seeds, shape=batch_shapes)
def test_from_matrix_inverts_to_matrix(rep, seed, shape):
    m = rot.to_matrix(random_input(jax.random.PRNGKey(seed), rep, shape), rep)
    assert_close(rot.to_matrix(rot.from_matrix(m, rep), rep), m)


@given(seed=seeds, shape=batch_shapes)
def test_axis_angle_and_quaternion_paths_give_the_same_matrix(seed, shape):
    v = random_rotvec(jax.random.PRNGKey(seed), shape, 2 * np.pi)
    assert_close(rot.quaternion_to_matrix(rot.axis_angle_to_quaternion(v)), rot.axis_angle_to_matrix(v))


@given(seed=seeds, shape=batch_shapes)
def test_quaternion_to_axis_angle_is_canonical_and_same_rotation(seed, shape):
    q = jax.random.normal(jax.random.PRNGKey(seed), shape + (4,))  # about half have w < 0
    v = rot.quaternion_to_axis_angle(q)
    assert (np.linalg.norm(np.asarray(v), axis=-1) <= np.pi + ATOL).all()
    assert_close(rot.axis_angle_to_matrix(v), rot.quaternion_to_matrix(q))


# ---------------------------------------------------------------- produced matrices are rotations


@pytest.mark.parametrize("rep", ["axis_angle", "quaternion", "rot6d"])
@given(seed=seeds, shape=batch_shapes)
def test_to_matrix_of_arbitrary_input_is_a_rotation(rep, seed, shape):
    # Angles beyond pi, non-unit quaternions and non-orthogonal 6D all map into SO(3).
    x = 3.0 * jax.random.normal(jax.random.PRNGKey(seed), shape + rot.REPRESENTATIONS[rep])
    assert_rotation(rot.to_matrix(x, rep))


# ---------------------------------------------------------------- finiteness at 0 and pi

ZERO_ANGLE_CASES = [
    pytest.param(rot.axis_angle_to_matrix, np.zeros(3), id="axis_angle_to_matrix"),
    pytest.param(rot.axis_angle_to_quaternion, np.zeros(3), id="axis_angle_to_quaternion"),
    pytest.param(rot.matrix_to_axis_angle, np.eye(3), id="matrix_to_axis_angle"),
    pytest.param(rot.matrix_to_quaternion, np.eye(3), id="matrix_to_quaternion"),
    pytest.param(rot.quaternion_to_axis_angle, [1.0, 0, 0, 0], id="quaternion_to_axis_angle"),
    pytest.param(rot.quaternion_to_axis_angle, [-1.0, 0, 0, 0], id="quaternion_to_axis_angle_neg"),
    pytest.param(rot.quaternion_to_matrix, [1.0, 0, 0, 0], id="quaternion_to_matrix"),
    pytest.param(rot.rot6d_to_matrix, [1.0, 0, 0, 0, 1, 0], id="rot6d_to_matrix"),
    pytest.param(rot.rot6d_to_matrix, np.zeros(6), id="rot6d_to_matrix_zero_input"),
]


@pytest.mark.parametrize("fn, x", ZERO_ANGLE_CASES)
def test_values_and_gradients_finite_at_zero_angle(fn, x):
    assert_finite_value_and_jacobian(fn, x)


def test_gradients_at_zero_angle_are_the_infinitesimal_generators():
    # dR/dv_k at v = 0 is skew(e_k); conversely the rotation vector of I + dR is vee(skew part of dR).
    jac = np.asarray(jax.jacrev(rot.axis_angle_to_matrix)(jnp.zeros(3)))  # [3, 3, 3(k)]
    assert_close(np.moveaxis(jac, -1, 0), rot._skew(jnp.eye(3)))
    inv = np.asarray(jax.jacrev(rot.matrix_to_axis_angle)(jnp.eye(3)))  # [3(k), 3, 3]
    assert_close(inv, 0.5 * np.asarray(rot._skew(jnp.eye(3))))


@pytest.mark.parametrize("angle", NEAR_PI, ids=["pi", "pi-1e-7", "pi-1e-4"])
@pytest.mark.parametrize("axis", PI_AXES, ids=str)
def test_values_and_gradients_finite_near_pi(axis, angle):
    v = jnp.asarray(unit(np.asarray(axis, np.float64)) * angle, jnp.float32)
    m = rot.axis_angle_to_matrix(v)
    q = rot.axis_angle_to_quaternion(v)
    for fn, x in [
        (rot.axis_angle_to_matrix, v),
        (rot.axis_angle_to_quaternion, v),
        (rot.matrix_to_axis_angle, m),
        (rot.matrix_to_quaternion, m),
        (rot.quaternion_to_axis_angle, q),
        (aa_mat_aa, v),
    ]:
        assert_finite_value_and_jacobian(fn, x)
    # The recovered rotation vector is +-v (ambiguous only at exactly pi): same matrix either way.
    assert_close(rot.axis_angle_to_matrix(rot.matrix_to_axis_angle(m)), m)


# ---------------------------------------------------------------- analytical cases


def test_quarter_turn_about_z_maps_x_to_y():
    m = rot.axis_angle_to_matrix(jnp.array([0.0, 0.0, np.pi / 2]))
    assert_close(m @ jnp.array([1.0, 0.0, 0.0]), [0.0, 1.0, 0.0])


def test_quarter_turn_about_z_quaternion_is_cos_sin_of_half_angle():
    expected = [np.cos(np.pi / 4), 0.0, 0.0, np.sin(np.pi / 4)]
    v = jnp.array([0.0, 0.0, np.pi / 2])
    assert_close(rot.axis_angle_to_quaternion(v), expected)
    assert_close(rot.matrix_to_quaternion(rot.axis_angle_to_matrix(v)), expected)


def test_rot6d_of_identity_is_first_two_rows():
    assert_close(rot.matrix_to_rot6d(jnp.eye(3)), [1.0, 0.0, 0.0, 0.0, 1.0, 0.0])


@pytest.mark.parametrize("rep", REPS)
def test_dispatcher_shapes_match_representations(rep):
    x = rot.from_matrix(jnp.eye(3)[None], rep)
    assert x.shape == (1,) + rot.REPRESENTATIONS[rep]
    assert rot.to_matrix(x, rep).shape == (1, 3, 3)


# ---------------------------------------------------------------- input validation


@pytest.mark.parametrize("dispatch", [rot.to_matrix, rot.from_matrix])
def test_dispatcher_rejects_unknown_rep(dispatch):
    with pytest.raises(ValueError, match="unknown rep 'euler'.*axis_angle.*matrix.*quaternion.*rot6d"):
        dispatch(jnp.eye(3), "euler")


WRONG_SHAPE_CASES = [
    (rot.axis_angle_to_matrix, "axis_angle", "[..., 3]", (5, 4)),
    (rot.axis_angle_to_quaternion, "axis_angle", "[..., 3]", (4,)),
    (rot.quaternion_to_matrix, "quaternion", "[..., 4]", (2, 3)),
    (rot.quaternion_to_axis_angle, "quaternion", "[..., 4]", ()),
    (rot.matrix_to_quaternion, "matrix", "[..., 3, 3]", (3,)),
    (rot.matrix_to_axis_angle, "matrix", "[..., 3, 3]", (2, 3, 4)),
    (rot.matrix_to_rot6d, "matrix", "[..., 3, 3]", (6,)),
    (rot.rot6d_to_matrix, "rot6d", "[..., 6]", (3, 3)),
    (functools.partial(rot.to_matrix, rep="matrix"), "matrix", "[..., 3, 3]", (9,)),
    (functools.partial(rot.from_matrix, rep="rot6d"), "matrix", "[..., 3, 3]", (6,)),
]


@pytest.mark.parametrize("fn, arg, expected, bad_shape", WRONG_SHAPE_CASES)
def test_wrong_trailing_shape_is_rejected(fn, arg, expected, bad_shape):
    message = f"expected {arg} of shape {expected}, got {bad_shape}"
    with pytest.raises(ValueError, match=re.escape(message)):
        fn(jnp.zeros(bad_shape))


# ---------------------------------------------------------------- eager vs jit, dtype

KERNELS = {
    "axis_angle_to_matrix": (rot.axis_angle_to_matrix, "axis_angle"),
    "matrix_to_axis_angle": (rot.matrix_to_axis_angle, "matrix"),
    "quaternion_to_matrix": (rot.quaternion_to_matrix, "quaternion"),
    "matrix_to_quaternion": (rot.matrix_to_quaternion, "matrix"),
    "axis_angle_to_quaternion": (rot.axis_angle_to_quaternion, "axis_angle"),
    "quaternion_to_axis_angle": (rot.quaternion_to_axis_angle, "quaternion"),
    "matrix_to_rot6d": (rot.matrix_to_rot6d, "matrix"),
    "rot6d_to_matrix": (rot.rot6d_to_matrix, "rot6d"),
}


@pytest.mark.parametrize("transform", TRANSFORMS)
@pytest.mark.parametrize("name", KERNELS)
def test_kernel_matches_eager_result(name, transform):
    fn, rep = KERNELS[name]
    x = random_input(jax.random.PRNGKey(0), rep, (4, 2))
    assert_close(transform(fn)(x), fn(x), atol=1e-6)


@pytest.mark.parametrize("name", KERNELS)
def test_kernel_preserves_float32(name):
    fn, rep = KERNELS[name]
    x = random_input(jax.random.PRNGKey(1), rep, (3,)).astype(jnp.float32)
    assert fn(x).dtype == jnp.float32
