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
:func:`csgn_table_training`): one recipe trains either, against the same critic (:func:`generator_network`
picks the functions; the generator's ``buffers`` are its spectral-norm vectors or its BatchNorm statistics).
The critic is spectrally normalised on every layer, as the authors' always is.

Data: windows of ``frames`` frames with ActFormer's snake padding, in the dataset's own frame (no canonical
turn: ActFormer's data stay in the camera's), turned into the generator's representation: ``skeleton``
(:func:`~jaxmotion.geometry.representations.skeleton_features`: root minus the clip's mean root, unit limb
vectors) or ``smpl`` (rot6d of 24 joints + the translation de-meaned over the window as a 25th joint). The
code's persons stay in their stored order (the datasets hold swapped copies); ``permute_persons`` shuffles them
per window, the paper's choice. ``sampling="sqrt"``: BABEL's square-root class resampling.

As a table row (:class:`~jaxmotion.evaluation.tables.Recipe`): ``fit`` returns an
:class:`~jaxmotion.pipelines.actformer.ActFormerFit`, ``sampler`` the protocol's sampler
(:mod:`jaxmotion.pipelines.actformer`).

Axes: N critic steps, B batch, P persons, T frames, V joints, C channels.
"""

from __future__ import annotations

import dataclasses
from pathlib import Path
from typing import Any, Literal

import jax
import jax.numpy as jnp
import optax

from jaxmotion.data import synthetic
from jaxmotion.data.motion import MotionDataset
from jaxmotion.data.pipeline import BatchSpec, Sampling
from jaxmotion.geometry.representations import actformer_features
from jaxmotion.geometry.skeletons import SMPL24, Skeleton
from jaxmotion.models import actformer as actformer_generator
from jaxmotion.models import csgn
from jaxmotion.models.actformer import GeneratorConfig
from jaxmotion.models.actformer_critic import CriticConfig, CriticGraphs, critic, init_critic
from jaxmotion.models.csgn import CSGNConfig
from jaxmotion.nn.gp_prior import gp_factors, length_scales, sample_gp, white_factors
from jaxmotion.nn.graph_coarsening import critic_adjacency
from jaxmotion.pipelines.actformer import ActFormerFit, actformer_sampler, fit_of
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
        if self.n_critic < 1 or self.batch_size < 1:
            raise ValueError(f"ActFormerTraining: n_critic and batch_size must be >= 1, got {self.n_critic}, "
                             f"{self.batch_size}")
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

    def fit(self, data: MotionDataset, key: jax.Array, workdir: str | Path | None = None, **loop_options
            ) -> ActFormerFit:
        return fit_of(train_actformer(data, self, key, workdir, **loop_options), data)

    def sampler(self, trained: ActFormerFit, skeleton: Skeleton):
        return actformer_sampler(trained, self, skeleton)


def generator_network(config: GeneratorConfig | CSGNConfig):
    """The module holding ``config``'s generator: ``init_generator(key, config) -> (params, buffers)`` and
    ``generate(config, params, buffers, z, labels, *, train) -> (motion, buffers)``."""
    if isinstance(config, CSGNConfig):
        return csgn
    if isinstance(config, GeneratorConfig):
        return actformer_generator
    raise ValueError(f"generator: expected a GeneratorConfig or a CSGNConfig, got {type(config).__name__}")


def latent_factors(training: ActFormerTraining) -> jax.Array:
    g = training.generator
    if training.prior == "gaussian":
        return jnp.asarray(white_factors(g.frames, g.latent))
    return jnp.asarray(gp_factors(g.frames, length_scales(g.latent, training.length_scale)))


def sample_latents(training: ActFormerTraining, factors: jax.Array, key: jax.Array, batch: int) -> jax.Array:
    """``[B, T, Z]`` (shared by the persons) or ``[B, P, T, Z]`` (``shared_z=False``)."""
    g = training.generator
    if training.shared_z or g.persons == 1:
        return sample_gp(key, factors, batch)
    return sample_gp(key, factors, batch * g.persons).reshape(batch, g.persons, g.frames, g.latent)


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
    factors = latent_factors(training)
    b = training.batch_size

    def fakes(g_params, g_sn, key):
        k_z, k_y = jax.random.split(key)
        labels = jax.random.randint(k_y, (b,), 0, g_cfg.num_classes)
        motion, g_sn = generate(g_cfg, g_params, g_sn, sample_latents(training, factors, k_z, b), labels, train=True)
        return motion, labels, g_sn

    def step(state: MultiState, batch: dict[str, jax.Array], key: jax.Array):
        reals, labels = real_batches(training, batch, parents)
        keys = jax.random.split(key, training.n_critic + 1)
        g_sn, c_sn = state.buffers["generator"], state.buffers["critic"]
        real_scores = fake_scores = None
        for i in range(training.n_critic):
            fake, fake_labels, g_sn = fakes(state.params["generator"], g_sn, keys[i])
            fake = jax.lax.stop_gradient(fake)

            def critic_loss(c_params, c_sn=c_sn, i=i, fake=fake, fake_labels=fake_labels):
                real_score, c_sn = critic(c_cfg, graphs, c_params, c_sn, reals[i], labels[i], train=True)
                fake_score, c_sn = critic(c_cfg, graphs, c_params, c_sn, fake, fake_labels, train=True)
                return _critic_loss(training.loss, real_score, fake_score), (c_sn, real_score, fake_score)

            (d_loss, (c_sn, real_scores, fake_scores)), grads = jax.value_and_grad(critic_loss, has_aux=True)(
                state.params["critic"])
            state = state.apply("critic", grads)

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



#: ActFormer's data per embedded stand-in: (generator joints, output, class sampling); persons and classes
#: come from the data. NTU-13's stand-in holds SMPL-24 joints, trained as limbs like NTU's skeletons; the SMPL
#: sets add the translation as a 25th node; BABEL resamples classes by the square root of their counts; GTA
#: Combat's 22 joints are limbs too (width 8 · 22 = 176, as the authors' GTA configs).
ACTFORMER_DATA = {"synth-ntu13": (24, "skeleton", "epoch"), "synth-ntu1p": (25, "skeleton", "epoch"),
                  "synth-ntu1p-smpl": (25, "smpl", "epoch"), "synth-babel120": (25, "smpl", "sqrt"),
                  "synth-ntu2p": (25, "skeleton", "epoch"),
                  **{f"synth-combat-{p}p": (22, "skeleton", "epoch") for p in range(2, 6)}}
#: The code's length: 500 epochs of the train split, an epoch being one pass of 64-clip batches through the
#: critic (4 per generator step).
PAPER_EPOCHS = 500


def actformer_table_training(dataset: str, profile: str) -> ActFormerTraining:
    """ActFormer as a table row on the embedded ``dataset`` (a key of :data:`ACTFORMER_DATA`) in ``profile``.

    paper: the authors' configs (``config/generator/*``: width 8 per joint, depth 2, 8 heads, critic base 32,
    batch 64, :data:`PAPER_EPOCHS` epochs of the stand-in's train split; for real data set ``loop.steps`` to
    500 epochs of it). cpu: the same generator, a critic of base 8 and batches of 16, 2 000 generator steps (at
    the paper's critic and batch a step takes about 3 s on 2 cores, 1.7 h for 2 000; ``benchmarks/RESULTS.md``).
    smoke: a few steps of a tiny model."""
    if dataset not in ACTFORMER_DATA:
        raise ValueError(f"dataset: expected one of {sorted(ACTFORMER_DATA)}, got {dataset!r}")
    variant = synthetic.VARIANTS[dataset]
    joints, output, sampling = ACTFORMER_DATA[dataset]
    generator = GeneratorConfig(num_classes=len(variant.classes), joints=joints, channels=6 if output == "smpl" else 3,
                                persons=variant.persons, output=output)
    common = dict(generator=generator, sampling=sampling)
    if profile == "smoke":
        tiny = dataclasses.replace(generator, width_per_joint=4, depth=1, heads=4)
        return ActFormerTraining(**{**common, "generator": tiny}, loop=LoopConfig(2, log_every=1, checkpoint_every=2),
                                 critic_base_channels=8, batch_size=4)
    if profile == "cpu":
        return ActFormerTraining(**common, loop=LoopConfig(2000, log_every=100, checkpoint_every=500),
                                 critic_base_channels=8, batch_size=16)
    if profile == "paper":
        clips = variant.splits["train"].num_sequences
        steps = PAPER_EPOCHS * clips // (4 * 64)
        return ActFormerTraining(**common, loop=LoopConfig(steps, log_every=100, checkpoint_every=1000))
    raise ValueError(f"profile: expected smoke, cpu or paper, got {profile!r}")



def csgn_table_training(dataset: str, profile: str, temporal: str = "conv") -> ActFormerTraining:
    """The graph-convolution generator (:class:`~jaxmotion.models.csgn.CSGNConfig`) in ActFormer's recipe on
    ``dataset`` in ``profile`` (:func:`actformer_table_training`'s critic, batch, steps and GP prior):
    ``temporal="conv"`` is the CSGN baseline of Tables 1-2 (conditional BatchNorm in the generator, the
    projection critic), ``"transformer"`` Table 3's row (2), graph convolutions with T-Formers over time."""
    training = actformer_table_training(dataset, profile)
    g = training.generator
    variant = synthetic.VARIANTS[dataset]
    skeleton = SMPL24 if variant.markers is None else variant.markers.skeleton
    parents = skeleton.parents + ((0,) if g.output == "smpl" else ())  # SMPL-25: the translation node
    generator = CSGNConfig(num_classes=g.num_classes, joints=g.joints, channels=g.channels, persons=g.persons,
                           frames=g.frames, output=g.output, parents=parents, temporal=temporal)
    if profile == "smoke":
        generator = dataclasses.replace(generator, widths=(8, 8, 8, 8), heads=2)
    return dataclasses.replace(training, generator=generator)
