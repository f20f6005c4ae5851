"""A PyTorch decoder of ACTOR's autoregressive baseline (Table 2's "autoregressive" row), the peer that
``benchmarks/bench_decoding.py`` times jaxmotion's cached frame-by-frame generation against.

Benchmark-only: it needs ``torch`` (``pip install -e ".[bench]"``); nothing in ``jaxmotion/`` or ``tests/``
imports this file.

Written from ``shared/reference/FACTS.md`` §3 and jaxmotion's description of the model
(``jaxmotion/models/actor.py``, ``jaxmotion/nn/transformer.py``), not copied from the authors' repository.
ACTOR's ``autotrans.py`` decoder is built from joeynmt layers, so the layers here are written as joeynmt's are,
batch first, with joeynmt's submodule names (``trg_trg_att.q_layer``, ``x_layer_norm``,
``feed_forward.pwff_layer.0`` ...):

* **Memory**: ``embedding(concat(z, a, τ_t))`` for every frame ``t`` (``a`` the one-hot action, ``τ_t =
  t / (len − 1)`` on real frames, 0 on padded ones), padded frames masked as keys.
* **Target** at frame ``t``: ``embedding_x(concat(x_{t−1}, a, τ_t)) + PE(t)`` with ``x_{−1} = 0``.
* **Layers** (pre-norm, LayerNorm eps 1e-6): ``h = x + att(LN(x))`` with causal self-attention over the real
  target frames, ``h = h + att(LN(h), memory)``, ``h = h + W₂ relu(W₁ LN(h))``; attention with separate
  biased q / k / v / output ``Linear`` layers and a ``-inf`` fill where masked, as joeynmt's
  ``MultiHeadedAttention``. Then the final ``layer_norm`` and ``output_layer`` (no bias); padded frames are
  set to zero.

**Frame-by-frame generation** (:func:`generate`): for each frame ``t`` the decoder runs again over the
frames decoded so far (``0 .. t``, the newest output fed back as the next target) and keeps its last output,
with no key/value cache: what a joeynmt decoder without incremental state does at inference. Each pass
covers only the prefix (not all ``T`` frames), which the causal mask makes exact and which is the cheaper of
the two ways to recompute.

Axes: B batch, T frames, J·C features per frame, d width, K classes.
"""

from __future__ import annotations

import math

import torch
from torch import nn

from benchmarks.peers.actor_torch import sinusoid_table

EPS = 1e-6  # joeynmt's LayerNorm eps


class MultiHeadedAttention(nn.Module):
    """joeynmt's attention: separate q / k / v / output projections, batch first."""

    def __init__(self, heads: int, dim: int):
        super().__init__()
        self.heads, self.head_dim = heads, dim // heads
        self.k_layer, self.v_layer, self.q_layer = nn.Linear(dim, dim), nn.Linear(dim, dim), nn.Linear(dim, dim)
        self.output_layer = nn.Linear(dim, dim)

    def forward(self, k: torch.Tensor, v: torch.Tensor, q: torch.Tensor, mask: torch.Tensor) -> torch.Tensor:
        """``k, v [B, Tk, d]``, ``q [B, Tq, d]``, ``mask [B, 1 or Tq, Tk]`` (True = may attend) -> ``[B, Tq, d]``."""
        batch = q.shape[0]

        def heads(x):
            return x.view(batch, -1, self.heads, self.head_dim).transpose(1, 2)  # [B, H, T, e]

        k, v, q = heads(self.k_layer(k)), heads(self.v_layer(v)), heads(self.q_layer(q))
        scores = (q / math.sqrt(self.head_dim)) @ k.transpose(2, 3)
        scores = scores.masked_fill(~mask.unsqueeze(1), float("-inf"))
        context = torch.softmax(scores, dim=-1) @ v  # [B, H, Tq, e]
        return self.output_layer(context.transpose(1, 2).reshape(batch, -1, self.heads * self.head_dim))


class PositionwiseFeedForward(nn.Module):
    def __init__(self, dim: int, ff: int):
        super().__init__()
        self.layer_norm = nn.LayerNorm(dim, eps=EPS)
        self.pwff_layer = nn.Sequential(nn.Linear(dim, ff), nn.ReLU(), nn.Dropout(0.0), nn.Linear(ff, dim),
                                        nn.Dropout(0.0))

    def forward(self, x: torch.Tensor) -> torch.Tensor:
        return self.pwff_layer(self.layer_norm(x)) + x


class TransformerDecoderLayer(nn.Module):
    """joeynmt's pre-norm decoder layer (eval mode: its dropouts are the identity and left out)."""

    def __init__(self, dim: int, ff: int, heads: int):
        super().__init__()
        self.trg_trg_att = MultiHeadedAttention(heads, dim)
        self.src_trg_att = MultiHeadedAttention(heads, dim)
        self.feed_forward = PositionwiseFeedForward(dim, ff)
        self.x_layer_norm = nn.LayerNorm(dim, eps=EPS)
        self.dec_layer_norm = nn.LayerNorm(dim, eps=EPS)

    def forward(self, x, memory, src_mask, trg_mask):
        x_norm = self.x_layer_norm(x)
        h1 = self.trg_trg_att(x_norm, x_norm, x_norm, mask=trg_mask) + x
        h2 = self.src_trg_att(memory, memory, self.dec_layer_norm(h1), mask=src_mask) + h1
        return self.feed_forward(h2)


class AutoregressiveDecoderPeer(nn.Module):
    """ACTOR's autoregressive decoder; parameter names match :func:`peer_weights` in the benchmark."""

    def __init__(self, features: int, num_classes: int, *, dim: int = 256, ff: int = 1024, layers: int = 8,
                 heads: int = 4):
        super().__init__()
        self.num_classes, self.dim = num_classes, dim
        self.embedding = nn.Linear(dim + num_classes + 1, dim)
        self.embedding_x = nn.Linear(features + num_classes + 1, dim)
        self.layers = nn.ModuleList(TransformerDecoderLayer(dim, ff, heads) for _ in range(layers))
        self.layer_norm = nn.LayerNorm(dim, eps=EPS)
        self.output_layer = nn.Linear(dim, features, bias=False)
        self.register_buffer("table", sinusoid_table(5000, dim), persistent=False)  # [L, d]

    def conditioning(self, actions: torch.Tensor, mask: torch.Tensor) -> torch.Tensor:
        """``[B, T, K + 1]``: the one-hot action and τ_t."""
        batch, frames = mask.shape
        onehot = nn.functional.one_hot(actions.long(), self.num_classes).float()[:, None].expand(batch, frames, -1)
        span = (mask.sum(1) - 1).clamp_min(1).float()
        time = torch.where(mask, torch.arange(frames, dtype=torch.float32)[None] / span[:, None], 0.0)
        return torch.cat([onehot, time[..., None]], dim=-1)

    def step(self, previous, memory, conditioning, mask, frames_done: int) -> torch.Tensor:
        """One pass over frames ``0 .. frames_done`` -> the output of the last, ``[B, J·C]``.
        ``previous [B, frames_done + 1, J·C]``: the targets' previous frames (zeros first)."""
        n = frames_done + 1
        h = self.embedding_x(torch.cat([previous, conditioning[:, :n]], dim=-1)) + self.table[:n]
        causal = torch.tril(torch.ones(n, n, dtype=torch.bool))
        trg_mask = mask[:, None, :n] & causal[None]  # [B, n, n]
        src_mask = mask[:, None, :]  # [B, 1, T]
        for layer in self.layers:
            h = layer(h, memory, src_mask, trg_mask)
        return self.output_layer(self.layer_norm(h[:, -1]))

    def forward(self, z: torch.Tensor, actions: torch.Tensor, mask: torch.Tensor) -> torch.Tensor:
        """Frame by frame, re-running the decoder over the prefix for every frame: ``z [B, d]``, ``actions
        [B]``, ``mask [B, T]`` -> ``[B, T, J·C]``, zero on padded frames."""
        batch, frames = mask.shape
        conditioning = self.conditioning(actions, mask)
        memory = self.embedding(torch.cat([z[:, None].expand(batch, frames, -1), conditioning], dim=-1))
        features = self.output_layer.weight.shape[0]
        output = z.new_zeros(batch, frames, features)
        for t in range(frames):
            previous = torch.cat([z.new_zeros(batch, 1, features), output[:, :t]], dim=1)
            frame = self.step(previous, memory, conditioning, mask, t)
            output[:, t] = frame.masked_fill(~mask[:, t, None], 0.0)
        return output


@torch.inference_mode()
def generate(model: AutoregressiveDecoderPeer, z: torch.Tensor, actions: torch.Tensor, durations: torch.Tensor,
             frames: int) -> torch.Tensor:
    """Generation as it is timed: eval mode, no autograd; ``[B, frames, J·C]``."""
    model.eval()
    mask = torch.arange(frames)[None] < durations[:, None]
    return model(z, actions, mask)
