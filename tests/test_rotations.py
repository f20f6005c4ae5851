"""Properties of jaxmotion.geometry.rotations: round trips, rotation validity, finite values and
gradients at angle 0 and near pi, analytical cases, input validation, eager/jit agreement, dtype.

Speed: compilation dominates, so property tests call jitted kernels (compiled once per batch shape and
shared by every test), hypothesis draws the seed and one of two batch shapes, and the eager tests all
use the batch shape ``BATCH`` so eager per-op compilations are shared too.
"""

import functools
import math
import re

import jax
import jax.numpy as jnp
import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from jaxmotion.geometry import rotations as rot

ATOL = 1e-5
BATCH = (2, 3)  # two leading axes
seeds = st.integers(0, 2**31 - 1)
batch_shapes = st.sampled_from([(5,), BATCH])
REPS = list(rot.REPRESENTATIONS)
VECTOR_REPS = ["axis_angle", "quaternion", "rot6d"]
TRANSFORMS = [pytest.param(lambda f: f, id="eager"), pytest.param(jax.jit, id="jit")]

# name -> (kernel, input rep, output rep)
KERNELS = {
    "axis_angle_to_matrix": (rot.axis_angle_to_matrix, "axis_angle", "matrix"),
    "matrix_to_axis_angle": (rot.matrix_to_axis_angle, "matrix", "axis_angle"),
    "quaternion_to_matrix": (rot.quaternion_to_matrix, "quaternion", "matrix"),
    "matrix_to_quaternion": (rot.matrix_to_quaternion, "matrix", "quaternion"),
    "axis_angle_to_quaternion": (rot.axis_angle_to_quaternion, "axis_angle", "quaternion"),
    "quaternion_to_axis_angle": (rot.quaternion_to_axis_angle, "quaternion", "axis_angle"),
    "matrix_to_rot6d": (rot.matrix_to_rot6d, "matrix", "rot6d"),
    "rot6d_to_matrix": (rot.rot6d_to_matrix, "rot6d", "matrix"),
}
KERNEL_NAMES = list(KERNELS)
JIT = {name: jax.jit(fn) for name, (fn, _, _) in KERNELS.items()}
TO_MATRIX = jax.jit(rot.to_matrix, static_argnames="rep")
FROM_MATRIX = jax.jit(rot.from_matrix, static_argnames="rep")

# A quarter turn about z (maps x to y) in every representation.
QUARTER_TURN_Z = {
    "axis_angle": [0.0, 0.0, np.pi / 2],
    "quaternion": [np.cos(np.pi / 4), 0.0, 0.0, np.sin(np.pi / 4)],
    "matrix": [[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]],
    "rot6d": [0.0, -1.0, 0.0, 1.0, 0.0, 0.0],
}
# skew(e_k) for k = x, y, z: column j of skew(e_k) is e_k x e_j.
GENERATORS = np.stack([np.cross(e, np.eye(3)).T for e in np.eye(3)])
NEAR_PI = [np.pi, np.pi - 1e-7, np.pi - 1e-4]
PI_AXES = [(1, 0, 0), (0, 1, 0), (0, 0, 1), (1, 1, 1), (1, -2, 0.5)]


# ---------------------------------------------------------------- helpers


# Draws come from one fixed-size pool per seed, so jax.random compiles once instead of per shape.
POOL_SIZE = 64


def normal(seed, shape):
    """Standard normals drawn with jax.random from ``seed``, as a float32 numpy array."""
    pool = np.asarray(jax.random.normal(jax.random.PRNGKey(seed), (POOL_SIZE,)))
    return pool[: math.prod(shape)].reshape(shape)


def uniform(seed, shape, maxval):
    """Uniform [0, maxval) draws with jax.random from ``seed`` (independent of ``normal``'s)."""
    key = jax.random.fold_in(jax.random.PRNGKey(seed), 1)
    pool = np.asarray(jax.random.uniform(key, (POOL_SIZE,), maxval=maxval))
    return pool[: math.prod(shape)].reshape(shape)


def unit(v):
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


def random_rotvec(seed, shape, max_angle):
    """Rotation vectors with uniform random axis and angle uniform in [0, max_angle)."""
    return (unit(normal(seed, shape + (3,))) * uniform(seed, shape + (1,), max_angle)).astype(np.float32)


def random_rotation(seed, shape):
    """Uniform rotations on SO(3) (normalised Gaussian quaternions)."""
    return JIT["quaternion_to_matrix"](normal(seed, shape + (4,)))


def random_input(seed, rep, shape):
    """Any vector of the representation, or a rotation matrix for "matrix"."""
    if rep == "matrix":
        return random_rotation(seed, shape)
    return normal(seed, shape + rot.REPRESENTATIONS[rep])


def batched(x):
    """``x`` broadcast to the eager-test batch shape BATCH, float32."""
    x = np.asarray(x, np.float32)
    return np.broadcast_to(x, BATCH + x.shape)


def assert_close(actual, expected, atol=ATOL):
    np.testing.assert_allclose(np.asarray(actual), np.asarray(expected), rtol=0, atol=atol)


def assert_rotation(m):
    m = np.asarray(m, np.float64)
    assert_close(m @ np.swapaxes(m, -1, -2), np.broadcast_to(np.eye(3), m.shape))
    assert_close(np.linalg.det(m), np.ones(m.shape[:-2]))


# ---------------------------------------------------------------- round trips


@given(seed=seeds, shape=batch_shapes)
def test_axis_angle_to_matrix_round_trip_recovers_rotvec(seed, shape):
    # Angles stop short of pi, where v and -v are the same rotation (pi itself is tested below).
    v = random_rotvec(seed, shape, np.pi - 1e-3)
    assert_close(JIT["matrix_to_axis_angle"](JIT["axis_angle_to_matrix"](v)), v)


@given(seed=seeds, shape=batch_shapes)
def test_axis_angle_to_quaternion_round_trip_recovers_rotvec(seed, shape):
    v = random_rotvec(seed, shape, np.pi - 1e-3)
    assert_close(JIT["quaternion_to_axis_angle"](JIT["axis_angle_to_quaternion"](v)), v)


@given(seed=seeds, shape=batch_shapes)
def test_quaternion_to_matrix_round_trip_recovers_unit_quaternion_up_to_sign(seed, shape):
    q = normal(seed, shape + (4,))  # non-unit on purpose
    out = np.asarray(JIT["matrix_to_quaternion"](JIT["quaternion_to_matrix"](q)))
    sign = np.sign(np.sum(out * q, axis=-1, keepdims=True))  # q and -q are the same rotation
    assert_close(out, sign * unit(q))


@given(seed=seeds, shape=batch_shapes)
def test_matrix_to_rot6d_round_trip_recovers_matrix(seed, shape):
    m = random_rotation(seed, shape)
    assert_close(JIT["rot6d_to_matrix"](JIT["matrix_to_rot6d"](m)), m)


@pytest.mark.parametrize("rep", REPS)
@given(seed=seeds, shape=batch_shapes)
def test_from_matrix_inverts_to_matrix(rep, seed, shape):
    m = TO_MATRIX(random_input(seed, rep, shape), rep=rep)
    assert_close(TO_MATRIX(FROM_MATRIX(m, rep=rep), rep=rep), m)


@given(seed=seeds, shape=batch_shapes)
def test_axis_angle_and_quaternion_paths_give_the_same_matrix(seed, shape):
    # Guards against consistent-but-wrong conventions that round trips alone cannot see.
    v = random_rotvec(seed, shape, 2 * np.pi)
    via_quaternion = JIT["quaternion_to_matrix"](JIT["axis_angle_to_quaternion"](v))
    assert_close(via_quaternion, JIT["axis_angle_to_matrix"](v))


@given(seed=seeds, shape=batch_shapes)
def test_quaternion_to_axis_angle_is_canonical_and_same_rotation(seed, shape):
    q = normal(seed, shape + (4,))  # about half have w < 0
    v = JIT["quaternion_to_axis_angle"](q)
    assert (np.linalg.norm(np.asarray(v), axis=-1) <= np.pi + ATOL).all()
    assert_close(JIT["axis_angle_to_matrix"](v), JIT["quaternion_to_matrix"](q))


@pytest.mark.parametrize("rep", VECTOR_REPS)
@given(seed=seeds, shape=batch_shapes)
def test_to_matrix_of_arbitrary_input_is_orthonormal_with_det_one(rep, seed, shape):
    # Angles beyond pi, non-unit quaternions and non-orthogonal 6D all land in SO(3).
    assert_rotation(TO_MATRIX(3.0 * random_input(seed, rep, shape), rep=rep))


# ---------------------------------------------------------------- finite at 0 and near pi


def special_rotvecs():
    """[16, 3]: the zero vector, then angles pi, pi - 1e-7 and pi - 1e-4 about several axes."""
    axes = unit(np.asarray(PI_AXES, np.float64))
    near_pi = (axes[:, None, :] * np.asarray(NEAR_PI)[:, None]).reshape(-1, 3)
    return np.concatenate([np.zeros((1, 3)), near_pi]).astype(np.float32)


def special_inputs(rep):
    """Angle 0 first, then at/near pi, in ``rep``; quaternions also negated (w <= 0). Vector reps end
    with the all-zero input: not a rotation, but a zero network output must not poison training."""
    v = special_rotvecs()
    if rep == "quaternion":
        q = np.asarray(JIT["axis_angle_to_quaternion"](v))
        return np.concatenate([q, -q, np.zeros((1, 4), np.float32)])
    x = np.asarray(FROM_MATRIX(JIT["axis_angle_to_matrix"](v), rep=rep))
    if rep == "rot6d":
        x = np.concatenate([x, np.zeros((1, 6), np.float32)])
    return x


@functools.cache
def batched_jacobian(fn):
    return jax.jit(jax.vmap(jax.jacrev(fn)))


@pytest.mark.parametrize("name", KERNEL_NAMES)
def test_values_and_gradients_finite_at_zero_angle_and_near_pi(name):
    fn, src, _ = KERNELS[name]
    x = special_inputs(src)
    assert np.isfinite(np.asarray(JIT[name](x))).all()
    assert np.isfinite(np.asarray(batched_jacobian(fn)(x))).all()


def test_matrix_to_axis_angle_recovers_the_rotation_at_and_near_pi():
    # At exactly pi the rotation vector is +-v: compare the matrices.
    m = JIT["axis_angle_to_matrix"](special_rotvecs())
    assert_close(JIT["axis_angle_to_matrix"](JIT["matrix_to_axis_angle"](m)), m)


def test_gradients_at_zero_angle_are_the_infinitesimal_generators():
    # dR/dv_k at v = 0 is skew(e_k); conversely the rotation vector of I + dR is vee(skew part of dR).
    # Row 0 of the special inputs is the zero vector / identity matrix (reuses compiled Jacobians).
    jac = np.asarray(batched_jacobian(rot.axis_angle_to_matrix)(special_inputs("axis_angle")))
    assert_close(np.moveaxis(jac[0], -1, 0), GENERATORS)  # [3, 3, 3(k)] -> [3(k), 3, 3]
    inv = np.asarray(batched_jacobian(rot.matrix_to_axis_angle)(special_inputs("matrix")))
    assert_close(inv[0], 0.5 * GENERATORS)  # [3(k), 3, 3]


# ---------------------------------------------------------------- analytical cases (eager)


def test_quarter_turn_about_z_maps_x_to_y():
    m = rot.axis_angle_to_matrix(batched(QUARTER_TURN_Z["axis_angle"]))
    assert_close(np.asarray(m) @ np.array([1.0, 0.0, 0.0]), batched([0.0, 1.0, 0.0]))


def test_quarter_turn_about_z_quaternion_is_cos_sin_of_quarter_pi():
    expected = batched([np.cos(np.pi / 4), 0.0, 0.0, np.sin(np.pi / 4)])
    v = batched(QUARTER_TURN_Z["axis_angle"])
    assert_close(rot.axis_angle_to_quaternion(v), expected)
    assert_close(rot.matrix_to_quaternion(rot.axis_angle_to_matrix(v)), expected)


def test_rot6d_of_identity_is_first_two_rows():
    assert_close(rot.matrix_to_rot6d(batched(np.eye(3))), batched([1.0, 0.0, 0.0, 0.0, 1.0, 0.0]))


@pytest.mark.parametrize("transform", TRANSFORMS)
@pytest.mark.parametrize("name", KERNEL_NAMES)
def test_kernel_converts_quarter_turn_about_z_eagerly_and_under_jit(name, transform):
    fn, src, dst = KERNELS[name]
    assert_close(transform(fn)(batched(QUARTER_TURN_Z[src])), batched(QUARTER_TURN_Z[dst]))


@pytest.mark.parametrize("rep", REPS)
def test_dispatcher_shapes_match_representations(rep):
    x = rot.from_matrix(batched(np.eye(3)), rep)
    assert x.shape == BATCH + rot.REPRESENTATIONS[rep]
    assert rot.to_matrix(x, rep).shape == BATCH + (3, 3)


# ---------------------------------------------------------------- input validation


@pytest.mark.parametrize("dispatch", [rot.to_matrix, rot.from_matrix])
def test_dispatcher_rejects_unknown_rep_listing_valid_names(dispatch):
    with pytest.raises(ValueError, match="unknown rep 'euler'.*axis_angle.*matrix.*quaternion.*rot6d"):
        dispatch(np.eye(3), "euler")


def rot_to_matrix(rep):
    return functools.partial(rot.to_matrix, rep=rep)


def rot_from_matrix(rep):
    return functools.partial(rot.from_matrix, rep=rep)


# (call, expected message up to the received shape, wrong input shape)
WRONG_SHAPE_CASES = [
    (rot.axis_angle_to_matrix, "axis_angle_to_matrix: expected axis_angle of shape [..., 3]", (5, 4)),
    (rot.axis_angle_to_quaternion, "axis_angle_to_quaternion: expected axis_angle of shape [..., 3]", (4,)),
    (rot.quaternion_to_matrix, "quaternion_to_matrix: expected quaternion of shape [..., 4]", (2, 3)),
    (rot.quaternion_to_axis_angle, "quaternion_to_axis_angle: expected quaternion of shape [..., 4]", ()),
    (rot.matrix_to_quaternion, "matrix_to_quaternion: expected matrix of shape [..., 3, 3]", (3,)),
    (rot.matrix_to_axis_angle, "matrix_to_axis_angle: expected matrix of shape [..., 3, 3]", (2, 3, 4)),
    (rot.matrix_to_rot6d, "matrix_to_rot6d: expected matrix of shape [..., 3, 3]", (6,)),
    (rot.rot6d_to_matrix, "rot6d_to_matrix: expected rot6d of shape [..., 6]", (3, 3)),
    # Dispatchers: the identity "matrix" rep checks itself; others report the kernel they call.
    (rot_to_matrix("matrix"), "to_matrix: expected matrix of shape [..., 3, 3]", (9,)),
    (rot_from_matrix("matrix"), "from_matrix: expected matrix of shape [..., 3, 3]", (4,)),
    (rot_to_matrix("rot6d"), "rot6d_to_matrix: expected rot6d of shape [..., 6]", (3,)),
    (rot_from_matrix("rot6d"), "matrix_to_rot6d: expected matrix of shape [..., 3, 3]", (6,)),
]


@pytest.mark.parametrize("fn, message, bad_shape", WRONG_SHAPE_CASES)
def test_wrong_trailing_shape_is_rejected_naming_expected_and_received_shape(fn, message, bad_shape):
    with pytest.raises(ValueError, match=re.escape(f"{message}, got {bad_shape}")):
        fn(np.zeros(bad_shape, np.float32))


# ---------------------------------------------------------------- eager vs jit, dtype


@pytest.mark.parametrize("name", KERNEL_NAMES)
def test_kernel_gives_same_result_eagerly_and_under_jit(name):
    fn, src, _ = KERNELS[name]
    x = random_input(0, src, BATCH)
    assert_close(JIT[name](x), fn(x), atol=1e-6)


@pytest.mark.parametrize("name", KERNEL_NAMES)
def test_kernel_preserves_float32(name):
    fn, src, _ = KERNELS[name]
    x = jnp.asarray(random_input(1, src, BATCH), jnp.float32)
    assert fn(x).dtype == jnp.float32
    assert JIT[name](x).dtype == jnp.float32


# ---------------------------------------------------------------- Euler angles (BVH's convention)

EULER_ORDERS = list(rot.EULER_ORDERS)
EULER_BATCH = 16  # one shape for every Euler test (each kernel compiles once), drawn from the 64-value pools
EULER_ATOL = {np.float32: 2e-5, np.float64: 1e-12}
# Angle ranges of the draws: first and third in (-pi, pi), the middle away from the lock.
EULER_RANGE = np.array([np.pi - 1e-3, np.pi / 2 - 1e-2, np.pi - 1e-3], np.float32)


def euler_inputs(seed, middle=None):
    """``[EULER_BATCH, 3]`` float32 angles in ``EULER_RANGE`` (every middle angle ``middle`` if given) and
    ``[EULER_BATCH, 3, 3]`` uniform rotations."""
    angles = (uniform(seed, (EULER_BATCH, 3), 2.0) - 1.0) * EULER_RANGE
    if middle is not None:
        angles[:, 1] = middle
    return angles, np.asarray(random_rotation(seed, (EULER_BATCH,)))


def euler_round_trip(angles, matrices, order):
    """The matrices of ``angles``, the angles read back from them and their matrices, then the angles read
    off ``matrices`` and their matrices (both reads in one call, to compile fewer kernels)."""
    forward = rot.euler_to_matrix(angles, order)
    read = rot.matrix_to_euler(jnp.concatenate([forward, matrices]), order)
    rebuilt = rot.euler_to_matrix(read, order)
    n = angles.shape[0]
    return forward, read[:n], rebuilt[:n], read[n:], rebuilt[n:]


EULER_JIT = jax.jit(euler_round_trip, static_argnames="order")


def elementary_rotation(axis, t):
    """Right-handed rotation about coordinate axis "X", "Y" or "Z", for column vectors: [N] -> [N, 3, 3]."""
    c, s, one, zero = np.cos(t), np.sin(t), np.ones_like(t), np.zeros_like(t)
    rows = {
        "X": [[one, zero, zero], [zero, c, -s], [zero, s, c]],
        "Y": [[c, zero, s], [zero, one, zero], [-s, zero, c]],
        "Z": [[c, -s, zero], [s, c, zero], [zero, zero, one]],
    }[axis]
    return np.moveaxis(np.array(rows, np.float64), -1, 0)


def check_euler_round_trip(outputs, angles, matrices, dtype, locked=False):
    forward, back, rebuilt, read, reread = outputs
    back, read = np.asarray(back), np.asarray(read)
    assert_close(rebuilt, forward, atol=EULER_ATOL[dtype])
    assert_close(reread, matrices, atol=EULER_ATOL[dtype])
    assert np.all(np.abs(read[:, 1]) <= np.pi / 2 + 1e-6) and np.all(np.abs(read) <= np.pi + 1e-6)
    if locked:
        assert np.all(back[:, 2] == 0.0)  # the whole turn in the first angle
        assert_close(back[:, 1], angles[:, 1], atol=1e-6)
    else:
        assert_close(back, angles, atol=EULER_ATOL[dtype])


@pytest.mark.parametrize("order", EULER_ORDERS)
def test_euler_to_matrix_is_the_product_of_axis_rotations_in_channel_order(order):
    angles, matrices = euler_inputs(0)
    first, second, third = (elementary_rotation(axis, angles[:, i].astype(np.float64)) for i, axis in enumerate(order))
    assert_close(EULER_JIT(angles, matrices, order)[0], first @ second @ third)


def test_zxy_quarter_turn_of_the_first_channel_turns_x_to_y():
    m = np.asarray(rot.euler_to_matrix(np.array([np.pi / 2, 0.0, 0.0], np.float32), "ZXY"))
    assert_close(m @ np.array([1.0, 0.0, 0.0]), [0.0, 1.0, 0.0])


@given(seed=seeds)
@pytest.mark.parametrize("order", EULER_ORDERS)
def test_matrix_to_euler_round_trip_recovers_angles_and_any_matrix(order, seed):
    angles, matrices = euler_inputs(seed)
    check_euler_round_trip(EULER_JIT(angles, matrices, order), angles, matrices, np.float32)


@given(seed=seeds, sign=st.sampled_from([1.0, -1.0]))
@pytest.mark.parametrize("order", EULER_ORDERS)
def test_gimbal_lock_puts_the_whole_turn_in_the_first_angle(order, seed, sign):
    angles, matrices = euler_inputs(seed, middle=sign * np.pi / 2)
    check_euler_round_trip(EULER_JIT(angles, matrices, order), angles, matrices, np.float32, locked=True)


@given(seed=seeds, sign=st.sampled_from([1.0, -1.0]), log_gap=st.floats(-9.0, -2.0))
@pytest.mark.parametrize("order", EULER_ORDERS)
def test_near_gimbal_lock_matrix_is_still_reproduced(order, seed, sign, log_gap):
    angles, matrices = euler_inputs(seed, middle=sign * (np.pi / 2 - 10.0**log_gap))
    forward, _, rebuilt, _, _ = EULER_JIT(angles, matrices, order)
    assert_close(rebuilt, forward, atol=EULER_ATOL[np.float32])


@pytest.mark.parametrize("middle", [None, np.pi / 2, -np.pi / 2])
def test_euler_kernels_agree_eagerly_and_under_jit(middle):
    angles, matrices = euler_inputs(5, middle=middle)
    for order in EULER_ORDERS:
        eager = euler_round_trip(angles, matrices, order)
        check_euler_round_trip(eager, angles, matrices, np.float32, locked=middle is not None)
        for jitted, direct in zip(EULER_JIT(angles, matrices, order), eager):
            assert_close(jitted, direct, atol=1e-6)


@pytest.mark.parametrize("middle", [None, np.pi / 2, -np.pi / 2, np.pi / 2 - 1e-9, -np.pi / 2 + 1e-12])
def test_euler_conversions_keep_float64_numpy_input_in_float64(middle):
    angles, matrices = (x.astype(np.float64) for x in euler_inputs(3))
    if middle is not None:
        angles[:, 1] = middle
    # float32 draws made orthonormal in float64
    matrices[:, 0] /= np.linalg.norm(matrices[:, 0], axis=-1, keepdims=True)
    matrices[:, 2] = np.cross(matrices[:, 0], matrices[:, 1])
    matrices[:, 2] /= np.linalg.norm(matrices[:, 2], axis=-1, keepdims=True)
    matrices[:, 1] = np.cross(matrices[:, 2], matrices[:, 0])
    exactly_locked = middle is not None and abs(middle) == np.pi / 2
    with jax.enable_x64(True):
        for order in EULER_ORDERS:
            outputs = euler_round_trip(angles, matrices, order)
            assert all(x.dtype == jnp.float64 for x in outputs)
            if middle is None or exactly_locked:
                check_euler_round_trip(outputs, angles, matrices, np.float64, locked=exactly_locked)
            else:  # next to the lock only the matrix is determined
                assert_close(outputs[2], outputs[0], atol=EULER_ATOL[np.float64])


@pytest.mark.parametrize("fn", [rot.euler_to_matrix, rot.matrix_to_euler])
def test_unknown_euler_order_is_rejected_listing_valid_orders(fn):
    with pytest.raises(ValueError, match=re.escape("unknown order 'XYX'; valid orders are ['XYZ', 'XZY'")):
        fn(np.zeros((3, 3), np.float32), "XYX")


def test_euler_wrong_trailing_shape_is_rejected():
    with pytest.raises(ValueError, match=re.escape("euler_to_matrix: expected angles of shape [..., 3], got (4,)")):
        rot.euler_to_matrix(np.zeros(4, np.float32), "ZXY")
    with pytest.raises(ValueError, match=re.escape("matrix_to_euler: expected matrix of shape [..., 3, 3], got (3,)")):
        rot.matrix_to_euler(np.zeros(3, np.float32), "ZXY")


@pytest.mark.parametrize("matrix, kind", [
    (np.diag([1.0, 1.0, -1.0]), "a reflection (determinant -1)"),
    (2.0 * np.eye(3), "scaled or sheared (determinant 8"),
    (np.diag([1.0, 1.0, 0.0]), "singular (determinant 0)"),
    (np.full((3, 3), np.nan), "not finite"),
])
def test_check_rotations_names_what_is_wrong_with_the_first_bad_matrix(matrix, kind):
    good = np.asarray(rot.axis_angle_to_matrix(jnp.array([[0.3, -1.2, 2.0], [0.0, 0.0, 0.0]])))
    batch = np.stack([good[0], good[1], matrix, good[0]]).reshape(2, 2, 3, 3)
    assert rot.check_rotations(good) is good
    with pytest.raises(ValueError, match=re.escape(f"poses: 1 of 4 matrices are not rotations; the first, at "
                                                   f"index (1, 0), is {kind}")):
        rot.check_rotations(batch, where="poses")


MATRIX_INPUTS = {
    "matrix_to_axis_angle": rot.matrix_to_axis_angle,
    "matrix_to_quaternion": rot.matrix_to_quaternion,
    "matrix_to_rot6d": rot.matrix_to_rot6d,
    "matrix_to_euler": functools.partial(rot.matrix_to_euler, order="ZXY"),
    "from_matrix": functools.partial(rot.from_matrix, rep="matrix"),
}
NON_ROTATIONS = [(np.diag([1.0, 1.0, -1.0]), "a reflection"), (1.2 * np.eye(3), "scaled or sheared")]


@pytest.mark.parametrize("name", MATRIX_INPUTS)
@pytest.mark.parametrize("matrix, kind", NON_ROTATIONS)
def test_converters_from_a_matrix_refuse_a_concrete_non_rotation_naming_themselves(name, matrix, kind):
    good = np.asarray(rot.axis_angle_to_matrix(jnp.array([[0.3, -1.2, 2.0], [0.5, 0.0, 0.1]])))
    batch = np.stack([good[0], matrix, good[1]]).astype(np.float32)
    with pytest.raises(ValueError, match=re.escape(f"{name}: matrix: 1 of 3 matrices are not rotations; the first, "
                                                   f"at index (1,), is {kind}")):
        MATRIX_INPUTS[name](batch)
    np.testing.assert_array_equal(MATRIX_INPUTS[name](batch, check=False)[0], MATRIX_INPUTS[name](good)[0])


def test_the_rotation_check_is_skipped_under_jit_and_lets_nan_through():
    """The documented contract: traced values are not checked (the hot paths pay nothing), and a NaN
    matrix comes out NaN rather than as an error (the loaders refuse non-finite input)."""
    reflection = jnp.diag(jnp.array([1.0, 1.0, -1.0]))
    assert np.isfinite(jax.jit(rot.matrix_to_axis_angle)(reflection)).all()
    nan = jnp.full((3, 3), jnp.nan)
    assert np.isnan(rot.matrix_to_axis_angle(nan)).all()


def test_slerp_turns_at_constant_speed_along_the_shorter_arc():
    axis = np.array([0.3, -0.5, 0.8]) / np.linalg.norm([0.3, -0.5, 0.8])
    q0 = np.asarray(rot.axis_angle_to_quaternion(np.zeros(3)))
    q1 = np.asarray(rot.axis_angle_to_quaternion(1.2 * axis))
    for t in (0.0, 0.25, 0.5, 1.0):  # halfway in angle, about the same axis
        np.testing.assert_allclose(rot.quaternion_to_axis_angle(rot.slerp(q0, q1, t)), 1.2 * t * axis, atol=1e-6)
    np.testing.assert_allclose(rot.quaternion_to_axis_angle(rot.slerp(q0, -q1, 0.5)), 0.6 * axis, atol=1e-6)  # -q1 = q1
    near = np.asarray(rot.axis_angle_to_quaternion(1e-4 * axis))
    np.testing.assert_allclose(rot.quaternion_to_axis_angle(rot.slerp(q0, near, 0.5)), 0.5e-4 * axis, atol=1e-8)
