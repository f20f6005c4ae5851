"""ActFormer's generator as a whole: either network (the Transformer of :mod:`jaxmotion.models.actformer` or the
graph-convolution one of :mod:`jaxmotion.models.csgn`) with the latent prior its sequences are drawn from.

:class:`ActFormerModel` is what generation needs besides the weights; :func:`generator_network` picks a config's
module, :func:`latent_factors` and :func:`sample_latents` draw the latent sequences (the GP prior, or white noise
for the Gaussian-prior ablation; one sequence per clip shared by its persons, or one per person).

Axes: B clips, P persons, T frames, Z latent channels.
"""

from __future__ import annotations

import dataclasses
from typing import Literal

import jax
import jax.numpy as jnp

from jaxmotion.models import actformer, csgn
from jaxmotion.models.actformer import GeneratorConfig
from jaxmotion.models.csgn import CSGNConfig
from jaxmotion.nn.gp_prior import gp_factors, length_scales, sample_gp, white_factors


@dataclasses.dataclass(frozen=True)
class ActFormerModel:
    """A generator and its latent prior: ``prior`` (``"gp"``, or ``"gaussian"``: white), the GP's
    ``length_scale`` and ``shared_z`` (one latent sequence per clip shared by its persons)."""

    generator: GeneratorConfig | CSGNConfig
    prior: Literal["gp", "gaussian"] = "gp"
    length_scale: float = 100.0
    shared_z: bool = True

    def __post_init__(self):
        if self.prior not in ("gp", "gaussian"):
            raise ValueError(f"ActFormerModel.prior: expected 'gp' or 'gaussian', got {self.prior!r}")


def generator_network(config: GeneratorConfig | CSGNConfig):
    """The module holding ``config``'s generator: ``init_generator(key, config) -> (params, buffers)`` and
    ``generate(config, params, buffers, z, labels, *, train) -> (motion, buffers)``."""
    if isinstance(config, CSGNConfig):
        return csgn
    if isinstance(config, GeneratorConfig):
        return actformer
    raise ValueError(f"generator: expected a GeneratorConfig or a CSGNConfig, got {type(config).__name__}")


def latent_factors(model: ActFormerModel) -> jax.Array:
    """The prior's factors ``[Z, T, T]`` (:func:`~jaxmotion.nn.gp_prior.sample_gp` draws with them)."""
    g = model.generator
    if model.prior == "gaussian":
        return jnp.asarray(white_factors(g.frames, g.latent))
    return jnp.asarray(gp_factors(g.frames, length_scales(g.latent, model.length_scale)))


def sample_latents(model: ActFormerModel, factors: jax.Array, key: jax.Array, batch: int) -> jax.Array:
    """``[B, T, Z]`` (shared by the persons) or ``[B, P, T, Z]`` (``shared_z=False``)."""
    g = model.generator
    if model.shared_z or g.persons == 1:
        return sample_gp(key, factors, batch)
    return sample_gp(key, factors, batch * g.persons).reshape(batch, g.persons, g.frames, g.latent)
