"""Control metrics: Neural Marionette's ΔTraj and ΔJPE, and ODMO's end-point error dist_e.

* **ΔTraj** (Neural Marionette, P-NM Sec. 5.1.2): "the L2 distance between the input trajectory and the
  generated root position per frame of root translation". The input trajectory is a ground-plane curve
  (P-NM Suppl. 1.4: "F : [1, ..., T] → R², which assigns a translation vector in the ground plane to a
  specified frame"), so the root is compared on the ground plane only: axes (x, z) of the library frame
  (+Y up). Per action, the mean over its frames of ``‖root_xz(t) − U(t)‖``; ΔTraj is the mean over
  actions.
* **ΔJPE** (Neural Marionette's Table 2, which names the column and never defines it). Defined here: the mean
  over an action's frames and joints of ``‖Ĵ_j(t) − J_j(t)‖``, Ĵ the action generated under the ground truth's own
  conditions (its context, tags, next tags, duration and path) with Z = µ and J the ground truth, both in the same
  frame; then the mean over actions. It measures how closely the model reproduces a real action from its
  conditions, as the paper's ablation reads it.
* **dist_e** (ODMO, P-OD Sec. 4.4): "the mean squared error between target end location r_e and the end
  location in the generated motion". As in ODMO's ``trajectory_customization.py``: per sample the squared
  Euclidean distance (summed over x, y, z, not averaged) between the target and the root (joint 0) at the
  last frame; the mean over the samples of each class, then the mean over classes.
* **hit rate** (ODMO's code only, logged beside dist_e as an "error rate"): per class, the fraction of
  samples whose end point lies strictly within ``tolerance · ‖target‖`` of the target (tolerance 0.1),
  then the mean over classes. Despite the code's name it counts successes, so higher is better.

Choices where the sources are silent:

* ΔTraj: mean over frames within an action, then over actions (each action weighs the same whatever its
  length); no alignment is applied, so root and trajectory must be in the same frame (Neural Marionette
  generates each action in a frame normalised on its initial pose, Suppl. Algorithm 1). Which actions to
  include (the paper's trajectories are for root-motion actions) is left to the caller. A length outside
  ``[1, T]`` gives NaN for that action.
* Units: ΔTraj and ΔJPE in the input unit (metres; the paper does not state its unit), dist_e in the input unit
  squared, the hit rate a fraction in [0, 1].
* Class means are plain means, as in ODMO (``np.mean`` over classes): a class without samples is NaN and
  so is the aggregate; a label outside ``[0, num_classes)`` makes the output NaN (a jittable function
  cannot raise on values).

Axes: N samples, T frames, J joints, C classes.
"""

from __future__ import annotations

import jax
import jax.numpy as jnp

_GROUND_AXES = [0, 2]  # x and z of the library frame (+Y up)


def _check_float(name: str, array: jax.Array, expected: str, shape_ok: bool) -> jax.Array:
    if not shape_ok:
        raise ValueError(f"{name}: expected {expected}, got {tuple(array.shape)}")
    return array.astype(jnp.promote_types(array.dtype, jnp.float32))


def _check_motions(motions: jax.Array) -> jax.Array:
    motions = jnp.asarray(motions)
    return _check_float("motions", motions, "[N, T, J, 3]", motions.ndim == 4 and motions.shape[-1] == 3)


def _check_ints(name: str, values: jax.Array, num_samples: int) -> jax.Array:
    values = jnp.asarray(values)
    if values.shape != (num_samples,) or not jnp.issubdtype(values.dtype, jnp.integer):
        raise ValueError(f"{name}: expected integer [N] = ({num_samples},), got {values.dtype} {tuple(values.shape)}")
    return values


def _trajectory_error(root_xz: jax.Array, trajectory: jax.Array, length: jax.Array) -> jax.Array:
    """``[T, 2], [T, 2], [] -> []``: mean ground-plane distance over the first ``length`` frames."""
    num_frames = root_xz.shape[0]
    frames = jnp.arange(num_frames) < length
    distance = jnp.linalg.norm(root_xz - trajectory, axis=-1)
    mean = jnp.where(frames, distance, 0.0).sum() / jnp.maximum(length, 1)
    return jnp.where((length >= 1) & (length <= num_frames), mean, jnp.nan)


@jax.jit
def trajectory_error_per_sample(
    motions: jax.Array, trajectories: jax.Array, lengths: jax.Array | None = None
) -> jax.Array:
    """Mean ground-plane distance between each action's root and its input trajectory, ``[N]``.

    Args:
      motions: ``[N, T, J, 3]`` generated joint positions, library frame (+Y up), root = joint 0.
      trajectories: ``[N, T, 2]`` input trajectory per frame, (x, z) on the ground plane.
      lengths: ``[N]`` int frames of each action (the rest is padding, never read); None = all T.
    """
    motions = _check_motions(motions)
    num_samples, num_frames = motions.shape[:2]
    trajectories = jnp.asarray(trajectories)
    trajectories = _check_float(
        "trajectories", trajectories, f"[N, T, 2] = ({num_samples}, {num_frames}, 2)",
        trajectories.shape == (num_samples, num_frames, 2),
    )
    if lengths is None:
        lengths = jnp.full(num_samples, num_frames)
    lengths = _check_ints("lengths", lengths, num_samples)
    root_xz = motions[:, :, 0, :][..., _GROUND_AXES]
    return jax.vmap(_trajectory_error)(root_xz, trajectories, lengths)


@jax.jit
def trajectory_error(motions: jax.Array, trajectories: jax.Array, lengths: jax.Array | None = None) -> jax.Array:
    """Neural Marionette's ΔTraj: :func:`trajectory_error_per_sample` averaged over actions -> scalar."""
    return trajectory_error_per_sample(motions, trajectories, lengths).mean()


def _joint_error(generated: jax.Array, truth: jax.Array, length: jax.Array) -> jax.Array:
    """``[T, J, 3]`` twice, ``[] -> []``: mean joint distance over the first ``length`` frames."""
    num_frames = generated.shape[0]
    distance = jnp.linalg.norm(generated - truth, axis=-1).mean(axis=-1)  # [T]
    mean = jnp.where(jnp.arange(num_frames) < length, distance, 0.0).sum() / jnp.maximum(length, 1)
    return jnp.where((length >= 1) & (length <= num_frames), mean, jnp.nan)


@jax.jit
def joint_position_error_per_sample(generated: jax.Array, truth: jax.Array, lengths: jax.Array | None = None
                                    ) -> jax.Array:
    """ΔJPE of each action, ``[N]``: ``generated`` and ``truth`` ``[N, T, J, 3]`` joint positions in one frame,
    ``lengths [N]`` frames of each (the rest padding, never read; None = all T). NaN for a length outside
    ``[1, T]``."""
    generated = _check_motions(generated)
    truth = jnp.asarray(truth)
    truth = _check_float("truth", truth, f"the shape of generated {tuple(generated.shape)}", truth.shape == generated.shape)
    num_samples, num_frames = generated.shape[:2]
    lengths = jnp.full(num_samples, num_frames) if lengths is None else _check_ints("lengths", lengths, num_samples)
    return jax.vmap(_joint_error)(generated, truth, lengths)


@jax.jit
def joint_position_error(generated: jax.Array, truth: jax.Array, lengths: jax.Array | None = None) -> jax.Array:
    """ΔJPE: :func:`joint_position_error_per_sample` averaged over actions -> scalar."""
    return joint_position_error_per_sample(generated, truth, lengths).mean()


def _class_mean(values: jax.Array, labels: jax.Array, num_classes: int) -> jax.Array:
    """Mean over classes of the per-class mean of ``values [N]``; NaN if a class is empty or a label invalid."""
    onehot = jax.nn.one_hot(labels, num_classes, dtype=values.dtype)
    per_class = jnp.matmul(values, onehot, precision=jax.lax.Precision.HIGHEST) / onehot.sum(axis=0)
    valid = jnp.all((labels >= 0) & (labels < num_classes))
    return jnp.where(valid, per_class.mean(), jnp.nan)


@jax.jit
def end_point_squared_error(motions: jax.Array, targets: jax.Array) -> jax.Array:
    """Squared distance of each target from the root at the last frame -> ``[N]`` (input unit²).

    ``motions [N, T, J, 3]`` (root = joint 0), ``targets [N, 3]``.
    """
    motions = _check_motions(motions)
    targets = jnp.asarray(targets)
    targets = _check_float(
        "targets", targets, f"[N, 3] = ({motions.shape[0]}, 3)", targets.shape == (motions.shape[0], 3)
    )
    return jnp.sum((targets - motions[:, -1, 0, :]) ** 2, axis=-1)


@jax.jit(static_argnames='num_classes')
def end_point_error(motions: jax.Array, targets: jax.Array, labels: jax.Array, num_classes: int) -> jax.Array:
    """ODMO's dist_e: mean over classes of the class-mean squared end-point error -> scalar (unit²).

    ``motions [N, T, J, 3]`` generated from the origin, ``targets [N, 3]`` requested end locations,
    ``labels [N]`` int class, ``num_classes`` static.
    """
    squared_error = end_point_squared_error(motions, targets)
    return _class_mean(squared_error, _check_ints("labels", labels, squared_error.shape[0]), num_classes)


@jax.jit(static_argnames='num_classes')
def end_point_hit_rate(
    motions: jax.Array, targets: jax.Array, labels: jax.Array, num_classes: int, tolerance: float = 0.1
) -> jax.Array:
    """Mean over classes of the fraction of end points within ``tolerance · ‖target‖`` -> scalar in [0, 1].

    Arguments as :func:`end_point_error`; ``tolerance`` may be traced.
    """
    squared_error = end_point_squared_error(motions, targets)
    labels = _check_ints("labels", labels, squared_error.shape[0])
    hits = squared_error < tolerance**2 * jnp.sum(jnp.asarray(targets, squared_error.dtype) ** 2, axis=-1)
    return _class_mean(hits.astype(squared_error.dtype), labels, num_classes)
