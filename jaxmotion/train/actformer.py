"""Training ActFormer (:mod:`jaxmotion.models.actformer`, :mod:`jaxmotion.models.actformer_critic`) as the
authors' ``processor/generator.py`` does (FACTS 5).

:class:`ActFormerTraining` is the recipe: per loop step ``n_critic`` (4) critic updates, each on a new real
batch and fresh fakes (labels drawn uniformly), then one generator update; the code's hinge loss (critic
``relu(1 - D(real)) + relu(1 + D(fake))``, generator ``-D(fake)``) or the paper's conditional WGAN (``loss="wgan"``:
critic ``D(fake) - D(real)``); Adam 2e-4 with betas (0, 0.999) for both. Every forward pass in training moves its
spectral-norm power iterations, as PyTorch's hooks do: the critic's twice per critic update (real, then fake)
and once in the generator update, the generator's once per fake batch; the vectors live in the state's
``buffers``. Latent sequences come from the GP prior (``prior="gaussian"``: white, the ablation), one per clip
shared by its persons (``shared_z=False``: one per person). ``critic_pooling``: the critic on the stacked
persons (``"concat"``, the code) or on each person with its features pooled (Table 4's avg / max / attention).

The generator is ActFormer's Transformer (:class:`~jaxmotion.models.actformer.GeneratorConfig`) or the
graph-convolution one of CSGN and of Table 3's row (2) (:class:`~jaxmotion.models.csgn.CSGNConfig`,
:func:`~jaxmotion.recipes.actformer.csgn_table_training`): one recipe trains either, against the same critic (:func:`generator_network`
picks the functions; the generator's ``buffers`` are its spectral-norm vectors or its BatchNorm statistics).
The critic is spectrally normalised on every layer, as the authors' always is.

Data: windows of ``frames`` frames with ActFormer's snake padding, in the dataset's own frame (no canonical
turn: ActFormer's data stay in the camera's), turned into the generator's representation: ``skeleton``
(:func:`~jaxmotion.geometry.representations.skeleton_features`: root minus the clip's mean root, unit limb
vectors) or ``smpl`` (rot6d of 24 joints + the translation de-meaned over the window as a 25th joint). The
code's persons stay in their stored order (the datasets hold swapped copies); ``permute_persons`` shuffles them
per window, the paper's choice. ``sampling="sqrt"``: BABEL's square-root class resampling.

Its generator is :class:`jaxmotion.pipelines.actformer.ActFormerGenerator`; its table rows and profile sizes
are in :mod:`jaxmotion.recipes.actformer`.

Axes: N critic steps, B batch, P persons, T frames, V joints, C channels.
"""

from __future__ import annotations

import dataclasses
from pathlib import Path
from typing import Any, Literal

import jax
import jax.numpy as jnp
import optax

from jaxmotion.config import check_at_least
from jaxmotion.data.motion import MotionDataset
from jaxmotion.data.pipeline import BatchSpec, Sampling
from jaxmotion.geometry.representations import actformer_features
from jaxmotion.models.actformer import GeneratorConfig
from jaxmotion.models.actformer_prior import ActFormerModel, generator_network, latent_factors, sample_latents
from jaxmotion.models.actformer_critic import CriticConfig, CriticGraphs, critic, init_critic
from jaxmotion.models.csgn import CSGNConfig
from jaxmotion.nn.graph_coarsening import critic_adjacency
from jaxmotion.train.fit import fit
from jaxmotion.train.loop import LoopConfig
from jaxmotion.train.state import MultiState


@dataclasses.dataclass(frozen=True)
class ActFormerTraining:
    """Everything that determines an ActFormer training run (defaults: the authors' configs)."""

    generator: GeneratorConfig | CSGNConfig
    loop: LoopConfig
    critic_base_channels: int = 32
    loss: Literal["hinge", "wgan"] = "hinge"
    n_critic: int = 4
    learning_rate: float = 2e-4
    betas: tuple[float, float] = (0.0, 0.999)
    batch_size: int = 64
    prior: Literal["gp", "gaussian"] = "gp"
    length_scale: float = 100.0
    shared_z: bool = True
    permute_persons: bool = False
    sampling: Sampling = "epoch"
    critic_pooling: Literal["concat", "avg", "max", "attention"] = "concat"

    def __post_init__(self):
        check_at_least(self, 1, "critic_base_channels", "n_critic", "batch_size")
        if self.loss not in ("hinge", "wgan") or self.prior not in ("gp", "gaussian"):
            raise ValueError(f"ActFormerTraining: loss {self.loss!r} / prior {self.prior!r} unknown")
        if self.permute_persons and self.generator.persons < 2:
            raise ValueError("ActFormerTraining.permute_persons: needs a generator of several persons")
        if self.critic_pooling != "concat" and self.generator.persons < 2:
            raise ValueError(f"ActFormerTraining.critic_pooling: {self.critic_pooling!r} pools over persons; the "
                             f"generator has one")

    @property
    def critic(self) -> CriticConfig:
        g = self.generator
        stacked = self.critic_pooling == "concat"
        return CriticConfig(num_classes=g.num_classes, joints=g.joints,
                            channels=g.persons * g.channels if stacked else g.channels,
                            base_channels=self.critic_base_channels, pooling=self.critic_pooling)

    @property
    def batch(self) -> BatchSpec:
        """All ``n_critic`` real batches of a step drawn at once (split by :func:`real_batches`)."""
        return BatchSpec(batch_size=self.n_critic * self.batch_size, window=self.generator.frames, padding="snake",
                         canonical=False, sampling=self.sampling, permute_persons=self.permute_persons)

    @property
    def model(self) -> ActFormerModel:
        """The generator and its latent prior: what generation needs besides the weights."""
        return ActFormerModel(self.generator, self.prior, self.length_scale, self.shared_z)


def motion_features(batch: dict[str, jax.Array], generator: GeneratorConfig, parents: tuple[int, ...]) -> jax.Array:
    """A pipeline batch -> the generator's representation, ``[B, T, V, C]`` or ``[B, P, T, V, C]``."""
    kind = "rot6d+translation" if generator.output == "smpl" else "limbs"
    return actformer_features(kind, parents, batch["joints"], batch.get("translation"), batch.get("rotations"))


def real_batches(training: ActFormerTraining, batch: dict[str, jax.Array], parents: tuple[int, ...]
                 ) -> tuple[jax.Array, jax.Array]:
    """``(motions [N, B, ...], labels [N, B])``: the step's windows split into its critic updates."""
    n, b = training.n_critic, training.batch_size
    motions = motion_features(batch, training.generator, parents)
    return motions.reshape(n, b, *motions.shape[1:]), batch["actions"].reshape(n, b)


def actformer_state(training: ActFormerTraining, graphs: CriticGraphs, key: jax.Array) -> MultiState:
    k_g, k_c = jax.random.split(key)
    g_params, g_sn = generator_network(training.generator).init_generator(k_g, training.generator)
    c_params, c_sn = init_critic(k_c, training.critic, graphs)
    adam = optax.adam(training.learning_rate, b1=training.betas[0], b2=training.betas[1])
    return MultiState.create({"generator": g_params, "critic": c_params}, {"generator": adam, "critic": adam},
                             buffers={"generator": g_sn, "critic": c_sn})


def _critic_loss(loss: str, real: jax.Array, fake: jax.Array) -> jax.Array:
    if loss == "hinge":
        return jnp.mean(jax.nn.relu(1.0 - real)) + jnp.mean(jax.nn.relu(1.0 + fake))
    return jnp.mean(fake) - jnp.mean(real)


def actformer_step(training: ActFormerTraining, graphs: CriticGraphs, parents: tuple[int, ...]):
    """The loop's step function ``(state, batch, key) -> (state, metrics)``."""
    g_cfg, c_cfg = training.generator, training.critic
    generate = generator_network(g_cfg).generate
    factors = latent_factors(training.model)
    b = training.batch_size

    def fakes(g_params, g_sn, key):
        k_z, k_y = jax.random.split(key)
        labels = jax.random.randint(k_y, (b,), 0, g_cfg.num_classes)
        motion, g_sn = generate(g_cfg, g_params, g_sn, sample_latents(training.model, factors, k_z, b), labels, train=True)
        return motion, labels, g_sn

    def critic_update(carry, inputs):
        state, g_sn, c_sn = carry
        real, real_labels, key = inputs
        fake, fake_labels, g_sn = fakes(state.params["generator"], g_sn, key)
        fake = jax.lax.stop_gradient(fake)

        def critic_loss(c_params):
            real_score, moved = critic(c_cfg, graphs, c_params, c_sn, real, real_labels, train=True)
            fake_score, moved = critic(c_cfg, graphs, c_params, moved, fake, fake_labels, train=True)
            return _critic_loss(training.loss, real_score, fake_score), (moved, real_score, fake_score)

        (d_loss, (c_sn, real_score, fake_score)), grads = jax.value_and_grad(critic_loss, has_aux=True)(
            state.params["critic"])
        return (state.apply("critic", grads), g_sn, c_sn), (d_loss, real_score, fake_score)

    def step(state: MultiState, batch: dict[str, jax.Array], key: jax.Array):
        reals, labels = real_batches(training, batch, parents)
        keys = jax.random.split(key, training.n_critic + 1)
        # the critic's updates as a loop, not unrolled: XLA compiles one copy of the update instead of n_critic
        (state, g_sn, c_sn), (d_losses, real_scores, fake_scores) = jax.lax.scan(
            critic_update, (state, state.buffers["generator"], state.buffers["critic"]), (reals, labels, keys[:-1]))
        d_loss, real_scores, fake_scores = d_losses[-1], real_scores[-1], fake_scores[-1]

        def generator_loss(g_params):
            fake, fake_labels, moved_g = fakes(g_params, g_sn, keys[-1])
            score, moved_c = critic(c_cfg, graphs, state.params["critic"], c_sn, fake, fake_labels, train=True)
            return -jnp.mean(score), (moved_g, moved_c)

        (g_loss, (g_sn, c_sn)), grads = jax.value_and_grad(generator_loss, has_aux=True)(state.params["generator"])
        state = state.apply("generator", grads).with_buffer("generator", g_sn).with_buffer("critic", c_sn)
        return state.next_step(), {"critic_loss": d_loss, "generator_loss": g_loss,
                                   "real_score": jnp.mean(real_scores), "fake_score": jnp.mean(fake_scores)}

    return step


def _check_data(training: ActFormerTraining, data: MotionDataset) -> None:
    g = training.generator
    joints = g.joints - (1 if g.output == "smpl" else 0)  # SMPL-25: 24 joints + the translation
    if data.skeleton.num_joints != joints or data.persons != g.persons or data.num_classes != g.num_classes:
        raise ValueError(f"data: {data.name} has {data.skeleton.num_joints} joints, {data.persons} person(s) and "
                         f"{data.num_classes} classes; the generator expects {joints}, {g.persons} and {g.num_classes}")


def critic_graphs(training: ActFormerTraining, parents: tuple[int, ...]) -> CriticGraphs:
    """The critic's adjacencies for a skeleton (plus the translation node, parent 0, for SMPL-25)."""
    extra = (0,) if training.generator.output == "smpl" else ()
    return CriticGraphs(*critic_adjacency(tuple(parents) + extra))


def train_actformer(data: MotionDataset, training: ActFormerTraining, key: jax.Array,
                    workdir: str | Path | None = None, *, graphs: CriticGraphs | None = None, progress: bool = True,
                    **loop_options: Any) -> MultiState:
    """Train on ``data`` (resuming from ``workdir``'s checkpoints) and return the final state; ``graphs``: the
    critic's adjacencies, by default :func:`critic_graphs` of ``data``'s skeleton."""
    _check_data(training, data)
    parents = data.skeleton.parents
    graphs = critic_graphs(training, parents) if graphs is None else graphs
    return fit(data, key, init_state=lambda k: actformer_state(training, graphs, k),
               step_fn=actformer_step(training, graphs, parents), batch=training.batch, loop=training.loop,
               workdir=workdir, progress=progress, **loop_options)
