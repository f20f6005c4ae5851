"""Anatomical joint angles on the SMPL-24 tree, their joint limits, and conversion to local rotations.

A pose is ``angles [..., J, 3]`` in degrees: three named channels per joint (``CHANNELS``), e.g.
``left_knee.flex`` or ``right_shoulder.elev``. Channels are defined for the LEFT side; a right joint
uses the same names and meanings (flexion is flexion, abduction moves the limb away from the midline)
and its rotation is the mirror image (x -> -x) of the left one, so the sign conventions of
MOTION_FACTS section 2 hold on both sides by construction:

* pelvis (global): ``heading`` (+ turns to the subject's left, about +Y), ``tilt`` (+ leans forward),
  ``obliquity`` (+ raises the left hip); rotation ``Ry(heading) Rx(tilt) Rz(obliquity)``.
* hips: ``flex`` (-X), ``abd`` (+Z on the left), ``rot`` internal rotation (-Y on the left).
* knees: ``flex`` (+X). Ankles: ``dorsi`` (-X), ``inv`` inversion, ``out`` toe-out.
* spine1-3, neck, head: ``flex`` (+X, forward), ``bend`` (+ toward the left), ``twist`` (+ toward the left).
* collars: ``elev`` (shrug / upward rotation, +Z on the left), ``protr`` (protraction).
* shoulders: the humerus relative to the THORAX (not the collar) in the ISB style: ``plane`` of elevation
  (0 = sideways, 90 = forward, negative = behind, above 90 = across the body), ``elev`` (0 = hanging,
  90 = horizontal, 180 = overhead) and ``rot`` (internal rotation). Rotation ``Ry(-plane) Rz(elev)
  Ry(plane - rot) B`` with ``B = Rz(-90)`` taking the T-pose arm down; the stored local rotation is
  relative to the collar, so collar motion never moves the arm's direction, only the shoulder joint.
* elbows: ``flex`` (-Y on the left in T-pose), ``pron`` forearm pronation. Wrists: ``flex``, ``dev``.
* feet (toe joints) and hands are leaves: their rotation moves no joint, so they stay at zero.
"""

from __future__ import annotations

import jax
import jax.numpy as jnp
import numpy as np

from jaxmotion.geometry.skeletons import SMPL24

_AXIS = {"x": 0, "y": 1, "z": 2}


def _spec(channels, axes, euler_from_channels, limits, base_deg_z=0.0):
    return {"channels": channels, "axes": axes, "matrix": np.asarray(euler_from_channels, float),
            "limits": limits, "base_deg_z": base_deg_z}


def _diag(*signs):
    return np.diag(signs).astype(float)


_INF = np.inf
# Per joint (left-side conventions): channel names, Euler axes (R = R_a0 R_a1 R_a2), the linear map
# channels -> Euler angles, and active range-of-motion limits in degrees (MOTION_FACTS section 2; spine
# and neck totals split over their SMPL joints).
_LEFT_SPECS = {
    "pelvis": _spec(("heading", "tilt", "obliquity"), "yxz", _diag(1, 1, 1),
                    ((-_INF, _INF), (-60, 85), (-30, 30))),
    "hip": _spec(("flex", "abd", "rot"), "xzy", _diag(-1, 1, -1), ((-30, 125), (-30, 45), (-45, 45))),
    "knee": _spec(("flex", "var", "rot"), "xzy", _diag(1, 0, 0), ((-5, 150), (0, 0), (0, 0))),
    "ankle": _spec(("dorsi", "inv", "out"), "xzy", _diag(-1, -1, 1), ((-50, 20), (-25, 35), (-30, 30))),
    "foot": _spec(("flex", "abd", "rot"), "xzy", _diag(0, 0, 0), ((0, 0), (0, 0), (0, 0))),
    "spine1": _spec(("flex", "bend", "twist"), "xzy", _diag(1, -1, 1), ((-20, 45), (-15, 15), (-10, 10))),
    "spine2": _spec(("flex", "bend", "twist"), "xzy", _diag(1, -1, 1), ((-15, 25), (-10, 10), (-20, 20))),
    "spine3": _spec(("flex", "bend", "twist"), "xzy", _diag(1, -1, 1), ((-10, 15), (-8, 8), (-20, 20))),
    "neck": _spec(("flex", "bend", "twist"), "xzy", _diag(1, -1, 1), ((-40, 35), (-25, 25), (-45, 45))),
    "head": _spec(("flex", "bend", "twist"), "xzy", _diag(1, -1, 1), ((-35, 30), (-20, 20), (-40, 40))),
    "collar": _spec(("elev", "protr", "none"), "zyx", _diag(1, -1, 0), ((-10, 40), (-20, 25), (0, 0))),
    "shoulder": _spec(("plane", "elev", "rot"), "yzy", [[-1, 0, 0], [0, 1, 0], [1, 0, -1]],
                      ((-100, 140), (0, 178), (-90, 75)), base_deg_z=-90.0),
    "elbow": _spec(("flex", "pron", "none"), "yxz", _diag(-1, 1, 0), ((0, 150), (-80, 80), (0, 0))),
    "wrist": _spec(("flex", "dev", "none"), "zyx", _diag(-1, 1, 0), ((-70, 80), (-30, 20), (0, 0))),
    "hand": _spec(("flex", "dev", "none"), "zyx", _diag(0, 0, 0), ((0, 0), (0, 0), (0, 0))),
}


def _joint_spec(name):
    return _LEFT_SPECS[name.removeprefix("left_").removeprefix("right_")]


JOINTS = SMPL24.joint_names
NUM_JOINTS = len(JOINTS)
#: ``CHANNELS[j]`` = the three channel names of joint j.
CHANNELS = tuple(_joint_spec(n)["channels"] for n in JOINTS)
#: ``[J, 3, 2]`` lower and upper limit of every channel, degrees.
LIMITS = np.array([_joint_spec(n)["limits"] for n in JOINTS], dtype=float)
LIMITS.flags.writeable = False

_MIRRORED = np.array([n.startswith("right_") for n in JOINTS])
# Mirroring x -> -x maps a rotation R to M R M, M = diag(-1, 1, 1): entry (a, b) changes sign iff
# exactly one of a, b is the x axis.
_MIRROR_SIGNS = np.where(_MIRRORED[:, None, None], np.array([[1, -1, -1], [-1, 1, 1], [-1, 1, 1]]), 1.0)
_EULER_AXES = np.array([[_AXIS[a] for a in _joint_spec(n)["axes"]] for n in JOINTS])  # [J, 3]
_EULER_FROM_CHANNELS = np.stack([_joint_spec(n)["matrix"] for n in JOINTS])  # [J, 3, 3]
_CHANNELS_FROM_EULER = np.linalg.pinv(_EULER_FROM_CHANNELS)
_SHOULDERS = np.array([SMPL24.index("left_shoulder"), SMPL24.index("right_shoulder")])
_COLLARS = np.array([SMPL24.index("left_collar"), SMPL24.index("right_collar")])


def _axis_rotations(axes: np.ndarray, radians: np.ndarray) -> np.ndarray:
    """Rotations about coordinate axes: ``axes [J]`` ints, ``radians [..., J]`` -> ``[..., J, 3, 3]``."""
    c, s = np.cos(radians), np.sin(radians)
    out = np.zeros(radians.shape + (3, 3))
    i, j = (axes + 1) % 3, (axes + 2) % 3  # the rotated plane, ordered so that i -> j is positive
    k = np.arange(len(axes))
    out[..., k, axes, axes] = 1.0
    out[..., k, i, i] = c
    out[..., k, j, j] = c
    out[..., k, j, i] = s
    out[..., k, i, j] = -s
    return out


def _base_rotations() -> np.ndarray:
    zs = np.radians([_joint_spec(n)["base_deg_z"] for n in JOINTS])
    return _axis_rotations(np.full(NUM_JOINTS, 2), zs) * _MIRROR_SIGNS  # [J, 3, 3]


_BASE = _base_rotations()


def angles_to_rotmats(angles: np.ndarray) -> np.ndarray:
    """Anatomical angles ``[..., J, 3]`` (degrees) -> local rotation matrices ``[..., J, 3, 3]`` (float64)."""
    euler = np.radians(np.einsum("jab,...jb->...ja", _EULER_FROM_CHANNELS, angles))
    r = _axis_rotations(_EULER_AXES[:, 0], euler[..., 0])
    r = r @ _axis_rotations(_EULER_AXES[:, 1], euler[..., 1])
    r = r @ _axis_rotations(_EULER_AXES[:, 2], euler[..., 2])
    r = r * _MIRROR_SIGNS @ _BASE
    # Shoulder channels describe the humerus relative to the thorax: take the collar's share out.
    collars = r[..., _COLLARS, :, :]
    r[..., _SHOULDERS, :, :] = np.swapaxes(collars, -1, -2) @ r[..., _SHOULDERS, :, :]
    return r


# Rotations as nested 3x3 lists whose entries are python floats (known constants) or [F] arrays: the
# structural zeros and ones of the Euler factors then cost nothing, and XLA sees only elementwise
# multiply-adds (about twice as fast on CPU as batched 3x3 products; jaxlib 0.10.2's YNNPACK fusion also
# miscompiles the broadcast-multiply-reduce form of those).


def _times(x, y):
    """Product of two matrix entries; None where it is structurally zero."""
    if isinstance(x, float) and x == 0.0 or isinstance(y, float) and y == 0.0:
        return None
    if isinstance(x, float) and x == 1.0:
        return y
    return x if isinstance(y, float) and y == 1.0 else x * y


def _product(a: list, b: list) -> list:
    """``a @ b`` of nested-list matrices."""
    out = []
    for i in range(3):
        row = []
        for k in range(3):
            terms = [t for t in (_times(a[i][m], b[m][k]) for m in range(3)) if t is not None]
            row.append(sum(terms[1:], terms[0]) if terms else 0.0)
        out.append(row)
    return out


def _constant(matrix: np.ndarray) -> list:
    return [[float(round(v, 12)) for v in row] for row in matrix]  # cos(90 deg) is a structural zero


def _axis_rotation(axis: int, c, s) -> list:
    """Rotation about coordinate axis ``axis`` (0, 1, 2 = x, y, z) with cosine ``c`` and sine ``s``."""
    m = _constant(np.eye(3))
    i, j = (axis + 1) % 3, (axis + 2) % 3
    m[i][i], m[j][j], m[j][i], m[i][j] = c, c, s, -s
    return m


@jax.jit
def angles_to_rotmats_f32(angles):
    """:func:`angles_to_rotmats` in float32 jax, for the generator's hot path: ``[F, J, 3]`` degrees ->
    ``[F, J, 3, 3]``. ``angles_to_rotmats`` (float64 numpy) stays the exact partner of
    :func:`rotmats_to_angles`; a test keeps the two equal."""
    rad = angles * np.float32(np.pi / 180.0)
    mats = []
    for j in range(NUM_JOINTS):
        r = _constant(np.eye(3))
        for n in range(3):  # R = R_a0 R_a1 R_a2, each Euler angle a fixed combination of the channels
            weights = _EULER_FROM_CHANNELS[j, n]
            terms = [float(w) * rad[:, j, c] for c, w in enumerate(weights) if w != 0.0]
            if terms:
                euler = sum(terms[1:], terms[0])
                r = _product(r, _axis_rotation(int(_EULER_AXES[j, n]), jnp.cos(euler), jnp.sin(euler)))
        signs = _MIRROR_SIGNS[j]
        r = [[r[i][k] if signs[i, k] > 0 else -r[i][k] for k in range(3)] for i in range(3)]
        mats.append(_product(r, _constant(_BASE[j])))
    for shoulder, collar in zip(_SHOULDERS, _COLLARS):  # humerus relative to the collar
        mats[shoulder] = _product([list(col) for col in zip(*mats[collar])], mats[shoulder])
    entries = [jnp.full(rad.shape[:1], v, rad.dtype) if isinstance(v, float) else v
               for m in mats for row in m for v in row]
    return jnp.stack(entries, axis=-1).reshape(rad.shape[:1] + (NUM_JOINTS, 3, 3))


def _euler_from_matrix(axes: tuple[int, int, int], m: np.ndarray) -> np.ndarray:
    """Angles (radians) ``[..., 3]`` with ``m = R_a0 R_a1 R_a2``; Tait-Bryan or proper (a0 == a2) Euler."""
    i, j, k = axes
    if i == k:  # proper Euler: k is the remaining axis
        k = 3 - i - j
        s = 1.0 if (j - i) % 3 == 1 else -1.0  # parity of (i, j, k)
        beta = np.arccos(np.clip(m[..., i, i], -1.0, 1.0))
        # At beta = 0 the first and last angles share one axis: report it all in the last.
        degenerate = np.sin(beta) < 1e-7
        a, b = (i + 1) % 3, (i + 2) % 3
        alpha = np.where(degenerate, 0.0, np.arctan2(m[..., j, i], -s * m[..., k, i]))
        gamma = np.where(degenerate, np.arctan2(m[..., b, a], m[..., a, a]),
                         np.arctan2(m[..., i, j], s * m[..., i, k]))
        return np.stack([alpha, beta, gamma], axis=-1)
    s = 1.0 if (j - i) % 3 == 1 else -1.0
    beta = np.arcsin(np.clip(s * m[..., i, k], -1.0, 1.0))
    alpha = np.arctan2(-s * m[..., j, k], m[..., k, k])
    gamma = np.arctan2(-s * m[..., i, j], m[..., i, i])
    return np.stack([alpha, beta, gamma], axis=-1)


def rotmats_to_angles(rotmats: np.ndarray) -> np.ndarray:
    """Inverse of :func:`angles_to_rotmats`: ``[..., J, 3, 3]`` -> angles ``[..., J, 3]`` in (-180, 180]."""
    r = np.array(rotmats, dtype=float)
    r[..., _SHOULDERS, :, :] = r[..., _COLLARS, :, :] @ r[..., _SHOULDERS, :, :]
    r = (r @ np.swapaxes(_BASE, -1, -2)) * _MIRROR_SIGNS
    euler = np.empty(r.shape[:-1])
    for axes in {tuple(a) for a in _EULER_AXES.tolist()}:
        joints = np.flatnonzero((_EULER_AXES == axes).all(axis=1))
        euler[..., joints, :] = _euler_from_matrix(axes, r[..., joints, :, :])
    angles = np.degrees(np.einsum("jab,...jb->...ja", _CHANNELS_FROM_EULER, euler))
    return 180.0 - np.mod(180.0 - angles, 360.0)


def clip_to_limits(angles: np.ndarray) -> np.ndarray:
    """Angles ``[..., J, 3]`` clipped channel by channel into ``LIMITS``."""
    return np.clip(angles, LIMITS[:, :, 0], LIMITS[:, :, 1])


def channel(name: str) -> tuple[int, int]:
    """``"left_knee.flex"`` -> (joint index, channel index)."""
    joint, _, chan = name.partition(".")
    j = SMPL24.index(joint)
    if chan not in CHANNELS[j]:
        raise ValueError(f"channel: {joint} has channels {CHANNELS[j]}, not {chan!r}")
    return j, CHANNELS[j].index(chan)
