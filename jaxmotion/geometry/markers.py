"""Other skeletons' joints placed on an SMPL-24 body: NTU-25 (Kinect v2) and GTA-22.

One motion engine drives SMPL-24 bodies; a dataset on another skeleton reads its joints off the posed body
through a marker set. Each target joint is a marker rigidly attached to one SMPL joint: its position is
``p_src + G_src @ (s * offset)``, with ``G_src`` the source joint's global rotation, ``offset`` a rest vector
in that joint's frame (template body, metres; zero puts the marker on the joint itself) and ``s`` the body's
size relative to the template (:func:`body_scale`), so markers move with the bones they sit on.

The placement rules (where the target skeleton has a joint SMPL lacks, or puts one elsewhere) are the
``_RULES`` of each set below, one line each with its reason; both sets are checked against their trees in
``tests/test_markers.py`` (every target bone joins neighbouring body parts, lengths near the real sets').

Axes: ``...`` any leading axes (bodies, frames), J SMPL joints (24), K markers.
"""

from __future__ import annotations

import dataclasses
import functools

import jax
import jax.numpy as jnp
import numpy as np

from jaxmotion.geometry.kinematics import forward_kinematics_transforms
from jaxmotion.geometry.rotations import axis_angle_to_matrix
from jaxmotion.geometry.skeletons import GTA22, NTU25, SMPL24, Skeleton

_HIGHEST = jax.lax.Precision.HIGHEST


@dataclasses.dataclass(frozen=True, eq=False)
class MarkerSet:
    """A target skeleton's joints as markers on SMPL-24.

    Attributes:
      skeleton: the target layout (its joint order is the markers' order).
      sources: per target joint, the SMPL-24 joint it is attached to.
      offsets: ``[K, 3]`` float32 rest vectors in the source joints' frames, template body (metres).
    """

    skeleton: Skeleton
    sources: tuple[int, ...]
    offsets: np.ndarray

    def __post_init__(self):
        k = self.skeleton.num_joints
        if len(self.sources) != k or not all(0 <= s < SMPL24.num_joints for s in self.sources):
            raise ValueError(f"sources: expected {k} SMPL-24 joint indices, got {self.sources}")
        offsets = np.array(self.offsets, np.float32)
        if offsets.shape != (k, 3):
            raise ValueError(f"offsets: expected shape ({k}, 3), got {offsets.shape}")
        offsets.flags.writeable = False
        object.__setattr__(self, "offsets", offsets)


def _marker_set(skeleton: Skeleton, rules: dict[str, tuple[str, tuple[float, float, float]]]) -> MarkerSet:
    missing = set(skeleton.joint_names) - set(rules)
    if missing:
        raise ValueError(f"{skeleton.name}: no placement rule for {sorted(missing)}")
    return MarkerSet(skeleton, tuple(SMPL24.index(rules[n][0]) for n in skeleton.joint_names),
                     np.array([rules[n][1] for n in skeleton.joint_names], np.float32))


_ON = (0.0, 0.0, 0.0)
_TEMPLATE = SMPL24.offsets
_HAND = {side: tuple(float(v) for v in _TEMPLATE[SMPL24.index(f"{side}_hand")]) for side in ("left", "right")}
_COLLARS_MID = tuple(float(v) for v in (_TEMPLATE[SMPL24.index("left_collar")]
                                         + _TEMPLATE[SMPL24.index("right_collar")]) / 2)
_HEAD_CENTRE = (0.0, 0.05, 0.02)  # SMPL's head joint sits at the skull base; Kinect's and GTA's head joint is mid-head


def _scaled(v, factor):
    return tuple(factor * x for x in v)


def _plus(a, b):
    return tuple(x + y for x, y in zip(a, b))


def _thumb(side: str):
    # Rest pose: the hand points along +-X, palm down, thumb forward (+Z); Kinect's thumb joint is ~4 cm
    # from its hand joint.
    return _plus(_HAND[side], (0.01 if side == "left" else -0.01, -0.01, 0.035))


_NTU25_RULES = {
    "spine_base": ("pelvis", _ON),
    "spine_mid": ("spine2", _ON),  # mid-back
    "neck": ("neck", _ON),
    "head": ("head", _HEAD_CENTRE),
    "spine_shoulder": ("spine3", (0.0, 0.145, -0.038)),  # neck base: NTU's is 6.9 cm below its neck joint
    **{f"{side}_{part}": (f"{side}_{smpl}", _ON) for side in ("left", "right")
       for part, smpl in (("shoulder", "shoulder"), ("elbow", "elbow"), ("wrist", "wrist"), ("hand", "hand"),
                          ("hip", "hip"), ("knee", "knee"), ("ankle", "ankle"), ("foot", "foot"))},
    # fingertips ~6 cm past Kinect's hand joint (NTU's average hand-tip bone is 5.6 cm)
    **{f"{side}_hand_tip": (f"{side}_wrist", _scaled(_HAND[side], 1.65)) for side in ("left", "right")},
    **{f"{side}_thumb": (f"{side}_wrist", _thumb(side)) for side in ("left", "right")},
}

_GTA22_RULES = {
    "pelvis": ("pelvis", _ON),
    "spine3": ("spine1", _ON),  # GTA's spine runs spine3 (lowest) .. spine0 (highest) from the pelvis up
    "spine2": ("spine2", _ON),
    "spine1": ("spine3", _ON),
    "spine0": ("spine3", _COLLARS_MID),  # upper chest, between the clavicles
    "neck": ("neck", _ON),
    "head_center": ("head", _HEAD_CENTRE),
    "head_top": ("head", (0.0, 0.17, 0.01)),  # the crown, ~17 cm above SMPL's head joint on a 1.70 m body
    **{f"{side}_{part}": (f"{side}_{smpl}", _ON) for side in ("left", "right")
       for part, smpl in (("clavicle", "collar"), ("shoulder", "shoulder"), ("elbow", "elbow"),
                          ("wrist", "wrist"), ("hip", "hip"), ("knee", "knee"), ("ankle", "ankle"))},
}

NTU25_ON_SMPL24 = _marker_set(NTU25, _NTU25_RULES)
GTA22_ON_SMPL24 = _marker_set(GTA22, _GTA22_RULES)
MARKER_SETS = {s.skeleton.name: s for s in (NTU25_ON_SMPL24, GTA22_ON_SMPL24)}


def body_scale(offsets: jax.Array) -> jax.Array:
    """``[..., 24, 3]`` a body's rest offsets -> ``[...]`` its size relative to the template: the ratio of
    the summed bone lengths."""
    lengths = jnp.linalg.norm(jnp.asarray(offsets)[..., 1:, :], axis=-1).sum(-1)
    return lengths / float(np.linalg.norm(_TEMPLATE[1:], axis=-1).sum())


def place_markers(markers: MarkerSet, global_rotmats: jax.Array, joints: jax.Array, scale: jax.Array) -> jax.Array:
    """Markers on posed bodies: ``global_rotmats [..., 24, 3, 3]``, ``joints [..., 24, 3]`` (FK's outputs),
    ``scale`` (broadcastable to ``[...]``) -> ``[..., K, 3]``."""
    sources = np.asarray(markers.sources)
    offsets = jnp.asarray(scale)[..., None, None] * jnp.asarray(markers.offsets)  # [..., K, 3]
    return joints[..., sources, :] + jnp.einsum("...kij,...kj->...ki", global_rotmats[..., sources, :, :], offsets,
                                                precision=_HIGHEST)


@functools.partial(jax.jit, static_argnames="markers")
def markers_from_rotations(markers: MarkerSet, rotations: jax.Array, translation: jax.Array,
                           offsets: jax.Array) -> jax.Array:
    """A target skeleton's joints from an SMPL-24 motion: ``rotations [..., T, 24, 3]`` axis-angle (joint 0
    global), ``translation [..., T, 3]``, the body's rest ``offsets [24, 3]`` (or ``[..., 24, 3]`` per
    body, ``...`` the leading axes) -> ``[..., T, K, 3]``."""
    global_rot, joints = forward_kinematics_transforms(axis_angle_to_matrix(rotations), translation, offsets,
                                                      SMPL24.parents)
    bodies = jnp.shape(offsets)[:-2]  # a prefix of the poses' leading axes (forward kinematics checks it)
    scale = body_scale(offsets).reshape(bodies + (1,) * (rotations.ndim - 2 - len(bodies)))
    return place_markers(markers, global_rot, joints, scale)
