"""Neural Marionette's table rows and sizes: models that continue a context (MARIONET, and the baselines its
Table 1 adapts: MANN, Action2Motion) and ACTOR, the context-free reference row, trained on synth-mag's actions and
scored by the single-action protocol (:mod:`jaxmotion.evaluation.actions`).

* :class:`MarionetRecipe`, :class:`MannRecipe`, :class:`A2MContextRecipe` (:class:`ContextRecipe`s): a context
  model's trainer config as a row: fit trains it on the takes' action items and keeps a start bank of the training
  data; its generator is a :class:`~jaxmotion.pipelines.marionette.ContextGenerator`.
* :class:`ContextFreeRecipe`: ACTOR as a row: trained on the takes' actions (each labelled with its first tag),
  placed after each test action's context to be scored (:func:`~jaxmotion.pipelines.marionette.context_free_sampler`).
* :func:`marionet_training`, :func:`mann_training`, :func:`a2m_training`, :func:`actor_training`: the smoke / cpu /
  paper sizes; :func:`action_table` the data, evaluator and protocol per profile; :func:`run_action_table` trains
  a table's rows (:func:`~jaxmotion.recipes.tables.fit_rows`) and scores them together.
* :class:`ChainRow`, :func:`program_table`, :func:`run_program_table`: the multi-action tables (3-5): a context
  model chained (:mod:`jaxmotion.pipelines.multi_action`) on the overall and sufficient test programs
  (:mod:`jaxmotion.evaluation.multi_action`).
"""

from __future__ import annotations

import dataclasses
import functools
import json
from collections.abc import Mapping, Sequence
from pathlib import Path
from types import MappingProxyType
from typing import Any, NamedTuple

import jax
import numpy as np

from jaxmotion.config import check_at_least
from jaxmotion.data.datasets import check_dataset_name, load_dataset
from jaxmotion.data.motion import MotionDataset
from jaxmotion.data.segments import label_transitions
from jaxmotion.evaluation.actions import MARIONETTE_COLUMNS, ActionProtocol, action_set, evaluate_actions
from jaxmotion.evaluation.multi_action import (MULTI_ACTION_COLUMNS, MultiActionProtocol, candidate_actions,
                                               evaluate_programs, test_programs)
from jaxmotion.evaluation.recognizers import RecognizerTraining, trained_recognizer
from jaxmotion.evaluation.tables import paper_columns
from jaxmotion.models.actor import ActorConfig
from jaxmotion.models.mann import MannConfig
from jaxmotion.models.marionet import MarionetConfig
from jaxmotion.pipelines.artefacts import DataFacts
from jaxmotion.pipelines.marionette import ContextGenerator, StartBank, context_free_sampler, start_bank
from jaxmotion.pipelines.multi_action import ChainOptions, chain_actions, joined
from jaxmotion.recipes.actor import CPU_BASELINE, ActorRecipe
from jaxmotion.recipes.evaluators import evaluator_spec
from jaxmotion.recipes.tables import fit_rows
from jaxmotion.train.a2m import A2MActionTraining, train_a2m_actions
from jaxmotion.train.actor import ActorTraining
from jaxmotion.train.loop import LoopConfig
from jaxmotion.train.mann import MannTraining, train_mann
from jaxmotion.train.marionet import MarionetTraining, train_marionet
from jaxmotion.train.writers import WriterFactory
from jaxmotion.viz import save_curves

#: A context model's trainer config -> its training function.
TRAINERS = MappingProxyType({MarionetTraining: train_marionet, MannTraining: train_mann,
                             A2MActionTraining: train_a2m_actions})
#: Starts per tag a trained context model keeps (its start bank).
STARTS_PER_TAG = 8


class ContextFit(NamedTuple):
    """What a context model's fit gives: its parameters and the start bank of its training data."""

    params: Any
    starts: StartBank


class ContextRecipe:
    """A context model as a table row (module docstring); a subclass is a frozen dataclass whose one field, named
    after the model (so a config's row tells which recipe it is), is its trainer config."""

    @property
    def training(self) -> MarionetTraining | MannTraining | A2MActionTraining:
        return getattr(self, dataclasses.fields(self)[0].name)

    def fit(self, data: MotionDataset, key: jax.Array, workdir: str | Path | None = None, **loop_options
            ) -> ContextFit:
        params = TRAINERS[type(self.training)](data, self.training, key, workdir, **loop_options)
        return ContextFit(params, start_bank(data, STARTS_PER_TAG))

    def generator(self, trained: ContextFit, facts: DataFacts) -> ContextGenerator:
        return ContextGenerator(self.training.model, trained.params, facts, trained.starts,
                                max_frames=self.training.max_frames)


@dataclasses.dataclass(frozen=True)
class MarionetRecipe(ContextRecipe):
    marionet: MarionetTraining

    @property
    def fit_key(self) -> MarionetTraining:
        """What determines the fit: without time unrolling, tag injection (which acts on the unrolling's queries
        only) does not, so Table 2's "w/o TU" and "w/o TU and w/o TI" train once."""
        model = self.marionet.model
        if model.time_unrolling:
            return self.marionet
        return dataclasses.replace(self.marionet, model=dataclasses.replace(model, tag_injection=False))


@dataclasses.dataclass(frozen=True)
class MannRecipe(ContextRecipe):
    mann: MannTraining


@dataclasses.dataclass(frozen=True)
class A2MContextRecipe(ContextRecipe):
    """Action2Motion adapted (not :class:`~jaxmotion.recipes.a2m.A2MRecipe`, the original on class labels)."""

    a2m: A2MActionTraining


@dataclasses.dataclass(frozen=True)
class ContextFreeRecipe:
    """ACTOR as Neural Marionette's reference row: trained on the takes' actions (each labelled with its first tag),
    generating for a label and a duration."""

    actor: ActorTraining

    def fit(self, data: MotionDataset, key: jax.Array, workdir: str | Path | None = None, **loop_options) -> Any:
        return ActorRecipe(self.actor).fit(data.action_items(context=0).data, key, workdir, **loop_options)

    def generator(self, trained: Any, facts: DataFacts):
        return ActorRecipe(self.actor).generator(trained, facts)


def action_sampler_of(generator: Any):
    """The single-action protocol's sampler of a trained row: a context model's own, a context-free generator's
    class sampler placed after each context."""
    if hasattr(generator, "action_sampler"):
        return generator.action_sampler()
    return context_free_sampler(generator.sampler())


# --- sizes --------------------------------------------------------------------------------------------------------

#: synth-mag's training actions per epoch at batch 30 (6 458 action items with context): the paper's 1 000 epochs.
PAPER_STEPS = 1000 * 6458 // 30
_SMOKE_LOOP = LoopConfig(2, log_every=1, checkpoint_every=0)
#: Every row's steps in the cpu profile (batch 30: 7 epochs of synth-mag's actions), so the rows see the same data.
CPU_STEPS = 1500
CPU_LOOP = LoopConfig(CPU_STEPS, log_every=100, checkpoint_every=500)
#: The cpu and paper profiles' batches of similar durations for MANN and A2M (``length_buckets``). Not MARIONET's:
#: trained so, its cpu row scored FID 28.2 and accuracy 0.25 against 18.4 and 0.37 from mixed batches (the same
#: code, one run each, 2026-12-07), where MANN's and A2M's were no worse; MARIONET's batches stay mixed.
LENGTH_BUCKETS = 4


def marionet_training(profile: str, **switches) -> MarionetTraining:
    """MARIONET in ``profile``; ``switches``: the ablations' model fields (``time_unrolling``, ``tag_injection``,
    ``next_tag``) and ``scheduled_sampling``. smoke: :meth:`MarionetConfig.tiny` without dropout, 2 steps at batch
    8; cpu: d 64, 4 heads, FF 256, layers 2 / 2 / 2, a 16-number path embedding, no dropout, Adam 1e-3 for
    :data:`CPU_STEPS` at batch 30 (about 0.5 s a step on 2 cores; the paper's 1e-4 is for 215 000 steps; 1e-3
    reached at 500 steps the loss 3e-4 reached at 950); paper: the supplement's model and training. Dropout
    regularises the paper's 1,000 epochs; in the cpu profile's 7 it only slows learning (with the supplement's
    dropouts the decoder had not learnt to read its input poses by the end, and its actions moved half as much as
    the real ones)."""
    scheduled = switches.pop("scheduled_sampling", True)
    if profile in ("smoke", "cpu"):
        switches = {"encoder_dropout": 0.0, "unroll_dropout": 0.0, "decoder_dropout": 0.0, "path_dropout": 0.0,
                    **switches}
    if profile == "smoke":
        return MarionetTraining(MarionetConfig.tiny(**switches), _SMOKE_LOOP, batch_size=8,
                                scheduled_sampling=scheduled)
    if profile == "cpu":
        model = MarionetConfig(width=64, heads=4, ff=256, decoder_layers=2, path_width=16, **switches)
        return MarionetTraining(model, CPU_LOOP, learning_rate=1e-3, scheduled_sampling=scheduled)
    if profile == "paper":
        return MarionetTraining(MarionetConfig(**switches), LoopConfig(PAPER_STEPS, log_every=100,
                                                                       checkpoint_every=5000),
                                scheduled_sampling=scheduled)
    raise ValueError(f"profile: expected smoke, cpu or paper, got {profile!r}")


def mann_training(profile: str) -> MannTraining:
    """MANN adapted (:class:`~jaxmotion.train.mann.MannTraining`) in ``profile``. smoke: :meth:`MannConfig.tiny`, 2
    steps at batch 8; cpu: 4 experts of 256 units, Adam 3e-4 for :data:`CPU_STEPS` at batch 30 (MARIONET's cpu
    schedule); paper: 8 experts of 512, Adam 1e-4, MARIONET's steps."""
    if profile == "smoke":
        return MannTraining(MannConfig.tiny(dropout=0.0), _SMOKE_LOOP, batch_size=8)
    if profile == "cpu":
        return MannTraining(MannConfig(experts=4, hidden=256), CPU_LOOP, learning_rate=3e-4,
                            length_buckets=LENGTH_BUCKETS)
    if profile == "paper":
        return MannTraining(MannConfig(), LoopConfig(PAPER_STEPS, log_every=100, checkpoint_every=5000),
                            length_buckets=LENGTH_BUCKETS)
    raise ValueError(f"profile: expected smoke, cpu or paper, got {profile!r}")


def a2m_training(profile: str) -> A2MActionTraining:
    """Action2Motion adapted (:class:`~jaxmotion.train.a2m.A2MActionTraining`) in ``profile``. smoke: hidden 8,
    2 steps at batch 8; cpu: its sizes for :data:`CPU_STEPS` at batch 30 (as MARIONET's cpu row: rows of one table
    see the same data); paper: its recipe."""
    base = A2MActionTraining()
    if profile == "smoke":
        model = dataclasses.replace(base.model, hidden=8, latent=4, decoder_layers=1)
        return A2MActionTraining(model, _SMOKE_LOOP, batch_size=8)
    if profile == "cpu":
        return A2MActionTraining(base.model, CPU_LOOP, batch_size=30, length_buckets=LENGTH_BUCKETS)
    if profile == "paper":
        return dataclasses.replace(base, length_buckets=LENGTH_BUCKETS)
    raise ValueError(f"profile: expected smoke, cpu or paper, got {profile!r}")


def actor_training(profile: str) -> ActorTraining:
    """ACTOR, the reference row, on synth-mag's actions (31 classes) in ``profile``, on ACTOR's 60-frame windows
    (it generates each test action's own duration, 31 to 120 frames). smoke: 1 layer, 2 steps; cpu: ACTOR's cpu
    baseline (d 64, 2 layers, Adam 3e-4) for :data:`CPU_STEPS` at batch 30; paper: the paper's model, batch 20,
    1 000 epochs."""
    if profile == "smoke":
        model = ActorConfig(num_classes=31, width=16, ff=32, layers=1, heads=2, dropout=0.0)
        return ActorTraining(model, _SMOKE_LOOP, batch_size=8)
    if profile == "cpu":
        return dataclasses.replace(CPU_BASELINE, model=dataclasses.replace(CPU_BASELINE.model, num_classes=31),
                                   loop=CPU_LOOP, batch_size=30)
    if profile == "paper":
        return ActorTraining(ActorConfig(num_classes=31), LoopConfig(1000 * 6458 // 20, log_every=100,
                                                                     checkpoint_every=10_000))
    raise ValueError(f"profile: expected smoke, cpu or paper, got {profile!r}")


# --- tables -------------------------------------------------------------------------------------------------------


@dataclasses.dataclass(frozen=True)
class ActionTable:
    """Where Neural Marionette's single-action tables train and are scored: the multi-action ``dataset`` (its train
    split trains the rows, its test split's actions are regenerated), its ``seed`` and ``count`` (takes per split;
    None: all), the evaluator and the protocol."""

    dataset: str
    seed: int
    count: int | None
    evaluator: RecognizerTraining
    protocol: ActionProtocol

    def __post_init__(self):
        check_dataset_name(self.dataset, "ActionTable.dataset")
        check_at_least(self, 0, "seed")
        check_at_least(self, 1, "count")


def action_table(profile: str, *, joint_error: bool = False) -> ActionTable:
    """synth-mag with its evaluator (``synth-mag/transformer``) in ``profile``: smoke, 12 takes and 24 test actions
    over 2 repetitions; cpu, 5 repetitions over every test action; paper, 10 (the paper's counts are unstated)."""
    evaluator = evaluator_spec("synth-mag/transformer", profile)
    if profile == "smoke":
        return ActionTable("synth-mag", 0, 12, evaluator, ActionProtocol(repetitions=2, count=24, chunk=24,
                                                                          joint_error=joint_error))
    repetitions = {"cpu": 5, "paper": 10}.get(profile)
    if repetitions is None:
        raise ValueError(f"profile: expected smoke, cpu or paper, got {profile!r}")
    return ActionTable("synth-mag", 0, None, evaluator,
                       ActionProtocol(repetitions=repetitions, joint_error=joint_error))


#: Neural Marionette's experiments: their rows train alike (the same recipes, data and key stream), so each passes
#: the others' run folders as ``lenders`` and resumes a row another has finished instead of training it again.
EXPERIMENTS = ("marionet_single", "marionet_ablation", "marionet_multi", "marionet_next_tag", "marionet_revision")


def run_action_table(rows: Mapping[str, Any], table: ActionTable, *, workdir: str | Path, train_key: jax.Array,
                     eval_key: jax.Array, data_root: str | None = None, mesh=None,
                     writers: Sequence[WriterFactory] = (), lenders: Sequence[str | Path] = ()
                     ) -> dict[str, dict[str, np.ndarray]]:
    """Train every row on the train split's actions (:func:`~jaxmotion.recipes.tables.fit_rows`, generators written
    beside their checkpoints; ``writers``: their training-log writers; ``lenders``: other tables' run folders whose
    finished rows it may resume) and score them together on the test split's (Neural Marionette's columns; the Real
    row last). Rows: context recipes (:class:`ContextRecipe`) and :class:`ContextFreeRecipe`."""
    train = load_dataset(table.dataset, "train", seed=table.seed, data_root=data_root, count=table.count)
    test = load_dataset(table.dataset, "test", seed=table.seed, data_root=data_root, count=table.count)
    actions = action_set(test, max_frames=table.protocol.max_frames, count=table.protocol.count)
    recognizer, _ = trained_recognizer(table.evaluator, data_root=data_root)  # before any row trains
    generators = fit_rows(rows, train, train_key, workdir, lenders, mesh=mesh, writers=writers)
    samplers = {name: action_sampler_of(generator) for name, generator in generators.items()}
    scored = evaluate_actions(eval_key, samplers, recognizer, actions, table.protocol)
    return paper_columns({**{name: scored[name] for name in samplers}, "Real": scored["Real"]}, MARIONETTE_COLUMNS,
                         percent=frozenset())  # the paper prints accuracy as a fraction


# --- multi-action tables ---------------------------------------------------------------------------------------


@dataclasses.dataclass(frozen=True)
class ChainRow:
    """A row of the multi-action tables: a context model's recipe and how its chain corrects itself (Table 5's
    rows differ by ``options`` alone and train once)."""

    recipe: MarionetRecipe | MannRecipe | A2MContextRecipe
    options: ChainOptions = ChainOptions()


@dataclasses.dataclass(frozen=True)
class ProgramTable:
    """Where the multi-action tables train and are scored: ``single`` (the single-action tables' data and evaluator:
    the rows train exactly as there, so their fits are shared), the test ``sets`` (``"overall"``, ``"sufficient"``),
    the ``protocol`` and the revision classifier (``reviser``, trained apart from the evaluator; None: the
    evaluator itself, the paper's possible reading)."""

    single: ActionTable
    sets: tuple[str, ...]
    protocol: MultiActionProtocol
    reviser: RecognizerTraining | None

    def __post_init__(self):
        if not self.sets or any(s not in ("overall", "sufficient") for s in self.sets):
            raise ValueError(f"ProgramTable.sets: expected one or more of 'overall', 'sufficient', got {self.sets}")


#: Column labels of the two test sets, as the paper's Table 3.
SET_LABELS = MappingProxyType({"overall": "O", "sufficient": "S"})


def program_table(profile: str, sets: tuple[str, ...] = ("overall", "sufficient")) -> ProgramTable:
    """synth-mag with its evaluator and a revision classifier (``synth-mag/transformer-seed1``: the same recipe,
    another seed) in ``profile``: smoke, 4 programs of 4 actions; cpu, 200 programs of 20 actions per set over 3
    repetitions; paper, one program per candidate (the paper's 764 on BABEL-MAG) over 3. The smoke's evaluator, a
    few steps trained, is confident of few actions: every test action is a candidate."""
    single = action_table(profile)
    reviser = evaluator_spec("synth-mag/transformer-seed1", profile)
    if profile == "smoke":
        protocol = MultiActionProtocol(actions=4, confidence=0.0, count=4, repetitions=1, chunk=4, window=10)
    elif profile in ("cpu", "paper"):
        protocol = MultiActionProtocol(count=200 if profile == "cpu" else None, repetitions=3)
    else:
        raise ValueError(f"profile: expected smoke, cpu or paper, got {profile!r}")
    return ProgramTable(single, tuple(sets), protocol, reviser)


def run_program_table(rows: Mapping[str, ChainRow], table: ProgramTable, *, workdir: str | Path, train_key: jax.Array,
                      eval_key: jax.Array, data_root: str | None = None, mesh=None,
                      writers: Sequence[WriterFactory] = (), lenders: Sequence[str | Path] = ()
                      ) -> tuple[dict[str, dict[str, np.ndarray]], dict[str, dict[str, dict[str, np.ndarray]]]]:
    """Train every row's recipe (:func:`~jaxmotion.recipes.tables.fit_rows`: rows that differ by their chain options
    train once; ``writers`` and ``lenders`` as :func:`run_action_table`'s) and score the chains on each test set.
    Returns the table (columns ``"<metric> (O)"``, ``"<metric> (S)"``: Acc, FID, Δpose, Δvel, then Motion QR, PJ,
    AUJ, Trans. FID) and the curves per set and row (:func:`~jaxmotion.evaluation.multi_action.evaluate_programs`)."""
    single = table.single
    train = load_dataset(single.dataset, "train", seed=single.seed, data_root=data_root, count=single.count)
    test = load_dataset(single.dataset, "test", seed=single.seed, data_root=data_root, count=single.count)
    actions = action_set(test, max_frames=single.protocol.max_frames)
    recognizer, _ = trained_recognizer(single.evaluator, data_root=data_root)
    revising = any(row.options.shadow_start == "revision" for row in rows.values())
    reviser = None
    if revising:
        reviser = recognizer if table.reviser is None else trained_recognizer(table.reviser, data_root=data_root)[0]
    generators = fit_rows({name: row.recipe for name, row in rows.items()}, train, train_key, workdir, lenders,
                          mesh=mesh, writers=writers)
    chains = {name: functools.partial(chain_actions, generators[name], options=row.options, reviser=reviser,
                                      local_paths=True) for name, row in rows.items()}
    candidates = candidate_actions(recognizer, actions, table.protocol.confidence)
    transitions = label_transitions(train.segments)
    cells: dict[str, dict[str, np.ndarray]] = {name: {} for name in rows}
    curves = {}
    for i, kind in enumerate(table.sets):
        programs = test_programs(jax.random.fold_in(eval_key, i), actions, candidates, transitions, kind,
                                 table.protocol)
        scored, curves[kind] = evaluate_programs(jax.random.fold_in(eval_key, 100 + i), chains, joined, recognizer,
                                                 programs, test, table.protocol)
        for name, metrics in paper_columns(scored, MULTI_ACTION_COLUMNS, percent=frozenset()).items():
            cells[name].update({f"{column} ({SET_LABELS[kind]})": value for column, value in metrics.items()})
    return cells, curves


def save_index_curves(workdir: Path, curves: Mapping[str, Mapping[str, Mapping[str, np.ndarray]]], name: str) -> None:
    """``curves.json`` and ``<name>.png``: each metric against the action index, one line per row and set."""
    panels = {column: {f"{row}-{SET_LABELS[kind]}": curve[metric].tolist()
                       for kind, rows in curves.items() for row, curve in rows.items()}
              for metric, column in (("accuracy", "Acc"), ("FID", "FID"), ("action_qr", "Action QR"),
                                     ("motion_qr", "Motion QR"))}
    (workdir / "curves.json").write_text(json.dumps(panels, indent=1))
    actions = len(next(iter(next(iter(panels.values())).values())))
    save_curves(workdir / f"{name}.png", list(range(1, actions + 1)), panels, xlabel="action index")
