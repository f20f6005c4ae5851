"""MANN (Mode-Adaptive Neural Networks, Zhang, Starke, Komura and Saito, SIGGRAPH 2018) adapted to Neural
Marionette's single-action task: the MANN row of Neural Marionette's Table 1 (and the MANN rows of Table 3).

MANN predicts a character's next frame with one 3-layer MLP whose weights are, for each sample, a blend of K
expert MLPs' weights; a small gating MLP reads a few features of the current state and outputs the K blend weights
(a softmax). Neural Marionette "carefully adapted" it to take the action's tags, the context, the next tag and the
ground path, and says no more (MARIONETTE.md §5, "Baselines": K and the gating inputs are [U]). This module's
reading, every choice documented on :class:`MannConfig`:

* **One frame of the motion network** reads the ``K_ctx`` = 6 poses before it (the context's at first, a sliding
  window over the action's own poses after), each the paper's 135 numbers
  (:func:`~jaxmotion.geometry.representations.pose135`), with the window's ground position made relative to its
  last pose (x and z minus the last root's x and z; the height kept), so the network sees the motion, not where it
  stands; the action's tags and the next action's tags (multi-hot ``[C]``); the ground path's points at frames
  ``t + s`` for ``s`` in ``path_ahead`` (0, 10, 20; clamped to the action's last frame), as offsets from the last
  root's ground position, so it can steer (zeros in for in-place actions, as MARIONET's path); and a time code,
  the frames left ``r = T_a - t`` (``T_a`` the action's duration) as ``r / T_a`` (the phase, 1 at the first frame)
  and ``r / max_frames`` (how long is left). MANN's own inputs (a 12-point trajectory, joint positions and
  velocities) have no counterpart in the 135-number pose; the window stands in for its velocities.
* **The gate** reads the tags, the next tags, the time code, the last root velocity (the last two poses' root
  translations differenced, in m/s at BABEL-MAG's 30 Hz) and the first path offset (``path_ahead[0]``). MANN's gate
  reads the action variables, the target velocity and the feet's velocities: the tags stand in for the first, the
  path offset for the second and the root's velocity for the third, which the pose does not hold.
  A 3-layer MLP (``gating_hidden`` 32, ELU, as MANN) -> K softmax weights.
* **Blending.** Each expert layer has ``weight [K, out, in]``, ``bias [K, out]``; the blended layer is
  ``(sum_k a_k W_k) x + sum_k a_k b_k = sum_k a_k (W_k x + b_k)``: the second form is used (exact, and no per-sample
  weight matrix is built; it costs K dense layers, as blending would), ELU after the first two layers, dropout on
  every layer's input (MANN's keep probability 0.7, i.e. ``dropout`` 0.3, in both networks).
* **Output**: ``output="residual"`` (the default) predicts the change from the last pose, ``"pose"`` the pose.
  Inputs are not standardised (MANN divides by the data's mean and deviation): 6D rotations lie in [-1, 1], and the
  relative ground positions, heights and offsets are metres, all of order one.

Teacher forcing (:func:`mann_forward`) runs every frame at once on the true poses before it; generation
(:func:`mann_continue`) feeds its own poses back through ``jax.lax.scan``, and equals :func:`mann_forward` run on
what it generated (``tests/test_mann.py``). MANN is deterministic given its inputs (no latent), as the original.

Axes: B actions, K_ctx = 6 context poses, T frames (padded to the batch's longest), C tags, D = 135 pose numbers,
S path samples ahead, E experts.
"""

from __future__ import annotations

import dataclasses
from typing import Literal, NamedTuple

import jax
import jax.numpy as jnp
import numpy as np

from jaxmotion.config import check_at_least
from jaxmotion.data.segments import CONTEXT_FRAMES
from jaxmotion.geometry.representations import POSE135_SIZE
from jaxmotion.nn.core import LinearParams, dropout, init_linear, linear, split_key, torch_uniform

#: Context poses MANN reads, as MARIONET (S§3): the sliding window's length.
CONTEXT = CONTEXT_FRAMES
#: BABEL-MAG's frame rate (S§3): the gate reads the root's velocity in m/s.
FRAME_RATE = 30.0
_ROOT = slice(POSE135_SIZE - 3, POSE135_SIZE)  # the root translation (x, y up, z) in the 135 numbers
_GROUND = np.array([POSE135_SIZE - 3, POSE135_SIZE - 1])  # its ground (x, z)


@dataclasses.dataclass(frozen=True)
class MannConfig:
    """MANN's architecture; the defaults are MANN's sizes (Zhang et al. 2018: K = 8 experts, 512 hidden units, a
    gate of 32 hidden units, ELU, keep probability 0.7).

    ``experts`` K (8: MANN reports 4 enough and 8 sharper); ``hidden`` (512) the motion network's two hidden layers;
    ``gating_hidden`` (32) the gate's two hidden layers; ``dropout`` (0.3) on every layer's input of both networks;
    ``path_ahead`` ((0, 10, 20)) the frames ahead of ``t`` at which the path is read (clamped to the action's last
    frame); ``max_frames`` (120) the scale of the time code's frames left (not a limit); ``output`` ``"residual"``
    (the next pose = the last pose + the network's output) or ``"pose"`` (the network's output).
    """

    num_tags: int = 31
    experts: int = 8
    hidden: int = 512
    gating_hidden: int = 32
    dropout: float = 0.3
    path_ahead: tuple[int, ...] = (0, 10, 20)
    max_frames: int = 120
    output: Literal["residual", "pose"] = "residual"

    def __post_init__(self):
        check_at_least(self, 1, "num_tags", "experts", "hidden", "gating_hidden", "max_frames")
        if not 0.0 <= self.dropout < 1.0:
            raise ValueError(f"MannConfig.dropout: expected in [0, 1), got {self.dropout}")
        if not self.path_ahead or min(self.path_ahead) < 0:
            raise ValueError(f"MannConfig.path_ahead: expected one or more frames >= 0, got {self.path_ahead}")
        if self.output not in ("residual", "pose"):
            raise ValueError(f"MannConfig.output: expected 'residual' or 'pose', got {self.output!r}")

    @classmethod
    def tiny(cls, **changes) -> MannConfig:
        """A test-sized model (2 experts, 32 hidden units, a gate of 8)."""
        return cls(**{"experts": 2, "hidden": 32, "gating_hidden": 8, **changes})

    @property
    def motion_inputs(self) -> int:
        """The motion network's input size: the window, the tags twice, the path offsets, the time code."""
        return CONTEXT * POSE135_SIZE + 2 * self.num_tags + 2 * len(self.path_ahead) + 2

    @property
    def gating_inputs(self) -> int:
        """The gate's input size: the tags twice, the time code, the root velocity, the nearest path offset."""
        return 2 * self.num_tags + 2 + 3 + 2


class ExpertLinearParams(NamedTuple):
    weight: jax.Array  # [E, out, in]
    bias: jax.Array  # [E, out]


class MannParams(NamedTuple):
    gating: tuple[LinearParams, LinearParams, LinearParams]  # gating_inputs -> g -> g -> E
    experts: tuple[ExpertLinearParams, ExpertLinearParams, ExpertLinearParams]  # motion_inputs -> h -> h -> 135


def _init_experts(key: jax.Array, experts: int, in_dim: int, out_dim: int) -> ExpertLinearParams:
    """K ``torch.nn.Linear`` default initialisations, stacked."""
    k_w, k_b = jax.random.split(key)
    return ExpertLinearParams(torch_uniform(k_w, (experts, out_dim, in_dim), in_dim),
                              torch_uniform(k_b, (experts, out_dim), in_dim))


def init_mann(key: jax.Array, config: MannConfig) -> MannParams:
    """Fresh parameters (PyTorch's default initialisation, as every model of the library; each expert its own)."""
    keys = jax.random.split(key, 6)
    g, h = config.gating_hidden, config.hidden
    gating_sizes = (config.gating_inputs, g, g, config.experts)
    expert_sizes = (config.motion_inputs, h, h, POSE135_SIZE)
    return MannParams(
        gating=tuple(init_linear(keys[i], gating_sizes[i], gating_sizes[i + 1]) for i in range(3)),
        experts=tuple(_init_experts(keys[3 + i], config.experts, expert_sizes[i], expert_sizes[i + 1])
                      for i in range(3)),
    )


class FrameInputs(NamedTuple):
    motion: jax.Array  # [..., motion_inputs]
    gating: jax.Array  # [..., gating_inputs]


def frame_inputs(window: jax.Array, tags: jax.Array, next_tags: jax.Array, ahead: jax.Array,
                 time_code: jax.Array) -> FrameInputs:
    """One frame's inputs from ``window [..., K_ctx, 135]`` (the poses before it, oldest first), ``tags``,
    ``next_tags [..., C]``, ``ahead [..., S, 2]`` (the path's ground points at ``t + path_ahead``) and ``time_code
    [..., 2]`` (:func:`frame_schedule`) -> :class:`FrameInputs` (the layouts in the module docstring)."""
    last = window[..., -1, :]
    ground = last[..., _GROUND]  # [..., 2]
    relative = window.at[..., _GROUND].add(-ground[..., None, :])  # the ground position about the last root's
    offsets = ahead - ground[..., None, :]  # [..., S, 2]
    tags, next_tags = tags.astype(window.dtype), next_tags.astype(window.dtype)
    motion = jnp.concatenate([relative.reshape(*window.shape[:-2], -1), tags, next_tags,
                              offsets.reshape(*offsets.shape[:-2], -1), time_code], axis=-1)
    velocity = FRAME_RATE * (last[..., _ROOT] - window[..., -2, _ROOT])
    gating = jnp.concatenate([tags, next_tags, time_code, velocity, offsets[..., 0, :]], axis=-1)
    return FrameInputs(motion, gating)


def frame_schedule(config: MannConfig, path: jax.Array, mask: jax.Array) -> tuple[jax.Array, jax.Array]:
    """What each frame reads besides the poses: ``path [B, T, 2]`` (ground x, z per frame; zeros for in-place
    actions) and ``mask [B, T]`` (each action's first ``T_a`` frames) -> ``ahead [B, T, S, 2]`` (the path at
    ``t + s`` for ``s`` in ``path_ahead``, clamped to frame ``T_a - 1``) and ``time_code [B, T, 2]`` (``r / T_a``,
    ``r / max_frames`` with ``r = T_a - t`` the frames left; negative on padding, which nothing real reads)."""
    frames = mask.shape[1]
    duration = jnp.sum(mask, axis=1)  # [B]
    last = jnp.maximum(duration - 1, 0)[:, None, None]
    index = jnp.minimum(jnp.arange(frames)[:, None] + jnp.asarray(config.path_ahead)[None], last)  # [B, T, S]
    ahead = jax.vmap(lambda p, i: p[i])(path, index)
    remaining = (duration[:, None] - jnp.arange(frames)).astype(path.dtype)  # T_a .. 1, then <= 0
    time_code = jnp.stack([remaining / jnp.maximum(duration, 1)[:, None], remaining / config.max_frames], axis=-1)
    return ahead, time_code


def _mlp(layers, config: MannConfig, x: jax.Array, key: jax.Array | None, blend=None) -> jax.Array:
    """Three layers, ELU between, dropout on every layer's input; ``blend [..., E]`` mixes expert layers."""
    keys = split_key(key, len(layers))
    for i, (layer, k) in enumerate(zip(layers, keys)):
        x = dropout(x, config.dropout, k)
        x = linear(layer, x) if blend is None else _blended(layer, blend, x)
        if i < len(layers) - 1:
            x = jax.nn.elu(x)
    return x


def _blended(layer: ExpertLinearParams, blend: jax.Array, x: jax.Array) -> jax.Array:
    """``(sum_k a_k W_k) x + sum_k a_k b_k``, computed as ``sum_k a_k (W_k x + b_k)``: one product of ``x`` with
    the experts' weights side by side (``[E out, in]``, a reshape, no copy), then the blend: ``blend [..., E]``,
    ``x [..., in]`` -> ``[..., out]``."""
    experts, out, inputs = layer.weight.shape
    each = (x @ layer.weight.reshape(experts * out, inputs).T).reshape(*x.shape[:-1], experts, out) + layer.bias
    return jnp.einsum("...k,...ko->...o", blend, each)


def gating_weights(params: MannParams, config: MannConfig, gating: jax.Array,
                   key: jax.Array | None = None) -> jax.Array:
    """The gate: ``gating [..., gating_inputs]`` (:class:`FrameInputs`) -> blend weights ``[..., E]`` (a softmax:
    positive, summing to 1); dropout with a ``key``."""
    return jax.nn.softmax(_mlp(params.gating, config, gating, key), axis=-1)


def predict_frame(params: MannParams, config: MannConfig, inputs: FrameInputs, last: jax.Array,
                  key: jax.Array | None = None) -> tuple[jax.Array, jax.Array]:
    """One frame: :class:`FrameInputs` and ``last [..., 135]`` (the pose before it) -> ``(pose [..., 135], blend
    weights [..., E])``; dropout with a ``key``."""
    k_gate, k_motion = split_key(key, 2)
    blend = gating_weights(params, config, inputs.gating, k_gate)
    out = _mlp(params.experts, config, inputs.motion, k_motion, blend)
    return (last + out if config.output == "residual" else out), blend


def _check(context: jax.Array, tags: jax.Array, next_tags: jax.Array, path: jax.Array, mask: jax.Array,
           config: MannConfig) -> None:
    batch, frames = mask.shape
    expected = {"context": (context, (batch, CONTEXT, POSE135_SIZE)), "tags": (tags, (batch, config.num_tags)),
                "next_tags": (next_tags, (batch, config.num_tags)), "path": (path, (batch, frames, 2))}
    for name, (array, shape) in expected.items():
        if tuple(array.shape) != shape:
            raise ValueError(f"{name}: expected shape {list(shape)} (mask is {list(mask.shape)}), got "
                             f"{list(array.shape)}")


def teacher_forced(params: MannParams, config: MannConfig, context: jax.Array, tags: jax.Array,
                   next_tags: jax.Array, path: jax.Array, target: jax.Array, mask: jax.Array,
                   key: jax.Array | None = None) -> tuple[jax.Array, jax.Array]:
    """:func:`mann_forward` with the gate's blend weights: ``(poses [B, T, 135], blend [B, T, E])``."""
    _check(context, tags, next_tags, path, mask, config)
    if target.shape != (*mask.shape, POSE135_SIZE):
        raise ValueError(f"target: expected shape {[*mask.shape, POSE135_SIZE]}, got {list(target.shape)}")
    frames = mask.shape[1]
    sequence = jnp.concatenate([context, target], axis=1)  # [B, K_ctx + T, 135]
    windows = sequence[:, jnp.arange(frames)[:, None] + jnp.arange(CONTEXT)[None]]  # [B, T, K_ctx, 135]
    ahead, time_code = frame_schedule(config, path, mask)
    every = (*mask.shape, config.num_tags)
    inputs = frame_inputs(windows, jnp.broadcast_to(tags[:, None], every),
                          jnp.broadcast_to(next_tags[:, None], every), ahead, time_code)
    poses, blend = predict_frame(params, config, inputs, windows[..., -1, :], key)
    return jnp.where(mask[..., None], poses, 0.0), blend


def mann_forward(params: MannParams, config: MannConfig, context: jax.Array, tags: jax.Array,
                 next_tags: jax.Array, path: jax.Array, target: jax.Array, mask: jax.Array,
                 key: jax.Array | None = None) -> jax.Array:
    """Teacher forcing, every frame at once: ``context [B, K_ctx, 135]``, ``tags``, ``next_tags [B, C]`` (multi-hot),
    ``path [B, T, 2]``, ``target [B, T, 135]`` (the true poses: frame t reads the ``K_ctx`` poses before it, the
    context's first), ``mask [B, T]`` (bool, each action's first frames) -> poses ``[B, T, 135]``, zero on
    padding (which no real frame reads). Dropout with a ``key`` (training)."""
    return teacher_forced(params, config, context, tags, next_tags, path, target, mask, key)[0]


def mann_continue(params: MannParams, config: MannConfig, context: jax.Array, tags: jax.Array,
                  next_tags: jax.Array, path: jax.Array, mask: jax.Array, key: jax.Array | None = None) -> jax.Array:
    """Generation, frame by frame on its own poses (``jax.lax.scan``; eval mode): the inputs of
    :func:`mann_forward` without a target -> poses ``[B, T, 135]``, zero on padding. The contract of
    :func:`jaxmotion.models.marionet.generate`; ``key`` is accepted for it and ignored: MANN has no latent, so,
    as the original, it is deterministic given its inputs. Equals :func:`mann_forward` run on the poses it
    produced (``tests/test_mann.py``)."""
    del key
    _check(context, tags, next_tags, path, mask, config)
    ahead, time_code = frame_schedule(config, path, mask)

    def step(window, frame):
        ahead_t, time_t, real = frame  # [B, S, 2], [B, 2], [B]
        pose, _ = predict_frame(params, config, frame_inputs(window, tags, next_tags, ahead_t, time_t),
                                window[:, -1])
        pose = jnp.where(real[:, None], pose, 0.0)
        return jnp.concatenate([window[:, 1:], pose[:, None]], axis=1), pose

    _, poses = jax.lax.scan(step, context, (ahead.swapaxes(0, 1), time_code.swapaxes(0, 1), mask.T))
    return poses.swapaxes(0, 1)
