"""A PyTorch ODMO of the same architecture as jaxmotion's (:mod:`jaxmotion.models.odmo`): the peer that
``benchmarks/bench_odmo.py`` times against the library in the same run.

Benchmark-only: it needs ``torch`` (``pip install -e ".[bench]"``), which is neither a runtime nor a test
dependency of jaxmotion, and nothing in ``jaxmotion/`` or ``tests/`` imports this file.

Written from the paper (Lu et al., ACM MM 2022, §3.2 and Suppl. Table S2), ``shared/reference/FACTS.md`` §6
and jaxmotion's docstrings, not copied from the authors' repository. Module and parameter names follow the
authors' ``Ensemble`` (``tgenerator.expand``, ``LMPencoder.fc.1.running_mean``, ``mgenerator.rnn.weight_ih_l1``,
``tgenerator.activation_fun``, ``mgenerator.relu`` ...), so the state dict that
``jaxmotion.models.odmo.state_dict(params, stats)`` gives loads with ``strict=True`` once the BatchNorm
counters ``num_batches_tracked`` (which jaxmotion does not keep) are added (:func:`load_jaxmotion`).

The model (batch-first tensors; every recurrence is ``nn.LSTM(batch_first=True)``):

* **LMP encoder** (``LMPencoder``): every joint minus its frame's root, ``encoder`` LSTM (F -> 64), its last
  layer's final hidden state through ``fc`` = ``Linear 256, BatchNorm1d, PReLU, Linear 256, BatchNorm1d,
  PReLU, Linear 2Z`` -> µ, logvar. The code is ``z = µ + exp(logvar / 2)·ε``.
* **Trajectory generator** (``tgenerator``): ``[outer(one-hot, z) flattened class-major (c·Z + z), end root]``
  -> ``expand`` Linear(in -> in·(T−1)) -> PReLU, viewed ``[B, T−1, in]`` -> ``embedding`` Linear 128 ->
  ``rnn`` LSTM 2 x 128 -> 3 x (``out_fc{0,1,2}`` Linear 128 -> PReLU) -> ``out_fc`` Linear 3: root velocities;
  the trajectory is the running sum of ``[0, velocities]``. One PReLU (``activation_fun``) for all four.
* **Motion generator** (``mgenerator``): ``encoder_embedding`` Linear(3 -> 128) -> PReLU -> ``encoder_rnn``
  LSTM 2 x 128 over the predicted trajectory; its final ``(h, c)`` starts the decoder. Decoder step ``t``
  reads ``[previous pose (F), outer(one-hot, z) (C·Z), (t+1)/T]`` through ``embedding`` Linear 128 -> PReLU,
  ``rnn`` LSTM 2 x 128 (one step per call: the recurrence is autoregressive) and ``out_fc`` Linear F. The
  previous pose is zeros at step 0, then the decoder's output ``t−1`` or, where ``teacher_mask[t−1]``, the
  true pose ``t−1``. One PReLU (``relu``) serves both embeddings. The time feature is ``1/T`` accumulated in
  float32, one addition per step.

**As jaxmotion computes it** (same numbers up to float32 summation order), and as a competent PyTorch user
would: the decoder embedding's condition and bias share (``outer(one-hot, z) @ W_cond + b``) is constant over
a sequence and is computed once per sequence, not once per frame (jaxmotion's ``decode_motion`` does the
same); the per-frame layers of the trajectory generator run on the whole sequence at once.

**Both halves of a pair in one pass**: the training step concatenates the two halves (``2B`` sequences) for
every LSTM, linear layer and the decoder loop, and splits them only for BatchNorm, where each half is
normalised with its own batch statistics and the running statistics move once per half, first half first
(what the authors' two sequential ``Ensemble.forward`` calls do; jaxmotion's ``encode(..., groups=2)``).
Fewer, larger calls than two passes, so this is the faster of the two fair choices.

**Loss** (``jaxmotion.losses.odmo.pair_loss`` at ``ODMOLossConfig()``'s defaults), per sequence, each a sum over
frames, batch means summed over the two halves: motion ``Σ_t mean_f w_f (m̂ − m)²`` (``w`` 5 on y); trajectory
``Σ_t mean_xyz w (r̂ − r)²`` on root positions plus consistency ``Σ_t mean_xyz (m̂_root − r̂)²``; KL of
``N(0, exp logvar)`` to ``N(0, 0.05²)`` summed over the code; contrastive on µ,
``½ [same · relu(d² − 0.25) + (1 − same) · relu(5 − √(d² + 1e-9))²]``. Optimiser:
``clip_grad_norm_(…, 1)`` then ``torch.optim.Adam`` (lr 1e-3).

Axes: B pairs (2B sequences in a step), T frames, J joints, F = 3J, C classes, Z code.
"""

from __future__ import annotations

import numpy as np
import torch
from torch import nn
from torch.nn import functional as F

# ------------------------------------------------------------------------------------------------ model


def condition(actions: torch.Tensor, code: torch.Tensor, num_classes: int) -> torch.Tensor:
    """The flattened outer product of the one-hot class and the code: ``[B], [B, Z] -> [B, C·Z]``."""
    one_hot = F.one_hot(actions.long(), num_classes).to(code.dtype)
    return (one_hot[:, :, None] * code[:, None, :]).reshape(code.shape[0], -1)


def time_feature(frames: int) -> torch.Tensor:
    """``(t+1)/T`` for ``t = 0..T−1``, as ``1/T`` added once per step in float32: ``[T]``."""
    step, t, out = np.float32(1.0 / frames), np.float32(0.0), np.empty(frames, np.float32)
    for i in range(frames):
        t = np.float32(t + step)
        out[i] = t
    return torch.from_numpy(out)


class LMPEncoder(nn.Module):
    def __init__(self, pose_dim: int, code_dim: int, hidden: int = 64, layers: int = 1, width: int = 256):
        super().__init__()
        self.encoder = nn.LSTM(pose_dim, hidden, layers, batch_first=True)
        self.fc = nn.Sequential(nn.Linear(hidden, width), nn.BatchNorm1d(width), nn.PReLU(),
                                nn.Linear(width, width), nn.BatchNorm1d(width), nn.PReLU(),
                                nn.Linear(width, 2 * code_dim))

    def forward(self, poses: torch.Tensor, groups: int = 1) -> tuple[torch.Tensor, torch.Tensor]:
        """``poses [B, T, F]`` -> ``µ, logvar [B, Z]``; ``groups``: consecutive equal parts of the batch that
        BatchNorm sees apart (the two halves of a pair batch), in order."""
        joints = poses.reshape(*poses.shape[:-1], -1, 3)
        lmp = (joints - joints[..., :1, :]).reshape(poses.shape)
        _, (h, _) = self.encoder(lmp)
        out = torch.cat([self.fc(part) for part in h[-1].chunk(groups)])  # BatchNorm sees each part alone
        return out.chunk(2, dim=-1)


class TrajGenerator(nn.Module):
    def __init__(self, num_classes: int, code_dim: int, frames: int, hidden: int = 128, layers: int = 2):
        super().__init__()
        self.num_classes, self.frames = num_classes, frames
        d_in = num_classes * code_dim + 3
        self.expand = nn.Linear(d_in, d_in * (frames - 1))
        self.embedding = nn.Linear(d_in, hidden)
        self.rnn = nn.LSTM(hidden, hidden, layers, batch_first=True)
        self.out_fc0 = nn.Linear(hidden, hidden)
        self.out_fc1 = nn.Linear(hidden, hidden)
        self.out_fc2 = nn.Linear(hidden, hidden)
        self.out_fc = nn.Linear(hidden, 3)
        self.activation_fun = nn.PReLU()

    def forward(self, code: torch.Tensor, actions: torch.Tensor, end: torch.Tensor) -> torch.Tensor:
        """``code [B, Z]``, ``actions [B]``, ``end [B, 3]`` -> root velocities ``[B, T−1, 3]``."""
        x = torch.cat([condition(actions, code, self.num_classes), end], -1)
        x = self.activation_fun(self.expand(x)).view(x.shape[0], self.frames - 1, -1)
        x, _ = self.rnn(self.embedding(x))
        for layer in (self.out_fc0, self.out_fc1, self.out_fc2):
            x = self.activation_fun(layer(x))
        return self.out_fc(x)


def integrate(velocities: torch.Tensor) -> torch.Tensor:
    """``[B, T−1, 3]`` -> positions ``[B, T, 3]`` from the origin."""
    return torch.cumsum(torch.cat([torch.zeros_like(velocities[:, :1]), velocities], 1), 1)


class MotionGenerator(nn.Module):
    def __init__(self, pose_dim: int, num_classes: int, code_dim: int, frames: int, hidden: int = 128,
                 layers: int = 2):
        super().__init__()
        self.pose_dim, self.num_classes, self.frames = pose_dim, num_classes, frames
        self.encoder_embedding = nn.Linear(3, hidden)
        self.encoder_rnn = nn.LSTM(hidden, hidden, layers, batch_first=True)
        self.embedding = nn.Linear(pose_dim + num_classes * code_dim + 1, hidden)
        self.rnn = nn.LSTM(hidden, hidden, layers, batch_first=True)
        self.out_fc = nn.Linear(hidden, pose_dim)
        self.relu = nn.PReLU()
        self.register_buffer("time", time_feature(frames), persistent=False)

    def forward(self, code: torch.Tensor, actions: torch.Tensor, trajectory: torch.Tensor,
                teacher: torch.Tensor | None = None, teacher_mask: torch.Tensor | None = None) -> torch.Tensor:
        """``code [B, Z]``, ``actions [B]``, ``trajectory [B, T, 3]`` -> ``poses [B, T, F]``. ``teacher [B, T, F]``
        and ``teacher_mask`` (bool ``[T, B]``): where ``teacher_mask[t]``, step ``t + 1`` reads ``teacher[:, t]``."""
        _, state = self.encoder_rnn(self.relu(self.encoder_embedding(trajectory)))
        f = self.pose_dim
        w = self.embedding.weight
        w_pose, w_cond, w_time = w[:, :f], w[:, f:-1], w[:, -1]
        constant = F.linear(condition(actions, code, self.num_classes), w_cond, self.embedding.bias)  # [B, H]
        previous = code.new_zeros(code.shape[0], f)
        outputs = []
        for t in range(self.frames):
            x = self.relu(F.linear(previous, w_pose) + constant + self.time[t] * w_time)
            top, state = self.rnn(x[:, None], state)
            out = self.out_fc(top[:, 0])
            outputs.append(out)
            if teacher is not None and t + 1 < self.frames:
                previous = torch.where(teacher_mask[t][:, None], teacher[:, t], out)
            else:
                previous = out
        return torch.stack(outputs, 1)


class ODMOPeer(nn.Module):
    """ODMO's ``Ensemble``: ``tgenerator``, ``LMPencoder``, ``mgenerator`` (HumanAct12 sizes by default)."""

    def __init__(self, num_joints: int = 24, num_classes: int = 12, frames: int = 60, code_dim: int = 20):
        super().__init__()
        pose_dim = 3 * num_joints
        self.code_dim, self.frames = code_dim, frames
        self.tgenerator = TrajGenerator(num_classes, code_dim, frames)
        self.LMPencoder = LMPEncoder(pose_dim, code_dim)
        self.mgenerator = MotionGenerator(pose_dim, num_classes, code_dim, frames)

    def forward(self, poses: torch.Tensor, actions: torch.Tensor, eps: torch.Tensor | None = None,
                teacher_mask: torch.Tensor | None = None, groups: int = 1) -> dict[str, torch.Tensor]:
        """``poses [B, T, F]`` (root of frame 0 at the origin) -> ``mu, logvar [B, Z]``, ``trajectory
        [B, T, 3]`` (predicted, from the true end root), ``poses [B, T, F]`` (decoded); ``eps [B, Z]``: the
        reparameterisation noise (drawn here when None)."""
        mu, logvar = self.LMPencoder(poses, groups)
        if eps is None:
            eps = torch.randn_like(mu)
        code = mu + torch.exp(0.5 * logvar) * eps
        trajectory = integrate(self.tgenerator(code, actions, poses[:, -1, :3]))
        decoded = self.mgenerator(code, actions, trajectory, teacher=poses, teacher_mask=teacher_mask)
        return {"mu": mu, "logvar": logvar, "trajectory": trajectory, "poses": decoded}

    def generate(self, code: torch.Tensor, actions: torch.Tensor, end: torch.Tensor) -> dict[str, torch.Tensor]:
        """Motions from codes ``[B, Z]``, classes ``[B]`` and end roots ``[B, 3]``; no teacher forcing."""
        trajectory = integrate(self.tgenerator(code, actions, end))
        return {"poses": self.mgenerator(code, actions, trajectory), "trajectory": trajectory}


def load_jaxmotion(model: ODMOPeer, arrays: dict[str, np.ndarray]) -> ODMOPeer:
    """Load ``jaxmotion.models.odmo.state_dict(params, stats)`` (numpy, the authors' names) with
    ``strict=True``; the BatchNorm counters jaxmotion does not keep start at 0."""
    tensors = {name: torch.from_numpy(np.array(value, np.float32, copy=True)) for name, value in arrays.items()}
    for name, buffer in model.state_dict().items():
        if name.endswith("num_batches_tracked"):
            tensors.setdefault(name, torch.zeros_like(buffer))
    model.load_state_dict(tensors, strict=True)
    return model


# ------------------------------------------------------------------------------------------------ loss


def _frame_error(prediction: torch.Tensor, target: torch.Tensor, y_weight: float) -> torch.Tensor:
    """``Σ_t mean_c w_c (prediction − target)²``: ``[B, T, C]`` twice -> ``[B]``, ``w`` = y_weight on y."""
    w = torch.ones(prediction.shape[-1], dtype=prediction.dtype)
    w[1::3] = y_weight
    return ((prediction - target).square() * w).mean(-1).sum(-1)


def pair_loss(out: dict[str, torch.Tensor], poses: torch.Tensor, same: torch.Tensor, *, y_weight: float = 5.0,
              prior_std: float = 0.05, margin: float = 5.0, slack: float = 0.25):
    """The loss of a pair batch from one forward pass over both halves (``2B`` rows, first halves first):
    the total and its terms (each a batch mean), as ``jaxmotion.losses.odmo.pair_loss`` at its defaults."""
    b = same.shape[0]
    root = poses[..., :3]
    motion = _frame_error(out["poses"], poses, y_weight)
    trajectory = (_frame_error(out["trajectory"], root, y_weight)
                  + (out["poses"][..., :3] - out["trajectory"]).square().mean(-1).sum(-1))
    logvar = out["logvar"]
    kl = (np.log(prior_std) - 0.5 * logvar + logvar.exp() / (2.0 * prior_std**2) - 0.5).sum(-1)
    mu = out["mu"]
    d2 = (mu[b:] - mu[:b]).square().sum(-1)
    contrastive = 0.5 * torch.where(same, F.relu(d2 - slack), F.relu(margin - torch.sqrt(d2 + 1e-9)).square())
    pair = lambda v: (v[:b] + v[b:]).mean()
    terms = {"motion": pair(motion), "trajectory": pair(trajectory), "kl": pair(kl),
             "contrastive": contrastive.mean()}
    return sum(terms.values()), terms


# --------------------------------------------------------------------------------------------- training


def make_optimizer(model: nn.Module, learning_rate: float = 1e-3) -> torch.optim.Optimizer:
    return torch.optim.Adam(model.parameters(), lr=learning_rate)


def pair_inputs(batch: dict) -> tuple[torch.Tensor, torch.Tensor, torch.Tensor]:
    """A pipeline pair batch (``first``/``second`` with ``joints [B, T, J, 3]`` and ``actions [B]``, ``same
    [B]``) -> ``poses [2B, T, F]``, ``actions [2B]``, ``same [B]`` (first halves first)."""
    first, second = batch["first"], batch["second"]
    joints = torch.cat([first["joints"], second["joints"]])
    poses = joints.reshape(*joints.shape[:2], -1)
    return poses, torch.cat([first["actions"], second["actions"]]), batch["same"].bool()


def train_step(model: ODMOPeer, optimizer, batch: dict, *, rate: float = 1.0, eps: torch.Tensor | None = None,
               teacher_mask: torch.Tensor | None = None, clip_norm: float = 1.0) -> torch.Tensor:
    """One step on a pair batch: both halves through the model in train mode (one pass, BatchNorm per half),
    :func:`pair_loss`, backward, ``clip_grad_norm_``, Adam. ``teacher_mask [T, 2B]`` (None: one Bernoulli
    draw with probability ``rate`` per decoder step and half, shared by the half's rows, as the authors'
    code draws), ``eps [2B, Z]`` (None: drawn). Returns the loss before the update (detached)."""
    model.train()
    poses, actions, same = pair_inputs(batch)
    b = same.shape[0]
    if teacher_mask is None:
        draws = torch.rand(2, model.frames) < rate
        teacher_mask = draws.T.repeat_interleave(b, dim=1)
    out = model(poses, actions, eps=eps, teacher_mask=teacher_mask, groups=2)
    loss, _ = pair_loss(out, poses, same)
    optimizer.zero_grad(set_to_none=True)
    loss.backward()
    torch.nn.utils.clip_grad_norm_(model.parameters(), clip_norm)
    optimizer.step()
    return loss.detach()


@torch.inference_mode()
def generate(model: ODMOPeer, code: torch.Tensor, actions: torch.Tensor, end: torch.Tensor):
    """Sampling as it is timed: eval mode, no autograd, trajectory then decoder."""
    model.eval()
    return model.generate(code, actions, end)
