"""A PyTorch ACTOR of the same architecture as jaxmotion's Transformer ACTOR: the peer that
``benchmarks/bench_actor.py`` times against the library in the same run.

Benchmark-only: it needs ``torch`` (``pip install -e ".[bench]"``), which is neither a runtime nor a test
dependency of jaxmotion, and nothing in ``jaxmotion/`` or ``tests/`` imports this file.

Written from the paper (Petrovich et al., ICCV 2021, §3 and appendix C) and ``shared/reference/FACTS.md`` §3,
not copied from the authors' repository. Submodule and parameter names follow the authors' modules
(``encoder.muQuery``, ``encoder.skelEmbedding``, ``decoder.actionBiases``, ``decoder.seqTransDecoder.layers.{i}``
...) so that a state dict keyed that way, such as the one the benchmark builds from jaxmotion's parameters with
``jaxmotion.nn.transformer.state_dict``, loads with ``strict=True``.

The model (sequence-first inside, as the authors' code and torch 1.7 are; the public methods take batch-first
tensors):

* **Encoder**: ``skelEmbedding`` Linear(J·C -> d) per frame; the action's ``muQuery`` and ``sigmaQuery`` tokens
  prepended; sinusoidal positions 0..T+1 added, then dropout; ``nn.TransformerEncoder`` of post-norm
  ``nn.TransformerEncoderLayer`` (GELU, no final norm) with the padded frames masked as keys; outputs 0 and 1
  are µ and log σ².
* **Latent**: ``z = µ + exp(logvar / 2) · ε``, ε ~ N(0, I) (or given, for a parity check).
* **Decoder**: memory = one token ``z + actionBiases[a]``; queries = zeros + positions 0..T-1, then dropout;
  ``nn.TransformerDecoder`` of post-norm ``nn.TransformerDecoderLayer`` (GELU, no causal mask, padded queries
  masked as keys); ``finalLayer`` Linear(d -> J·C); padded frames set to zero.
* **Losses** (the ones jaxmotion's step uses): L_P = MSE over the real frames of the whole rot6d + translation
  tensor; KL = -½ Σ (1 + logvar - µ² - exp logvar) summed over batch and dimensions; optionally L_J = MSE of
  root-centred joints from forward kinematics of the rot6d rotations on a fixed skeleton (parents, offsets).
* **Optimiser**: ``torch.optim.AdamW`` (lr 1e-4, weight decay 0.01 in the paper).

Axes: B batch, T frames, J joints (+1 translation row), C channels, d width, K classes.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
import torch
from torch import nn

# ------------------------------------------------------------------------------------------- geometry


def axis_angle_to_matrix(v: torch.Tensor) -> torch.Tensor:
    """Rodrigues: rotation vectors ``[..., 3]`` -> matrices ``[..., 3, 3]`` (column-vector convention)."""
    sq = (v * v).sum(-1, keepdim=True)[..., None]  # [..., 1, 1]
    small = sq < 1e-8
    safe = torch.where(small, torch.ones_like(sq), sq)
    angle = safe.sqrt()
    a = torch.where(small, 1.0 - sq / 6.0, torch.sin(angle) / angle)  # sin θ / θ
    half = 0.5 * angle
    b = torch.where(small, 0.5 - sq / 24.0, 0.5 * (torch.sin(half) / half).square())  # (1 - cos θ) / θ²
    x, y, z = v.unbind(-1)
    zero = torch.zeros_like(x)
    skew = torch.stack([zero, -z, y, z, zero, -x, -y, x, zero], -1).reshape(*v.shape[:-1], 3, 3)
    eye = torch.eye(3, dtype=v.dtype, device=v.device)
    return eye + a * skew + b * (skew @ skew)


def matrix_to_rot6d(m: torch.Tensor) -> torch.Tensor:
    """``[..., 3, 3]`` -> ``[..., 6]``: the first two rows (the representation ACTOR trains on)."""
    return m[..., :2, :].reshape(*m.shape[:-2], 6)


def _unit(x: torch.Tensor) -> torch.Tensor:
    return x / (x * x).sum(-1, keepdim=True).clamp_min(1e-12).sqrt()


def rot6d_to_matrix(x: torch.Tensor) -> torch.Tensor:
    """``[..., 6]`` -> ``[..., 3, 3]`` by Gram-Schmidt on the two rows; the third row is their cross product."""
    a1, a2 = x[..., :3], x[..., 3:]
    b1 = _unit(a1)
    b2 = _unit(a2 - (b1 * a2).sum(-1, keepdim=True) * b1)
    b3 = torch.cross(b1, b2, dim=-1)
    return torch.stack([b1, b2, b3], dim=-2)


def forward_kinematics(local: torch.Tensor, offsets: torch.Tensor, parents: Sequence[int]) -> torch.Tensor:
    """Joint positions ``[..., J, 3]`` from local rotations ``[..., J, 3, 3]`` and rest offsets ``[J, 3]``
    (parent to child, in the parent's frame), the root at the origin; ``parents[0] = -1``."""
    order = _topological(parents)
    rotations: list[torch.Tensor | None] = [None] * len(parents)
    positions: list[torch.Tensor | None] = [None] * len(parents)
    rotations[0] = local[..., 0, :, :]
    positions[0] = torch.zeros(local.shape[:-3] + (3,), dtype=local.dtype, device=local.device)
    for j in order[1:]:
        p = parents[j]
        rotations[j] = rotations[p] @ local[..., j, :, :]
        positions[j] = positions[p] + (rotations[p] @ offsets[j][:, None])[..., 0]
    return torch.stack(positions, dim=-2)


def _topological(parents: Sequence[int]) -> list[int]:
    children: dict[int, list[int]] = {}
    for j, p in enumerate(parents):
        children.setdefault(p, []).append(j)
    order, frontier = [], list(children.get(-1, []))
    while frontier:
        j = frontier.pop(0)
        order.append(j)
        frontier.extend(children.get(j, []))
    if len(order) != len(parents) or order[0] != 0:
        raise ValueError(f"parents: expected a tree rooted at joint 0, got {tuple(parents)}")
    return order


def actor_features(rotations: torch.Tensor, translation: torch.Tensor) -> torch.Tensor:
    """ACTOR's input tensor: axis-angle ``rotations [B, T, J, 3]`` and ``translation [B, T, 3]`` ->
    ``[B, T, J + 1, 6]``, each joint in rot6d, then the translation relative to frame 0 padded to 6 channels."""
    rot6d = matrix_to_rot6d(axis_angle_to_matrix(rotations))
    relative = translation - translation[:, :1]
    row = torch.cat([relative, torch.zeros_like(relative)], dim=-1)[:, :, None]
    return torch.cat([rot6d, row], dim=2)


# ---------------------------------------------------------------------------------------------- model


def sinusoid_table(length: int, dim: int) -> torch.Tensor:
    """``[length, dim]``: column 2i is sin(p / 10000^(2i/dim)), column 2i+1 the cosine of the same angle."""
    position = np.arange(length, dtype=np.float64)[:, None]
    column = np.arange(dim)
    angle = position * np.exp((column - column % 2) * (-math.log(10000.0) / dim))
    return torch.from_numpy(np.where(column % 2 == 0, np.sin(angle), np.cos(angle)).astype(np.float32))


class PositionalEncoding(nn.Module):
    """Adds the sinusoid of each position to a sequence-first ``[T, B, d]`` input, then dropout."""

    def __init__(self, dim: int, dropout: float, max_len: int = 5000):
        super().__init__()
        self.dropout = nn.Dropout(dropout)
        self.register_buffer("table", sinusoid_table(max_len, dim)[:, None], persistent=False)  # [L, 1, d]

    def forward(self, x: torch.Tensor) -> torch.Tensor:
        return self.dropout(x + self.table[: x.shape[0]])


class Encoder(nn.Module):
    def __init__(self, features: int, num_classes: int, dim: int, ff: int, layers: int, heads: int,
                 dropout: float):
        super().__init__()
        self.muQuery = nn.Parameter(torch.randn(num_classes, dim))
        self.sigmaQuery = nn.Parameter(torch.randn(num_classes, dim))
        self.skelEmbedding = nn.Linear(features, dim)
        self.sequence_pos_encoder = PositionalEncoding(dim, dropout)
        layer = nn.TransformerEncoderLayer(dim, heads, ff, dropout, activation="gelu")
        self.seqTransEncoder = nn.TransformerEncoder(layer, layers, enable_nested_tensor=False)

    def forward(self, x: torch.Tensor, actions: torch.Tensor, mask: torch.Tensor):
        """``x [B, T, J·C]``, ``actions [B]``, ``mask [B, T]`` (True = real frame) -> µ, logvar ``[B, d]``."""
        h = self.skelEmbedding(x).transpose(0, 1)  # [T, B, d]
        tokens = torch.stack([self.muQuery[actions], self.sigmaQuery[actions]])  # [2, B, d]
        h = self.sequence_pos_encoder(torch.cat([tokens, h]))
        real = torch.cat([torch.ones_like(mask[:, :2]), mask], dim=1)
        out = self.seqTransEncoder(h, src_key_padding_mask=~real)
        return out[0], out[1]


class Decoder(nn.Module):
    def __init__(self, features: int, num_classes: int, dim: int, ff: int, layers: int, heads: int,
                 dropout: float):
        super().__init__()
        self.actionBiases = nn.Parameter(torch.randn(num_classes, dim))
        self.sequence_pos_encoder = PositionalEncoding(dim, dropout)
        layer = nn.TransformerDecoderLayer(dim, heads, ff, dropout, activation="gelu")
        self.seqTransDecoder = nn.TransformerDecoder(layer, layers)
        self.finalLayer = nn.Linear(dim, features)

    def forward(self, z: torch.Tensor, actions: torch.Tensor, mask: torch.Tensor) -> torch.Tensor:
        """``z [B, d]``, ``actions [B]``, ``mask [B, T]`` -> ``[B, T, J·C]``, zero on padded frames."""
        batch, frames = mask.shape
        memory = (z + self.actionBiases[actions])[None]  # [1, B, d]
        queries = self.sequence_pos_encoder(z.new_zeros(frames, batch, z.shape[-1]))
        out = self.seqTransDecoder(tgt=queries, memory=memory, tgt_key_padding_mask=~mask)
        return self.finalLayer(out).transpose(0, 1).masked_fill(~mask[..., None], 0.0)


class ActorPeer(nn.Module):
    """ACTOR's Transformer VAE: ``num_joints`` rows (24 rotations + translation) of ``channels`` (6)."""

    def __init__(self, num_classes: int, *, num_joints: int = 25, channels: int = 6, dim: int = 256,
                 ff: int = 1024, layers: int = 8, heads: int = 4, dropout: float = 0.1):
        super().__init__()
        self.num_joints, self.channels, self.dim = num_joints, channels, dim
        features = num_joints * channels
        self.encoder = Encoder(features, num_classes, dim, ff, layers, heads, dropout)
        self.decoder = Decoder(features, num_classes, dim, ff, layers, heads, dropout)

    def forward(self, x: torch.Tensor, actions: torch.Tensor, mask: torch.Tensor,
                eps: torch.Tensor | None = None) -> dict[str, torch.Tensor]:
        """``x [B, T, J, C]`` -> ``{"output" [B, T, J, C], "mu", "logvar", "z" [B, d]}``; ``eps``: the
        reparameterisation noise (drawn here when None)."""
        batch, frames = mask.shape
        mu, logvar = self.encoder(x.reshape(batch, frames, -1), actions, mask)
        if eps is None:
            eps = torch.randn_like(mu)
        z = mu + torch.exp(0.5 * logvar) * eps
        output = self.decoder(z, actions, mask).reshape(batch, frames, self.num_joints, self.channels)
        return {"output": output, "mu": mu, "logvar": logvar, "z": z}

    def generate(self, actions: torch.Tensor, durations: torch.Tensor, frames: int,
                 z: torch.Tensor | None = None) -> tuple[torch.Tensor, torch.Tensor]:
        """z ~ N(0, I) (or given ``[B, d]``) decoded: ``(x [B, frames, J, C], mask [B, frames])``."""
        if z is None:
            z = torch.randn(actions.shape[0], self.dim)
        mask = torch.arange(frames)[None] < durations[:, None]
        x = self.decoder(z, actions, mask).reshape(*mask.shape, self.num_joints, self.channels)
        return x, mask


# --------------------------------------------------------------------------------------------- losses


def masked_mse(prediction: torch.Tensor, target: torch.Tensor, mask: torch.Tensor) -> torch.Tensor:
    """Mean squared error over the real frames (``mask [B, T]``) of ``[B, T, ...]`` tensors."""
    squared = (prediction - target).square().reshape(*mask.shape, -1)
    return (squared * mask[..., None]).sum() / (mask.sum().clamp_min(1) * squared.shape[-1])


def kl_to_standard_normal(mu: torch.Tensor, logvar: torch.Tensor) -> torch.Tensor:
    """KL(N(µ, exp logvar) || N(0, I)) summed over batch and dimensions."""
    return -0.5 * torch.sum(1.0 + logvar - mu.square() - logvar.exp())


class Skeleton:
    """The fixed skeleton of L_J: ``parents`` (root -1 first) and rest ``offsets [J, 3]``."""

    def __init__(self, parents: Sequence[int], offsets):
        self.parents = tuple(int(p) for p in parents)
        self.offsets = torch.from_numpy(np.array(offsets, np.float32))

    def joints(self, x: torch.Tensor) -> torch.Tensor:
        """Root-centred joints ``[B, T, J, 3]`` from the rotation rows of ``x [B, T, J + 1, 6]``."""
        return forward_kinematics(rot6d_to_matrix(x[:, :, :-1]), self.offsets, self.parents)


def actor_loss(out: dict[str, torch.Tensor], x: torch.Tensor, mask: torch.Tensor, *, motion: float = 1.0,
               joints: float = 0.0, kl: float = 1e-5, skeleton: Skeleton | None = None):
    """``motion · L_P + joints · L_J + kl · KL`` and each term."""
    terms = {}
    if motion:
        terms["motion"] = masked_mse(out["output"], x, mask)
    if joints:
        if skeleton is None:
            raise ValueError("joints > 0 needs a skeleton")
        terms["joints"] = masked_mse(skeleton.joints(out["output"]), skeleton.joints(x), mask)
    terms["kl"] = kl_to_standard_normal(out["mu"], out["logvar"])
    weights = {"motion": motion, "joints": joints, "kl": kl}
    total = sum(weights[name] * value for name, value in terms.items())
    return total, terms


# ------------------------------------------------------------------------------------------- training


def make_optimizer(model: nn.Module, learning_rate: float = 1e-4, weight_decay: float = 0.01):
    return torch.optim.AdamW(model.parameters(), lr=learning_rate, weight_decay=weight_decay)


def train_step(model: ActorPeer, optimizer, batch: dict[str, torch.Tensor], *, eps: torch.Tensor | None = None,
               **loss_weights) -> torch.Tensor:
    """One step on a pipeline batch (axis-angle ``rotations [B, T, J, 3]``, ``translation [B, T, 3]``,
    ``actions [B]``, ``mask [B, T]``): features, forward, loss, backward, AdamW. Returns the loss before the
    update (detached)."""
    model.train()
    x = actor_features(batch["rotations"], batch["translation"])
    out = model(x, batch["actions"], batch["mask"], eps)
    loss, _ = actor_loss(out, x, batch["mask"], **loss_weights)
    optimizer.zero_grad(set_to_none=True)
    loss.backward()
    optimizer.step()
    return loss.detach()


@torch.inference_mode()
def generate(model: ActorPeer, actions: torch.Tensor, durations: torch.Tensor, frames: int,
             z: torch.Tensor | None = None):
    """Generation as it is timed: eval mode (no dropout), no autograd."""
    model.eval()
    return model.generate(actions, durations, frames, z)
