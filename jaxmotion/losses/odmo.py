"""ODMO's training loss (P-OD eq. 1-5; the authors' ``Trainer``, OD ``src/modules/trainer.py``, and
``ContrastiveLoss``, ``models.py``), as jit-compiled kernels.

A training example is a **pair** of windows ``(M_1, M_2)`` with classes ``c_1, c_2``; both pass through the
autoencoder (:func:`jaxmotion.models.odmo.forward`) and

    L = mean_b(L_traj,1 + L_traj,2) + mean_b(L_mre,1 + L_mre,2) + mean_b(KL_1 + KL_2) + mean_b(L_ctr)

per sequence (each a sum over frames ``t``; ``w`` weights the vertical coordinate by ``y_weight``, 5 on
HumanAct12 and UESTC, 1 on MoCap):

* **motion reconstruction** ``L_mre = Σ_t mean_f w_f (m̂_t,f − m_t,f)²`` over the ``F`` pose features;
* **trajectory** ``Σ_t mean_xyz w (r̂_t − r_t)²`` on the root **positions** (the code) plus the
  **consistency** term ``Σ_t mean_xyz (m̂_t^root − r̂_t)²`` (not y-weighted) between the motion
  generator's root and the trajectory generator's; ``trajectory="velocities"`` is eq. 2 of the paper,
  ``Σ_t mean_xyz w (v̂_t − (r_t − r_{t−1}))²`` over the ``T − 1`` predicted velocities;
* **KL** of ``q = N(0, σ_q²)`` (the code keeps the mean out: it regularises only the spread) to the prior
  ``N(0, σ²)``, summed over the code's dimensions. The code's ``sigma`` 0.05 is the prior's **standard
  deviation** (``prior="std"``, default); the paper writes σ² = 0.05, a variance (``prior="variance"``).
  Table S1's σ² values are passed as ``prior_scale`` under either reading;
* **contrastive** on the code means, ``d² = ‖µ_1 − µ_2‖²``:
  ``½ [same · relu(d² − 0.25) + (1 − same) · relu(α − √(d² + 1e-9))²]`` with margin ``α`` 5 (the code);
  ``same_class="squared"`` uses the paper's ``d²`` for same-class pairs.

Ablation switches: ``contrastive=False`` (−L_es: the KL stays, as in the code's ``use_contrastive``),
``trajectory_loss=False`` (−L_traj: trajectory and consistency terms off, the code's ``use_traj_loss``),
``consistency=False`` (−L_cons: the consistency term only).

Axes: B batch, T frames, F pose features (joint-major), Z code.
"""

from __future__ import annotations

import dataclasses
from typing import Literal

import jax
import jax.numpy as jnp


@dataclasses.dataclass(frozen=True, kw_only=True)
class ODMOLossConfig:
    """Weights and switches of ODMO's loss (defaults: the authors' code on HumanAct12)."""

    y_weight: float = 5.0  # HumanAct12 and UESTC 5, CMU MoCap 1
    margin: float = 5.0  # α
    same_class: Literal["hinge", "squared"] = "hinge"  # code: relu(d² − slack); paper: d²
    same_class_slack: float = 0.25
    prior_scale: float = 0.05
    prior: Literal["std", "variance"] = "std"  # what prior_scale is: code, the prior's std; paper, its variance
    trajectory: Literal["positions", "velocities"] = "positions"  # code: positions (+ consistency); paper: eq. 2
    contrastive: bool = True  # False: −L_es
    trajectory_loss: bool = True  # False: −L_traj (trajectory and consistency terms)
    consistency: bool = True  # False: −L_cons

    def __post_init__(self):
        if self.same_class not in ("hinge", "squared"):
            raise ValueError(f"ODMOLossConfig.same_class: expected 'hinge' or 'squared', got {self.same_class!r}")
        if self.prior not in ("std", "variance"):
            raise ValueError(f"ODMOLossConfig.prior: expected 'std' or 'variance', got {self.prior!r}")
        if self.trajectory not in ("positions", "velocities"):
            raise ValueError(f"ODMOLossConfig.trajectory: expected 'positions' or 'velocities', got {self.trajectory!r}")
        for name in ("y_weight", "margin", "prior_scale"):
            if not getattr(self, name) > 0:
                raise ValueError(f"ODMOLossConfig.{name}: expected > 0, got {getattr(self, name)!r}")

    @property
    def prior_std(self) -> float:
        return self.prior_scale if self.prior == "std" else self.prior_scale ** 0.5


def _y_weights(channels: int, y_weight: float) -> jax.Array:
    """``[channels]``: 1, with ``y_weight`` on every vertical coordinate (index 1 mod 3)."""
    return jnp.where(jnp.arange(channels) % 3 == 1, y_weight, 1.0).astype(jnp.float32)


def weighted_frame_error(prediction: jax.Array, target: jax.Array, y_weight: float) -> jax.Array:
    """``Σ_t mean_c w_c (prediction − target)²``: ``[B, T, C]`` twice -> ``[B]`` (``C`` = 3 per joint)."""
    w = _y_weights(prediction.shape[-1], y_weight)
    return (jnp.square(prediction - target) * w).mean(-1).sum(-1)


def motion_loss(decoded: jax.Array, poses: jax.Array, y_weight: float) -> jax.Array:
    """``L_mre``: ``[B, T, F]`` twice -> ``[B]``."""
    return weighted_frame_error(decoded, poses, y_weight)


def trajectory_loss(out: dict[str, jax.Array], poses: jax.Array, config: ODMOLossConfig) -> jax.Array:
    """The trajectory term (positions or velocities) plus, when on, the consistency term: ``[B]``."""
    root = poses[..., :3]  # [B, T, 3]
    if config.trajectory == "positions":
        loss = weighted_frame_error(out["trajectory"], root, config.y_weight)
    else:
        loss = weighted_frame_error(out["velocities"], root[:, 1:] - root[:, :-1], config.y_weight)
    if config.consistency:
        loss = loss + jnp.square(out["poses"][..., :3] - out["trajectory"]).mean(-1).sum(-1)
    return loss


def prior_kl(logvar: jax.Array, prior_std: float) -> jax.Array:
    """``KL(N(0, exp(logvar)) ‖ N(0, prior_std²))`` summed over the code: ``[B, Z] -> [B]``."""
    log_ratio = jnp.log(prior_std) - 0.5 * logvar
    return (log_ratio + jnp.exp(logvar) / (2.0 * prior_std**2) - 0.5).sum(-1)


def contrastive_loss(mu_1: jax.Array, mu_2: jax.Array, same: jax.Array, config: ODMOLossConfig) -> jax.Array:
    """``[B, Z]`` twice and ``same [B]`` (bool: the pair shares a class) -> ``[B]``."""
    d2 = jnp.square(mu_2 - mu_1).sum(-1)
    pull = jax.nn.relu(d2 - config.same_class_slack) if config.same_class == "hinge" else d2
    push = jnp.square(jax.nn.relu(config.margin - jnp.sqrt(d2 + 1e-9)))
    return 0.5 * jnp.where(same, pull, push)


def pair_loss(out_1: dict[str, jax.Array], out_2: dict[str, jax.Array], poses_1: jax.Array, poses_2: jax.Array,
              same: jax.Array, config: ODMOLossConfig) -> tuple[jax.Array, dict[str, jax.Array]]:
    """The total loss of a batch of pairs from the two forward passes, and its terms (each a batch mean,
    before the switches drop a term): ``loss``, ``motion``, ``trajectory``, ``kl``, ``contrastive``."""
    terms = {
        "motion": (motion_loss(out_1["poses"], poses_1, config.y_weight)
                   + motion_loss(out_2["poses"], poses_2, config.y_weight)).mean(),
        "trajectory": (trajectory_loss(out_1, poses_1, config) + trajectory_loss(out_2, poses_2, config)).mean(),
        "kl": (prior_kl(out_1["logvar"], config.prior_std) + prior_kl(out_2["logvar"], config.prior_std)).mean(),
        "contrastive": contrastive_loss(out_1["mu"], out_2["mu"], same, config).mean(),
    }
    loss = terms["motion"] + terms["kl"]
    if config.trajectory_loss:
        loss = loss + terms["trajectory"]
    if config.contrastive:
        loss = loss + terms["contrastive"]
    return loss, {"loss": loss, **terms}
