"""ODMO (Lu et al., ACM MM 2022): a contrastive LSTM VAE on root-relative motion that decodes the
trajectory first, then the whole motion.

Sources: the paper (P-OD §3.2, Suppl. Table S2) and the authors' code (OD ``src/modules/models.py``:
``LMPEncoder``, ``TrajGenerator``, ``MotionGenerator``; ``ensemble.py``; ``initializer.py``;
``param/param_*.py``). Axes: ``B`` batch, ``T`` frames, ``J`` joints, ``F = J·3`` pose
features (joint-major: ``x0 y0 z0 x1 ...``; joint 0 is the root), ``C`` classes, ``Z`` code size, ``H``
hidden sizes.

**Three networks.**

* **LMP encoder** ``E``: the local movement profile, every joint minus its frame's root
  (:func:`local_movement`), through an LSTM (1 layer, 64 units); its last hidden state through
  ``Linear 256 → BatchNorm → PReLU → Linear 256 → BatchNorm → PReLU → Linear 2Z`` gives the code mean
  ``µ`` and the log-variance (``Z`` = 20). The code is ``z = µ + σ·ε`` with ``σ = exp(logvar / 2)``.
* **Trajectory generator** ``G_r``: its input is the flattened outer product of the one-hot class and
  the code (``[B, C·Z]``, index ``c·Z + z``) and the end root position ``r_e`` (zeros without
  ``use_end``: the −r_e ablation); ``Linear(in → in·(T−1)) → PReLU``, reshaped to ``[B, T−1, in]``,
  ``Linear 128`` (no activation), an LSTM (2 × 128), ``3 × (Linear 128 → PReLU)`` and ``Linear 3`` give
  ``T − 1`` root velocities; positions are their running sum from the origin (:func:`integrate`), ``T``
  frames. One PReLU (one learned slope) serves all four activations, as in the code.
* **Motion generator** ``G_m``: a trajectory encoder (``Linear(3 → 128) → PReLU``, LSTM 2 × 128) reads the
  predicted trajectory; its final ``(h, c)`` starts the decoder. The decoder's step ``t`` reads
  ``[previous pose (F), outer(one-hot, z) (C·Z), (t+1)/T]`` through ``Linear 128 → PReLU``, an LSTM
  (2 × 128) and ``Linear F``. The previous pose is zeros at the first step and then the decoder's own
  output, or with teacher forcing (``teacher_mask[t]``) the true pose ``t``. One PReLU serves both
  embeddings, as in the code. The output is the whole motion (root included), in the window's frame.

Widths per dataset (the code's ``param_*.py``; :meth:`ODMOConfig.humanact12` etc.): HumanAct12 24 joints,
12 classes, 60 frames (decoder input 313); UESTC 18 joints, 40 classes, 60 frames (855; trajectory input
803); CMU MoCap 20 joints, 7 classes, 100 frames (201). The embedded stand-ins have 24 joints, so
:meth:`ODMOConfig.for_data` sizes the model from the dataset.

**Switches** (code's choice the default): ``use_end`` (−r_e); ``lmp_input`` (the encoder reads the LMP;
the code's ``use_lmp``, False = the whole motion). The loss switches (prior σ as standard deviation or
variance, same-class contrastive term, trajectory loss on positions or velocities, which terms) are
:class:`jaxmotion.losses.odmo.ODMOLossConfig`'s.

**Parameters** mirror the authors' ``Ensemble`` state dict (:func:`state_dict` gives its names:
``tgenerator.expand.weight``, ``LMPencoder.fc.1.running_mean``, ``mgenerator.rnn.weight_ih_l1``, ...)
with PyTorch's shapes and default initialisation; BatchNorm running statistics are a separate pytree
(:class:`ODMOStats`) that train mode returns updated. Everything is jittable; sizes are static.

**Speed** (same numbers up to float32 summation order): the condition's share of each embedding
(``outer(one-hot, z) @ W_cond``) is constant over a sequence, so it is computed once per sequence, not
once per frame; the trajectory generator's per-frame layers run on the whole sequence at once; on a CPU
every recurrence's step is recomputed in the backward pass instead of stored
(:func:`jaxmotion.nn.recurrent.recompute_on_cpu`: a 512-pair training step 5.3 -> 2.8 s on 2 cores).
"""

from __future__ import annotations

import dataclasses
from typing import NamedTuple

import jax
import jax.numpy as jnp
import numpy as np

from jaxmotion.data.labels import check_actions
from jaxmotion.nn.core import (
    BatchNormParams,
    BatchNormStats,
    LinearParams,
    PReLUParams,
    batch_norm,
    init_batch_norm,
    init_linear,
    init_prelu,
    linear,
    prelu,
)
from jaxmotion.nn.recurrent import (
    LSTMParams,
    LSTMState,
    init_lstm_stack,
    lstm_stack,
    lstm_stack_step,
    recompute_on_cpu,
)

# ------------------------------------------------------------------------------------------------- config


@dataclasses.dataclass(frozen=True, kw_only=True)
class ODMOConfig:
    """Sizes and architecture switches (defaults: the authors' code)."""

    num_joints: int  # J; F = 3J
    num_classes: int  # C
    num_frames: int = 60  # T (CMU MoCap 100)
    code_dim: int = 20  # Z ("mu_dim")
    encoder_hidden: int = 64  # "em_hidden_dim"
    encoder_layers: int = 1  # "em_num_hidlayers"
    encoder_width: int = 256  # the two Linear-BN-PReLU blocks
    trajectory_hidden: int = 128  # "tg_hidden_dim"
    trajectory_layers: int = 2  # "tg_num_hidlayers"
    motion_hidden: int = 128  # "mg_hidden_dim"
    motion_layers: int = 2  # "mg_num_hidlayers"
    use_end: bool = True  # False: the −r_e ablation (the end root is zeroed)
    lmp_input: bool = True  # the encoder reads the local movement profile (the code's use_lmp)

    def __post_init__(self):
        for name in ("num_joints", "num_classes", "code_dim", "encoder_hidden", "encoder_layers", "encoder_width",
                     "trajectory_hidden", "trajectory_layers", "motion_hidden", "motion_layers"):
            value = getattr(self, name)
            if not isinstance(value, int) or value < 1:
                raise ValueError(f"ODMOConfig.{name}: expected a positive int, got {value!r}")
        if not isinstance(self.num_frames, int) or self.num_frames < 2:
            raise ValueError(f"ODMOConfig.num_frames: expected an int >= 2 (T − 1 velocities), got {self.num_frames!r}")

    @property
    def pose_dim(self) -> int:
        return 3 * self.num_joints

    @property
    def condition_dim(self) -> int:
        """Width of the flattened outer product of the one-hot class and the code: ``C·Z``."""
        return self.num_classes * self.code_dim

    @property
    def trajectory_input(self) -> int:
        return self.condition_dim + 3

    @property
    def decoder_input(self) -> int:
        """The decoder step's input: previous pose, condition, time (HumanAct12 313, UESTC 855, MoCap 201)."""
        return self.pose_dim + self.condition_dim + 1

    @classmethod
    def humanact12(cls, **overrides) -> ODMOConfig:
        return cls(**{"num_joints": 24, "num_classes": 12, "num_frames": 60, **overrides})

    @classmethod
    def uestc(cls, **overrides) -> ODMOConfig:
        return cls(**{"num_joints": 18, "num_classes": 40, "num_frames": 60, **overrides})

    @classmethod
    def mocap(cls, **overrides) -> ODMOConfig:
        return cls(**{"num_joints": 20, "num_classes": 7, "num_frames": 100, **overrides})


# --------------------------------------------------------------------------------------------- parameters


class LMPEncoderParams(NamedTuple):
    encoder: tuple[LSTMParams, ...]  # LSTM(F, 64)
    fc0: LinearParams  # [256, 64]
    bn1: BatchNormParams  # [256]
    act2: PReLUParams
    fc3: LinearParams  # [256, 256]
    bn4: BatchNormParams
    act5: PReLUParams
    fc6: LinearParams  # [2Z, 256]: µ, then the log-variance


class TrajectoryGeneratorParams(NamedTuple):
    expand: LinearParams  # [in·(T−1), in]
    embedding: LinearParams  # [128, in]
    rnn: tuple[LSTMParams, ...]
    out_fc0: LinearParams
    out_fc1: LinearParams
    out_fc2: LinearParams
    out_fc: LinearParams  # [3, 128]
    activation: PReLUParams  # shared by the four activations


class MotionGeneratorParams(NamedTuple):
    encoder_embedding: LinearParams  # [128, 3]
    encoder_rnn: tuple[LSTMParams, ...]
    embedding: LinearParams  # [128, F + C·Z + 1]: previous pose, condition, time (in that order)
    rnn: tuple[LSTMParams, ...]
    out_fc: LinearParams  # [F, 128]
    activation: PReLUParams  # shared by both embeddings


class ODMOParams(NamedTuple):
    trajectory: TrajectoryGeneratorParams
    encoder: LMPEncoderParams
    motion: MotionGeneratorParams


class ODMOStats(NamedTuple):
    """The LMP encoder's BatchNorm running statistics."""

    bn1: BatchNormStats
    bn4: BatchNormStats


def init_odmo(key: jax.Array, config: ODMOConfig) -> tuple[ODMOParams, ODMOStats]:
    """Fresh parameters with PyTorch's default initialisation, and fresh running statistics."""
    k_traj, k_enc, k_motion = jax.random.split(key, 3)
    w, h_t, h_m = config.encoder_width, config.trajectory_hidden, config.motion_hidden
    keys = jax.random.split(k_enc, 4)
    bn1, bn1_stats = init_batch_norm((w,))
    bn4, bn4_stats = init_batch_norm((w,))
    encoder = LMPEncoderParams(
        encoder=init_lstm_stack(keys[0], config.pose_dim, config.encoder_hidden, config.encoder_layers),
        fc0=init_linear(keys[1], config.encoder_hidden, w), bn1=bn1, act2=init_prelu(),
        fc3=init_linear(keys[2], w, w), bn4=bn4, act5=init_prelu(),
        fc6=init_linear(keys[3], w, 2 * config.code_dim))
    d_in = config.trajectory_input
    keys = jax.random.split(k_traj, 7)
    trajectory = TrajectoryGeneratorParams(
        expand=init_linear(keys[0], d_in, d_in * (config.num_frames - 1)),
        embedding=init_linear(keys[1], d_in, h_t),
        rnn=init_lstm_stack(keys[2], h_t, h_t, config.trajectory_layers),
        out_fc0=init_linear(keys[3], h_t, h_t), out_fc1=init_linear(keys[4], h_t, h_t),
        out_fc2=init_linear(keys[5], h_t, h_t), out_fc=init_linear(keys[6], h_t, 3), activation=init_prelu())
    keys = jax.random.split(k_motion, 5)
    motion = MotionGeneratorParams(
        encoder_embedding=init_linear(keys[0], 3, h_m),
        encoder_rnn=init_lstm_stack(keys[1], h_m, h_m, config.motion_layers),
        embedding=init_linear(keys[2], config.decoder_input, h_m),
        rnn=init_lstm_stack(keys[3], h_m, h_m, config.motion_layers),
        out_fc=init_linear(keys[4], h_m, config.pose_dim), activation=init_prelu())
    return ODMOParams(trajectory, encoder, motion), ODMOStats(bn1_stats, bn4_stats)




# ------------------------------------------------------------------------------- the authors' state dict

_LSTM_NAMES = ("weight_ih", "weight_hh", "bias_ih", "bias_hh")


def _named(prefix: str, module) -> dict[str, jax.Array]:
    if isinstance(module, (LinearParams, BatchNormParams)):
        return {f"{prefix}.weight": module.weight, f"{prefix}.bias": module.bias}
    if isinstance(module, BatchNormStats):
        return {f"{prefix}.running_mean": module.running_mean, f"{prefix}.running_var": module.running_var}
    if isinstance(module, PReLUParams):
        return {f"{prefix}.weight": module.weight}
    # a tuple of LSTM layers: torch.nn.LSTM's weight_ih_l0, ...
    return {f"{prefix}.{name}_l{layer}": leaf for layer, p in enumerate(module)
            for name, leaf in zip(_LSTM_NAMES, p, strict=True)}


_ENCODER_NAMES = {"encoder": "encoder", "fc0": "fc.0", "bn1": "fc.1", "act2": "fc.2", "fc3": "fc.3", "bn4": "fc.4",
                  "act5": "fc.5", "fc6": "fc.6"}
_TRAJECTORY_NAMES = {"activation": "activation_fun"}
_MOTION_NAMES = {"activation": "relu"}


def _entries(params: ODMOParams, stats: ODMOStats | None = None) -> dict[str, jax.Array]:
    """Name -> leaf in the authors' naming; without ``stats`` the order is ``jax.tree.leaves(params)``'s."""
    out = {}
    for field, module in zip(params.trajectory._fields, params.trajectory):
        out |= _named(f"tgenerator.{_TRAJECTORY_NAMES.get(field, field)}", module)
    for field, module in zip(params.encoder._fields, params.encoder):
        out |= _named(f"LMPencoder.{_ENCODER_NAMES[field]}", module)
    for field, module in zip(params.motion._fields, params.motion):
        out |= _named(f"mgenerator.{_MOTION_NAMES.get(field, field)}", module)
    if stats is not None:
        out |= _named("LMPencoder.fc.1", stats.bn1) | _named("LMPencoder.fc.4", stats.bn4)
    return out


def state_dict(params: ODMOParams, stats: ODMOStats | None = None) -> dict[str, np.ndarray]:
    """The parameters (and running statistics) under the authors' ``Ensemble.state_dict()`` names, as numpy
    arrays: load them into the PyTorch model with ``load_state_dict(..., strict=False)`` (the BatchNorm
    counters ``num_batches_tracked`` are not kept here)."""
    return {name: np.asarray(leaf) for name, leaf in _entries(params, stats).items()}


def load_state_dict(arrays, config: ODMOConfig) -> tuple[ODMOParams, ODMOStats]:
    """Parameters and running statistics from arrays under the authors' names (e.g. a converted
    ``torch.load`` of a released ``.pkg``); every name :func:`state_dict` gives must be there, with its shape."""
    like_params, like_stats = jax.eval_shape(lambda: init_odmo(jax.random.key(0), config))
    expected = _entries(like_params, like_stats)
    missing = sorted(set(expected) - set(arrays))
    if missing:
        raise ValueError(f"state dict: missing {len(missing)} arrays, e.g. {missing[:3]}")
    for name, like in expected.items():
        if tuple(np.shape(arrays[name])) != like.shape:
            raise ValueError(f"state dict: {name} has shape {tuple(np.shape(arrays[name]))}, expected {like.shape}")
    leaf = {name: jnp.asarray(arrays[name], jnp.float32) for name in expected}
    params = jax.tree.unflatten(jax.tree.structure(like_params), [leaf[name] for name in _entries(like_params)])
    stats = ODMOStats(*(BatchNormStats(leaf[f"LMPencoder.fc.{i}.running_mean"], leaf[f"LMPencoder.fc.{i}.running_var"])
                        for i in (1, 4)))
    return params, stats


# ------------------------------------------------------------------------------------------------ inputs


def flatten_poses(joints: jax.Array) -> jax.Array:
    """``joints [..., T, J, 3]`` -> ``[..., T, F]`` (joint-major)."""
    return joints.reshape(*joints.shape[:-2], -1)


def unflatten_poses(poses: jax.Array) -> jax.Array:
    """``[..., T, F]`` -> ``[..., T, J, 3]``."""
    return poses.reshape(*poses.shape[:-1], -1, 3)


def local_movement(poses: jax.Array) -> jax.Array:
    """The local movement profile: every joint minus its frame's root, ``[..., T, F] -> [..., T, F]``."""
    joints = unflatten_poses(poses)
    return flatten_poses(joints - joints[..., :1, :])


def condition(actions: jax.Array, code: jax.Array, num_classes: int) -> jax.Array:
    """The flattened outer product of the one-hot class and the code: ``[B], [B, Z] -> [B, C·Z]``."""
    one_hot = jax.nn.one_hot(actions, num_classes, dtype=code.dtype)
    return (one_hot[:, :, None] * code[:, None, :]).reshape(code.shape[0], -1)


def _check_poses(name: str, poses: jax.Array, config: ODMOConfig, frames: int | None = None) -> jax.Array:
    poses = jnp.asarray(poses, jnp.float32)
    t = "T" if frames is None else str(frames)
    if poses.ndim != 3 or poses.shape[-1] != config.pose_dim or (frames is not None and poses.shape[1] != frames):
        raise ValueError(f"{name}: expected [B, {t}, {config.pose_dim}] (B, T, F = 3 × {config.num_joints} joints), "
                         f"got {tuple(poses.shape)}")
    return poses


def _check_rows(name: str, array: jax.Array, batch: int, width: int) -> jax.Array:
    array = jnp.asarray(array, jnp.float32)
    if array.shape != (batch, width):
        raise ValueError(f"{name}: expected [{batch}, {width}], got {tuple(array.shape)}")
    return array


# ------------------------------------------------------------------------------------------------ encoder


def encode(config: ODMOConfig, params: ODMOParams, buffers: ODMOStats, poses: jax.Array, *, train: bool,
           groups: int = 1) -> tuple[jax.Array, jax.Array, ODMOStats]:
    """``poses [B, T, F]`` -> ``(µ [B, Z], logvar [B, Z], buffers)`` (``buffers``: the BatchNorm running
    statistics). ``train``: BatchNorm on the batch's
    statistics, the running ones updated and returned; otherwise on the running ones (the code's
    ``enable_eval``, used for mode discovery and sampling).

    ``groups``: the batch is that many consecutive equal parts that the code passes through the encoder one
    after the other (the two halves of ODMO's pairs): in train mode each part is normalised with its own
    statistics and the running ones move once per part, in order. Everything else is per sequence, so
    one pass over the whole batch gives the numbers of separate passes, in fewer, larger steps."""
    poses = _check_poses("poses", poses, config)
    if poses.shape[0] % groups:
        raise ValueError(f"groups: the batch of {poses.shape[0]} does not split into {groups} equal parts")
    p = params.encoder
    x = local_movement(poses) if config.lmp_input else poses
    _, final = lstm_stack(p.encoder, jnp.swapaxes(x, 0, 1))

    def norm(bn, bn_stats, h):
        parts = []
        for part in jnp.split(h, groups):
            part, bn_stats = batch_norm(bn, bn_stats, part, train=train)
            parts.append(part)
        return jnp.concatenate(parts), bn_stats

    h, bn1 = norm(p.bn1, buffers.bn1, linear(p.fc0, final.h[-1]))
    h, bn4 = norm(p.bn4, buffers.bn4, linear(p.fc3, prelu(p.act2, h)))
    mu, logvar = jnp.split(linear(p.fc6, prelu(p.act5, h)), 2, axis=-1)
    return mu, logvar, ODMOStats(bn1, bn4)


def sample_code(key: jax.Array, mu: jax.Array, logvar: jax.Array) -> jax.Array:
    """``z = µ + exp(logvar / 2)·ε``: ``[B, Z]`` -> ``[B, Z]``."""
    return mu + jnp.exp(0.5 * logvar) * jax.random.normal(key, mu.shape, mu.dtype)


# ------------------------------------------------------------------------------------------------ decoders


def trajectory_velocities(params: ODMOParams, code: jax.Array, actions: jax.Array, end: jax.Array,
                          config: ODMOConfig) -> jax.Array:
    """The trajectory generator: ``code [B, Z]``, ``actions [B]``, ``end [B, 3]`` (the end root; ignored
    without ``use_end``) -> root velocities ``[B, T−1, 3]``."""
    p = params.trajectory
    b = code.shape[0]
    if not config.use_end:
        end = jnp.zeros_like(end)
    x = jnp.concatenate([condition(actions, code, config.num_classes), end], -1)  # [B, in]
    x = prelu(p.activation, linear(p.expand, x)).reshape(b, config.num_frames - 1, -1)
    x = linear(p.embedding, x)
    hs, _ = lstm_stack(p.rnn, jnp.swapaxes(x, 0, 1))  # [T−1, B, H]
    x = jnp.swapaxes(hs, 0, 1)
    for layer in (p.out_fc0, p.out_fc1, p.out_fc2):
        x = prelu(p.activation, linear(layer, x))
    return linear(p.out_fc, x)


def integrate(velocities: jax.Array) -> jax.Array:
    """Positions from velocities, starting at the origin: ``[B, T−1, 3] -> [B, T, 3]``."""
    zeros = jnp.zeros_like(velocities[:, :1])
    return jnp.cumsum(jnp.concatenate([zeros, velocities], axis=1), axis=1)


def time_feature(num_frames: int) -> jax.Array:
    """The decoder's time input ``(t+1)/T`` for ``t = 0..T−1``, accumulated in float32 as the code adds
    ``1/T`` at every step: ``[T]``."""
    return jnp.cumsum(jnp.full((num_frames,), 1.0 / num_frames, jnp.float32))


def decode_motion(params: ODMOParams, code: jax.Array, actions: jax.Array, trajectory: jax.Array, config: ODMOConfig,
                  *, teacher: jax.Array | None = None, teacher_mask: jax.Array | None = None) -> jax.Array:
    """The motion generator: ``code [B, Z]``, ``actions [B]``, ``trajectory [B, T, 3]`` -> ``poses [B, T, F]``.

    ``teacher [B, T, F]`` and ``teacher_mask`` (bool, ``[T]`` shared by the batch or ``[T, B]``): where
    ``teacher_mask[t]``, step ``t + 1`` reads the true pose ``teacher[:, t]`` instead of the decoder's output
    ``t`` (teacher forcing; None: never).
    """
    p = params.motion
    b, t_len, f = code.shape[0], config.num_frames, config.pose_dim
    # trajectory encoder: its final state starts the decoder
    enc_in = prelu(p.activation, linear(p.encoder_embedding, trajectory))
    _, state = lstm_stack(p.encoder_rnn, jnp.swapaxes(enc_in, 0, 1))
    # the decoder embedding split by input block: previous pose, condition, time
    w = p.embedding.weight
    w_pose, w_cond, w_time = w[:, :f], w[:, f:f + config.condition_dim], w[:, -1]
    constant = condition(actions, code, config.num_classes) @ w_cond.T + p.embedding.bias  # [B, H]
    if teacher is None:
        teacher, teacher_mask = jnp.zeros((t_len, b, f), jnp.float32), jnp.zeros((t_len, 1), bool)
    else:
        teacher = jnp.swapaxes(teacher, 0, 1)
        teacher_mask = jnp.zeros((t_len,), bool) if teacher_mask is None else jnp.asarray(teacher_mask, bool)
        if teacher_mask.shape not in ((t_len,), (t_len, b)):
            raise ValueError(f"teacher_mask: expected [{t_len}] or [{t_len}, {b}] (T or T, B), got "
                             f"{tuple(teacher_mask.shape)}")
        teacher_mask = teacher_mask.reshape(t_len, -1)

    def step(carry, inputs):
        state, previous = carry
        time, true_pose, forced = inputs
        x = prelu(p.activation, previous @ w_pose.T + constant + time * w_time)
        state, top = lstm_stack_step(p.rnn, state, x)
        out = linear(p.out_fc, top)
        return (state, jnp.where(forced[:, None], true_pose, out)), out

    carry = (LSTMState(state.h, state.c), jnp.zeros((b, f), jnp.float32))
    _, poses = jax.lax.scan(recompute_on_cpu(step), carry, (time_feature(t_len), teacher, teacher_mask))
    return jnp.swapaxes(poses, 0, 1)


def generate(config: ODMOConfig, params: ODMOParams, code: jax.Array, actions: jax.Array, end: jax.Array
             ) -> dict[str, jax.Array]:
    """Motions from codes: ``code [B, Z]``, ``actions [B]`` (int), ``end [B, 3]`` (requested end root) ->
    ``poses [B, T, F]``, ``trajectory [B, T, 3]`` (the trajectory generator's), no teacher forcing."""
    code = jnp.asarray(code, jnp.float32)
    if code.ndim != 2 or code.shape[1] != config.code_dim:
        raise ValueError(f"code: expected [B, {config.code_dim}] (B, Z), got {tuple(code.shape)}")
    b = code.shape[0]
    check_actions(actions, config.num_classes, count=b)
    end = _check_rows("end", end, b, 3)
    trajectory = integrate(trajectory_velocities(params, code, actions, end, config))
    return {"poses": decode_motion(params, code, actions, trajectory, config), "trajectory": trajectory}


def forward(config: ODMOConfig, params: ODMOParams, buffers: ODMOStats, poses: jax.Array, actions: jax.Array, *,
            key: jax.Array, train: bool, teacher_mask: jax.Array | None = None, groups: int = 1
            ) -> dict[str, jax.Array]:
    """One pass of the autoencoder as the code's ``Ensemble.forward``: encode, sample ``z`` with ``key``,
    decode the trajectory with the true end root, then the motion on the predicted trajectory.

    ``poses [B, T, F]`` (a window, root of frame 0 at the origin), ``actions [B]``, ``teacher_mask [T]`` or
    ``[T, B]`` (see :func:`decode_motion`), ``groups`` (see :func:`encode`). Returns ``mu, logvar, code [B, Z]``, ``velocities [B, T−1, 3]``,
    ``trajectory [B, T, 3]`` (predicted), ``poses [B, T, F]`` (decoded) and ``buffers``.
    """
    poses = _check_poses("poses", poses, config, config.num_frames)
    check_actions(actions, config.num_classes, count=poses.shape[0])
    mu, logvar, buffers = encode(config, params, buffers, poses, train=train, groups=groups)
    code = sample_code(key, mu, logvar)
    velocities = trajectory_velocities(params, code, actions, poses[:, -1, :3], config)
    trajectory = integrate(velocities)
    decoded = decode_motion(params, code, actions, trajectory, config, teacher=poses, teacher_mask=teacher_mask)
    return {"mu": mu, "logvar": logvar, "code": code, "velocities": velocities, "trajectory": trajectory,
            "poses": decoded, "buffers": buffers}
