"""Neural Marionette's training loss (§4.2.2, Eqs. 1-2; weights from the supplement's §3), on the 135-number pose
(:func:`~jaxmotion.geometry.representations.pose135`).

Per pass, with ``R`` the 22 joints' 6D rotations, ``D`` the root translation and ``J`` joint positions:

    L_X     = mse(X, X^) + lambda_V mse(X', X^')          X' = X_t - X_(t-1), over consecutive real frames
    L_Recon = lambda_R L_R + lambda_D L_D + lambda_J L_J
    L       = lambda_1 L_Recon(first pass) + lambda_2 L_Recon(second pass) + lambda_KL KL

Weights: lambda_R 1, lambda_D 0.5, lambda_J 2, lambda_V 2, lambda_KL 1e-8; lambda_1, lambda_2 are the trainer's
(1 and 0 without scheduled sampling, 0.1 and 0.9 while it is active). Choices where the paper is silent: squared
errors are means over the real frames and the numbers of a frame (``masked_mse``, as ACTOR's code); the KL to
N(0, I) is summed over the batch and the latent (ACTOR's code); joints are "local": forward kinematics of the
rotations on the skeleton given (SMPL-24's template for the mean shape; the hands at rest) with the root at the
origin, so the translation is D's alone.

Axes: B actions, T frames, d latent size.
"""

from __future__ import annotations

import dataclasses

import jax
import jax.numpy as jnp

from jaxmotion.geometry.kinematics import forward_kinematics
from jaxmotion.geometry.representations import POSE135_JOINTS, pose135_rotmats
from jaxmotion.geometry.skeletons import Skeleton
from jaxmotion.losses.core import kl_to_standard_normal, masked_mse, masked_velocity_mse


@dataclasses.dataclass(frozen=True)
class MarionetLossWeights:
    """lambda_R, lambda_D, lambda_J, lambda_V and lambda_KL (the supplement's values)."""

    rotations: float = 1.0
    translation: float = 0.5
    joints: float = 2.0
    velocity: float = 2.0
    kl: float = 1e-8


def local_joints(poses: jax.Array, skeleton: Skeleton) -> jax.Array:
    """``poses [B, T, 135]`` -> joint positions ``[B, T, 24, 3]`` about the root on ``skeleton`` (an SMPL-24 one):
    forward kinematics of :func:`~jaxmotion.geometry.representations.pose135_rotmats`."""
    return forward_kinematics(pose135_rotmats(poses), jnp.zeros((*poses.shape[:2], 3), poses.dtype), skeleton.offsets,
                              skeleton.parents, check=False)


def reconstruction(prediction: jax.Array, target: jax.Array, mask: jax.Array, weights: MarionetLossWeights,
                   skeleton: Skeleton) -> tuple[jax.Array, dict[str, jax.Array]]:
    """``L_Recon`` of ``prediction`` against ``target [B, T, 135]`` over ``mask [B, T]`` -> ``(value, {rotations,
    translation, joints})``, each term with its velocity part."""
    split = POSE135_JOINTS * 6
    parts = {"rotations": (prediction[..., :split], target[..., :split]),
             "translation": (prediction[..., split:], target[..., split:]),
             "joints": (local_joints(prediction, skeleton), local_joints(target, skeleton))}
    terms = {name: masked_mse(p, t, mask) + weights.velocity * masked_velocity_mse(p, t, mask)
             for name, (p, t) in parts.items()}
    return sum(getattr(weights, name) * value for name, value in terms.items()), terms


def marionet_loss(first: jax.Array, second: tuple[jax.Array, dict[str, jax.Array]] | None, target: jax.Array,
                  mask: jax.Array, mu: jax.Array, log_variance: jax.Array, *, weights: MarionetLossWeights,
                  skeleton: Skeleton, first_weight: float | jax.Array = 1.0, second_weight: float | jax.Array = 0.0
                  ) -> tuple[jax.Array, dict[str, jax.Array]]:
    """Eq. 2: the teacher-forced pass ``first`` against ``target [B, T, 135]`` over ``mask [B, T]``, the
    scheduled-sampling pass's :func:`reconstruction` ``second`` (None: none; the trainer runs it only when it
    weighs), plus the KL of ``mu``, ``log_variance [B, d]`` -> ``(loss, {term: value})``."""
    total, terms = reconstruction(first, target, mask, weights, skeleton)
    total = first_weight * total
    if second is not None:
        again, second_terms = second
        total = total + second_weight * again
        terms.update({f"{name} (second pass)": value for name, value in second_terms.items()})
    terms["kl"] = kl_to_standard_normal(mu, log_variance)
    total = total + weights.kl * terms["kl"]
    return total, {**terms, "loss": total}
