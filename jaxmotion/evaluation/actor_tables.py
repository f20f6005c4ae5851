"""What the ACTOR tables share: train named variants of ACTOR on one dataset, score each with the ACTOR
protocol, and lay the rows out in the paper's columns next to the paper's reported numbers.

An ACTOR experiment (``experiments/actor_*.py``) is a config holding :class:`ActorData`, a mapping of
row names to :class:`~jaxmotion.train.actor.ActorTraining` (the variants of its table), the evaluator
spec and the protocol; its ``run`` is a few calls into this module. Every variant trains from the same
key (same initialisation where shapes agree, same batches), so rows differ only by what the table varies.
Each variant trains in its own folder ``<workdir>/<row slug>/`` and resumes from its checkpoints there.

Tables 1-3 span two datasets each: a :class:`TableDataset` per dataset (:func:`embedded_table_dataset`
gives the embedded stand-ins in each profile), :func:`run_datasets` to score the rows on each and
:func:`side_by_side` to lay them out with dataset-prefixed columns (``"NTU-13 FID_tr"``).
"""

from __future__ import annotations

import dataclasses
import re
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path
from typing import Any

import jax
import numpy as np

from jaxmotion.data import synthetic
from jaxmotion.data.datasets import load_dataset
from jaxmotion.data.motion import MotionDataset
from jaxmotion.evaluation.protocol import ProtocolConfig, Sampler, evaluate
from jaxmotion.evaluation.recognizers import (
    RecognizerTraining,
    evaluator_spec,
    trained_recognizer,
)
from jaxmotion.experiment import RunContext
from jaxmotion.losses.actor import ActorLossWeights
from jaxmotion.models.actor import ActorConfig, AnyActorParams
from jaxmotion.pipelines.actor import actor_sampler
from jaxmotion.train.actor import ActorTraining, train_actor

# the protocol's metric names -> ACTOR's column names, in the paper's order
COLUMNS = {"FID_tr": "FID_tr", "FID_test": "FID_test", "FID": "FID_tr", "accuracy": "Acc. (%)",
           "diversity": "Div.", "multimodality": "Multimod."}


@dataclasses.dataclass(frozen=True)
class ActorData:
    """The dataset an ACTOR table trains and evaluates on.

    ``count``: the first ``count`` sequences of each split only (smoke runs). ``test_split``: evaluate
    against the test split too (FID_test), as on UESTC; NTU-13 and HumanAct12 have train only (FID_tr).
    """

    name: str = "synth-uestc"
    seed: int = 0
    count: int | None = None
    test_split: bool = True

    def __post_init__(self):
        variant = synthetic.VARIANTS.get(self.name)
        if self.test_split and variant is not None and "test" not in variant.splits:
            raise ValueError(f"ActorData.test_split: {self.name} has no test split; set test_split=False")


def load_actor_data(data: ActorData, data_root: str | None = None) -> dict[str, MotionDataset]:
    """The real sets the protocol compares with: ``{"tr": train}`` plus ``"test"`` when there is one."""
    sets = {"tr": load_dataset(data.name, "train", seed=data.seed, data_root=data_root, count=data.count)}
    if data.test_split:
        sets["test"] = load_dataset(data.name, "test", seed=data.seed, data_root=data_root, count=data.count)
    return sets


def slug(name: str) -> str:
    """A folder name for a table row: ``"w/o µ/Σ tokens"`` -> ``"w-o-tokens"``."""
    text = re.sub(r"[^a-z0-9.+]+", "-", name.lower()).strip("-")
    return text or "row"


def train_variants(variants: Mapping[str, ActorTraining], train: MotionDataset, key: jax.Array,
                   workdir: str | Path, *, progress: bool = True) -> dict[str, AnyActorParams]:
    """Train every variant from the same ``key`` in ``<workdir>/<slug(name)>/``; returns their parameters."""
    folders = [slug(name) for name in variants]
    if len(set(folders)) != len(folders):
        raise ValueError(f"variants: row names must give distinct folder names, got {list(variants)}")
    return {name: train_actor(train, training, key, str(Path(workdir) / folder), progress=progress)
            for (name, training), folder in zip(variants.items(), folders)}


def samplers_of(params: Mapping[str, AnyActorParams], variants: Mapping[str, ActorTraining],
                data: MotionDataset) -> dict[str, Sampler]:
    """The protocol's samplers of trained variants (joints by FK on ``data``'s skeleton)."""
    return {name: actor_sampler(params[name], variants[name], data.skeleton) for name in variants}


def paper_rows(rows: Mapping[str, Mapping[str, list[float]]]) -> dict[str, dict[str, np.ndarray]]:
    """Protocol rows -> ACTOR's columns (accuracy in %), in the paper's column order."""
    return {name: {COLUMNS[k]: 100 * np.asarray(cells[k]) if k == "accuracy" else np.asarray(cells[k])
                   for k in COLUMNS if k in cells}
            for name, cells in rows.items()}


def evaluate_variants(key: jax.Array, samplers: Mapping[str, Sampler], real: Mapping[str, MotionDataset],
                      evaluator: RecognizerTraining, protocol: ProtocolConfig, *,
                      data_root: str | None = None) -> dict[str, dict[str, np.ndarray]]:
    """Score ``samplers`` (one repetition's real draws shared by all) and return rows in ACTOR's columns,
    the Real row last."""
    recognizer, _ = trained_recognizer(evaluator, data_root=data_root)
    rows = paper_rows(evaluate(key, samplers, recognizer, real, protocol))
    return {**{name: rows[name] for name in samplers}, "Real": rows["Real"]}


def run_variants(variants: Mapping[str, ActorTraining], data: ActorData, evaluator: RecognizerTraining,
                 protocol: ProtocolConfig, *, workdir: str | Path, train_key: jax.Array, eval_key: jax.Array,
                 data_root: str | None = None) -> dict[str, dict[str, np.ndarray]]:
    """A whole ACTOR table: load ``data``, train every variant, score them together; rows in ACTOR's columns."""
    real = load_actor_data(data, data_root)
    params = train_variants(variants, real["tr"], train_key, workdir)
    return evaluate_variants(eval_key, samplers_of(params, variants, real["tr"]), real, evaluator, protocol,
                             data_root=data_root)


def replace_path(obj, path: str, value):
    """``dataclasses.replace`` through a dotted field path: ``replace_path(training, "losses.kl", 1e-4)``."""
    head, _, rest = path.partition(".")
    if not dataclasses.is_dataclass(obj) or head not in {f.name for f in dataclasses.fields(obj)}:
        raise ValueError(f"{path!r}: {type(obj).__name__} has no field {head!r}")
    return dataclasses.replace(obj, **{head: replace_path(getattr(obj, head), rest, value) if rest else value})


@dataclasses.dataclass(frozen=True)
class TableDataset:
    """One dataset of a table that spans several (ACTOR's Tables 1-3): its column prefix (the paper's name,
    ``"NTU-13"``), the data, the headline training on it (which the table's rows vary), the evaluator and
    the protocol."""

    label: str
    data: ActorData
    training: ActorTraining
    evaluator: RecognizerTraining
    protocol: ProtocolConfig


def side_by_side(tables: Mapping[str, Mapping[str, Mapping[str, Any]]]) -> dict[str, dict[str, Any]]:
    """Tables of several datasets, ``{label: {row: {column: cell}}}``, as one: row ``r`` holds every
    dataset's cells of ``r`` under columns prefixed with the dataset's label (``"UESTC FID_test"``); rows in
    first-seen order."""
    rows: dict[str, dict[str, Any]] = {}
    for label, table in tables.items():
        for name, cells in table.items():
            rows.setdefault(name, {}).update({f"{label} {column}": cell for column, cell in cells.items()})
    return rows


@dataclasses.dataclass(frozen=True)
class _Embedded:
    dataset: str
    evaluator: str  # evaluator_spec name: the recogniser the paper scores this dataset with
    test_split: bool
    num_classes: int
    clips: int  # training clips: an epoch is clips // batch steps
    paper_epochs: int  # FACTS.md §3: the paper's main runs (the ablations' shorter runs are not attributed)


#: The paper's datasets in Tables 1-3 -> their embedded stand-ins.
EMBEDDED = {
    "NTU-13": _Embedded("synth-ntu13", "synth-ntu13/gru", False, 13, 3900, 2000),
    "UESTC": _Embedded("synth-uestc", "synth-uestc/stgcn", True, 40, 10_650, 1000),
    "HumanAct12": _Embedded("synth-humanact12", "synth-humanact12/gru", False, 12, 1200, 5000),
}


CPU_PROTOCOL = ProtocolConfig(repetitions=5, max_real=1000)


def embedded_table_dataset(label: str, profile: str, cpu: ActorTraining,
                           cpu_protocol: ProtocolConfig = CPU_PROTOCOL) -> TableDataset:
    """The embedded stand-in of the paper's dataset ``label`` (a key of :data:`EMBEDDED`) in ``profile``.

    smoke: a 1-layer model without dropout (its random bits triple a step's compile time on CPU), L_P only,
    2 steps, 80 clips, 2 repetitions of 40 motions. cpu: the experiment's ``cpu`` training and protocol
    (sized to its budget; by default 5 repetitions of up to 1 000 motions). paper: the paper's model, batch
    20 and epochs, L_P + L_J (L_J stands in for the paper's L_V, which needs an SMPL model), ACTOR's
    protocol. The model's number of classes is set to the dataset's in every profile.
    """
    if label not in EMBEDDED:
        raise ValueError(f"label: expected one of {sorted(EMBEDDED)}, got {label!r}")
    if profile not in ("smoke", "cpu", "paper"):
        raise ValueError(f"profile: expected smoke, cpu or paper, got {profile!r}")
    spec = EMBEDDED[label]
    data = ActorData(spec.dataset, count=80 if profile == "smoke" else None, test_split=spec.test_split)
    if profile == "smoke":
        model = ActorConfig(num_classes=spec.num_classes, latent=16, ff=32, layers=1, heads=2, dropout=0.0)
        training = ActorTraining(model, steps=2, batch_size=8, log_every=2, checkpoint_every=0)
        protocol = ProtocolConfig(repetitions=2, max_real=40, chunk=40)
    elif profile == "cpu":
        training = dataclasses.replace(cpu, model=dataclasses.replace(cpu.model, num_classes=spec.num_classes))
        protocol = cpu_protocol
    else:
        training = ActorTraining(ActorConfig(num_classes=spec.num_classes),
                                 steps=spec.paper_epochs * (spec.clips // 20), losses=ActorLossWeights(joints=1.0),
                                 checkpoint_every=10_000)
        protocol = ProtocolConfig.actor()
    return TableDataset(label, data, training, evaluator_spec(spec.evaluator, profile), protocol)


def reported_row(numbers: Mapping[str, Sequence[float | None]]) -> dict[str, float]:
    """A row of a paper's table, ``{dataset label: values}`` with the values in the paper's column order
    (FID_tr, FID_test where the dataset has a test split, Acc. (%), Div., Multimod.; None where the paper
    prints no number), as cells under dataset-prefixed columns, laid out as :func:`side_by_side` does."""
    cells = {}
    for label, values in numbers.items():
        columns = [c for c in dict.fromkeys(COLUMNS.values()) if c != "FID_test" or EMBEDDED[label].test_split]
        if len(values) != len(columns):
            raise ValueError(f"numbers[{label!r}]: expected {len(columns)} values ({', '.join(columns)}), "
                             f"got {len(values)}")
        cells.update({f"{label} {column}": value for column, value in zip(columns, values) if value is not None})
    return cells


# (dataset, its training set, the folder to train in, the training key) -> the rows' samplers
SamplersOf = Callable[[TableDataset, MotionDataset, Path, jax.Array], Mapping[str, Sampler]]


def run_datasets(datasets: Sequence[TableDataset], samplers: SamplersOf, ctx: RunContext) -> dict[str, dict[str, Any]]:
    """A table over several datasets: on each, ``samplers`` trains the rows' models in
    ``<ctx.workdir>/<slug(label)>/`` and returns their samplers, which are scored together with the dataset's
    evaluator and protocol (keys ``"train <label>"`` and ``"eval <label>"``); rows :func:`side_by_side`,
    the Real row last."""
    labels = [dataset.label for dataset in datasets]
    if len({slug(label) for label in labels}) != len(labels):
        raise ValueError(f"datasets: labels must give distinct folder names, got {labels}")
    tables = {}
    for dataset in datasets:
        real = load_actor_data(dataset.data, ctx.data_root)
        made = samplers(dataset, real["tr"], ctx.workdir / slug(dataset.label), ctx.key(f"train {dataset.label}"))
        tables[dataset.label] = evaluate_variants(ctx.key(f"eval {dataset.label}"), made, real, dataset.evaluator,
                                                  dataset.protocol, data_root=ctx.data_root)
    return side_by_side(tables)
