"""A PyTorch MARIONET (Neural Marionette's single-action generator) of the same architecture as
``jaxmotion.models.marionet``: the peer that ``benchmarks/bench_marionet.py`` times against the library in the
same run.

Benchmark-only: it needs ``torch`` (``pip install -e ".[bench]"``), which is neither a runtime nor a test
dependency of jaxmotion, and nothing in ``jaxmotion/`` or ``tests/`` imports this file.

Written from the paper (Wang et al., 2022, §4.2, Fig. 3, Eqs. 1-2 and the supplement's Table 2) as
``shared/reference/MARIONETTE.md`` §1.4-1.6 reads it, with the choices the paper leaves open taken as
``jaxmotion.models.marionet.MarionetConfig`` documents them; not copied from any code. Submodules are named as the
fields of jaxmotion's ``MarionetParams`` (``pose_embedding``, ``encoder.layers.{i}``, ``unroll``, ``path``,
``decoder``, ``pose_head`` ...) and the Transformer blocks are torch's own ``nn.TransformerEncoder`` /
``nn.TransformerDecoder`` (batch first, post-norm, no final norm), so the state dict
``jaxmotion.nn.transformer.state_dict`` makes of jaxmotion's parameters loads with ``strict=True``
(:func:`marionet_state_dict`, :func:`build_peer`).

The model (batch first; masks are True on real frames, negated for torch's ``key_padding_mask``):

* **Condition encoder**: 8 tokens, the 6 context poses through the pose embedding (Linear 135 -> d, ReLU), the
  action's tags and the next action's tags (multi-hot) through the tag embedding (Linear C -> d, ReLU); a
  sinusoidal position code 0..7 added, dropout, a 2-layer encoder (GELU); the tag token's output through two
  Linear layers gives mu and log sigma^2; ``Z = mu + sigma eps`` in training, ``Z = mu`` in eval mode.
* **Time unrolling**: queries = the reverse position code (T .. 1, the frames left) + the tag embedding,
  dropout; memory = Z alone; a 2-layer decoder (ReLU) whose self-attention masks the padded frames as keys; its
  outputs through Linear d -> d - 32 and a ReLU.
* **Path**: Linear 2 -> 32 and a ReLU per frame, then a 1-layer, 1-head, 32-wide encoder (ReLU, FF 64) with the
  padded frames masked; joined to the unrolled latents as the frame controls ``[B, T, d]``.
* **Motion decoder**: the previous poses (the last context pose, then the action's) through the shared pose
  embedding, plus a forward position code, dropout; a 6-layer causal decoder (GELU) cross-attending to the
  controls, both padding masks on; Linear d -> 135; padded frames zero.
* **Generation** (:func:`generate`) as the paper describes it (§4.2.3): one frame at a time, each new pose fed
  back and the whole causal decoder run again over every frame so far (no key/value cache).
* **Training** (:func:`train_step`): the loss of ``jaxmotion.losses.marionet`` (L_R, L_D, L_J each with its
  velocity term, weights 1 / 0.5 / 2 and lambda_V 2; KL summed, 1e-8; L_J on forward kinematics of the 6D
  rotations on the SMPL-24 skeleton about the root) on the teacher-forced pass and, while scheduled sampling is
  on and the first pass is within ``gate``, on a second pass of the decoder over a per-frame mix of true and
  predicted (detached) poses, weighted 0.1 / 0.9, as ``jaxmotion.train.marionet.marionet_step`` does; Adam 1e-4.
  The inputs are made from a pipeline batch of action items here too (:func:`marionet_inputs`: normalised at the
  last context pose, facing +Z over the origin, the 135-number pose, the ground path for root-motion tags).

Geometry helpers (Rodrigues, 6D Gram-Schmidt, forward kinematics) and the shared loss kernels are the ACTOR
peer's (``benchmarks/peers/actor_torch.py``), all plain torch.

Axes: B actions, K context frames, T frames, C tags, d width.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
import torch
from torch import nn
from torch.nn import functional as F

from benchmarks.peers.actor_torch import (axis_angle_to_matrix, forward_kinematics, kl_to_standard_normal,
                                          masked_mse, rot6d_to_matrix)

CONTEXT = 6
BODY_JOINTS = 22
POSE_SIZE = BODY_JOINTS * 6 + 3  # 135
STACKS = ("encoder", "unroll", "path", "decoder")  # the submodules that are layer stacks

# ---------------------------------------------------------------------------------------------- model


class Sinusoid(nn.Module):
    """Sinusoidal codes of (float) positions ``[N]`` -> ``[N, d]``: column 2i sin(p / 10000^(2i/d)), column
    2i+1 the cosine of the same angle, computed in float32 as jaxmotion's ``sinusoidal_encoding``."""

    def __init__(self, dim: int):
        super().__init__()
        column = np.arange(dim)
        inv_freq = np.exp((column - column % 2) * (-math.log(10000.0) / dim)).astype(np.float32)
        self.register_buffer("inv_freq", torch.from_numpy(inv_freq), persistent=False)
        self.register_buffer("even", torch.from_numpy(column % 2 == 0), persistent=False)

    def forward(self, positions: torch.Tensor) -> torch.Tensor:
        angle = positions.to(torch.float32)[:, None] * self.inv_freq
        return torch.where(self.even, torch.sin(angle), torch.cos(angle))


class MarionetPeer(nn.Module):
    """MARIONET; the arguments are ``MarionetConfig``'s fields (its defaults: the supplement's Table 2)."""

    def __init__(self, num_tags: int = 31, width: int = 256, heads: int = 8, ff: int = 1024, encoder_layers: int = 2,
                 unroll_layers: int = 2, decoder_layers: int = 6, path_width: int = 32, path_layers: int = 1,
                 encoder_dropout: float = 0.1, unroll_dropout: float = 0.01, decoder_dropout: float = 0.1,
                 path_dropout: float = 0.001, time_unrolling: bool = True, tag_injection: bool = True,
                 next_tag: bool = True):
        super().__init__()
        d = width
        self.width, self.time_unrolling, self.tag_injection, self.next_tag = d, time_unrolling, tag_injection, next_tag
        self.pose_embedding = nn.Linear(POSE_SIZE, d)
        self.tag_embedding = nn.Linear(num_tags, d)
        self.encoder = nn.TransformerEncoder(
            nn.TransformerEncoderLayer(d, heads, ff, encoder_dropout, activation="gelu", batch_first=True),
            encoder_layers, enable_nested_tensor=False)
        self.mu = nn.Linear(d, d)
        self.log_variance = nn.Linear(d, d)
        self.unroll = nn.TransformerDecoder(
            nn.TransformerDecoderLayer(d, heads, ff, unroll_dropout, activation="relu", batch_first=True),
            unroll_layers)
        self.unroll_embedding = nn.Linear(d, d - path_width)
        self.path_embedding = nn.Linear(2, path_width)
        self.path = None if not path_layers else nn.TransformerEncoder(
            nn.TransformerEncoderLayer(path_width, 1, 2 * path_width, path_dropout, activation="relu",
                                       batch_first=True),
            path_layers, enable_nested_tensor=False)
        self.decoder = nn.TransformerDecoder(
            nn.TransformerDecoderLayer(d, heads, ff, decoder_dropout, activation="gelu", batch_first=True),
            decoder_layers)
        self.pose_head = nn.Linear(d, POSE_SIZE)
        self.positions = Sinusoid(d)
        self.encoder_input_dropout = nn.Dropout(encoder_dropout)
        self.unroll_input_dropout = nn.Dropout(unroll_dropout)
        self.decoder_input_dropout = nn.Dropout(decoder_dropout)

    def embed_tags(self, tags: torch.Tensor) -> torch.Tensor:
        return F.relu(self.tag_embedding(tags.to(torch.float32)))

    def encode(self, context: torch.Tensor, tags: torch.Tensor, next_tags: torch.Tensor):
        """``context [B, K, 135]``, ``tags``, ``next_tags [B, C]`` -> ``(mu, log_variance) [B, d]``."""
        if not self.next_tag:
            next_tags = torch.zeros_like(next_tags)
        tokens = torch.cat([F.relu(self.pose_embedding(context)), self.embed_tags(tags)[:, None],
                            self.embed_tags(next_tags)[:, None]], dim=1)  # [B, K + 2, d]
        tokens = tokens + self.positions(torch.arange(tokens.shape[1]))
        pooled = self.encoder(self.encoder_input_dropout(tokens))[:, context.shape[1]]  # the tag token
        return self.mu(pooled), self.log_variance(pooled)

    def controls(self, z: torch.Tensor, tags: torch.Tensor, path: torch.Tensor, mask: torch.Tensor) -> torch.Tensor:
        """``z [B, d]``, ``tags [B, C]``, ``path [B, T, 2]``, ``mask [B, T]`` -> frame controls ``[B, T, d]``."""
        batch, frames = mask.shape
        if self.time_unrolling:
            remaining = mask.sum(1, keepdim=True) - torch.arange(frames)  # T .. 1, then <= 0 on padding
            queries = self.positions(remaining.reshape(-1)).reshape(batch, frames, self.width)
            if self.tag_injection:
                queries = queries + self.embed_tags(tags)[:, None]
            latents = self.unroll(self.unroll_input_dropout(queries), z[:, None], tgt_key_padding_mask=~mask)
        else:
            latents = z[:, None].expand(batch, frames, self.width)
        unrolled = F.relu(self.unroll_embedding(latents))
        steps = F.relu(self.path_embedding(path))
        if self.path is not None:
            steps = self.path(steps, src_key_padding_mask=~mask)
        return torch.cat([unrolled, steps], dim=-1)

    def decode(self, controls: torch.Tensor, previous: torch.Tensor, mask: torch.Tensor,
               memory_mask: torch.Tensor | None = None) -> torch.Tensor:
        """Motion decoder, one causal pass: ``previous [B, n, 135]`` (the pose before each frame) -> poses
        ``[B, n, 135]``, zero where ``mask [B, n]`` is False; ``memory_mask [B, T]`` the controls' (default
        ``mask``: n = T)."""
        length = previous.shape[1]
        tokens = F.relu(self.pose_embedding(previous)) + self.positions(torch.arange(length))
        causal = torch.ones(length, length, dtype=torch.bool).triu(1)  # True = not allowed
        out = self.decoder(self.decoder_input_dropout(tokens), controls, tgt_mask=causal, tgt_is_causal=True,
                           tgt_key_padding_mask=~mask,
                           memory_key_padding_mask=~(mask if memory_mask is None else memory_mask))
        return self.pose_head(out).masked_fill(~mask[..., None], 0.0)

    def forward(self, context, tags, next_tags, path, target, mask, eps: torch.Tensor | None = None) -> dict:
        """Teacher forced: ``target [B, T, 135]`` the true poses -> ``{"poses", "mu", "log_variance",
        "controls"}``. Z = mu + sigma eps in training (``eps`` drawn when None), mu in eval mode."""
        mu, log_variance = self.encode(context, tags, next_tags)
        if self.training:
            eps = torch.randn_like(mu) if eps is None else eps
            z = mu + torch.exp(0.5 * log_variance) * eps
        else:
            z = mu
        controls = self.controls(z, tags, path, mask)
        previous = torch.cat([context[:, -1:], target[:, :-1]], dim=1)
        return {"poses": self.decode(controls, previous, mask), "mu": mu, "log_variance": log_variance,
                "controls": controls}


def marionet_state_dict(params) -> dict[str, np.ndarray]:
    """jaxmotion's ``MarionetParams`` as the peer's state dict (its field names are the peer's submodules; the
    layer stacks as torch's ``layers.{i}.``), copied to writable float32 arrays."""
    from jaxmotion.nn.transformer import state_dict  # the benchmark's side; the peer itself needs only torch

    weights = {}
    for name in params._fields:
        value = getattr(params, name)
        if value is not None:
            weights.update(state_dict(value, f"{name}.", stacked=name in STACKS))
    return {name: np.array(value, np.float32, copy=True) for name, value in weights.items()}


def build_peer(config, params=None) -> MarionetPeer:
    """The peer at ``config``'s sizes (a ``MarionetConfig``), holding a copy of ``params`` (``MarionetParams``;
    None: torch's own initialisation), loaded with ``strict=True``."""
    if config.latent != "log_variance":
        raise ValueError("the PyTorch peer regresses log sigma^2, as MarionetConfig's only latent")
    fields = ("num_tags", "width", "heads", "ff", "encoder_layers", "unroll_layers", "decoder_layers", "path_width",
              "path_layers", "encoder_dropout", "unroll_dropout", "decoder_dropout", "path_dropout",
              "time_unrolling", "tag_injection", "next_tag")
    model = MarionetPeer(**{name: getattr(config, name) for name in fields})
    if params is not None:
        model.load_state_dict({name: torch.from_numpy(value) for name, value in marionet_state_dict(params).items()},
                              strict=True)
    return model


# --------------------------------------------------------------------------------------------- inputs


def marionet_inputs(batch: dict[str, torch.Tensor], root_tags: torch.Tensor) -> dict[str, torch.Tensor]:
    """A pipeline batch of action items (axis-angle ``rotations [B, K + T, 24, 3]``, ``translation [B, K + T, 3]``,
    ``mask [B, K + T]``, ``tags``, ``next_tags [B, C]`` bool) -> ``context [B, K, 135]``, ``target [B, T, 135]``,
    ``mask [B, T]``, ``path [B, T, 2]``, ``tags``, ``next_tags``: every frame moved by the rigid map that turns
    the last context pose to face +Z (about +Y) and puts its root over the origin (the height kept); the ground
    path is the normalised root's (x, z) for actions with a root-motion tag (``root_tags [C]``), else zeros."""
    rotations, translation = batch["rotations"], batch["translation"]
    matrices = axis_angle_to_matrix(rotations[:, :, :BODY_JOINTS])  # [B, F, 22, 3, 3]
    last_root, last_place = matrices[:, CONTEXT - 1, 0], translation[:, CONTEXT - 1]
    heading = last_root[..., :, 2]  # R e_z
    yaw = torch.atan2(heading[..., 0], heading[..., 2])
    c, s = torch.cos(yaw), torch.sin(yaw)
    zero, one = torch.zeros_like(c), torch.ones_like(c)
    turn = torch.stack([torch.stack([c, zero, -s], -1), torch.stack([zero, one, zero], -1),
                        torch.stack([s, zero, c], -1)], -2)  # [B, 3, 3], R_y(-yaw)
    shift = -(turn @ (last_place * last_place.new_tensor([1.0, 0.0, 1.0]))[..., None])[..., 0]
    root = turn[:, None] @ matrices[:, :, 0]  # [B, F, 3, 3]
    matrices = torch.cat([root[:, :, None], matrices[:, :, 1:]], dim=2)
    moved = (turn[:, None] @ translation[..., None])[..., 0] + shift[:, None]
    poses = torch.cat([matrices[..., :2, :].reshape(*matrices.shape[:2], BODY_JOINTS * 6), moved], dim=-1)
    mask = batch["mask"][:, CONTEXT:]
    moves = (batch["tags"] & root_tags).any(-1)
    ground = poses[:, CONTEXT:, POSE_SIZE - 3:][..., [0, 2]]
    path = torch.where((moves[:, None] & mask)[..., None], ground, torch.zeros_like(ground))
    return {"context": poses[:, :CONTEXT], "target": poses[:, CONTEXT:], "mask": mask, "path": path,
            "tags": batch["tags"], "next_tags": batch["next_tags"]}


# --------------------------------------------------------------------------------------------- losses


class LossWeights:
    """lambda_R, lambda_D, lambda_J, lambda_V, lambda_KL (the supplement's; ``MarionetLossWeights``)."""

    def __init__(self, rotations: float = 1.0, translation: float = 0.5, joints: float = 2.0, velocity: float = 2.0,
                 kl: float = 1e-8):
        self.rotations, self.translation, self.joints, self.velocity, self.kl = (rotations, translation, joints,
                                                                                 velocity, kl)


class Skeleton:
    """SMPL-24's ``parents`` (root -1 first) and rest ``offsets [24, 3]``."""

    def __init__(self, parents: Sequence[int], offsets):
        self.parents = tuple(int(p) for p in parents)
        self.offsets = torch.from_numpy(np.array(offsets, np.float32))

    def local_joints(self, poses: torch.Tensor) -> torch.Tensor:
        """``poses [B, T, 135]`` -> joints ``[B, T, 24, 3]`` about the root: the 22 body joints' 6D rotations
        orthonormalised, the hands at rest, forward kinematics with the root at the origin."""
        body = rot6d_to_matrix(poses[..., :BODY_JOINTS * 6].reshape(*poses.shape[:2], BODY_JOINTS, 6))
        hands = torch.eye(3).expand(*poses.shape[:2], len(self.parents) - BODY_JOINTS, 3, 3)
        return forward_kinematics(torch.cat([body, hands], dim=2), self.offsets, self.parents)


def masked_velocity_mse(prediction: torch.Tensor, target: torch.Tensor, mask: torch.Tensor) -> torch.Tensor:
    """:func:`masked_mse` of frame-to-frame differences over the pairs of consecutive real frames."""
    return masked_mse(prediction.diff(dim=1), target.diff(dim=1), mask[:, 1:] & mask[:, :-1])


def reconstruction(prediction, target, mask, weights: LossWeights, skeleton: Skeleton):
    """L_Recon = lambda_R L_R + lambda_D L_D + lambda_J L_J, each with its velocity term -> ``(value, terms)``."""
    split = BODY_JOINTS * 6
    parts = {"rotations": (prediction[..., :split], target[..., :split]),
             "translation": (prediction[..., split:], target[..., split:]),
             "joints": (skeleton.local_joints(prediction), skeleton.local_joints(target))}
    terms = {name: masked_mse(p, t, mask) + weights.velocity * masked_velocity_mse(p, t, mask)
             for name, (p, t) in parts.items()}
    return sum(getattr(weights, name) * value for name, value in terms.items()), terms


def marionet_loss(first, second, target, mask, mu, log_variance, *, weights: LossWeights, skeleton: Skeleton,
                  first_weight: float = 1.0, second_weight: float = 0.0):
    """Eq. 2: ``first_weight L_Recon(first) + second_weight L_Recon(second) + lambda_KL KL`` -> ``(loss, terms)``."""
    total, terms = reconstruction(first, target, mask, weights, skeleton)
    total = first_weight * total
    if second is not None:
        again, second_terms = reconstruction(second, target, mask, weights, skeleton)
        total = total + second_weight * again
        terms.update({f"{name} (second pass)": value for name, value in second_terms.items()})
    terms["kl"] = kl_to_standard_normal(mu, log_variance)
    return total + weights.kl * terms["kl"], terms


# ------------------------------------------------------------------------------------------- training


def make_optimizer(model: nn.Module, learning_rate: float = 1e-4):
    return torch.optim.Adam(model.parameters(), lr=learning_rate)


def train_step(model: MarionetPeer, optimizer, batch: dict[str, torch.Tensor], root_tags: torch.Tensor, *,
               share: float, sampling: bool = True, gate: float = 0.02, weights: LossWeights | None = None,
               skeleton: Skeleton, eps: torch.Tensor | None = None, mix: torch.Tensor | None = None) -> torch.Tensor:
    """One step on a pipeline batch: inputs, the teacher-forced pass (Z sampled, dropout on), the second pass
    when ``sampling`` is on and the first pass's squared error is below ``gate`` (each frame after the first
    reads the predicted pose with probability ``share``, or where ``mix [B, T - 1]`` is True), the loss,
    backward, Adam. ``eps [B, d]``: the reparameterisation noise (drawn when None). Returns the loss before the
    update (detached)."""
    model.train()
    weights = LossWeights() if weights is None else weights
    x = marionet_inputs(batch, root_tags)
    target, mask = x["target"], x["mask"]
    first = model(x["context"], x["tags"], x["next_tags"], x["path"], target, mask, eps=eps)
    second, use = None, False
    if sampling:
        use = bool(masked_mse(first["poses"].detach(), target, mask) < gate)
    if use:
        predicted = first["poses"][:, :-1].detach()
        if mix is None:
            mix = torch.rand(predicted.shape[:2]) < share
        mixed = torch.where(mix[..., None], predicted, target[:, :-1])
        second = model.decode(first["controls"], torch.cat([x["context"][:, -1:], mixed], dim=1), mask)
    loss, _ = marionet_loss(first["poses"], second, target, mask, first["mu"], first["log_variance"],
                            weights=weights, skeleton=skeleton, first_weight=0.1 if use else 1.0,
                            second_weight=0.9 if use else 0.0)
    optimizer.zero_grad(set_to_none=True)
    loss.backward()
    optimizer.step()
    return loss.detach()


# ----------------------------------------------------------------------------------------- inference


@torch.inference_mode()
def forward(model: MarionetPeer, context, tags, next_tags, path, target, mask) -> torch.Tensor:
    """The teacher-forced pass in eval mode (Z = mu, no dropout): poses ``[B, T, 135]``."""
    model.eval()
    return model(context, tags, next_tags, path, target, mask)["poses"]


@torch.inference_mode()
def generate(model: MarionetPeer, context, tags, next_tags, path, mask, eps: torch.Tensor | None = None
             ) -> torch.Tensor:
    """Frame by frame, eval mode, as the paper generates (§4.2.3): the first input is the last context pose; at
    frame t the whole causal decoder runs over the t + 1 inputs so far and its last output is the new pose,
    fed back as the next input. ``mask [B, T]`` gives each action's duration; Z = mu (or mu + sigma ``eps``)
    -> poses ``[B, T, 135]``, zero on padding."""
    model.eval()
    mu, log_variance = model.encode(context, tags, next_tags)
    z = mu if eps is None else mu + torch.exp(0.5 * log_variance) * eps
    controls = model.controls(z, tags, path, mask)
    previous, poses = context[:, -1:], []
    for t in range(mask.shape[1]):
        pose = model.decode(controls, previous, mask[:, :t + 1], mask)[:, -1]
        poses.append(pose)
        previous = torch.cat([previous, pose[:, None]], dim=1)
    return torch.stack(poses, dim=1)
