"""Action2Motion's GRU VAE (Guo et al. 2020), the recurrent baseline of ACTOR's Table 3, on joint coordinates.

Sources: A2M ``models/motion_vae.py`` (``GaussianGRU``, ``DecoderGRU``), ``trainer/vae_trainer.py`` (``train``,
``evaluate``, ``kl_criterion``, ``trainIters``), ``train_motion_vae.py`` and ``checkpoints/vae/*/opt.txt``. Only
the joint-coordinate ("xyz") variant is implemented, not the Lie-algebra decoder.

**Model.** Axes: ``B`` batch, ``T`` frames, ``F`` pose features (``J·3``, joint-major), ``C`` classes, ``H``
hidden, ``Z`` latent. At frame ``t`` the condition is

    c_t = [x_prev (F), one_hot(action) (C), t / (L − 1) (1, only with ``time_counter``)]

with ``x_prev = 0`` at ``t = 0`` and ``L`` the sequence length. Three recurrent nets, each a ``Linear`` embedding
to ``H`` (no activation after it), a stack of GRU cells started from zero hidden states, and linear heads:

* prior ``p(z_t | c_≤t)``: input ``c_t``; 1 GRU cell; heads ``mu_net``, ``logvar_net`` -> ``Z``.
* posterior ``q(z_t | ·)``: input ``[x_t, one_hot, time]``, i.e. the **current true pose in place of the previous
  pose** (the same input width as the prior; in the original the posterior does not see ``x_prev``); 1 GRU cell.
* decoder: input ``[c_t, z_t]`` (in that order); 2 stacked GRU cells; ``output`` Linear -> ``F``.

Training decodes ``z_t`` sampled from the posterior; the prior runs alongside only for the KL. Generation
samples ``z_t`` from the prior and feeds each output back as the next ``x_prev``.

**Loss** (``Trainer.train``). Per frame, ``nn.MSELoss`` averages over batch *and* features, while
``kl_criterion`` sums the element-wise Gaussian KL over batch and latent dimensions and divides by the batch
size. Both are summed over frames (not averaged; the logged values divide by ``T`` afterwards):

    loss = (1/B) Σ_b Σ_t [ (1/F) Σ_f (x_btf − x̂_btf)²  +  λ Σ_z KL(q_btz ‖ p_btz) ]

so the KL of a frame is a per-sample **sum** over the ``Z`` latent dimensions, where the reconstruction of a
frame is a per-sample **mean** over the ``F`` pose features. ``λ`` is :attr:`A2MVAEConfig.kl_weight`:
released xyz configurations (``vanila_vae_tf*``) use 1e-4 on every dataset; the Lie ones use 1e-3
(HumanAct12) and 1e-2 (NTU-13, CMU mocap). ``skip_prob`` (random frames left out of the loss) is 0 in all of
them and is not implemented.

**The feedback quirk.** The original draws ``random.random() < tf_ratio`` (0.6) **once per training iteration**;
when it holds, every frame of that batch gets the model's **own** previous output as ``x_prev`` (gradients flow
through it, it is not detached), otherwise the ground truth ``x_{t−1}`` — the opposite of what the name
"teacher forcing" suggests. :attr:`A2MVAEConfig.own_output_feedback` is that probability of feeding back the
own output (named for what it does, not after ``tf_ratio``). ``feedback_scope="sequence"`` (default) reproduces the code: one Bernoulli draw per loss call,
shared by all frames and all sequences of the batch. ``"step"`` draws once per frame (shared by the batch), for
experiments; it is not what the authors ran. The draws come from the ``key`` passed to :func:`a2m_vae_loss`.

**Additions to the original** (documented choices):

* ``mask [B, T]`` (True = real frame; sequences padded at the end, e.g. by repeating their last frame):
  masked frames add nothing to either term; the divisor stays ``B``. Because every net is causal, padding after
  a sequence's end cannot influence its real frames, so a padded batch gives the loss of the unpadded one.
* the time counter of each sequence uses its own length ``L_b`` (number of real frames), ``t / (L_b − 1)``, so
  that training on a padded batch sees the same counter as generating ``L_b`` frames. Without a mask
  ``L_b = T`` (the original, where all clips of a batch have ``motion_length`` frames). ``L = 1`` gives 0.
* per-frame random keys are ``fold_in(key, t)``, so a sequence's first frames draw the same noise whatever
  the padded length.
* the condition may be any ``[B, C]`` vector in place of the one-hot (class ids ``[B]`` still give the one-hot,
  with identical numbers), and frame 0's ``x_prev`` may be a given ``first_pose [B, F]`` instead of zeros
  (:func:`a2m_vae_forward`, :func:`a2m_vae_loss`, :func:`a2m_generate`; the defaults are the original).
  ``a2m_generate(key=None)`` decodes the prior's mean at every frame.

**Neural Marionette's adaptation** (its Table 1 and 3 baseline, §5.1.1: A2M "with two changes": 6D rotations
instead of the Lie representation, and "the same initial pose as our setting rather than a rest pose"; no
trajectory). One code path with the original, only the inputs differ: the pose is MARIONET's 135 numbers
(:func:`jaxmotion.geometry.representations.pose135`: 22 joints' 6D rotations + the root translation) in the
normalised frame of the last context pose, ``pose_dim = 135``; the condition is the action's multi-hot tags
``[B, 31]`` in place of the one-hot class; the initial pose is the last context pose, fed as ``x_prev`` at frame
0 instead of zeros, in training (``first_pose``) and generation. The next tag, the path and the other five context
frames are not given to it (the paper says nothing of them). :func:`a2m_continue` generates with MARIONET's
contract; the trainer is :func:`jaxmotion.train.a2m.train_a2m_actions`.

**Training configuration** (:class:`A2MOptimizer`; batch, clip length and steps in
:class:`jaxmotion.train.a2m.A2MTraining`): three torch ``Adam(lr 2e-4, betas (0.9, 0.999),
weight_decay 1e-5)`` optimisers, one per net (equivalent to one Adam over all parameters: Adam is per
element); torch's ``weight_decay`` is an L2 term added to the gradient before the Adam moments (not AdamW),
see :func:`a2m_optimizer`. Batch 128; FACTS gives 50k iterations (the paper), while the released xyz
``opt.txt`` files record ``iters`` 300k (NTU-13, mocap) and 500k (HumanAct12). Clip length: 60 frames
(CMU mocap 100). Note also that the released xyz runs have ``time_counter: False`` and the Lie runs ``True``;
the default here is ``True``.

Parameters mirror the PyTorch module names (``prior_net`` / ``posterior_net``: ``embed``, ``gru.{i}``,
``mu_net``, ``logvar_net``; ``decoder``: ``embed``, ``gru.{i}``, ``output``), with PyTorch's shapes and its
default initialisation (every weight and bias U(±1/√fan_in); for GRU cells fan_in = H).
"""

from __future__ import annotations

import dataclasses
from typing import Literal, NamedTuple

import jax
import jax.numpy as jnp
import numpy as np
import optax

from jaxmotion.data.labels import check_actions
from jaxmotion.nn.core import LinearParams, init_linear, linear
from jaxmotion.nn.recurrent import GRUParams, gru_stack_step, init_gru

# ------------------------------------------------------------------------------------------------- configs


@dataclasses.dataclass(frozen=True, kw_only=True)
class A2MVAEConfig:
    """Sizes and loss settings of the GRU VAE (defaults: the released configurations)."""

    pose_dim: int  # F = J·3 (HumanAct12 72, CMU mocap 60, NTU-13 54)
    num_classes: int  # C
    kl_weight: float  # λ; xyz runs 1e-4, Lie runs 1e-3 (HumanAct12) / 1e-2 (NTU-13, mocap)
    hidden: int = 128
    latent: int = 30
    prior_layers: int = 1
    posterior_layers: int = 1
    decoder_layers: int = 2
    time_counter: bool = True
    own_output_feedback: float = 0.6  # probability of feeding back the model's OWN previous output (``tf_ratio``)
    feedback_scope: Literal["sequence", "step"] = "sequence"

    def __post_init__(self):
        for name in ("pose_dim", "num_classes", "hidden", "latent", "prior_layers", "posterior_layers",
                     "decoder_layers"):
            value = getattr(self, name)
            if not isinstance(value, int) or value < 1:
                raise ValueError(f"{name}: expected a positive int, got {value!r}")
        if not self.kl_weight >= 0:
            raise ValueError(f"kl_weight: expected >= 0, got {self.kl_weight!r}")
        if not 0.0 <= self.own_output_feedback <= 1.0:
            raise ValueError(f"own_output_feedback: expected a probability in [0, 1], got {self.own_output_feedback!r}")
        if self.feedback_scope not in ("sequence", "step"):
            raise ValueError(f"feedback_scope: expected 'sequence' or 'step', got "
                             f"{self.feedback_scope!r}")

    @property
    def condition_dim(self) -> int:
        """Width of ``c_t`` (and of the posterior's input): ``F + C (+ 1)``."""
        return self.pose_dim + self.num_classes + int(self.time_counter)


@dataclasses.dataclass(frozen=True, kw_only=True)
class A2MOptimizer:
    """The authors' optimiser settings (``opt.txt``); batch size, clip length and the number of steps are
    :class:`jaxmotion.train.a2m.A2MTraining`'s."""

    learning_rate: float = 2e-4
    b1: float = 0.9
    b2: float = 0.999
    weight_decay: float = 1e-5  # torch Adam's coupled L2 (added to the gradient), not AdamW


def a2m_optimizer(config: A2MOptimizer) -> optax.GradientTransformation:
    """torch ``Adam(lr, betas, weight_decay)``: L2 ``weight_decay · θ`` added to the gradient, then Adam."""
    adam = optax.adam(config.learning_rate, b1=config.b1, b2=config.b2, eps=1e-8)
    if config.weight_decay:
        return optax.chain(optax.add_decayed_weights(config.weight_decay), adam)
    return adam


# ---------------------------------------------------------------------------------------------- parameters


class A2MGaussianGRUParams(NamedTuple):
    """``GaussianGRU``: prior or posterior net."""

    embed: LinearParams  # [H, D_in], [H]
    gru: tuple[GRUParams, ...]  # cells, input H, hidden H
    mu_net: LinearParams  # [Z, H], [Z]
    logvar_net: LinearParams  # [Z, H], [Z]


class A2MDecoderParams(NamedTuple):
    """``DecoderGRU``."""

    embed: LinearParams  # [H, D_in + Z], [H]
    gru: tuple[GRUParams, ...]
    output: LinearParams  # [F, H], [F]


class A2MVAEParams(NamedTuple):
    prior_net: A2MGaussianGRUParams
    posterior_net: A2MGaussianGRUParams
    decoder: A2MDecoderParams


def _init_gaussian_gru(key: jax.Array, in_dim: int, hidden: int, latent: int, layers: int) -> A2MGaussianGRUParams:
    k_embed, k_gru, k_mu, k_logvar = jax.random.split(key, 4)
    return A2MGaussianGRUParams(
        embed=init_linear(k_embed, in_dim, hidden),
        gru=tuple(init_gru(k, hidden, hidden) for k in jax.random.split(k_gru, layers)),
        mu_net=init_linear(k_mu, hidden, latent),
        logvar_net=init_linear(k_logvar, hidden, latent),
    )


def init_a2m_vae(key: jax.Array, config: A2MVAEConfig) -> A2MVAEParams:
    """Fresh parameters with PyTorch's default initialisation."""
    k_prior, k_post, k_dec = jax.random.split(key, 3)
    d_in, h = config.condition_dim, config.hidden
    k_embed, k_gru, k_out = jax.random.split(k_dec, 3)
    decoder = A2MDecoderParams(
        embed=init_linear(k_embed, d_in + config.latent, h),
        gru=tuple(init_gru(k, h, h) for k in jax.random.split(k_gru, config.decoder_layers)),
        output=init_linear(k_out, h, config.pose_dim),
    )
    return A2MVAEParams(
        prior_net=_init_gaussian_gru(k_prior, d_in, h, config.latent, config.prior_layers),
        posterior_net=_init_gaussian_gru(k_post, d_in, h, config.latent, config.posterior_layers),
        decoder=decoder,
    )




# ----------------------------------------------------------------------------------------------- functions


def gaussian_kl(mu1: jax.Array, logvar1: jax.Array, mu2: jax.Array, logvar2: jax.Array) -> jax.Array:
    """Element-wise ``KL(N(mu1, exp(logvar1)) ‖ N(mu2, exp(logvar2)))`` (no reduction)."""
    return (0.5 * (logvar2 - logvar1) + (jnp.exp(logvar1) + jnp.square(mu1 - mu2)) / (2.0 * jnp.exp(logvar2))
            - 0.5)


def _gaussian_step(p: A2MGaussianGRUParams, hs, x):
    hs, top = gru_stack_step(p.gru, hs, linear(p.embed, x))
    return hs, linear(p.mu_net, top), linear(p.logvar_net, top)


def _decoder_step(p: A2MDecoderParams, hs, x):
    hs, top = gru_stack_step(p.gru, hs, linear(p.embed, x))
    return hs, linear(p.output, top)


def _sample(key: jax.Array, mu: jax.Array, logvar: jax.Array) -> jax.Array:
    return mu + jnp.exp(0.5 * logvar) * jax.random.normal(key, mu.shape, mu.dtype)


def _zeros_state(batch: int, hidden: int, layers: int) -> tuple[jax.Array, ...]:
    return tuple(jnp.zeros((batch, hidden), jnp.float32) for _ in range(layers))


def _step_keys(key: jax.Array, num_frames: int) -> jax.Array:
    """One key per frame, ``fold_in(key, t)``: frame t's key does not depend on the number of frames."""
    return jax.vmap(jax.random.fold_in, (None, 0))(key, jnp.arange(num_frames))


def _time_counter(lengths: jax.Array, num_frames: int) -> jax.Array:
    """``lengths [B]`` -> ``[T, B, 1]`` with ``t / (L_b − 1)`` (0 where ``L_b <= 1``)."""
    t = jnp.arange(num_frames, dtype=jnp.float32)[:, None]
    denom = jnp.maximum(lengths.astype(jnp.float32) - 1.0, 1.0)[None, :]
    return (t / denom)[..., None]


def _feedback_draws(key: jax.Array, config: A2MVAEConfig, num_frames: int) -> jax.Array:
    """``[T]`` bool: True where frame t's output (not the ground truth) becomes frame t + 1's ``x_prev``."""
    if config.feedback_scope == "sequence":
        return jnp.broadcast_to(jax.random.bernoulli(key, config.own_output_feedback), (num_frames,))
    return jax.random.bernoulli(key, config.own_output_feedback, (num_frames,))


def a2m_vae_forward(config: A2MVAEConfig, params: A2MVAEParams, poses: jax.Array, actions: jax.Array, *,
                    key: jax.Array, mask: jax.Array | None = None,
                    first_pose: jax.Array | None = None) -> dict[str, jax.Array]:
    """Training-mode pass: posterior samples, decoding with the feedback quirk, prior alongside.

    ``poses [B, T, F]``, ``actions``: class ids ``[B]`` (int; one-hot, the original) or a condition ``[B, C]``
    (bool or float, e.g. multi-hot tags; used as is in place of the one-hot), ``mask [B, T]`` (bool, True = real
    frame; None = all real), ``first_pose [B, F]``: frame 0's ``x_prev`` (None: zeros, the original).
    ``key`` is split into the feedback draw(s) and the per-frame posterior noise.

    Returns ``recon [B, T, F]`` (decoded poses), ``mu_q, logvar_q, mu_p, logvar_p [B, T, Z]``,
    ``feedback [T]`` (bool, True where frame t's ``x_prev`` was the model's own output; frame 0 always gets
    ``first_pose``) and ``mask [B, T]``.
    """
    poses = jnp.asarray(poses)
    if poses.ndim != 3 or poses.shape[-1] != config.pose_dim or poses.shape[1] < 1:
        raise ValueError(f"poses: expected shape [B, T, {config.pose_dim}] (B, T >= 1, F = pose_dim), "
                         f"got {poses.shape}")
    b, t_len, _ = poses.shape
    condition = _condition(actions, config.num_classes, count=b)
    first_pose = _first_pose(first_pose, config.pose_dim, b)
    if mask is None:
        mask = jnp.ones((b, t_len), bool)
    else:
        mask = jnp.asarray(mask)
        if mask.shape != (b, t_len):
            raise ValueError(f"mask: expected shape [{b}, {t_len}] (B, T), got {mask.shape}")
        mask = mask.astype(bool)
    poses = poses.astype(jnp.float32)

    k_feedback, k_noise = jax.random.split(key)
    own = _feedback_draws(k_feedback, config, t_len)

    poses_t = jnp.swapaxes(poses, 0, 1)  # [T, B, F]
    if config.time_counter:
        extras = _time_counter(mask.sum(1), t_len)  # [T, B, 1]
    else:
        extras = jnp.zeros((t_len, b, 0), jnp.float32)

    def step(carry, inputs):
        h_prior, h_post, h_dec, x_prev = carry
        x_t, extra_t, key_t, own_t = inputs
        label = jnp.concatenate([condition, extra_t], -1)
        cond = jnp.concatenate([x_prev, label], -1)
        h_post, mu_q, logvar_q = _gaussian_step(params.posterior_net, h_post, jnp.concatenate([x_t, label], -1))
        h_prior, mu_p, logvar_p = _gaussian_step(params.prior_net, h_prior, cond)
        z = _sample(key_t, mu_q, logvar_q)
        h_dec, x_hat = _decoder_step(params.decoder, h_dec, jnp.concatenate([cond, z], -1))
        x_next = jnp.where(own_t, x_hat, x_t)
        return (h_prior, h_post, h_dec, x_next), (x_hat, mu_q, logvar_q, mu_p, logvar_p)

    h = config.hidden
    carry = (_zeros_state(b, h, config.prior_layers), _zeros_state(b, h, config.posterior_layers),
             _zeros_state(b, h, config.decoder_layers), first_pose)
    # own[t] decides what becomes x_prev of frame t + 1; shift so that ``feedback[t]`` describes frame t.
    _, outs = jax.lax.scan(step, carry, (poses_t, extras, _step_keys(k_noise, t_len), own))
    recon, mu_q, logvar_q, mu_p, logvar_p = (jnp.swapaxes(o, 0, 1) for o in outs)
    feedback = jnp.concatenate([jnp.zeros((1,), bool), own[:-1]])
    return dict(recon=recon, mu_q=mu_q, logvar_q=logvar_q, mu_p=mu_p, logvar_p=logvar_p, feedback=feedback,
                mask=mask)


def a2m_vae_loss(config: A2MVAEConfig, params: A2MVAEParams, poses: jax.Array, actions: jax.Array, *,
                 key: jax.Array, mask: jax.Array | None = None,
                 first_pose: jax.Array | None = None) -> tuple[jax.Array, dict[str, jax.Array]]:
    """``(loss, metrics)`` of a batch; see the module docstring for the exact normalisation.

    ``poses [B, T, F]``, ``actions [B]`` (int) or ``[B, C]`` (a condition), ``mask [B, T]`` (bool, True = real
    frame; None = all real), ``first_pose [B, F]`` (None: zeros), as in :func:`a2m_vae_forward`.
    ``metrics``: ``loss``, ``recon`` (Σ_t MSE), ``kl`` (Σ_t KL / B, before λ), and the per-frame averages the
    authors log, ``loss_per_frame``, ``recon_per_frame``, ``kl_per_frame`` (divided by the mean number of
    real frames per sequence, which is ``T`` without a mask).
    """
    out = a2m_vae_forward(config, params, poses, actions, key=key, mask=mask, first_pose=first_pose)
    b = out["recon"].shape[0]
    m = out["mask"].astype(jnp.float32)  # [B, T]
    se = jnp.square(out["recon"] - jnp.asarray(poses, jnp.float32)).mean(-1)  # [B, T]
    kl = gaussian_kl(out["mu_q"], out["logvar_q"], out["mu_p"], out["logvar_p"]).sum(-1)  # [B, T]
    recon = (se * m).sum() / b
    kl = (kl * m).sum() / b
    loss = recon + config.kl_weight * kl
    frames = jnp.maximum(m.sum() / b, 1.0)
    metrics = dict(loss=loss, recon=recon, kl=kl, loss_per_frame=loss / frames, recon_per_frame=recon / frames,
                   kl_per_frame=kl / frames)
    return loss, metrics


def a2m_generate(config: A2MVAEConfig, params: A2MVAEParams, actions: jax.Array, num_frames: int, *,
                 key: jax.Array | None, first_pose: jax.Array | None = None) -> jax.Array:
    """Sample motions: ``actions`` (class ids ``[B]`` or a condition ``[B, C]``, as in :func:`a2m_vae_forward`)
    -> ``poses [B, num_frames, F]``.

    ``z_t`` from the learned prior (``key`` None: its mean), each output fed back as the next ``x_prev``
    (``first_pose [B, F]`` at frame 0; None: zeros, the original), time counter ``t / (num_frames − 1)``.
    ``num_frames`` is a Python int (static under ``jit``).
    """
    if not isinstance(num_frames, int) or num_frames < 1:
        raise ValueError(f"num_frames: expected a positive int, got {num_frames!r}")
    condition = _condition(actions, config.num_classes)
    b = condition.shape[0]
    first_pose = _first_pose(first_pose, config.pose_dim, b)
    return _prior_rollout(config, params, condition, first_pose, jnp.full((b,), num_frames), num_frames, key)


def _condition(actions, num_classes: int, *, count: int | None = None, where: str = "actions") -> jax.Array:
    """The per-sequence condition ``[B, C]`` (float32): class ids ``[B]`` (int) -> their one-hot (the original);
    a bool or float ``[B, C]`` (multi-hot tags, Neural Marionette's adaptation) -> itself."""
    dtype = actions.dtype if hasattr(actions, "dtype") else np.asarray(actions).dtype
    if np.ndim(actions) == 2 and (jnp.issubdtype(dtype, jnp.floating) or jnp.issubdtype(dtype, jnp.bool_)):
        shape = np.shape(actions)
        if shape[1] != num_classes or (count is not None and shape[0] != count):
            rows = "B" if count is None else count
            raise ValueError(f"{where}: expected a [{rows}, {num_classes}] condition (one column per class) or "
                             f"[{rows}] integer class ids, got {dtype} {tuple(shape)}")
        return jnp.asarray(actions, jnp.float32)
    check_actions(actions, num_classes, count=count, where=where)
    return jax.nn.one_hot(jnp.asarray(actions), num_classes, dtype=jnp.float32)


def _first_pose(first_pose, pose_dim: int, batch: int) -> jax.Array:
    """Frame 0's ``x_prev [B, F]``: ``first_pose`` or zeros (the original's rest pose)."""
    if first_pose is None:
        return jnp.zeros((batch, pose_dim), jnp.float32)
    if np.shape(first_pose) != (batch, pose_dim):
        raise ValueError(f"first_pose: expected shape [{batch}, {pose_dim}] (B, F = pose_dim), got "
                         f"{tuple(np.shape(first_pose))}")
    return jnp.asarray(first_pose, jnp.float32)


def _prior_rollout(config: A2MVAEConfig, params: A2MVAEParams, condition: jax.Array, first_pose: jax.Array,
                   lengths: jax.Array, num_frames: int, key: jax.Array | None) -> jax.Array:
    """Generation: ``condition [B, C]``, ``first_pose [B, F]``, ``lengths [B]`` (each row's time counter runs over
    its own length) -> ``poses [B, num_frames, F]``; ``z_t`` sampled from the prior with ``fold_in(key, t)``, or
    its mean where ``key`` is None."""
    b = condition.shape[0]
    if config.time_counter:
        extras = _time_counter(lengths, num_frames)
    else:
        extras = jnp.zeros((num_frames, b, 0), jnp.float32)

    def step(carry, inputs):
        h_prior, h_dec, x_prev = carry
        extra_t, key_t = inputs
        cond = jnp.concatenate([x_prev, condition, extra_t], -1)
        h_prior, mu_p, logvar_p = _gaussian_step(params.prior_net, h_prior, cond)
        z = mu_p if key_t is None else _sample(key_t, mu_p, logvar_p)
        h_dec, x_hat = _decoder_step(params.decoder, h_dec, jnp.concatenate([cond, z], -1))
        return (h_prior, h_dec, x_hat), x_hat

    carry = (_zeros_state(b, config.hidden, config.prior_layers),
             _zeros_state(b, config.hidden, config.decoder_layers), first_pose)
    keys = None if key is None else _step_keys(key, num_frames)
    _, poses = jax.lax.scan(step, carry, (extras, keys), length=num_frames)
    return jnp.swapaxes(poses, 0, 1)


# ------------------------------------------------------------------------- Neural Marionette's adaptation


def a2m_continue(params: A2MVAEParams, config: A2MVAEConfig, context: jax.Array, tags: jax.Array,
                 next_tags: jax.Array, path: jax.Array, mask: jax.Array, key: jax.Array | None = None) -> jax.Array:
    """The adapted A2M of Neural Marionette's Table 1 continuing a motion, with MARIONET's contract
    (:func:`jaxmotion.models.marionet.generate`): ``context [B, K, F]`` (K = 6 there; poses in the normalised
    frame of the last one), ``tags [B, C]`` (multi-hot, the condition), ``next_tags [B, C]``, ``path [B, T, 2]``,
    ``mask [B, T]`` (bool, each action's duration as its first frames) -> ``poses [B, T, F]``, zero on padding.

    Generation from the prior (:func:`a2m_generate`) with the last context pose as frame 0's ``x_prev`` (the
    "initial pose" the paper gives A2M in place of the rest pose) and the time counter over each action's own
    duration (``mask.sum(1)``), so an action's frames do not depend on the batch's longest. ``next_tags``, ``path``
    and the context before its last pose are **not** given to A2M (the paper gives it no trajectory; the rest is
    unspecified): they are checked for shape and ignored. ``key`` None: ``z_t`` = the prior's mean at every frame
    (MARIONET's ``Z = mu`` reading). ``config`` is static under ``jit``.
    """
    context = jnp.asarray(context)
    if context.ndim != 3 or context.shape[1] < 1 or context.shape[2] != config.pose_dim:
        raise ValueError(f"context: expected shape [B, K, {config.pose_dim}] (K >= 1 frames, F = pose_dim), got "
                         f"{context.shape}")
    b = context.shape[0]
    condition = _condition(tags, config.num_classes, count=b, where="tags")
    if np.shape(next_tags) != (b, config.num_classes):
        raise ValueError(f"next_tags: expected shape [{b}, {config.num_classes}] (B, C), got "
                         f"{tuple(np.shape(next_tags))}")
    if np.ndim(mask) != 2 or np.shape(mask)[0] != b or np.shape(mask)[1] < 1:
        raise ValueError(f"mask: expected shape [{b}, T] (B, T >= 1 frames), got {tuple(np.shape(mask))}")
    frames = np.shape(mask)[1]
    if np.shape(path) != (b, frames, 2):
        raise ValueError(f"path: expected shape [{b}, {frames}, 2] (B, T, ground x and z), got {tuple(np.shape(path))}")
    mask = jnp.asarray(mask).astype(bool)
    poses = _prior_rollout(config, params, condition, context[:, -1].astype(jnp.float32), mask.sum(1), frames, key)
    return jnp.where(mask[..., None], poses, 0.0)
