"""Motion representations the generators read and write, shared by the papers that use them.

* **Rotations + translation row** (ACTOR; ActFormer's SMPL data, FACTS §1.3 and §2): each joint's rotation
  in a rotation representation (rot6d: 6 channels), then one extra "joint" holding the root translation
  zero-padded to the same channels, ``[..., T, J + 1, C]``. ACTOR keeps the translation relative to frame 0
  (``origin="first"``); ActFormer de-means it over the segment (``origin="mean"``).
* **Root + unit limb vectors** (ActFormer's NTU-25 and GTA-22 data, FACTS §1.3): joint 0 holds the root
  position minus the mean root over every frame and person of the clip, every other joint the unit vector
  from its parent, ``(x_c - x_p) / (|x_c - x_p| + 1e-4)``. Joints are rebuilt from the root by
  ``x_c = x_p + u_c * length_c`` with one length per bone: the dataset's average bone lengths
  (:func:`mean_bone_lengths`, ActFormer's ``avglength``), so the rebuilt body has average proportions.
* **The 135-number pose** (Neural Marionette, MARIONETTE.md §1.2): the 22 body joints of SMPL-H (SMPL-24 without
  its two hand joints) as rot6d, joint after joint, then the root translation: ``[..., T, 22 * 6 + 3]``
  (:func:`pose135`). Back to the library's record the hands get the identity rotation (:func:`from_pose135`).

Axes: ``...`` leading axes (batch), P persons, T frames, J joints, C channels.
"""

from __future__ import annotations

from typing import Literal

import jax
import jax.numpy as jnp
import numpy as np

from jaxmotion.geometry.rotations import REPRESENTATIONS, axis_angle_to_matrix, from_matrix, matrix_to_axis_angle, to_matrix
from jaxmotion.geometry.skeletons import topological_order

Origin = Literal["first", "mean"]
#: ActFormer's guard against zero-length limbs in the unit vectors (AF:datasets/ntu120/prepare_ntu_data.py).
LIMB_EPS = 1e-4


def _check(name: str, array: jax.Array, trailing: tuple[int | None, ...], min_ndim: int, expected: str) -> None:
    shape = jnp.shape(array)
    if len(shape) < min_ndim or any(t is not None and s != t for s, t in zip(shape[len(shape) - len(trailing):],
                                                                             trailing)):
        raise ValueError(f"{name}: expected shape {expected}, got {tuple(shape)}")


def _origin(translation: jax.Array, origin: Origin) -> jax.Array:
    if origin == "first":
        return translation[..., :1, :]
    if origin == "mean":
        return jnp.mean(translation, axis=-2, keepdims=True)
    raise ValueError(f"origin: expected 'first' or 'mean', got {origin!r}")


def rotation_features(rotations: jax.Array, translation: jax.Array, rep: str = "rot6d",
                      origin: Origin = "first") -> jax.Array:
    """``rotations [..., T, J, 3]`` axis-angle (joint 0 global), ``translation [..., T, 3]`` ->
    ``[..., T, J + 1, C]``: the rotations in ``rep`` (C = 6 rot6d, 4, 3 or 9 matrix), then the translation
    relative to ``origin`` (frame 0, or the mean over the frames), zero-padded to C."""
    _check("rotations", rotations, (None, 3), 3, "[..., T, J, 3]")
    _check("translation", translation, (3,), 2, "[..., T, 3]")
    if jnp.shape(translation) != jnp.shape(rotations)[:-2] + (3,):
        raise ValueError(f"translation: expected shape {tuple(jnp.shape(rotations)[:-2]) + (3,)} (the rotations' "
                         f"[..., T] and 3), got {tuple(jnp.shape(translation))}")
    feats = from_matrix(axis_angle_to_matrix(rotations), rep)
    feats = feats.reshape(*rotations.shape[:-1], -1)  # [..., T, J, C]
    relative = translation - _origin(translation, origin)
    row = jnp.pad(relative, [(0, 0)] * (relative.ndim - 1) + [(0, feats.shape[-1] - 3)])[..., None, :]
    return jnp.concatenate([feats, row], axis=-2)


def split_rotation_features(features: jax.Array, rep: str = "rot6d") -> tuple[jax.Array, jax.Array]:
    """Inverse of :func:`rotation_features`: ``[..., T, J + 1, C]`` -> ``(rotations [..., T, J, 3],
    translation [..., T, 3])``, the translation relative to the origin the features were made with. Features
    are what a network produced, not checked as rotations: ``matrix`` rows are projected onto a rotation."""
    channels = int(np.prod(REPRESENTATIONS[rep])) if rep in REPRESENTATIONS else None
    _check("features", features, (channels,), 3, f"[..., T, J + 1, {channels}] for {rep!r}")
    rots = features[..., :-1, :].reshape(*features.shape[:-2], features.shape[-2] - 1, *REPRESENTATIONS[rep])
    return matrix_to_axis_angle(to_matrix(rots, rep), check=False), features[..., -1, :3]


#: The body joints of the 135-number pose: SMPL-24's first 22 (its hand joints, 22 and 23, dropped).
POSE135_JOINTS = 22
POSE135_SIZE = POSE135_JOINTS * 6 + 3


def pose135(rotations: jax.Array, translation: jax.Array) -> jax.Array:
    """``rotations [..., T, 24, 3]`` SMPL-24 axis-angle, ``translation [..., T, 3]`` -> ``[..., T, 135]``: rot6d of
    joints 0-21 (the first two rows of each matrix, as everywhere in the library), then the translation as it is
    (absolute in whatever frame it is given: Marionette's normalised frame, see
    :func:`~jaxmotion.geometry.kinematics.heading_transform`)."""
    _check("rotations", rotations, (24, 3), 3, "[..., T, 24, 3] (SMPL-24)")
    _check("translation", translation, (3,), 2, "[..., T, 3]")
    if jnp.shape(translation) != jnp.shape(rotations)[:-2] + (3,):
        raise ValueError(f"translation: expected shape {tuple(jnp.shape(rotations)[:-2]) + (3,)} (the rotations' "
                         f"[..., T] and 3), got {tuple(jnp.shape(translation))}")
    body = from_matrix(axis_angle_to_matrix(rotations[..., :POSE135_JOINTS, :]), "rot6d")  # [..., T, 22, 6]
    return jnp.concatenate([body.reshape(*body.shape[:-2], POSE135_JOINTS * 6), translation], axis=-1)


def pose135_rotmats(pose: jax.Array) -> jax.Array:
    """``[..., T, 135]`` (any 6D, e.g. a network's, orthonormalised) -> SMPL-24 local rotation matrices
    ``[..., T, 24, 3, 3]``, the hands at rest (identity)."""
    _check("pose", pose, (POSE135_SIZE,), 2, f"[..., T, {POSE135_SIZE}]")
    body = to_matrix(pose[..., :POSE135_JOINTS * 6].reshape(*pose.shape[:-1], POSE135_JOINTS, 6), "rot6d")
    hands = jnp.broadcast_to(jnp.eye(3, dtype=body.dtype), (*pose.shape[:-1], 24 - POSE135_JOINTS, 3, 3))
    return jnp.concatenate([body, hands], axis=-3)


def from_pose135(pose: jax.Array) -> tuple[jax.Array, jax.Array]:
    """Inverse of :func:`pose135`: ``[..., T, 135]`` -> ``(rotations [..., T, 24, 3]`` axis-angle with the hands at
    rest (:func:`pose135_rotmats`), ``translation [..., T, 3])``."""
    return matrix_to_axis_angle(pose135_rotmats(pose), check=False), pose[..., POSE135_JOINTS * 6:]


def limb_vectors(joints: jax.Array, parents: tuple[int, ...]) -> jax.Array:
    """``joints [..., J, 3]`` -> ``[..., J, 3]``: the root position, then each joint's unit vector from its
    parent (ActFormer's divisor ``|d| + 1e-4``)."""
    _check("joints", joints, (len(parents), 3), 2, f"[..., {len(parents)}, 3]")
    topological_order(parents)  # validates the tree
    parent = np.array([max(p, 0) for p in parents])
    delta = joints - joints[..., parent, :]
    units = delta / (jnp.linalg.norm(delta, axis=-1, keepdims=True) + LIMB_EPS)
    return units.at[..., 0, :].set(joints[..., 0, :])


def joints_from_limb_vectors(vectors: jax.Array, parents: tuple[int, ...], lengths: jax.Array) -> jax.Array:
    """Inverse of :func:`limb_vectors` given the bone lengths: ``vectors [..., J, 3]``, ``lengths [J]`` (one per
    child joint, the root's ignored) -> joints ``[..., J, 3]``, walking the tree from the root."""
    _check("vectors", vectors, (len(parents), 3), 2, f"[..., {len(parents)}, 3]")
    lengths = jnp.asarray(lengths, vectors.dtype)
    if lengths.shape != (len(parents),):
        raise ValueError(f"lengths: expected shape [J] = ({len(parents)},), got {tuple(lengths.shape)}")
    joints = [None] * len(parents)
    order = topological_order(parents)
    joints[0] = vectors[..., 0, :]
    for j in order[1:]:
        joints[j] = joints[parents[j]] + vectors[..., j, :] * lengths[j]
    return jnp.stack(joints, axis=-2)


def mean_bone_lengths(joints: jax.Array, parents: tuple[int, ...]) -> jax.Array:
    """``joints [..., J, 3]`` (any frames of a dataset) -> ``[J]`` the mean length of each joint's bone to its
    parent, 0 for the root: what :func:`joints_from_limb_vectors` rebuilds with."""
    _check("joints", joints, (len(parents), 3), 2, f"[..., {len(parents)}, 3]")
    parent = np.array([max(p, 0) for p in parents])
    lengths = jnp.linalg.norm(joints - joints[..., parent, :], axis=-1)
    return jnp.mean(lengths.reshape(-1, len(parents)), axis=0)


def skeleton_features(joints: jax.Array, parents: tuple[int, ...]) -> jax.Array:
    """ActFormer's skeleton representation of clips of persons: ``joints [..., P, T, J, 3]`` ->
    ``[..., P, T, J, 3]``, the roots minus their mean over every frame and person of the clip, then unit limb
    vectors (:func:`limb_vectors`)."""
    _check("joints", joints, (None, None, len(parents), 3), 4, f"[..., P, T, {len(parents)}, 3]")
    centre = jnp.mean(joints[..., 0, :], axis=(-3, -2), keepdims=True)[..., None, :]  # [..., 1, 1, 1, 3]
    return limb_vectors(joints - centre, parents)


def actformer_features(kind: str, parents: tuple[int, ...], joints: jax.Array, translation: jax.Array | None = None,
                       rotations: jax.Array | None = None) -> jax.Array:
    """ActFormer's representation of windows of one person ``[B, T, J, 3]`` or several ``[B, P, T, J, 3]`` (what
    its generator writes and its recognisers read): ``limbs`` (:func:`skeleton_features`) ``[B, (P,) T, J, 3]``,
    or ``rot6d+translation`` (:func:`rotation_features`, the translation de-meaned over the window as node J)
    ``[B, (P,) T, J + 1, 6]`` from axis-angle ``rotations`` and ``translation [B, (P,) T, 3]``."""
    if kind == "limbs":
        single = joints.ndim == 4
        features = skeleton_features(joints[:, None] if single else joints, parents)
        return features[:, 0] if single else features
    if kind == "rot6d+translation":
        if rotations is None or translation is None:
            raise ValueError("rotations, translation: rot6d+translation needs both (axis-angle [B, T, J, 3] and "
                             "[B, T, 3]); the motions have joint positions only")
        return rotation_features(rotations, translation, "rot6d", origin="mean")
    raise ValueError(f"kind: expected 'limbs' or 'rot6d+translation', got {kind!r}")
