"""Jitter of joint trajectories: the mean magnitude of their second difference (acceleration per frame²), and
the jerk around transitions of multi-action motions.

:func:`mean_acceleration`: ACTOR's denoising use case (encode-decode lowers the jitter of noisy monocular estimates)
and the calibration of the embedded UESTC noise against VIBE's published acceleration error.

:func:`transition_jerk`, :func:`jerk_scores` (FlowMDM's Peak Jerk and Area Under the Jerk, as its code computes
them: ``calculate_jerk`` and ``evaluate_jerk``): the jerk of a frame is the third difference of the joint positions
(unit per frame³), its L1 norm over x, y, z, the largest over joints; at each frame of a window of ``window`` frames
centred on a transition (frames ``b - window / 2 .. b + window / 2 - 1`` for a transition at frame ``b``) it is
averaged over all transitions; **PJ** is the largest of these means, **AUJ** the sum over the window of their
distance to the real motions' mean jerk. FlowMDM's constant for BABEL (0.016383045) is that of BABEL's real
motions; here the reference is measured on the real data the motions are scored against
(:func:`mean_jerk`). A transition whose window (with the three frames the differences need) leaves its motion does
not count.

Axes: N sequences, T frames, J joints, B transitions, L window frames.
"""

from __future__ import annotations

import functools

import jax
import jax.numpy as jnp


@jax.jit
def mean_acceleration(joints: jax.Array, mask: jax.Array | None = None) -> jax.Array:
    """Mean over sequences, interior frames and joints of ``‖x[t+1] − 2 x[t] + x[t−1]‖``, in the input unit
    per frame²: ``joints [N, T, J, 3]``, ``mask [N, T]`` (real frames; a frame counts when it and both
    neighbours are real) -> scalar. NaN when no frame qualifies (T < 3)."""
    if joints.ndim != 4 or joints.shape[-1] != 3:
        raise ValueError(f"joints: expected [N, T, J, 3], got {tuple(joints.shape)}")
    if mask is None:
        mask = jnp.ones(joints.shape[:2], bool)
    elif mask.shape != joints.shape[:2]:
        raise ValueError(f"mask: expected [N, T] = {tuple(joints.shape[:2])}, got {tuple(mask.shape)}")
    accel = jnp.linalg.norm(joints[:, 2:] - 2.0 * joints[:, 1:-1] + joints[:, :-2], axis=-1).mean(axis=-1)
    valid = mask[:, 2:] & mask[:, 1:-1] & mask[:, :-2]
    return jnp.sum(jnp.where(valid, accel, 0.0)) / valid.sum()


def _jerk(joints: jax.Array) -> jax.Array:
    """``[..., T, J, 3] -> [..., T - 3]``: per frame, the largest L1 norm over joints of the third difference."""
    x = joints
    third = x[..., 3:, :, :] - 3.0 * x[..., 2:-1, :, :] + 3.0 * x[..., 1:-2, :, :] - x[..., :-3, :, :]
    return jnp.abs(third).sum(axis=-1).max(axis=-1)


@jax.jit
def mean_jerk(joints: jax.Array, lengths: jax.Array) -> jax.Array:
    """The real motions' mean jerk (the reference of AUJ): ``joints [N, T, J, 3]``, ``lengths [N]`` -> scalar, the
    mean over every frame whose four positions lie within its motion."""
    jerk = _jerk(joints)
    valid = jnp.arange(jerk.shape[1])[None] + 3 < lengths[:, None]
    return jnp.sum(jnp.where(valid, jerk, 0.0)) / jnp.sum(valid)


@functools.partial(jax.jit, static_argnames="window")
def transition_jerk(joints: jax.Array, lengths: jax.Array, boundaries: jax.Array, window: int = 30) -> jax.Array:
    """The mean jerk at each frame of the transition window: ``joints [N, T, J, 3]`` (motions of ``lengths [N]``
    frames), ``boundaries [N, B]`` (each transition's first frame of the next action) -> ``[window]``; NaN where no
    transition's window fits in its motion."""
    if window < 2 or window % 2:
        raise ValueError(f"window: expected an even number of frames >= 2, got {window}")
    first = boundaries - window // 2  # [N, B]: the window's first frame
    frames = first[..., None] + jnp.arange(window + 3)  # the positions its jerks read: [N, B, L + 3]
    valid = (first >= 0) & (first + window + 3 <= lengths[:, None])
    positions = jax.vmap(lambda j, f: j[jnp.clip(f, 0, j.shape[0] - 1)])(joints, frames)  # [N, B, L + 3, J, 3]
    jerk = _jerk(positions)  # [N, B, L]
    return jnp.sum(jnp.where(valid[..., None], jerk, 0.0), axis=(0, 1)) / jnp.sum(valid)


def jerk_scores(curve: jax.Array, reference: jax.Array | float) -> dict[str, float]:
    """``{"peak_jerk": PJ, "area_under_jerk": AUJ}`` from :func:`transition_jerk`'s ``curve [L]`` and the real
    motions' mean jerk ``reference``."""
    curve = jnp.asarray(curve)
    return {"peak_jerk": float(jnp.max(curve)), "area_under_jerk": float(jnp.sum(jnp.abs(curve - reference)))}
