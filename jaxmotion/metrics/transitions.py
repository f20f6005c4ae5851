"""Neural Marionette's multi-action metrics: transition gaps (Δpose, Δvel) and qualification ratios.

Neural Marionette (P-NM, Sec. 5.2.2, "Transition Smoothness" and "Qualification Ratio"):

* **Δpose** (cm): "the L2 distance of per-joint position between the end pose of the previous action and
  the start one in the current action". Here: the mean over joints of ``‖p_b − p_{b−1}‖`` where ``b`` is
  the first frame of the current action.
* **Δvel** (cm/frame): "the difference of per-joint velocity between the end of the previous action and
  the start of the current action". Here: the mean over joints of
  ``‖(p_{b+1} − p_b) − (p_{b−1} − p_{b−2})‖``: each velocity is a one-frame difference taken inside its
  own action (the last two frames of the previous action, the first two of the current one), so the
  jump across the boundary, which Δpose already measures, does not enter Δvel.
* **Action QR**: "the percentage of accurately classified actions among all independent actions in a
  generated motion sequence ... We report the average of all testing data": per motion, the fraction of
  its actions recognised as their tag; then the mean over motions.
* **Motion QR** (eq. 7): "number of qualified animations / number of all animations", an animation being
  qualified "only if all actions are recognized correctly".
* **Curves** (Fig. 8, Fig. 10): the paper plots these metrics "as more actions are sequentially
  generated"; ``qualification_ratio_curves`` gives both QRs of the first n actions for every n. The paper
  plots no threshold sweep.

Choices where the paper is silent:

* "per-joint ... distance" is read as the mean over joints of the per-joint Euclidean distance (the
  MPJPE convention), not the norm of the stacked pose vector.
* A transition whose previous or current action has fewer than two frames (or whose boundaries are out
  of order or out of range) has no velocity on one side: both of its gaps are NaN, so a bad boundary
  cannot go unnoticed. The mean gaps are plain means, NaN if any transition is.
* The paper's table averages "from the second action to the last one"; transitions start at the second
  action by construction. For the QRs the caller chooses: pass ``correct[:, 1:]`` to leave the first
  action out as the table does.
* QRs are fractions in [0, 1] (the paper prints percentages).

Units: joint positions in metres, at the evaluation frame rate (BABEL-MAG: 30 Hz); gaps come out in cm
and cm/frame.

Axes: M motions, T frames, J joints, B transitions (= actions − 1), A actions.
"""

from __future__ import annotations

import jax
import jax.numpy as jnp

_CM_PER_M = 100.0


def _check_motions(name: str, motions: jax.Array, expected: str, ndim: int) -> jax.Array:
    motions = jnp.asarray(motions)
    if motions.ndim != ndim or motions.shape[-1] != 3:
        raise ValueError(f"{name}: expected {expected}, got {tuple(motions.shape)}")
    return motions.astype(jnp.promote_types(motions.dtype, jnp.float32))


def _check_boundaries(boundaries: jax.Array, expected: str, leading: tuple[int, ...]) -> jax.Array:
    """Require integer ``[*leading, B]`` with B >= 1."""
    boundaries = jnp.asarray(boundaries)
    if (
        boundaries.ndim != len(leading) + 1
        or boundaries.shape[:-1] != leading
        or boundaries.shape[-1] < 1
        or not jnp.issubdtype(boundaries.dtype, jnp.integer)
    ):
        raise ValueError(
            f"boundaries: expected integer {expected} with B >= 1, got {boundaries.dtype} {tuple(boundaries.shape)}"
        )
    return boundaries


def _check_correct(correct: jax.Array) -> jax.Array:
    correct = jnp.asarray(correct)
    if correct.ndim != 2 or correct.dtype != jnp.bool_:
        raise ValueError(f"correct: expected bool [M, A], got {correct.dtype} {tuple(correct.shape)}")
    return correct


def _transition_gaps(motion: jax.Array, boundaries: jax.Array) -> tuple[jax.Array, jax.Array]:
    num_frames = motion.shape[0]
    previous = jnp.concatenate([jnp.zeros(1, boundaries.dtype), boundaries[:-1]])
    following = jnp.concatenate([boundaries[1:], jnp.full(1, num_frames, boundaries.dtype)])
    valid = (boundaries - previous >= 2) & (following - boundaries >= 2)
    # Frames b-2, b-1 (end of the previous action) and b, b+1 (start of the current one): [B, 4, J, 3].
    window = jnp.take(motion, boundaries[:, None] + jnp.arange(-2, 2), axis=0, mode="clip")
    before, last, first, after = (window[:, i] for i in range(4))
    pose_gap = jnp.linalg.norm(first - last, axis=-1).mean(axis=-1)
    velocity_gap = jnp.linalg.norm((after - first) - (last - before), axis=-1).mean(axis=-1)
    return (jnp.where(valid, _CM_PER_M * pose_gap, jnp.nan), jnp.where(valid, _CM_PER_M * velocity_gap, jnp.nan))


@jax.jit
def transition_gaps(motion: jax.Array, boundaries: jax.Array) -> tuple[jax.Array, jax.Array]:
    """Δpose and Δvel of every transition of one multi-action motion.

    Args:
      motion: ``[T, J, 3]`` joint positions in metres, the actions concatenated in order.
      boundaries: ``[B]`` int, the first frame of each action after the first, increasing; every action
        must have at least two frames (``2 <= b_1``, ``b_{i+1} − b_i >= 2``, ``b_B <= T − 2``).

    Returns:
      ``(pose_gap [B] in cm, velocity_gap [B] in cm/frame)``; NaN for a transition that breaks the
      frame requirement above.
    """
    motion = _check_motions("motion", motion, "[T, J, 3]", 3)
    boundaries = _check_boundaries(boundaries, "[B]", ())
    return _transition_gaps(motion, boundaries)


@jax.jit
def mean_transition_gaps(motions: jax.Array, boundaries: jax.Array) -> tuple[jax.Array, jax.Array]:
    """Δpose (cm) and Δvel (cm/frame) of a test set: the mean over all transitions of all motions.

    ``motions [M, T, J, 3]``, each padded to a common T after its last action (the padding is never read
    as long as the last action has two real frames), ``boundaries [M, B]`` as in :func:`transition_gaps`
    -> ``(pose_gap, velocity_gap)`` scalars.
    """
    motions = _check_motions("motions", motions, "[M, T, J, 3]", 4)
    boundaries = _check_boundaries(boundaries, f"[M, B] with M = {motions.shape[0]}", motions.shape[:1])
    pose_gap, velocity_gap = jax.vmap(_transition_gaps)(motions, boundaries)
    return pose_gap.mean(), velocity_gap.mean()


@jax.jit
def action_qr(correct: jax.Array) -> jax.Array:
    """Action-level QR, in [0, 1]: the mean over motions of each motion's fraction of correct actions.

    ``correct [M, A]`` bool: action a of motion m was recognised as its tag.
    """
    return _check_correct(correct).mean(axis=1).mean()


@jax.jit
def motion_qr(correct: jax.Array) -> jax.Array:
    """Motion-level QR (eq. 7): ``correct [M, A]`` bool -> fraction of motions with every action correct."""
    return _check_correct(correct).all(axis=1).mean()


@jax.jit
def qualification_ratio_curves(correct: jax.Array) -> tuple[jax.Array, jax.Array]:
    """Both QRs over the first n actions for n = 1..A, as plotted against the number of actions (Fig. 8).

    ``correct [M, A]`` bool -> ``(action_qr [A], motion_qr [A])``; entry ``n − 1`` equals
    ``action_qr(correct[:, :n])`` and ``motion_qr(correct[:, :n])``.
    """
    correct = _check_correct(correct).astype(jnp.float32)
    hits = jnp.cumsum(correct, axis=1) / jnp.arange(1, correct.shape[1] + 1)
    all_so_far = jnp.cumprod(correct, axis=1)
    return hits.mean(axis=0), all_so_far.mean(axis=0)
