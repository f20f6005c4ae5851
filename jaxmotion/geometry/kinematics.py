"""Forward kinematics, skeleton measurements, canonicalisation and dataset frame conversion.

Conventions (library frame: metres, +Y up, the subject faces +Z at rest, +X is the subject's left):
  * rotations act on column vectors (v' = R v); local rotations are relative to the parent joint;
  * global rotation ``G_j = G_parent(j) @ local_j``; position ``p_j = p_parent(j) + G_parent(j) @ offset_j``,
    where ``offset_j`` is the rest vector from the parent to joint j in the parent's rest frame;
  * the root (joint 0) sits at ``root_translation``: its offset row is ignored.

``parents`` is always a static tuple (see :mod:`jaxmotion.geometry.skeletons`); it need not be
topologically ordered.
"""

from __future__ import annotations

import functools
import math

import jax
import jax.numpy as jnp
import numpy as np

from jaxmotion.geometry.rotations import axis_angle_to_matrix, check_rotations, matrix_to_axis_angle
from jaxmotion.geometry.skeletons import bones, topological_order

# 3x3 products are far from compute-bound, and the default precision on GPU/TPU (TF32/bf16) would put
# millimetre errors on the end effectors after a nine-bone chain.
_matmul = functools.partial(jnp.matmul, precision=jax.lax.Precision.HIGHEST)


def _shape_error(name: str, expected: str, received: tuple[int, ...]) -> ValueError:
    return ValueError(f"{name}: expected shape {expected}, got {tuple(received)}")


def _pose_transforms(
    local_rotmats: jax.Array, root_translation: jax.Array, offsets: jax.Array, parents: tuple[int, ...]
) -> tuple[jax.Array, jax.Array]:
    """FK of one pose: ``[J, 3, 3], [3], [J, 3] -> ([J, 3, 3] global rotations, [J, 3] positions)``.

    One chained product per joint, in topological order. Measured on a 2-core CPU at 1 200 SMPL poses,
    this beat processing all joints of a tree depth at once (gather + batched matmul: 1.3-3x slower,
    depending on how levels are reassembled) and a ``lax.scan`` over joints (4x slower, though it
    compiles 4x faster).
    """
    num_joints = len(parents)
    rotations: list[jax.Array | None] = [None] * num_joints
    positions: list[jax.Array | None] = [None] * num_joints
    rotations[0], positions[0] = local_rotmats[0], root_translation
    for joint in topological_order(parents)[1:]:
        parent = parents[joint]
        rotations[joint] = _matmul(rotations[parent], local_rotmats[joint])
        positions[joint] = positions[parent] + _matmul(rotations[parent], offsets[joint])
    return jnp.stack(rotations), jnp.stack(positions)


def _fk_arguments(local_rotmats, root_translation, offsets, parents, fn, check):
    """The FK arguments as arrays after checking the tree, the shapes and (when concrete) the rotations."""
    topological_order(parents)  # validates the tree, cached
    num_joints = len(parents)
    local_rotmats = jnp.asarray(local_rotmats)
    root_translation = jnp.asarray(root_translation)
    offsets = jnp.asarray(offsets, dtype=local_rotmats.dtype)
    if local_rotmats.ndim < 3 or local_rotmats.shape[-3:] != (num_joints, 3, 3):
        raise _shape_error("local_rotmats", f"[..., {num_joints}, 3, 3]", local_rotmats.shape)
    batch = local_rotmats.shape[:-3]
    if root_translation.shape != (*batch, 3):
        raise _shape_error("root_translation", str([*batch, 3]), root_translation.shape)
    body_shape = offsets.shape[:-2]
    if offsets.ndim < 2 or offsets.shape[-2:] != (num_joints, 3) or body_shape != batch[: len(body_shape)]:
        expected = f"[{num_joints}, 3] or [*B, {num_joints}, 3] with B a prefix of {list(batch)}"
        raise _shape_error("offsets", expected, offsets.shape)
    if check:
        check_rotations(local_rotmats, where=f"{fn}: local_rotmats", allow_nonfinite=True)
    return local_rotmats, root_translation, offsets


@functools.partial(jax.jit, static_argnames="parents")
def _fk_transforms(local_rotmats, root_translation, offsets, parents):
    """The FK kernel on checked arguments (see :func:`forward_kinematics_transforms`)."""
    num_joints, batch, body_shape = len(parents), local_rotmats.shape[:-3], offsets.shape[:-2]
    # Flatten to [bodies, frames, ...]: one code path for shared ([J, 3]: one body) and per-body offsets.
    num_bodies, num_frames = math.prod(body_shape), math.prod(batch[len(body_shape) :])
    pose = functools.partial(_pose_transforms, parents=parents)
    frames = jax.vmap(pose, in_axes=(0, 0, None))
    rotations, joints = jax.vmap(frames)(
        local_rotmats.reshape(num_bodies, num_frames, num_joints, 3, 3),
        root_translation.reshape(num_bodies, num_frames, 3),
        offsets.reshape(num_bodies, num_joints, 3),
    )
    return rotations.reshape(*batch, num_joints, 3, 3), joints.reshape(*batch, num_joints, 3)


@functools.partial(jax.jit, static_argnames="parents")
def _fk_joints(local_rotmats, root_translation, offsets, parents):
    """Joint positions alone: compiled apart, so the compiler drops the unused leaf rotations."""
    return _fk_transforms(local_rotmats, root_translation, offsets, parents)[1]


def forward_kinematics_transforms(
    local_rotmats: jax.Array, root_translation: jax.Array, offsets: jax.Array, parents: tuple[int, ...],
    *, check: bool = True,
) -> tuple[jax.Array, jax.Array]:
    """Global joint rotations and positions from local rotations (what skinning needs).

    Args:
      local_rotmats: ``[..., J, 3, 3]`` rotation of each joint relative to its parent (the root's is global).
      root_translation: ``[..., 3]`` position of the root joint.
      offsets: ``[J, 3]`` rest offsets shared by every pose, or ``[*B, J, 3]`` per body, where ``B`` is a
        prefix of the poses' leading axes: e.g. ``[B, J, 3]`` with ``[B, T, J, 3, 3]`` motions gives each
        body its own bone lengths, shared across its frames.
      parents: static parent tuple, ``-1`` for the root (joint 0).
      check: refuse concrete ``local_rotmats`` that are not rotations (a scaled matrix would stretch the
        body, a reflection mirror it); skipped under ``jit``, as the converters' check
        (:mod:`jaxmotion.geometry.rotations`). ``False`` poses the body with any 3x3, as ACTOR's loss does
        with a network's raw matrices.

    Returns:
      ``(global_rotmats [..., J, 3, 3], joints [..., J, 3])``; the kernel is jit-compiled, ``parents`` static.

    Raises:
      ValueError: on an invalid ``parents``, a shape that does not match the above, or (``check``) a
        finite ``local_rotmats`` entry that is not a rotation.
    """
    args = _fk_arguments(local_rotmats, root_translation, offsets, parents, "forward_kinematics_transforms", check)
    return _fk_transforms(*args, parents)


def forward_kinematics(
    local_rotmats: jax.Array, root_translation: jax.Array, offsets: jax.Array, parents: tuple[int, ...],
    *, check: bool = True,
) -> jax.Array:
    """Joint positions ``[..., J, 3]``; the arguments are those of :func:`forward_kinematics_transforms`."""
    return _fk_joints(*_fk_arguments(local_rotmats, root_translation, offsets, parents, "forward_kinematics",
                                     check), parents)


def _check_points(name: str, array: jax.Array, expected: str, min_ndim: int, num_joints: int | None = None):
    """Require ``array`` to be ``[..., 3]`` with at least ``min_ndim`` axes (and ``num_joints`` on axis -2)."""
    if (
        array.ndim < min_ndim
        or array.shape[-1] != 3
        or (num_joints is not None and array.shape[-2] != num_joints)
    ):
        raise _shape_error(name, expected, array.shape)


def bone_lengths(joints: jax.Array, parents: tuple[int, ...]) -> jax.Array:
    """Length of each bone: ``[..., J, 3] -> [..., J - 1]``, one per non-root joint, in joint order."""
    joints = jnp.asarray(joints)
    _check_points("joints", joints, f"[..., {len(parents)}, 3]", 2, len(parents))
    parent_index, child_index = (np.array(index) for index in zip(*bones(parents)))
    return jnp.linalg.norm(joints[..., child_index, :] - joints[..., parent_index, :], axis=-1)


def root_relative(joints: jax.Array) -> jax.Array:
    """Joints relative to their frame's root (joint 0): ``[..., T, J, 3] -> [..., T, J, 3]``."""
    joints = jnp.asarray(joints)
    _check_points("joints", joints, "[..., J, 3]", 2)
    return joints - joints[..., :1, :]


def root_trajectory(joints: jax.Array) -> jax.Array:
    """Root (joint 0) position per frame: ``[..., T, J, 3] -> [..., T, 3]``."""
    joints = jnp.asarray(joints)
    _check_points("joints", joints, "[..., J, 3]", 2)
    return joints[..., 0, :]


def canonicalize_transform(
    joints: jax.Array, left_hip: int, right_hip: int, up_axis: int = 1
) -> tuple[jax.Array, jax.Array]:
    """The rigid map ``x -> R x + t`` that puts frame 0 of a motion in the canonical pose.

    Canonical: the root of frame 0 at the origin, and the subject facing +Z at frame 0, by a rotation
    about the up axis only. Facing is ``cross(left_hip - right_hip, up)``, which is horizontal by
    construction; with +X left and +Y up it is +Z. For another ``up_axis`` u the axes are permuted
    cyclically: left = axis (u + 2) % 3, forward = axis (u + 1) % 3.

    Args:
      joints: ``[..., T, J, 3]`` joint positions; only frame 0 is read.
      left_hip, right_hip: joint indices of the hips (e.g. ``SMPL24.index("left_hip")``). They must not be
        vertically aligned at frame 0 (the facing is then undefined, and the result NaN).
      up_axis: index of the vertical axis.

    Returns:
      ``(R [..., 3, 3], t [..., 3])``. Apply it to joints with :func:`canonicalize`, or to a rotation-based
      motion with :func:`transform_root`.
    """
    joints = jnp.asarray(joints)
    _check_points("joints", joints, "[..., T, J, 3]", 3)
    num_joints = joints.shape[-2]
    if not (0 <= left_hip < num_joints and 0 <= right_hip < num_joints and left_hip != right_hip):
        raise ValueError(
            f"left_hip, right_hip: expected two distinct joint indices in [0, {num_joints}), "
            f"got {left_hip}, {right_hip}"
        )
    if up_axis not in (0, 1, 2):
        raise ValueError(f"up_axis: expected 0, 1 or 2, got {up_axis}")
    first = joints[..., 0, :, :]
    up = jnp.asarray(np.eye(3)[up_axis], dtype=joints.dtype)
    forward = jnp.cross(first[..., left_hip, :] - first[..., right_hip, :], up)
    forward = forward / jnp.linalg.norm(forward, axis=-1, keepdims=True)
    left = jnp.cross(up, forward)
    # Rows are the new axes expressed in the old frame, so R maps forward to the forward axis, etc.
    rows = {(up_axis + 2) % 3: left, up_axis: jnp.broadcast_to(up, forward.shape), (up_axis + 1) % 3: forward}
    rotation = jnp.stack([rows[axis] for axis in range(3)], axis=-2)
    translation = -_matmul(rotation, first[..., 0, :, None])[..., 0]
    return rotation, translation


def canonicalize(joints: jax.Array, left_hip: int, right_hip: int, up_axis: int = 1) -> jax.Array:
    """Motion ``[..., T, J, 3]`` moved so that frame 0 has its root at the origin and faces +Z.

    See :func:`canonicalize_transform` for the arguments.
    """
    rotation, translation = canonicalize_transform(joints, left_hip, right_hip, up_axis)
    rotated = jnp.einsum("...ij,...tkj->...tki", rotation, joints, precision=jax.lax.Precision.HIGHEST)
    return rotated + translation[..., None, None, :]


def transform_root(
    rotation: jax.Array, translation: jax.Array, root_rotmats: jax.Array, root_translation: jax.Array
) -> tuple[jax.Array, jax.Array]:
    """Apply a rigid map ``x -> R x + t`` to a rotation-based motion through its root.

    FK then moves every joint by the same map, because the root's global rotation and position are the
    only ones not relative to a parent.

    Args:
      rotation: ``[..., 3, 3]`` R, one per motion.
      translation: ``[..., 3]`` t, one per motion.
      root_rotmats: ``[..., T, 3, 3]`` global root rotation per frame.
      root_translation: ``[..., T, 3]`` root position per frame.

    Returns:
      ``(R @ root_rotmats [..., T, 3, 3], R @ root_translation + t [..., T, 3])``.

    Raises:
      ValueError: on a shape that does not match the above, or a concrete ``rotation`` or ``root_rotmats``
        that is not a rotation (a scaled R would stretch the path; skipped under ``jit``).
    """
    rotation, translation = jnp.asarray(rotation), jnp.asarray(translation)
    root_rotmats, root_translation = jnp.asarray(root_rotmats), jnp.asarray(root_translation)
    if rotation.ndim < 2 or rotation.shape[-2:] != (3, 3):
        raise _shape_error("rotation", "[..., 3, 3]", rotation.shape)
    batch = rotation.shape[:-2]
    if translation.shape != (*batch, 3):
        raise _shape_error("translation", str([*batch, 3]), translation.shape)
    if root_rotmats.shape[: len(batch)] != batch or root_rotmats.shape[len(batch) + 1 :] != (3, 3):
        raise _shape_error("root_rotmats", str([*batch, "T", 3, 3]), root_rotmats.shape)
    if root_translation.shape != root_rotmats.shape[:-1]:
        raise _shape_error("root_translation", str(list(root_rotmats.shape[:-1])), root_translation.shape)
    check_rotations(rotation, where="transform_root: rotation", allow_nonfinite=True)
    check_rotations(root_rotmats, where="transform_root: root_rotmats", allow_nonfinite=True)
    per_frame = rotation[..., None, :, :]  # the same R for every frame
    new_translation = _matmul(per_frame, root_translation[..., None])[..., 0] + translation[..., None, :]
    return _matmul(per_frame, root_rotmats), new_translation


def transform_motion(rotation: jax.Array, translation: jax.Array, rotations: jax.Array, root_translation: jax.Array
                     ) -> tuple[jax.Array, jax.Array]:
    """:func:`transform_root` for a motion stored as axis-angle: ``rotations [..., T, J, 3]`` (joint 0 global) and
    ``root_translation [..., T, 3]`` moved by ``x -> R x + t`` -> the same two, only joint 0's rotation changed."""
    root, moved = transform_root(rotation, translation, axis_angle_to_matrix(rotations[..., 0, :]), root_translation)
    return rotations.at[..., 0, :].set(matrix_to_axis_angle(root, check=False)), moved


def heading_transform(root_rotmat: jax.Array, root_translation: jax.Array) -> tuple[jax.Array, jax.Array]:
    """The rigid map ``x -> R x + t`` that turns a pose to face +Z and moves its root over the origin: Neural
    Marionette's normalisation at the last context frame (its Eqs. 3-5), in the library frame (+Y up).

    ``R`` is the rotation about +Y that takes the heading (the root's forward axis ``root_rotmat @ e_z`` projected on
    the ground: the yaw of a heading-first Euler decomposition, as the paper keeps the yaw of the root's Euler
    angles) to +Z; ``t`` moves the root's ground position (x, z) to the origin. The height is kept (the paper
    subtracts the whole translation; which components it means is open, and keeping the height keeps the floor at
    y = 0, where a seated or standing context can be told apart).

    Args:
      root_rotmat: ``[..., 3, 3]`` the root's global rotation at the frame (e.g. the last context frame).
      root_translation: ``[..., 3]`` its translation there.

    Returns:
      ``(R [..., 3, 3], t [..., 3])``. Normalise a motion with :func:`transform_root` (rotations) or
      :func:`apply_transform` (joints, paths); restore it with the :func:`inverse_transform`. A forward axis
      pointing straight up or down has no heading (the result is then a turn by an arbitrary angle).
    """
    root_rotmat, root_translation = jnp.asarray(root_rotmat), jnp.asarray(root_translation)
    if root_rotmat.ndim < 2 or root_rotmat.shape[-2:] != (3, 3):
        raise _shape_error("root_rotmat", "[..., 3, 3]", root_rotmat.shape)
    if root_translation.shape != root_rotmat.shape[:-2] + (3,):
        raise _shape_error("root_translation", str([*root_rotmat.shape[:-2], 3]), root_translation.shape)
    forward = root_rotmat[..., :, 2]  # R e_z
    yaw = jnp.arctan2(forward[..., 0], forward[..., 2])
    c, s = jnp.cos(yaw), jnp.sin(yaw)
    zero, one = jnp.zeros_like(c), jnp.ones_like(c)
    # R_y(-yaw): rows of the rotation by -yaw about +Y
    rotation = jnp.stack([jnp.stack([c, zero, -s], -1), jnp.stack([zero, one, zero], -1),
                          jnp.stack([s, zero, c], -1)], -2)
    ground = root_translation * jnp.asarray([1.0, 0.0, 1.0], root_translation.dtype)
    return rotation, -_matmul(rotation, ground[..., None])[..., 0]


def inverse_transform(rotation: jax.Array, translation: jax.Array) -> tuple[jax.Array, jax.Array]:
    """The inverse of the rigid map ``x -> R x + t``: ``(Rᵀ, -Rᵀ t)``, shapes as given."""
    inverse = jnp.swapaxes(jnp.asarray(rotation), -1, -2)
    return inverse, -_matmul(inverse, jnp.asarray(translation)[..., None])[..., 0]


def apply_transform(rotation: jax.Array, translation: jax.Array, points: jax.Array) -> jax.Array:
    """``points [..., N, 3]`` (joints of a frame, a path, every frame's joints flattened) mapped by ``x -> R x + t``
    with ``R [..., 3, 3]``, ``t [..., 3]`` broadcast over N."""
    points = jnp.asarray(points)
    _check_points("points", points, "[..., N, 3]", 2)
    moved = jnp.einsum("...ij,...nj->...ni", rotation, points, precision=jax.lax.Precision.HIGHEST)
    return moved + jnp.asarray(translation)[..., None, :]


def transform_ground_path(rotation: jax.Array, translation: jax.Array, path: jax.Array) -> jax.Array:
    """Ground points ``path [..., N, 2]`` (x, z at y = 0) mapped by ``x -> R x + t`` (``R [..., 3, 3]`` about +Y,
    ``t [..., 3]``, e.g. :func:`heading_transform`'s) and read back on the ground: ``[..., N, 2]``."""
    path = jnp.asarray(path)
    ground = jnp.stack([path[..., 0], jnp.zeros_like(path[..., 0]), path[..., 1]], axis=-1)
    return apply_transform(rotation, translation, ground)[..., jnp.array([0, 2])]


def library_to_humanact12_frame(points: jax.Array) -> jax.Array:
    """Library frame (+Y up, facing +Z) to the HumanAct12 / Action2Motion joint frame (y down, facing -Z).

    The map is the proper rotation by 180 degrees about X, ``(x, y, z) -> (x, -y, -z)``; it is its own
    inverse. ``points``: ``[..., 3]``.
    """
    points = jnp.asarray(points)
    _check_points("points", points, "[..., 3]", 1)
    return points * jnp.asarray([1.0, -1.0, -1.0], dtype=points.dtype)


def humanact12_to_library_frame(points: jax.Array) -> jax.Array:
    """HumanAct12 / Action2Motion joint frame (y down, facing -Z) to the library frame: ``[..., 3]``.

    The same 180-degree rotation about X as :func:`library_to_humanact12_frame` (an involution).
    """
    return library_to_humanact12_frame(points)
