"""A PyTorch ActFormer (generator and critic) of the same architecture as jaxmotion's
(:mod:`jaxmotion.models.actformer`, :mod:`jaxmotion.models.actformer_critic`): the peer that
``benchmarks/bench_actformer.py`` times against the library in the same run.

Benchmark-only: it needs ``torch`` (``pip install -e ".[bench]"``), which is neither a runtime nor a test
dependency of jaxmotion, and nothing in ``jaxmotion/`` or ``tests/`` imports this file.

Written from ``shared/reference/FACTS.md`` §5 and jaxmotion's docstrings and code, not copied from the authors'
repository. Scope: the multi-person generator with I-Formers (NTU-2P: ``persons >= 2``, one latent sequence
shared by the persons, ``skeleton`` output) and the critic with motion flow, both spectrally normalised.

**Spectral normalisation** is ``torch.nn.utils.spectral_norm`` (what the authors use), which computes what
:mod:`jaxmotion.nn.spectral_norm` does: in train mode every forward runs one power iteration from the stored
``weight_u`` / ``weight_v`` (moved in place, no gradient), then divides ``weight_orig`` by ``u·(W v)``; in eval
mode the stored vectors are used as they are. A 1-D weight (the last LayerNorm's gain) is a ``[D, 1]`` matrix.
:func:`load_jaxmotion` copies jaxmotion's parameters and power-iteration vectors into the ``weight_orig``,
``weight_u`` and ``weight_v`` tensors (``load_state_dict(strict=True)``).

The generator (``Generator``; width ``D = 8 V``):

* ``input_embedding`` SN-Linear(Z -> D) per frame of ``z [B, T, Z]``; the action token
  ``class_embedding[y]`` (``Embedding(K, D)``, not normalised) in front: ``[B, T + 1, D]``, the same for every
  person, plus the free positional tensor ``positions [T + 1, P, D]`` -> ``[B, T + 1, P, D]``.
* ``depth`` times: an I-Former (over the P persons of each token) then a T-Former (over the T + 1 tokens of each
  person). Each is a pre-LN block (LayerNorm eps 1e-6): ``x + proj(attention(qkv(LN(x))))``, then
  ``x + fc2(GELU(fc1(LN(x))))``; ``qkv`` SN-Linear(D -> 3D) with bias, heads contiguous in D, attention by
  ``F.scaled_dot_product_attention``; ``proj``, ``fc1`` (D -> mlp_ratio·D), ``fc2`` SN-Linears. The block norms
  are not normalised.
* ``final_norm`` (a LayerNorm eps 1e-6 whose gain is spectrally normalised) and ``head`` SN-Linear(D -> V·C) on
  the T frame tokens (the action token is dropped first: the norm and head act per token, so this gives the
  numbers jaxmotion gets by dropping it after the head) -> ``[B, P, T, V, C]``.
* Output normalisation ``skeleton``: joint 0 raw; every other joint ``tanh``, divided by its norm + 1e-4.

The critic (``Critic``; ``use_graph_conv: false``), on ``motion [B, P, T, V, C]``: persons stacked on the
channels, person-major (``p·C + c``), then the frame differences (zero at frame 0) as as many channels again.
Activations stay ``[B, V·C, T]`` with node-major channels, the layout every grouped convolution reads:

* ``conv0`` (V -> V, 32, time kernel 5, stride 1, padding 2, bias), ``down1`` (V -> L1, 64), ``down2``
  (L1 -> L2, 128), ``down3`` (L2 -> L2, 256) (time kernel 4, stride 2, padding 1, no bias): each a grouped
  SN-``Conv1d`` (one group per input node ``v``, into ``c·k`` channels), then ``Σ_k Σ_v A[k, w, v] · f_{k,v}``
  with the normalised hop kernels ``A [K, W, V]`` that jaxmotion's ``critic_graphs`` gives (passed in as numpy).
* ``conv4``: SN-``Conv2d(256, 512)`` with kernel ``(L2, 4)``, stride 2, padding ``(0, 1)``: one node; LeakyReLU
  0.2 after every layer; the sum over nodes and frames gives ``h [B, 512]``.
* score: ``conv5(h)`` (SN-Linear(512 -> 1)) ``+ <embedding[y], h>`` (SN-``Embedding(K, 512)``).

**Training** (:func:`train_iteration`, as ``jaxmotion.train.actformer.actformer_step``): 4 critic updates, each
on its own real batch and fresh fakes (generator in train mode under ``no_grad``), hinge loss
``mean relu(1 − D(real)) + mean relu(1 + D(fake))``; then one generator update with ``−mean D(fake)``, the
critic's parameters frozen for it (``requires_grad_(False)``: their gradients would be thrown away; the critic's
power iterations still move, in train mode, as in jaxmotion). Adam 2e-4, betas (0, 0.999), for both. Latents
come from the GP prior (``z = F_z n``, the factors ``[Z, T, T]`` jaxmotion's ``latent_factors`` gives) and
fake labels uniformly, drawn here unless given (the parity check gives the ones jaxmotion's step draws), on the
device of the inputs (CPU or CUDA: the models, their adjacency buffers and the inputs are moved together).

Axes: B batch, N critic updates, P persons, T frames (S = T + 1 tokens), V / W input / output nodes, C
channels, Z latent channels, D width, K classes / hop kernels.
"""

from __future__ import annotations

import numpy as np
import torch
from torch import nn
from torch.nn import functional as F

_EPS = 1e-6  # the generator's LayerNorm eps
_SLOPE = 0.2  # the critic's LeakyReLU
sn = nn.utils.spectral_norm  # one power iteration per train-mode forward, eps 1e-12, as jaxmotion's

# --------------------------------------------------------------------------------------------- generator


class Block(nn.Module):
    """One pre-LN Transformer block over the middle axis of ``[N, S, D]`` (an I- or a T-Former)."""

    def __init__(self, dim: int, heads: int, hidden: int):
        super().__init__()
        self.heads = heads
        self.norm1 = nn.LayerNorm(dim, eps=_EPS)
        self.qkv = sn(nn.Linear(dim, 3 * dim))
        self.proj = sn(nn.Linear(dim, dim))
        self.norm2 = nn.LayerNorm(dim, eps=_EPS)
        self.fc1 = sn(nn.Linear(dim, hidden))
        self.fc2 = sn(nn.Linear(hidden, dim))

    def forward(self, x: torch.Tensor) -> torch.Tensor:
        n, s, d = x.shape
        q, k, v = self.qkv(self.norm1(x)).view(n, s, 3, self.heads, d // self.heads).permute(2, 0, 3, 1, 4)
        context = F.scaled_dot_product_attention(q, k, v)  # [N, H, S, D/H]
        x = x + self.proj(context.transpose(1, 2).reshape(n, s, d))
        return x + self.fc2(F.gelu(self.fc1(self.norm2(x))))


def normalize_skeleton(x: torch.Tensor) -> torch.Tensor:
    """``[..., V, 3]``: joint 0 raw, the others ``tanh`` then divided by their norm + 1e-4."""
    limbs = torch.tanh(x[..., 1:, :])
    limbs = limbs / (torch.linalg.vector_norm(limbs, dim=-1, keepdim=True) + 1e-4)
    return torch.cat([x[..., :1, :], limbs], -2)


class Generator(nn.Module):
    """ActFormer's multi-person generator (NTU-2P sizes by default)."""

    def __init__(self, num_classes: int = 26, *, joints: int = 25, channels: int = 3, persons: int = 2,
                 frames: int = 60, latent: int = 120, width_per_joint: int = 8, depth: int = 2, heads: int = 8,
                 mlp_ratio: float = 2.0):
        super().__init__()
        if persons < 2:
            raise ValueError(f"persons: this peer is the I-Former generator of several persons, got {persons}")
        dim = width_per_joint * joints
        self.joints, self.channels = joints, channels
        self.input_embedding = sn(nn.Linear(latent, dim))
        self.class_embedding = nn.Embedding(num_classes, dim)
        self.positions = nn.Parameter(torch.zeros(frames + 1, persons, dim))
        self.blocks = nn.ModuleList(Block(dim, heads, int(dim * mlp_ratio)) for _ in range(2 * depth))
        self.final_norm = sn(nn.LayerNorm(dim, eps=_EPS))
        self.head = sn(nn.Linear(dim, joints * channels))

    def forward(self, z: torch.Tensor, labels: torch.Tensor) -> torch.Tensor:
        """``z [B, T, Z]`` (shared by the persons), ``labels [B]`` -> ``motion [B, P, T, V, C]``."""
        b = z.shape[0]
        x = torch.cat([self.class_embedding(labels)[:, None], self.input_embedding(z)], 1)  # [B, S, D]
        x = x[:, :, None] + self.positions  # [B, S, P, D]
        _, s, p, d = x.shape
        for interact, temporal in zip(self.blocks[0::2], self.blocks[1::2]):
            x = interact(x.reshape(b * s, p, d)).view(b, s, p, d)
            per_person = temporal(x.transpose(1, 2).reshape(b * p, s, d)).view(b, p, s, d)
            x = per_person.transpose(1, 2)
        out = self.head(self.final_norm(per_person[:, :, 1:]))  # [B, P, T, V·C]
        return normalize_skeleton(out.view(b, p, s - 1, self.joints, self.channels))


# ------------------------------------------------------------------------------------------------ critic


class GraphConv(nn.Module):
    """Node-specific temporal convolutions mixed by hop kernels: ``[B, V·C_in, T]`` -> ``[B, W·c, T']``."""

    def __init__(self, adjacency: np.ndarray, c_in: int, c_out: int, kernel: int, stride: int, padding: int,
                 bias: bool):
        super().__init__()
        hops, self.out_nodes, nodes = adjacency.shape
        self.conv = sn(nn.Conv1d(nodes * c_in, nodes * c_out * hops, kernel, stride, padding, groups=nodes,
                                 bias=bias))
        self.register_buffer("adjacency", torch.from_numpy(np.array(adjacency, np.float32)), persistent=False)

    def forward(self, x: torch.Tensor) -> torch.Tensor:
        hops, _, nodes = self.adjacency.shape
        y = self.conv(x)
        b, channels, t = y.shape
        y = y.view(b, nodes, channels // (nodes * hops), hops, t)  # channel v·(c·k) + c_i·k + k_i
        return torch.einsum("kwv,bvckt->bwct", self.adjacency, y).reshape(b, -1, t)


class Critic(nn.Module):
    """ActFormer's critic for the adjacencies ``graphs`` (conv0, down1, down2, down3, each ``[K, W, V]``);
    ``channels``: persons x C, the per-frame channels of a node before the motion flow."""

    def __init__(self, graphs, num_classes: int = 26, *, channels: int = 6, base_channels: int = 32,
                 time_kernel: int = 4):
        super().__init__()
        a0, a1, a2, a3 = (np.asarray(a) for a in graphs)
        c1, c2, c3, c4, c5 = (base_channels * m for m in (1, 2, 4, 8, 16))
        pad = (time_kernel - 2) // 2
        self.conv0 = GraphConv(a0, 2 * channels, c1, 5, 1, 2, bias=True)
        self.down1 = GraphConv(a1, c1, c2, time_kernel, 2, pad, bias=False)
        self.down2 = GraphConv(a2, c2, c3, time_kernel, 2, pad, bias=False)
        self.down3 = GraphConv(a3, c3, c4, time_kernel, 2, pad, bias=False)
        self.conv4 = sn(nn.Conv2d(c4, c5, (a3.shape[1], time_kernel), 2, (0, pad)))
        self.conv5 = sn(nn.Linear(c5, 1))
        self.embedding = sn(nn.Embedding(num_classes, c5))

    def forward(self, motion: torch.Tensor, labels: torch.Tensor) -> torch.Tensor:
        """``motion [B, P, T, V, C]``, ``labels [B]`` -> ``scores [B]``."""
        b, p, t, v, c = motion.shape
        x = motion.permute(0, 3, 1, 4, 2).reshape(b, v, p * c, t)  # person-major channels per node
        flow = torch.cat([torch.zeros_like(x[..., :1]), x[..., 1:] - x[..., :-1]], -1)
        x = torch.cat([x, flow], 2).reshape(b, -1, t)  # [B, V·2PC, T]
        for layer in (self.conv0, self.down1, self.down2, self.down3):
            x = F.leaky_relu(layer(x), _SLOPE)
        x = x.view(b, self.down3.out_nodes, -1, x.shape[-1]).transpose(1, 2)  # [B, C, W, T]
        h = F.leaky_relu(self.conv4(x), _SLOPE).sum((2, 3))  # [B, 512]
        return self.conv5(h)[:, 0] + (self.embedding(labels) * h).sum(-1)


# ------------------------------------------------------------------------------------------------ weights


def _sn_entries(name: str, weight, state) -> dict:
    """A spectrally normalised weight and its power-iteration vectors under ``torch.nn.utils.spectral_norm``'s
    names."""
    return {f"{name}.weight_orig": weight, f"{name}.weight_u": state.u, f"{name}.weight_v": state.v}


def generator_state_dict(params, spectral) -> dict[str, np.ndarray]:
    """jaxmotion's ``GeneratorParams`` and ``GeneratorSpectral`` under the peer's names."""
    out = {**_sn_entries("input_embedding", params.input_embedding.weight, spectral.input_embedding),
           "input_embedding.bias": params.input_embedding.bias, "class_embedding.weight": params.class_embedding,
           "positions": params.positions,
           **_sn_entries("final_norm", params.final_norm.weight, spectral.final_norm),
           "final_norm.bias": params.final_norm.bias,
           **_sn_entries("head", params.head.weight, spectral.head), "head.bias": params.head.bias}
    b, s = params.blocks, spectral.blocks
    for i in range(b.norm1.weight.shape[0]):  # the stacked blocks, I- and T-Formers alternating
        prefix = f"blocks.{i}."
        pick = lambda leaf, i=i: leaf[i]  # noqa: E731
        linears = {"qkv": (b.self_attn.in_proj_weight, b.self_attn.in_proj_bias, s.qkv),
                   "proj": (b.self_attn.out_proj.weight, b.self_attn.out_proj.bias, s.proj),
                   "fc1": (b.linear1.weight, b.linear1.bias, s.fc1), "fc2": (b.linear2.weight, b.linear2.bias, s.fc2)}
        for name, (weight, bias, state) in linears.items():
            out.update(_sn_entries(prefix + name, pick(weight), type(state)(pick(state.u), pick(state.v))))
            out[prefix + name + ".bias"] = pick(bias)
        for name in ("norm1", "norm2"):
            norm = getattr(b, name)
            out[prefix + name + ".weight"], out[prefix + name + ".bias"] = pick(norm.weight), pick(norm.bias)
    return out


def critic_state_dict(params, spectral) -> dict[str, np.ndarray]:
    """jaxmotion's ``CriticParams`` and ``CriticSpectral`` under the peer's names."""
    out = {}
    for name in ("conv0", "down1", "down2", "down3"):
        layer = getattr(params, name)
        out.update(_sn_entries(name + ".conv", layer.weight, getattr(spectral, name)))
        if layer.bias is not None:
            out[name + ".conv.bias"] = layer.bias
    return {**out, **_sn_entries("conv4", params.conv4_weight, spectral.conv4), "conv4.bias": params.conv4_bias,
            **_sn_entries("conv5", params.conv5.weight, spectral.conv5), "conv5.bias": params.conv5.bias,
            **_sn_entries("embedding", params.embedding, spectral.embedding)}


def load_jaxmotion(model: nn.Module, arrays: dict) -> nn.Module:
    """Load one of the state dicts above (copies of the arrays, so the jax buffers may be donated later) with
    ``strict=True``."""
    tensors = {name: torch.from_numpy(np.array(value, np.float32, copy=True)) for name, value in arrays.items()}
    model.load_state_dict(tensors, strict=True)
    return model


# ----------------------------------------------------------------------------------------------- training


def make_optimizers(generator: Generator, critic: Critic, learning_rate: float = 2e-4,
                    betas: tuple[float, float] = (0.0, 0.999)) -> tuple[torch.optim.Adam, torch.optim.Adam]:
    return (torch.optim.Adam(generator.parameters(), lr=learning_rate, betas=betas),
            torch.optim.Adam(critic.parameters(), lr=learning_rate, betas=betas))


def sample_latents(factors: torch.Tensor, batch: int) -> torch.Tensor:
    """``batch`` GP latent sequences ``[B, T, Z]`` from the factors ``[Z, T, T]`` (drawn on their device)."""
    channels, steps, _ = factors.shape
    return torch.einsum("zts,bzs->btz", factors, torch.randn(batch, channels, steps, device=factors.device))


def _step(optimizer: torch.optim.Optimizer, loss: torch.Tensor) -> None:
    optimizer.zero_grad(set_to_none=True)
    loss.backward()
    optimizer.step()


def train_iteration(generator: Generator, critic: Critic, optimizers, reals: torch.Tensor, real_labels: torch.Tensor,
                    *, factors: torch.Tensor | None = None, latents: torch.Tensor | None = None,
                    fake_labels: torch.Tensor | None = None, num_classes: int = 26
                    ) -> tuple[torch.Tensor, torch.Tensor]:
    """One loop step: ``N`` critic updates on ``reals [N, B, P, T, V, C]`` / ``real_labels [N, B]``, then one
    generator update. ``latents [N + 1, B, T, Z]`` and ``fake_labels [N + 1, B]`` (row ``i`` for update ``i``,
    the last for the generator's): drawn from ``factors`` and uniformly over ``num_classes`` when None, on the
    device of ``factors`` and ``real_labels`` (the models' device).
    Returns the last critic loss and the generator loss (detached; each before the update it drives)."""
    opt_g, opt_d = optimizers
    n, b = real_labels.shape
    if latents is None:
        latents = torch.stack([sample_latents(factors, b) for _ in range(n + 1)])
        fake_labels = torch.randint(0, num_classes, (n + 1, b), device=real_labels.device)
    generator.train()
    critic.train()
    for i in range(n):
        with torch.no_grad():  # jaxmotion's stop_gradient: the critic update does not reach the generator
            fake = generator(latents[i], fake_labels[i])
        real_score = critic(reals[i], real_labels[i])
        fake_score = critic(fake, fake_labels[i])
        d_loss = F.relu(1.0 - real_score).mean() + F.relu(1.0 + fake_score).mean()
        _step(opt_d, d_loss)
    critic.requires_grad_(False)
    g_loss = -critic(generator(latents[n], fake_labels[n]), fake_labels[n]).mean()
    _step(opt_g, g_loss)
    critic.requires_grad_(True)
    return d_loss.detach(), g_loss.detach()


@torch.inference_mode()
def generate(generator: Generator, z: torch.Tensor, labels: torch.Tensor) -> torch.Tensor:
    """Generation as it is timed: eval mode (the stored power-iteration vectors), no autograd."""
    generator.eval()
    return generator(z, labels)


@torch.inference_mode()
def score(critic: Critic, motion: torch.Tensor, labels: torch.Tensor) -> torch.Tensor:
    """Critic scores in eval mode (for the parity check)."""
    critic.eval()
    return critic(motion, labels)
