"""Paper tables: rows are method recipes, trained from one key, written as generators, scored together.

A **row** of a table is a trainer config (:class:`~jaxmotion.train.actor.ActorTraining`,
:class:`~jaxmotion.train.a2m.A2MTraining`, :class:`~jaxmotion.train.actformer.ActFormerTraining`) or a recipe
config that says more than training (:class:`~jaxmotion.recipes.odmo.ODMORecipe`); :func:`recipe_for` gives its
:class:`Recipe`: ``fit(data, key, workdir)`` trains (resuming from ``workdir``'s checkpoints) and
``generator(trained, facts)`` turns the result into the method's generator
(:class:`~jaxmotion.pipelines.artefacts.Generator`). :func:`fit_generator` does both and writes the generator to
``<workdir>/generator/`` beside the checkpoints, where :func:`jaxmotion.load_generator` finds it.

:func:`fit_rows` trains every row of a table from the same key (same data order, and the same initialisation where
shapes agree, so rows differ only by what the table varies) in its own folder ``<workdir>/<slug(row)>/``; rows
whose recipes share what determines the fit (ODMO and ODMO_conv: only their samplers differ) train once.
:func:`run_table` is a whole table on one dataset, :func:`run_tables` on several, side by side.

The paper datasets' tables per profile: :func:`table_dataset` (the stand-in, the evaluator each paper scores it
with, the protocol), :func:`actformer_table` (ActFormer's protocol and evaluators).
"""

from __future__ import annotations

import dataclasses
import re
import shutil
import sys
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path
from types import MappingProxyType
from typing import Any, Protocol

import jax
import numpy as np
from jax.sharding import Mesh

from jaxmotion.data import synthetic
from jaxmotion.data.datasets import paper_dataset
from jaxmotion.data.motion import MotionDataset
from jaxmotion.distributed import is_primary
from jaxmotion.files import read_json, write_json
from jaxmotion.evaluation.protocol import ProtocolConfig, Sampler
from jaxmotion.evaluation.recognizers import trained_recognizer
from jaxmotion.evaluation.tables import (
    ACTOR_COLUMNS,
    TableData,
    TableDataset,
    paper_columns,
    real_sets,
    score_rows,
    side_by_side,
    slug,
    table_evaluator,
)
from jaxmotion.pipelines.artefacts import DataFacts, Generator
from jaxmotion.recipes.a2m import A2MRecipe
from jaxmotion.recipes.actformer import ActFormerRecipe
from jaxmotion.recipes.actor import ActorRecipe
from jaxmotion.recipes.evaluators import evaluator_spec
from jaxmotion.recipes.odmo import ODMORecipe
from jaxmotion.train.a2m import A2MTraining
from jaxmotion.train.actformer import ActFormerTraining
from jaxmotion.train.actor import ActorTraining
from jaxmotion.train.loop import CHECKPOINT_FOLDER, TRAINING_LOG
from jaxmotion.train.writers import TENSORBOARD_FOLDER, WriterFactory

GENERATOR_FOLDER = "generator"


class Recipe(Protocol):
    """A method as a table row: how to train it, and its generator once trained."""

    def fit(self, data: MotionDataset, key: jax.Array, workdir: str | Path | None = None, **loop_options) -> Any: ...

    def generator(self, trained: Any, facts: DataFacts) -> Generator: ...


#: A trainer config -> the recipe that makes it a row.
RECIPES = MappingProxyType({ActorTraining: ActorRecipe, A2MTraining: A2MRecipe, ActFormerTraining: ActFormerRecipe})
#: What a table's row may be.
Row = ActorTraining | A2MTraining | ActFormerTraining | ODMORecipe


def recipe_for(row: Row | Recipe) -> Recipe:
    """The recipe of a row: a recipe (anything with ``fit`` and ``generator``) as it is, a trainer config wrapped
    by its paper's recipe."""
    if callable(getattr(row, "fit", None)) and callable(getattr(row, "generator", None)):
        return row
    if type(row) not in RECIPES:
        raise TypeError(f"row: expected one of {', '.join(t.__name__ for t in (*RECIPES, ODMORecipe))}, got "
                        f"{type(row).__name__}")
    return RECIPES[type(row)](row)


def fit_generator(row: Row | Recipe, data: MotionDataset, key: jax.Array, workdir: str | Path | None = None,
                  **loop_options) -> Generator:
    """Train ``row`` on ``data`` (resuming from ``workdir``'s checkpoints) and return its generator, also written
    to ``<workdir>/generator/`` when ``workdir`` is given."""
    recipe = recipe_for(row)
    generator = recipe.generator(recipe.fit(data, key, workdir, **loop_options), DataFacts.of(data))
    return generator if workdir is None else _written(generator, workdir)


def _written(generator: Generator, workdir: str | Path) -> Generator:
    """``generator``, written to ``<workdir>/generator/`` by the primary process (where loaders look for it)."""
    if is_primary():
        generator.save(Path(workdir) / GENERATOR_FOLDER)
    return generator


#: Each row folder's record of its fit (the recipe, a digest of the data, the key): what another table compares
#: before it borrows the folder's checkpoints (:func:`fit_rows`' ``lenders``).
FIT_RECORD = "fit.json"


def fit_rows(rows: Mapping[str, Row | Recipe], data: MotionDataset, key: jax.Array, workdir: str | Path,
             lenders: Sequence[str | Path] = (), **loop_options) -> dict[str, Generator]:
    """Train every row from the same ``key`` in ``<workdir>/<slug(row)>/`` and write each row's generator to
    ``<workdir>/<slug(row)>/generator/``; return the generators. Rows whose recipes share what determines the
    fit (a recipe's ``fit_key``, else the recipe itself) train once, in the first such row's folder.

    ``lenders``: run folders of other tables whose rows may be the same fits (Neural Marionette's tables train
    Table 1's rows again). A row with no checkpoints of its own takes those of a finished row there (its generator
    written) whose :data:`FIT_RECORD` is this row's (the same recipe, data and key), and resumes from their last
    step: the same parameters as training it here, without the training. One process only."""
    folders = [slug(name) for name in rows]
    if len(set(folders)) != len(folders):
        raise ValueError(f"rows: names must give distinct folder names, got {list(rows)}")
    fitted: list[tuple[Any, Any]] = []  # (what determines a fit, its result)
    facts = DataFacts.of(data)
    data_digest = data.digest()
    generators = {}
    for (name, row), folder in zip(rows.items(), folders):
        recipe = recipe_for(row)
        what = getattr(recipe, "fit_key", recipe)
        trained = next((result for known, result in fitted if known == what), None)
        if trained is None:
            record = {"recipe": repr(what), "data": data_digest, "key": jax.random.key_data(key).tolist()}
            lent = _borrow(record, Path(workdir) / folder, lenders)
            if lent is not None:
                print(f"[{name}] the same fit finished in {lent}: resuming from its checkpoints", file=sys.stderr)
            if is_primary():
                write_json(Path(workdir) / folder / FIT_RECORD, record)
            trained = recipe.fit(data, key, Path(workdir) / folder, **loop_options)
            fitted.append((what, trained))
        generators[name] = _written(recipe.generator(trained, facts), Path(workdir) / folder)
    return generators


def _borrow(record: dict, folder: Path, lenders: Sequence[str | Path]) -> Path | None:
    """Copy into ``folder`` (which has no checkpoints) the checkpoints and training log (with its TensorBoard
    event files, if any) of a finished row of ``lenders`` whose fit record is ``record``; return that row's folder,
    or None."""
    if (folder / CHECKPOINT_FOLDER).exists() or jax.process_count() > 1:
        return None
    for lender in lenders:
        for path in sorted(Path(lender).glob(f"*/{FIT_RECORD}")):
            row = path.parent
            if row.resolve() != folder.resolve() and (row / GENERATOR_FOLDER).is_dir() and (
                    row / CHECKPOINT_FOLDER).is_dir() and read_json(path) == record:
                shutil.copytree(row / CHECKPOINT_FOLDER, folder / CHECKPOINT_FOLDER)
                if (row / TRAINING_LOG).is_file():  # the training the checkpoints hold, logged
                    shutil.copy2(row / TRAINING_LOG, folder / TRAINING_LOG)
                if (row / TENSORBOARD_FOLDER).is_dir():
                    shutil.copytree(row / TENSORBOARD_FOLDER, folder / TENSORBOARD_FOLDER, dirs_exist_ok=True)
                return row
    return None


#: The cpu profile's protocol unless an experiment sizes its own: 5 repetitions of up to 1 000 motions.
CPU_PROTOCOL = ProtocolConfig(repetitions=5, max_real=1000)
#: The smoke profile's: 2 repetitions of 40 motions.
SMOKE_PROTOCOL = ProtocolConfig(repetitions=2, max_real=40, chunk=40)
#: The evaluator each paper scores a paper dataset's stand-in with (None: no recogniser knows its classes, GTA
#: Combat's one; ActFormer's tables use ActFormer's ST-GCNs, :func:`actformer_table`).
EVALUATOR_OF = MappingProxyType({
    "NTU-13": "synth-ntu13/gru", "UESTC": "synth-uestc/stgcn", "HumanAct12": "synth-humanact12/gru",
    "MoCap": "synth-cmu/gru", "NTURecon-1P": "synth-ntu1p-smpl/stgcn", "NTU-1P": "synth-ntu1p/stgcn",
    "BABEL": "synth-babel120/stgcn", "NTU-2P": "synth-ntu2p/stgcn",
    **{f"Combat {p}P": None for p in range(2, 6)},
})


def table_dataset(label: str, profile: str, *, cpu_protocol: ProtocolConfig = CPU_PROTOCOL,
                  paper_protocol: ProtocolConfig = ProtocolConfig.actor(), evaluator: str | None = None,
                  smoke_protocol: ProtocolConfig = SMOKE_PROTOCOL) -> TableDataset:
    """The embedded stand-in of the paper dataset ``label`` (:data:`~jaxmotion.data.datasets.PAPER_DATASETS`) in
    ``profile``: its standard evaluator (:data:`EVALUATOR_OF`, or ``evaluator``, an evaluator name: ODMO scores
    UESTC with its own GRU) in that profile (none if the stand-in has none); smoke: 80 clips and
    ``smoke_protocol``; cpu: ``cpu_protocol``; paper: ``paper_protocol``."""
    dataset = paper_dataset(label)
    data = TableData(dataset.stand_in, count=80 if profile == "smoke" else None, test_split=dataset.test_split)
    protocol = {"smoke": smoke_protocol, "cpu": cpu_protocol, "paper": paper_protocol}.get(profile)
    if protocol is None:
        raise ValueError(f"profile: expected smoke, cpu or paper, got {profile!r}")
    name = evaluator or EVALUATOR_OF[label]
    return TableDataset(label, data, None if name is None else evaluator_spec(name, profile), protocol)


#: ActFormer's smoke protocol: its settings at 3 motions per class and 2 repetitions.
ACTFORMER_SMOKE_PROTOCOL = ProtocolConfig(repetitions=2, sampling="per_class", per_class=3, chunk=64,
                                          accuracy="class_mean", class_fid=True, reference="tiles")


def actformer_table(label: str, profile: str) -> TableDataset:
    """The stand-in of ``label`` under ActFormer's protocol (:meth:`ProtocolConfig.actformer`; cpu: 5
    repetitions) with its ST-GCN evaluator; several persons add FID_a's one-person recogniser, NTU-1P's. GTA
    Combat (one class) has FID_a alone, from NTU-1P's recogniser on the 15 joints NTU and GTA share."""
    dataset = paper_dataset(label)
    combat = EVALUATOR_OF[label] is None
    table = table_dataset(label, profile, evaluator=None if combat else dataset.stand_in + "/stgcn",
                          paper_protocol=ProtocolConfig.actformer(), cpu_protocol=ProtocolConfig.actformer(5),
                          smoke_protocol=ACTFORMER_SMOKE_PROTOCOL)
    if synthetic.VARIANTS[table.data.name].persons == 1:
        return table
    person = "synth-ntu1p/stgcn-joints15" if combat else "synth-ntu1p/stgcn"
    return dataclasses.replace(table, person_evaluator=evaluator_spec(person, profile))


@dataclasses.dataclass(frozen=True)
class DatasetTable:
    """One dataset of a paper table: where and how it is scored (``table``) and its rows, row name -> what trains
    (a trainer config or a recipe config; :func:`recipe_for`). Overrides reach a row by name:
    ``--set tables.ntu13.rows.ActFormer.loop.steps=100``."""

    table: TableDataset
    rows: Mapping[str, Row]


def table_key(label: str) -> str:
    """A paper dataset's key in a table's mapping, usable in a ``--set`` path: ``"NTU-13"`` -> ``"ntu13"``."""
    return re.sub(r"[^a-z0-9]", "", label.lower())


#: What :func:`run_table` hands its ``pictures`` hook: the dataset, its rows' trained samplers, its train split.
PicturesHook = Callable[[TableDataset, Mapping[str, Sampler], MotionDataset], None]


def run_table(rows: Mapping[str, Row | Recipe], table: TableDataset, *, workdir: str | Path, train_key: jax.Array,
              eval_key: jax.Array, data_root: str | None = None, columns: Mapping[str, str] = ACTOR_COLUMNS,
              mesh: Mesh | None = None, writers: Sequence[WriterFactory] = (), pictures: PicturesHook | None = None
              ) -> dict[str, dict[str, np.ndarray]]:
    """A table on one dataset: load it, train every row (:func:`fit_rows` in ``workdir``), score them
    together (:func:`~jaxmotion.evaluation.tables.score_rows`); rows in the paper's ``columns``, the Real row
    last. ``mesh``: train and evaluate data-parallel on it (None: one device). ``writers``: the rows' training-log
    writers (:mod:`jaxmotion.train.writers`). ``pictures``: called once the rows are scored, to draw what they
    generate."""
    real = real_sets(table.data, data_root)
    recognizer = table_evaluator(table, real, data_root)  # before any row trains
    person = (None if table.person_evaluator is None
              else trained_recognizer(table.person_evaluator, data_root=data_root)[0].reading(real["train"].skeleton))
    generators = fit_rows(rows, real["train"], train_key, workdir, mesh=mesh, writers=writers)
    samplers = {name: generator.sampler() for name, generator in generators.items()}
    scored = paper_columns(score_rows(eval_key, samplers, real, recognizer, table.protocol, mesh=mesh,
                                      person_recognizer=person), columns)
    if pictures is not None:
        pictures(table, samplers, real["train"])
    return scored


def run_tables(tables: Sequence[DatasetTable], *, workdir: str | Path, key: Callable[[str], jax.Array],
               data_root: str | None = None, columns: Mapping[str, str] = ACTOR_COLUMNS, mesh: Mesh | None = None,
               writers: Sequence[WriterFactory] = (), pictures: PicturesHook | None = None
               ) -> dict[str, dict[str, Any]]:
    """A table over several datasets, side by side: on each, its rows train in ``<workdir>/<slug(label)>/`` from
    ``key("train <label>")`` and are scored from ``key("eval <label>")`` (``writers``, ``pictures``:
    :func:`run_table`'s, on each)."""
    labels = [dataset.table.label for dataset in tables]
    if len({slug(label) for label in labels}) != len(labels):
        raise ValueError(f"tables: labels must give distinct folder names, got {labels}")
    return side_by_side({label: run_table(dataset.rows, dataset.table, workdir=Path(workdir) / slug(label),
                                          train_key=key(f"train {label}"), eval_key=key(f"eval {label}"),
                                          data_root=data_root, columns=columns, mesh=mesh, writers=writers,
                                          pictures=pictures)
                         for label, dataset in zip(labels, tables)})
