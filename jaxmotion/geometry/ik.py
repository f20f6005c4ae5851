"""Analytic two-bone inverse kinematics: move the end of a three-joint chain (hip-knee-ankle, shoulder-elbow-wrist)
to a target by turning its first two joints.

Conventions (library frame: metres, +Y up, the subject faces +Z at rest, +X is the subject's left; rotations act on
column vectors, as in :mod:`jaxmotion.geometry.kinematics`). A chain is three joints ``root -> mid -> end``: the
root joint's rotation swings the upper bone (root to mid), the mid joint's the lower bone (mid to end). Both
kernels are written for one chain in one pose ``[3]`` / ``[J, 3, 3]``; callers ``jax.vmap`` them over frames.

The solution (ours; the usual analytic construction, stated so that its choices are visible):

* the end goes to the target's direction from the root, at the target's distance clamped to what the bones can
  span, ``[|l1 - l2|, l1 + l2]``: an unreachable target gets a straight chain pointing at it (a fully folded one
  if it lies closer than ``|l1 - l2|``), and bone lengths never change;
* the mid joint stays on the side of the root-to-target line where it was (the current mid joint is the pole):
  the new chain lies in the plane through the root, the target and the old mid joint;
* the root turn carries the old bend plane onto the new one, and the mid joint turns about the new plane's normal
  only, so a knee or elbow keeps bending about its own hinge (no twist is added between the two bones).

Where the chain is straight its positions give no bend plane, and where the mid joint lies on the root-to-target
line they give no pole; a ``hinge`` axis (the mid joint's bend axis, e.g. +X in an SMPL knee's frame: knees flex
about +X) stands in for both. With the target at the current end, the turns are the identity.
"""

from __future__ import annotations

import functools

import jax
import jax.numpy as jnp

from jaxmotion.geometry.rotations import axis_angle_to_matrix
from jaxmotion.geometry.skeletons import topological_order

__all__ = ["two_bone_ik", "two_bone_pose"]

# 3x3 products at full float32 precision (GPU/TPU defaults would put millimetre errors on the end).
_matmul = functools.partial(jnp.matmul, precision=jax.lax.Precision.HIGHEST)
# Below this sine of an angle a chain counts as straight, or the mid joint as on the root-to-target line:
# float32 positions of ~1 m give directions to ~1e-7, so the plane such a line spans would be noise.
_DEGENERATE_SINE = 1e-4


def _unit(vector: jax.Array) -> jax.Array:
    """``vector`` scaled to length 1 (zero stays zero: callers replace degenerate directions before using them)."""
    length = jnp.linalg.norm(vector)
    return vector / jnp.where(length > 0, length, 1.0)


def _off_axis(vector: jax.Array, axis: jax.Array) -> jax.Array:
    """The part of ``vector`` perpendicular to the unit ``axis``."""
    return vector - jnp.dot(vector, axis) * axis


def _frame(direction: jax.Array, normal: jax.Array) -> jax.Array:
    """The rotation with columns ``direction``, ``normal``, ``direction x normal`` (two orthonormal vectors)."""
    return jnp.stack([direction, normal, jnp.cross(direction, normal)], axis=-1)


def two_bone_ik(root: jax.Array, mid: jax.Array, end: jax.Array, target: jax.Array, hinge: jax.Array
                ) -> tuple[jax.Array, jax.Array]:
    """Turns of a chain's two joints that bring its end to ``target`` (as close as the bones allow).

    Args:
      root, mid, end: ``[3]`` current positions of the chain's joints (e.g. hip, knee, ankle).
      target: ``[3]`` where the end should go.
      hinge: ``[3]`` the mid joint's current bend axis (world frame; its length is ignored), used only where the
        positions leave the bend plane undefined (see the module docstring). A knee or elbow bending by a
        positive angle about ``hinge`` folds the chain.

    Returns:
      ``(root_turn [3, 3], mid_turn [3, 3])``, rotations in the world frame: the root joint's new global rotation
      is ``root_turn @ G_root``, the mid joint's ``mid_turn @ root_turn @ G_mid``; the mid joint moves to
      ``root + root_turn @ (mid - root)`` and the end to ``mid' + mid_turn @ root_turn @ (end - mid)``.
    """
    upper, lower = mid - root, end - mid
    upper_length, lower_length = jnp.linalg.norm(upper), jnp.linalg.norm(lower)
    to_target = target - root
    distance = jnp.linalg.norm(to_target)
    # A target on the root itself has no direction: keep the end's.
    toward = jnp.where(distance > 0, to_target / jnp.where(distance > 0, distance, 1.0), _unit(end - root))
    reach = jnp.clip(distance, jnp.abs(upper_length - lower_length), upper_length + lower_length)

    bend = jnp.cross(upper, lower)
    bent = jnp.linalg.norm(bend) > _DEGENERATE_SINE * upper_length * lower_length
    old_normal = jnp.where(bent, _unit(bend), _unit(_off_axis(_unit(hinge), _unit(upper))))
    pole = _off_axis(upper, toward)
    pole_known = jnp.linalg.norm(pole) > _DEGENERATE_SINE * upper_length
    # No pole from the positions: bend so that the chain folds about the old normal (hinge).
    side = jnp.where(pole_known, _unit(pole), _unit(jnp.cross(toward, old_normal)))
    new_normal = jnp.cross(side, toward)

    # Law of cosines: the angle at the root between the upper bone and the root-to-end line. At the limits of
    # reach the chain is exactly straight or folded: rounding there would make sqrt(1 - cos^2) ~ 1e-4, not 0.
    cosine = (upper_length**2 + reach**2 - lower_length**2) / (2 * upper_length * jnp.maximum(reach, 1e-12))
    cosine = jnp.clip(cosine, -1.0, 1.0)
    at_limit = (distance >= upper_length + lower_length) | (distance <= jnp.abs(upper_length - lower_length))
    sine = jnp.where(at_limit, 0.0, jnp.sqrt(jnp.maximum(1.0 - cosine**2, 0.0)))
    upper_direction = jnp.where(at_limit, jnp.sign(cosine), cosine) * toward + sine * side
    new_mid = root + upper_length * upper_direction
    new_end = root + reach * toward

    root_turn = _matmul(_frame(upper_direction, new_normal), _frame(_unit(upper), old_normal).T)
    # The lower bone after the root turn and where it must point: both lie in the new bend plane, so one turn
    # about its normal takes the first to the second.
    swung = _unit(_matmul(root_turn, lower))
    wanted = _unit(new_end - new_mid)
    angle = jnp.arctan2(jnp.dot(jnp.cross(swung, wanted), new_normal), jnp.dot(swung, wanted))
    return root_turn, axis_angle_to_matrix(angle * new_normal)


def two_bone_pose(local_rotmats: jax.Array, global_rotmats: jax.Array, joints: jax.Array, parents: tuple[int, ...],
                  chain: tuple[int, int, int], target: jax.Array, hinge: jax.Array) -> jax.Array:
    """One pose with a chain's end moved to ``target`` by :func:`two_bone_ik`, the end's global rotation kept.

    The chain's root and mid joints get new local rotations; the end joint's local rotation changes so that its
    global rotation stays what it was (a foot keeps its orientation in the world, and so does everything below
    it); every other joint's local rotation is unchanged.

    Args:
      local_rotmats: ``[J, 3, 3]`` local rotations (joint 0's global).
      global_rotmats, joints: ``[J, 3, 3]`` and ``[J, 3]``, the pose's forward kinematics
        (:func:`jaxmotion.geometry.kinematics.forward_kinematics_transforms`), computed once by the caller for
        all the chains it moves.
      parents: static parent tuple (``-1`` for joint 0).
      chain: static joint indices ``(root, mid, end)``, each the parent of the next (e.g. SMPL-24's
        ``(1, 4, 7)``: left hip, knee, ankle).
      target: ``[3]`` where the end joint should go.
      hinge: ``[3]`` the mid joint's bend axis in its own frame (SMPL knees: ``(1, 0, 0)``), see
        :func:`two_bone_ik`.

    Returns:
      ``[J, 3, 3]`` the new local rotations.

    Raises:
      ValueError: if ``chain`` is not three joints of ``parents``, each the parent of the next.
    """
    topological_order(parents)  # validates the tree
    if len(chain) != 3 or not all(0 <= joint < len(parents) for joint in chain):
        raise ValueError(f"chain: expected three joint indices in [0, {len(parents)}), got {chain}")
    root, mid, end = chain
    if parents[mid] != root or parents[end] != mid:
        raise ValueError(f"chain: expected each joint to be the parent of the next, got {chain} with parents "
                         f"{tuple(parents[joint] for joint in chain)}")
    root_turn, mid_turn = two_bone_ik(joints[root], joints[mid], joints[end], target,
                                      _matmul(global_rotmats[mid], hinge))
    new_root = _matmul(root_turn, global_rotmats[root])
    new_mid = _matmul(mid_turn, _matmul(root_turn, global_rotmats[mid]))
    above = global_rotmats[parents[root]] if parents[root] >= 0 else jnp.eye(3, dtype=global_rotmats.dtype)
    return (local_rotmats.at[root].set(_matmul(above.T, new_root))
            .at[mid].set(_matmul(new_root.T, new_mid))
            .at[end].set(_matmul(new_mid.T, global_rotmats[end])))
