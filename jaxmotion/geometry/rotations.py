"""Conversions among axis-angle, quaternion, rotation matrix and ACTOR's 6D representation.

Conventions (binding for the whole library):

* Column vectors: ``v' = R @ v``. For row arrays of points ``p`` of shape [..., N, 3] use
  ``p @ R.T`` (or ``jnp.einsum("...ij,...nj->...ni", R, p)``).
* Axis-angle is a rotation vector [..., 3]: direction = axis, norm = angle in radians.
* Quaternions are [..., 4] in (w, x, y, z) order, w the real part. ``axis_angle_to_quaternion``
  gives w >= 0 for angles in [0, pi]; ``matrix_to_quaternion`` returns a unit quaternion with w >= 0.
  ``quaternion_to_matrix`` accepts non-unit quaternions (scale s = 2 / |q|^2, as in pytorch3d).
* ``quaternion_to_axis_angle`` uses angle = 2 atan2(|v|, w) after flipping q to w >= 0, so the
  returned rotation vector is canonical: angle in [0, pi].
* 6D ("rot6d", ACTOR) = the first two ROWS of the matrix, flattened:
  [R00, R01, R02, R10, R11, R12], shape [..., 6]. The inverse is Gram-Schmidt:
  b1 = normalize(a1), b2 = normalize(a2 - <b1, a2> b1), b3 = b1 x b2, rows of R = (b1, b2, b3).
* Euler angles (BVH's): [..., 3] radians listed in the order of ``order``, one of ``EULER_ORDERS``.
  Order "ZXY" with angles (a, b, c) is ``R = R_z(a) @ R_x(b) @ R_y(c)``: intrinsic rotations (about Z,
  then the new X, then the newest Y), equivalently extrinsic ones in the reverse order, which is how
  BVH readers (Blender, MotionBuilder) apply a joint's channels ``Zrotation Xrotation Yrotation``.
  ``R_x(t)`` is the right-handed rotation by t about +X (``R_x(t) e_y = cos t e_y + sin t e_z``).

All functions are batched over any leading axes, jit-able and differentiable, and keep values and
gradients finite at angle 0 and at pi (double-where + Taylor branches; matrix -> quaternion picks the
best-conditioned of four candidates). The input dtype is preserved.

The conversions from a matrix (and forward kinematics, :mod:`jaxmotion.geometry.kinematics`) take
rotations: a reflection, a scaled or a singular matrix is a ``ValueError`` naming the function, through
:func:`check_rotations`. The check runs where values are concrete (an eager call, a loader, an export);
under ``jit`` and the other transformations it is skipped, since it would need a host round trip per call:
the library's jitted hot paths (losses, training and sampling steps) convert what a model produced, which
is checked where it entered or built as a rotation, and so cost nothing more. ``check=False`` converts
any 3x3 without the check (a projection onto some rotation), for a network's raw output. Non-finite
matrices pass the check and come out NaN, as in every numeric function; the loaders refuse them.
"""

import functools
from types import MappingProxyType

import jax
import jax.numpy as jnp
import numpy as np

__all__ = [
    "EULER_ORDERS",
    "REPRESENTATIONS",
    "axis_angle_to_matrix",
    "axis_angle_to_quaternion",
    "check_rotations",
    "euler_to_matrix",
    "from_matrix",
    "matrix_to_axis_angle",
    "matrix_to_euler",
    "matrix_to_quaternion",
    "matrix_to_rot6d",
    "quaternion_to_axis_angle",
    "quaternion_to_matrix",
    "rot6d_to_matrix",
    "to_matrix",
]

# Trailing shape of each representation (model configs derive feature sizes from it); read-only.
REPRESENTATIONS = MappingProxyType(
    {"axis_angle": (3,), "quaternion": (4,), "matrix": (3, 3), "rot6d": (6,)}
)

# Squared angle (or squared tan of the half angle) below which Taylor series replace the closed forms:
# theta < 1e-3, where the truncation error (~theta^6) is far below float64 precision.
_SMALL_SQ = 1e-6
# Squared-norm floor for the Gram-Schmidt normalisation: zero input gives finite values and gradients.
_NORM_EPS_SQ = 1e-12


def _checked(x, shape, fn, arg):
    """Return ``x`` as an array after checking its trailing shape; raise a ValueError naming ``arg``."""
    x = jnp.asarray(x)
    if x.shape[-len(shape):] != shape:
        dims = ", ".join(str(d) for d in shape)
        raise ValueError(f"{fn}: expected {arg} of shape [..., {dims}], got {tuple(x.shape)}")
    return x


def _rotation_defects(m):
    """``[..., 3, 3]`` -> ``(det [N], max |R Rᵀ - I| [N])`` over the flattened matrices, in the input's
    precision (at least float32). Entry planes ``[3, 3, N]`` and closed forms instead of batched 3x3 linear
    algebra: ten times faster in numpy, about the cost of the FK it guards."""
    dtype = np.float64 if m.dtype == np.float64 else np.float32
    rows = np.ascontiguousarray(m.reshape(-1, 9).T, dtype=dtype).reshape(3, 3, -1)
    error = np.max([np.abs((rows[i] * rows[j]).sum(axis=0) - (i == j)) for i in range(3) for j in range(i, 3)],
                   axis=0)
    cofactor = np.stack([rows[1, 1] * rows[2, 2] - rows[1, 2] * rows[2, 1],
                         rows[1, 2] * rows[2, 0] - rows[1, 0] * rows[2, 2],
                         rows[1, 0] * rows[2, 1] - rows[1, 1] * rows[2, 0]])
    return (rows[0] * cofactor).sum(axis=0), error


def check_rotations(matrices, *, where: str = "rotations", atol: float = 1e-3, allow_nonfinite: bool = False):
    """``matrices [..., 3, 3]`` if every one is a rotation (``R Rᵀ = I`` and ``det R = +1`` within ``atol``,
    and finite unless ``allow_nonfinite``), else a ``ValueError`` from ``where`` saying how many are not and
    what the first one is (a reflection, singular, scaled or sheared, not finite).

    Checks concrete values on the host (numpy, in the input's precision, at least float32); traced values
    (under ``jit``, ``vmap``, ``grad``) are returned unchecked.
    """
    if isinstance(matrices, jax.core.Tracer):
        return matrices
    m = np.asarray(matrices)
    if m.shape[-2:] != (3, 3):
        raise ValueError(f"{where}: expected rotation matrices [..., 3, 3], got {m.shape}")
    det, error = _rotation_defects(m)
    finite = np.isfinite(error)  # any non-finite entry makes its row's squared norm non-finite
    bad = finite & ((np.abs(det - 1) > atol) | (error > atol))
    if not allow_nonfinite:
        bad |= ~finite
    if bad.any():
        i = int(np.flatnonzero(bad)[0])
        if not finite[i]:
            kind = "not finite (NaN or infinite entries)"
        elif det[i] < -atol:
            kind = f"a reflection (determinant {det[i]:.3g})"
        elif abs(det[i]) <= atol:
            kind = f"singular (determinant {det[i]:.3g})"
        else:
            kind = f"scaled or sheared (determinant {det[i]:.3g}, max |R Rᵀ - I| {error[i]:.3g})"
        index = np.unravel_index(i, m.shape[:-2]) if m.ndim > 2 else ()
        raise ValueError(f"{where}: {int(bad.sum())} of {len(det)} matrices are not rotations; the first, at "
                         f"index {tuple(int(k) for k in index)}, is {kind}")
    return matrices


def _rotations_in(matrix, fn, check):
    """``matrix`` as an array of trailing shape (3, 3), checked as rotations (when concrete) if ``check``."""
    m = _checked(matrix, (3, 3), fn, "matrix")
    if check:
        check_rotations(m, where=f"{fn}: matrix", allow_nonfinite=True)
    return m


def _safe_sqrt(sq, small):
    """sqrt(sq) where ``small`` is False, 1 elsewhere, so its gradient is never inf (double-where trick)."""
    return jnp.sqrt(jnp.where(small, jnp.ones_like(sq), sq))


def _skew(v):
    """[..., 3] -> [..., 3, 3]: the cross-product matrix, skew(v) @ u = v x u."""
    x, y, z = v[..., 0], v[..., 1], v[..., 2]
    zero = jnp.zeros_like(x)
    rows = (
        jnp.stack([zero, -z, y], axis=-1),
        jnp.stack([z, zero, -x], axis=-1),
        jnp.stack([-y, x, zero], axis=-1),
    )
    return jnp.stack(rows, axis=-2)


def axis_angle_to_matrix(axis_angle):
    """[..., 3] -> [..., 3, 3]. Rodrigues: R = I + a K + b K^2 with K = skew(v) (v not normalised)."""
    v = _checked(axis_angle, (3,), "axis_angle_to_matrix", "axis_angle")
    sq = jnp.sum(v * v, axis=-1)
    small = sq < _SMALL_SQ
    theta = _safe_sqrt(sq, small)
    half = 0.5 * theta
    # a = sin(t)/t; b = (1 - cos t)/t^2 written as 2 sin^2(t/2)/t^2 to avoid cancellation in float32.
    a = jnp.where(small, 1.0 - sq / 6.0 + sq * sq / 120.0, jnp.sin(theta) / theta)
    b = jnp.where(small, 0.5 - sq / 24.0 + sq * sq / 720.0, 0.5 * jnp.square(jnp.sin(half) / half))
    k = _skew(v)
    eye = jnp.eye(3, dtype=k.dtype)
    return eye + a[..., None, None] * k + b[..., None, None] * (k @ k)


def axis_angle_to_quaternion(axis_angle):
    """[..., 3] -> [..., 4] (w, x, y, z); w = cos(t/2) >= 0 for angles t in [0, pi]."""
    v = _checked(axis_angle, (3,), "axis_angle_to_quaternion", "axis_angle")
    sq = jnp.sum(v * v, axis=-1)
    small = sq < _SMALL_SQ
    theta = _safe_sqrt(sq, small)
    w = jnp.where(small, 1.0 - sq / 8.0 + sq * sq / 384.0, jnp.cos(0.5 * theta))
    s = jnp.where(small, 0.5 - sq / 48.0 + sq * sq / 3840.0, jnp.sin(0.5 * theta) / theta)  # sin(t/2)/t
    return jnp.concatenate([w[..., None], s[..., None] * v], axis=-1)


def quaternion_to_matrix(quaternion):
    """[..., 4] (w, x, y, z), any non-zero norm -> [..., 3, 3]; s = 2/|q|^2 absorbs the norm."""
    q = _checked(quaternion, (4,), "quaternion_to_matrix", "quaternion")
    sq = jnp.sum(q * q, axis=-1)
    s = 2.0 / jnp.where(sq > 0, sq, jnp.ones_like(sq))  # zero quaternion -> identity, not NaN
    w, x, y, z = (q[..., i] for i in range(4))
    m = jnp.stack(
        [
            1 - s * (y * y + z * z), s * (x * y - z * w), s * (x * z + y * w),
            s * (x * y + z * w), 1 - s * (x * x + z * z), s * (y * z - x * w),
            s * (x * z - y * w), s * (y * z + x * w), 1 - s * (x * x + y * y),
        ],
        axis=-1,
    )
    return m.reshape(q.shape[:-1] + (3, 3))


def matrix_to_quaternion(matrix, *, check: bool = True):
    """[..., 3, 3] rotation -> [..., 4] unit quaternion (w, x, y, z) with w >= 0 (``check``: see the module).

    Row i of ``cand`` is 4 q_i q (diagonal entry d_i = 4 q_i^2). The row with the largest d_i is
    divided by 2 sqrt(d_i), which is >= 2 for a rotation (the d_i sum to 4), so values and gradients
    stay finite everywhere, 180 degrees included. Only the selected d_i is square-rooted: a sqrt of
    an unselected d_i = 0 would give an inf derivative and hence NaN gradients.
    """
    m = _rotations_in(matrix, "matrix_to_quaternion", check)
    m00, m01, m02 = m[..., 0, 0], m[..., 0, 1], m[..., 0, 2]
    m10, m11, m12 = m[..., 1, 0], m[..., 1, 1], m[..., 1, 2]
    m20, m21, m22 = m[..., 2, 0], m[..., 2, 1], m[..., 2, 2]
    d = jnp.stack(  # 4 w^2, 4 x^2, 4 y^2, 4 z^2
        [1 + m00 + m11 + m22, 1 + m00 - m11 - m22, 1 - m00 + m11 - m22, 1 - m00 - m11 + m22], axis=-1
    )
    cand = jnp.stack(
        [
            jnp.stack([d[..., 0], m21 - m12, m02 - m20, m10 - m01], axis=-1),
            jnp.stack([m21 - m12, d[..., 1], m10 + m01, m02 + m20], axis=-1),
            jnp.stack([m02 - m20, m10 + m01, d[..., 2], m12 + m21], axis=-1),
            jnp.stack([m10 - m01, m02 + m20, m12 + m21, d[..., 3]], axis=-1),
        ],
        axis=-2,
    )
    best = jnp.argmax(d, axis=-1)[..., None]
    row = jnp.take_along_axis(cand, best[..., None], axis=-2)[..., 0, :]
    d_best = jnp.take_along_axis(d, best, axis=-1)
    # The floor only matters for non-rotation input (max diagonal >= 1 for any rotation).
    q = row / (2.0 * jnp.sqrt(jnp.maximum(d_best, 1e-2)))
    return jnp.where(q[..., :1] < 0, -q, q)


def quaternion_to_axis_angle(quaternion):
    """[..., 4] (w, x, y, z), any non-zero norm -> [..., 3] rotation vector with angle in [0, pi].

    With q flipped to w >= 0: angle = 2 atan2(|v|, w) and the result is v * angle / |v|; for small
    t = |v| / w the factor is the series (2 / w)(1 - t^2/3 + t^4/5) of 2 atan(t) / |v|.
    """
    q = _checked(quaternion, (4,), "quaternion_to_axis_angle", "quaternion")
    q = jnp.where(q[..., :1] < 0, -q, q)  # q and -q are the same rotation; w >= 0 gives angle <= pi
    w, v = q[..., 0], q[..., 1:]
    sq = jnp.sum(v * v, axis=-1)
    small = sq <= _SMALL_SQ * w * w
    n = _safe_sqrt(sq, small)
    large_factor = 2.0 * jnp.arctan2(n, w) / n
    w_s = jnp.where(small & (w > 0), w, jnp.ones_like(w))  # 1 in the unused branch keeps 1/w finite
    t2 = sq / (w_s * w_s)
    small_factor = (2.0 / w_s) * (1.0 - t2 / 3.0 + t2 * t2 / 5.0)
    return jnp.where(small, small_factor, large_factor)[..., None] * v


def slerp(q0, q1, t):
    """Spherical linear interpolation of unit quaternions ``q0``, ``q1 [..., 4]`` at ``t [...]`` (0: ``q0``, 1:
    ``q1``) along the shorter arc (``q1`` flipped when the two lie more than 90 degrees apart); nearly equal
    rotations are interpolated linearly and renormalised (the arc's sine vanishes there)."""
    q0 = _checked(q0, (4,), "slerp", "q0")
    q1 = _checked(q1, (4,), "slerp", "q1")
    t = jnp.asarray(t, q0.dtype)[..., None]
    dot = jnp.sum(q0 * q1, axis=-1, keepdims=True)
    q1, dot = jnp.where(dot < 0, -q1, q1), jnp.abs(dot)
    near = dot > 0.9995
    angle = jnp.arccos(jnp.clip(jnp.where(near, 0.5, dot), -1.0, 1.0))
    arc = (jnp.sin((1 - t) * angle) * q0 + jnp.sin(t * angle) * q1) / jnp.sin(angle)
    line = (1 - t) * q0 + t * q1
    line = line / jnp.linalg.norm(line, axis=-1, keepdims=True)
    return jnp.where(near, line, arc)


def matrix_to_axis_angle(matrix, *, check: bool = True):
    """[..., 3, 3] rotation -> [..., 3] rotation vector with angle in [0, pi] (via the robust quaternion
    path; ``check``: see the module)."""
    m = _rotations_in(matrix, "matrix_to_axis_angle", check)
    return quaternion_to_axis_angle(matrix_to_quaternion(m, check=False))


def matrix_to_rot6d(matrix, *, check: bool = True):
    """[..., 3, 3] rotation -> [..., 6]: the first two rows, [R00, R01, R02, R10, R11, R12] (ACTOR;
    ``check``: see the module)."""
    m = _rotations_in(matrix, "matrix_to_rot6d", check)
    return m[..., :2, :].reshape(m.shape[:-2] + (6,))


def _normalize(x):
    """[..., 3] -> [..., 3] unit vector; the squared-norm floor keeps zero input finite."""
    return x / jnp.sqrt(jnp.maximum(jnp.sum(x * x, axis=-1, keepdims=True), _NORM_EPS_SQ))


def rot6d_to_matrix(rot6d):
    """[..., 6] (any, not necessarily orthogonal) -> [..., 3, 3] by Gram-Schmidt on the two rows."""
    x = _checked(rot6d, (6,), "rot6d_to_matrix", "rot6d")
    a1, a2 = x[..., :3], x[..., 3:]
    b1 = _normalize(a1)
    b2 = _normalize(a2 - jnp.sum(b1 * a2, axis=-1, keepdims=True) * b1)
    b3 = jnp.cross(b1, b2)
    return jnp.stack([b1, b2, b3], axis=-2)


_TO_MATRIX = {
    "axis_angle": axis_angle_to_matrix,
    "quaternion": quaternion_to_matrix,
    "matrix": functools.partial(_checked, shape=(3, 3), fn="to_matrix", arg="matrix"),  # identity
    "rot6d": rot6d_to_matrix,
}
_FROM_MATRIX = {
    "axis_angle": matrix_to_axis_angle,
    "quaternion": matrix_to_quaternion,
    "matrix": lambda m, check: _rotations_in(m, "from_matrix", check),  # identity
    "rot6d": matrix_to_rot6d,
}


def _converter(table, rep, fn):
    if rep not in table:
        raise ValueError(f"{fn}: unknown rep {rep!r}; valid names are {sorted(REPRESENTATIONS)}")
    return table[rep]


def to_matrix(x, rep):
    """[..., *REPRESENTATIONS[rep]] -> [..., 3, 3]."""
    return _converter(_TO_MATRIX, rep, "to_matrix")(x)


def from_matrix(m, rep, *, check: bool = True):
    """[..., 3, 3] rotation -> [..., *REPRESENTATIONS[rep]] (``check``: see the module)."""
    return _converter(_FROM_MATRIX, rep, "from_matrix")(m, check=check)


# --- Euler angles ----------------------------------------------------------------------------------------

#: The proper (Tait-Bryan) orders: each axis once. Proper Euler orders such as ZXZ do not occur in BVH.
EULER_ORDERS = ("XYZ", "XZY", "YXZ", "YZX", "ZXY", "ZYX")

# cos(middle angle) below this many float epsilons counts as gimbal lock: the first and third axes then
# coincide and only their combined angle is defined. Treating a matrix as locked costs an error of about
# cos(middle angle), so the threshold is kept near rounding level; just above it the first angle is noisy,
# but the third angle is fitted to it (below), so the matrix is still reproduced.
_LOCK_EPS = 4.0


def _euler_axes(order: str, fn: str) -> tuple[tuple[int, int, int], float]:
    """The axis indices (i, j, k) of ``order`` and its parity s: +1 for XYZ, YZX, ZXY, -1 for the others."""
    if order not in EULER_ORDERS:
        raise ValueError(f"{fn}: unknown order {order!r}; valid orders are {list(EULER_ORDERS)}")
    axes = tuple("XYZ".index(axis) for axis in order)
    return axes, (1.0 if (axes[1] - axes[0]) % 3 == 1 else -1.0)


# Every order reduces to XYZ by relabelling axes: with P = [e_i e_j e_k] (det P = s),
# R_i(a) R_j(b) R_k(c) = P R_x(s a) R_y(s b) R_z(s c) P^T, i.e. R[p_x, p_y] = R_xyz(s a, s b, s c)[x, y].
# Both directions are then closed forms on matrix entries: no 3x3 products, which keeps them cheap to
# compile and run.


def euler_to_matrix(angles, order: str):
    """[..., 3] radians, in the order of ``order`` -> [..., 3, 3] = R_first @ R_second @ R_third.

    ``order`` is one of ``EULER_ORDERS`` (static under jit); see the module docstring for the convention.
    """
    v = _checked(angles, (3,), "euler_to_matrix", "angles")
    axes, s = _euler_axes(order, "euler_to_matrix")
    (ca, cb, cc), (sa, sb, sc) = (jnp.cos(v[..., n]) for n in range(3)), (s * jnp.sin(v[..., n]) for n in range(3))
    xyz = (  # R_x(a) R_y(b) R_z(c), entry by entry (the sines carry the parity)
        (cb * cc, -cb * sc, sb),
        (sa * sb * cc + ca * sc, ca * cc - sa * sb * sc, -sa * cb),
        (sa * sc - ca * sb * cc, ca * sb * sc + sa * cc, ca * cb),
    )
    inverse = [axes.index(axis) for axis in range(3)]
    rows = [jnp.stack([xyz[inverse[r]][inverse[c]] for c in range(3)], axis=-1) for r in range(3)]
    return jnp.stack(rows, axis=-2)


def matrix_to_euler(matrix, order: str, *, check: bool = True):
    """[..., 3, 3] rotation -> [..., 3] radians (a, b, c) with ``euler_to_matrix((a, b, c), order) == matrix``.

    Ranges: a, c in [-pi, pi], the middle angle b in [-pi/2, pi/2]. At gimbal lock (b = +-pi/2, where only
    a combination of a and c is defined) c is 0 and the whole turn goes to a, so the matrix is still
    reproduced. ``order`` is one of ``EULER_ORDERS`` (static under jit); ``check``: see the module.

    In the XYZ labelling (A = the relabelled matrix, angles times the parity s): A[0, 2] = sin b,
    |(A[0, 0], A[0, 1])| = cos b, and column 2, R_x(a) R_y(b) e_z, gives a. The third angle is read from the
    residual ``(R_x(a) R_y(b))^T A = R_z(c)`` rather than from row 0, so the result reproduces the matrix
    even where row 0 is too small to fix c (near the lock).
    """
    axes, s = _euler_axes(order, "matrix_to_euler")
    m = _rotations_in(matrix, "matrix_to_euler", check)
    rel = [[m[..., axes[r], axes[c]] for c in range(3)] for r in range(3)]  # A: rel[r][c] = R[p_r, p_c]
    cos_b = jnp.hypot(rel[0][0], rel[0][1])
    b = jnp.arctan2(rel[0][2], cos_b)
    locked = cos_b < _LOCK_EPS * jnp.finfo(m.dtype).eps
    # Free: column 2 is (sin b, -sin a cos b, cos a cos b). Locked (c = 0): column 1 is (0, cos a, sin a).
    a = jnp.where(locked, jnp.arctan2(rel[2][1], rel[1][1]), jnp.arctan2(-rel[1][2], rel[2][2]))
    ca, sa, cb, sb = jnp.cos(a), jnp.sin(a), jnp.cos(b), jnp.sin(b)
    # Column 0 of the residual (R_x(a) R_y(b))^T A = R_z(c) is (cos c, sin c, 0).
    cos_c = cb * rel[0][0] + sa * sb * rel[1][0] - ca * sb * rel[2][0]
    sin_c = ca * rel[1][0] + sa * rel[2][0]
    c = jnp.where(locked, jnp.zeros_like(b), jnp.arctan2(sin_c, cos_c))
    return s * jnp.stack([a, b, c], axis=-1)
