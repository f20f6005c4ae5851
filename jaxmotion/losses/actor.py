"""ACTOR's training losses (paper §3.2; the authors' ``src/models/tools/losses.py``).

On ACTOR's motion tensor ``x [B, T, J + 1, C]`` (joint rotations in a representation with C channels,
then the translation row ``[tx, ty, tz, 0, ...]``) with ``mask [B, T]``:

* ``L_P`` (code: ``rc``) mean squared error over the real frames of the whole tensor, translation row
  included; ``L_R`` / ``L_D`` the same restricted to the rotation rows / the translation row (Table 1).
* ``L_J`` mean squared error of root-centred joint positions from forward kinematics of the rotations on
  a fixed skeleton (the paper's joint loss; FK replaces the SMPL joint regressor).
* ``L_V`` mean squared error of root-centred body vertices from an SMPL-format body layer, only when the
  user supplies a model file (``jaxmotion.geometry.body``); there is no substitute for it.
* ``KL`` the Gaussian KL to N(0, I), **summed** over batch and latent dimensions as in the code, weighted
  by λ_KL (1e-5).

Axes: B batch, T frames, J joints, C channels, d model width (the size of z).
"""

from __future__ import annotations

import dataclasses

import jax
import jax.numpy as jnp

from jaxmotion.geometry.body import BodyModel, body_forward_rotmats
from jaxmotion.geometry.kinematics import forward_kinematics
from jaxmotion.geometry.rotations import to_matrix
from jaxmotion.geometry.skeletons import Skeleton
from jaxmotion.losses.core import kl_to_standard_normal, masked_mse


@dataclasses.dataclass(frozen=True)
class ActorLossWeights:
    """Weights of each term; 0 leaves a term out. Defaults: the paper's final model without L_V."""

    motion: float = 1.0  # L_P: rotations and translation
    rotations: float = 0.0  # L_R alone (Table 1 rows without translation)
    translation: float = 0.0  # L_D alone
    joints: float = 0.0  # L_J
    vertices: float = 0.0  # L_V, needs a body model
    kl: float = 1e-5  # λ_KL


def root_centred_joints(x: jax.Array, rep: str, skeleton: Skeleton) -> jax.Array:
    """Joint positions with the root at the origin in every frame, from the rotation rows of ``x
    [B, T, J + 1, C]``, on ``skeleton``'s rest offsets: ``-> [B, T, J, 3]``. With ``rep="matrix"`` the
    network's raw matrices pose the body as they are (the authors' code does not orthogonalise them)."""
    rotmats = to_matrix(x[:, :, :-1], rep)
    return forward_kinematics(rotmats, jnp.zeros(x.shape[:2] + (3,), x.dtype), skeleton.offsets, skeleton.parents,
                              check=False)


def root_centred_vertices(x: jax.Array, rep: str, body: BodyModel) -> jax.Array:
    """Body vertices (mean shape) with the root joint at the origin in every frame: ``-> [B, T, V, 3]``."""
    vertices, joints = body_forward_rotmats(body, to_matrix(x[:, :, :-1], rep), check=False)
    return vertices - joints[..., :1, :]


def actor_loss(output: jax.Array, target: jax.Array, mask: jax.Array, mu: jax.Array, logvar: jax.Array, *,
               rep: str, weights: ActorLossWeights, skeleton: Skeleton,
               body: BodyModel | None = None) -> tuple[jax.Array, dict[str, jax.Array]]:
    """The weighted sum of ACTOR's terms and each term: ``output``, ``target [B, T, J + 1, C]``,
    ``mask [B, T]``, ``mu``, ``logvar [B, d]`` -> ``(loss, {term: value})``."""
    if weights.vertices and body is None:
        raise ValueError("weights.vertices > 0 needs an SMPL-format body model (L_V has no substitute); "
                         "pass body=load_body_model(path) or set the vertex weight to 0")
    terms = {}
    if weights.motion:
        terms["motion"] = masked_mse(output, target, mask)
    if weights.rotations:
        terms["rotations"] = masked_mse(output[:, :, :-1], target[:, :, :-1], mask)
    if weights.translation:
        terms["translation"] = masked_mse(output[:, :, -1, :3], target[:, :, -1, :3], mask)
    if weights.joints:
        terms["joints"] = masked_mse(root_centred_joints(output, rep, skeleton),
                                     root_centred_joints(target, rep, skeleton), mask)
    if weights.vertices:
        terms["vertices"] = masked_mse(root_centred_vertices(output, rep, body),
                                       root_centred_vertices(target, rep, body), mask)
    terms["kl"] = kl_to_standard_normal(mu, logvar)
    total = sum(getattr(weights, name) * value for name, value in terms.items())
    return total, {**terms, "loss": total}
