"""Paper tables, method-agnostic: rows are method recipes, scored together under one protocol.

A **recipe** is anything with ``fit(data, key, workdir, **loop_options) -> params`` and
``sampler(params, skeleton) -> Sampler`` (:class:`Recipe`); each paper's training config is one
(:class:`jaxmotion.train.actor.ActorTraining`, :class:`jaxmotion.train.a2m.A2MTraining`,
:class:`jaxmotion.train.odmo.ODMOTraining`). A table is a
mapping of row names to recipes: :func:`fit_rows` trains every row from the same key (same data order, and
the same initialisation where shapes agree, so rows differ only by what the table varies) in its own folder
``<workdir>/<slug(row)>/``, where it resumes from its checkpoints; :func:`table_evaluator` readies the dataset's evaluator (checking
it and the protocol against the data first) and :func:`score_rows` scores the samplers together with it (one repetition's real draws shared by all rows).

Rows come back in the protocol's metric names (``accuracy``, ``FID_train``, ``FID_test``, ``diversity``,
``multimodality``); :func:`paper_columns` renames them to a paper's columns (:data:`ACTOR_COLUMNS`,
:data:`ODMO_COLUMNS`, :data:`ACTFORMER_COLUMNS`; accuracy in %). Tables that span several datasets put them :func:`side_by_side` under dataset-prefixed
columns (``"UESTC FID_tr"``); :func:`reported_row` lays a paper's printed numbers out the same way.

The paper datasets' embedded stand-ins, with the evaluator each paper scores them with, are
:data:`STAND_INS`; :class:`TableData` names the dataset a table loads and :func:`real_sets` loads it;
:class:`TableDataset` adds the evaluator and the protocol (:func:`table_dataset`: a stand-in in a profile).
:func:`run_table` is a whole table on one dataset, :func:`run_tables` on several, side by side.
"""

from __future__ import annotations

import dataclasses
import re
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path
from typing import Any, Protocol

import jax
import numpy as np
from jax.sharding import Mesh

from jaxmotion.data import synthetic
from jaxmotion.data.datasets import check_dataset_name, load_dataset
from jaxmotion.data.motion import MotionDataset
from jaxmotion.evaluation.protocol import ProtocolConfig, Sampler, check_evaluator, check_real_sets, evaluate
from jaxmotion.evaluation.recognizers import RecognizerTraining, evaluator_spec, trained_recognizer
from jaxmotion.geometry.skeletons import Skeleton
from jaxmotion.models.recognition import Recognizer


class Recipe(Protocol):
    """A method as a table row: how to train it, and its protocol sampler once trained."""

    def fit(self, data: MotionDataset, key: jax.Array, workdir: str | Path | None = None, **loop_options) -> Any: ...

    def sampler(self, params: Any, skeleton: Skeleton) -> Sampler: ...


#: The protocol's metric names -> ACTOR's columns, in the paper's order (accuracy shown in %).
ACTOR_COLUMNS = {"FID_train": "FID_tr", "FID_test": "FID_test", "accuracy": "Acc. (%)", "diversity": "Div.",
                 "multimodality": "Multimod."}
#: ... and to ODMO's (Tables 1-2; HumanAct12's and MoCap's "FID" is against the training set, FID_tr here).
ODMO_COLUMNS = {"accuracy": "Acc", "FID_train": "FID_tr", "FID_test": "FID_test", "diversity": "Diversity",
                "multimodality": "MModality", "n_apd": "n-APD"}
#: ... and to ActFormer's (Tables 1-5; accuracy is its mean per-class recall, the FIDs against the train
#: split's tiles, FID_a from the one-person recogniser max-pooled over persons).
ACTFORMER_COLUMNS = {"accuracy": "Acc", "FIDm_train": "FID_m", "FID_train": "FID_w", "FIDam_train": "FIDa_m",
                     "FIDa_train": "FIDa_w"}
#: ... and to its GTA Combat columns (one class: FID_a alone, the one-person recogniser on the 15 common joints).
COMBAT_COLUMNS = {"FIDa_train": "FIDa"}
PERCENT = frozenset({"accuracy"})


@dataclasses.dataclass(frozen=True)
class StandIn:
    """The embedded dataset standing in for a paper dataset (``label``, the paper's name), the evaluator the
    papers score it with (a :func:`~jaxmotion.evaluation.recognizers.evaluator_spec` name; None: no recogniser
    knows its classes, GTA Combat's one) and whether its tables score against a test split too
    (``FID_test``)."""

    label: str
    dataset: str
    evaluator: str | None
    test_split: bool

    @property
    def num_classes(self) -> int:
        return len(synthetic.VARIANTS[self.dataset].classes)


#: The paper datasets -> their embedded stand-ins: ACTOR's and ODMO's, then ActFormer's (scored by its
#: ST-GCN evaluators against the train split only; its NTU-13 is ACTOR's stand-in with
#: ``evaluator="synth-ntu13/stgcn"``).
STAND_INS = {s.label: s for s in (
    StandIn("NTU-13", "synth-ntu13", "synth-ntu13/gru", False),
    StandIn("UESTC", "synth-uestc", "synth-uestc/stgcn", True),
    StandIn("HumanAct12", "synth-humanact12", "synth-humanact12/gru", False),
    StandIn("MoCap", "synth-cmu", "synth-cmu/gru", False),
    StandIn("NTURecon-1P", "synth-ntu1p-smpl", "synth-ntu1p-smpl/stgcn", False),
    StandIn("NTU-1P", "synth-ntu1p", "synth-ntu1p/stgcn", False),
    StandIn("BABEL", "synth-babel120", "synth-babel120/stgcn", False),
    StandIn("NTU-2P", "synth-ntu2p", "synth-ntu2p/stgcn", False),
    *(StandIn(f"Combat {p}P", f"synth-combat-{p}p", None, False) for p in range(2, 6)),
)}


@dataclasses.dataclass(frozen=True)
class TableData:
    """The dataset a table trains and evaluates on.

    ``count``: the first ``count`` sequences of each split only (smoke runs). ``test_split``: evaluate
    against the test split too (``FID_test``), as on UESTC; NTU-13 and HumanAct12 have a train split only.
    """

    name: str = "synth-uestc"
    seed: int = 0
    count: int | None = None
    test_split: bool = True

    def __post_init__(self):
        check_dataset_name(self.name, "TableData.name")
        variant = synthetic.VARIANTS.get(self.name)
        if self.test_split and variant is not None and "test" not in variant.splits:
            raise ValueError(f"TableData.test_split: {self.name} has no test split; set test_split=False")


def real_sets(data: TableData, data_root: str | None = None) -> dict[str, MotionDataset]:
    """The real sets the protocol compares with: ``{"train": ...}`` plus ``"test"`` when there is one."""
    sets = {"train": load_dataset(data.name, "train", seed=data.seed, data_root=data_root, count=data.count)}
    if data.test_split:
        sets["test"] = load_dataset(data.name, "test", seed=data.seed, data_root=data_root, count=data.count)
    return sets


def slug(name: str) -> str:
    """A folder name for a table row: ``"w/o µ/Σ tokens"`` -> ``"w-o-tokens"``."""
    text = re.sub(r"[^a-z0-9.+]+", "-", name.lower()).strip("-")
    return text or "row"


def fit_rows(rows: Mapping[str, Recipe], data: MotionDataset, key: jax.Array, workdir: str | Path,
             **loop_options) -> dict[str, Sampler]:
    """Train every row from the same ``key`` in ``<workdir>/<slug(row)>/``; return their samplers. Rows whose
    recipes share what determines the fit (a recipe's ``training`` attribute, else the recipe itself: ODMO
    and ODMO_conv differ only in their sampler) train once, in the first such row's folder."""
    folders = [slug(name) for name in rows]
    if len(set(folders)) != len(folders):
        raise ValueError(f"rows: names must give distinct folder names, got {list(rows)}")
    fitted: list[tuple[Any, Any]] = []  # (what determines a fit, its result)
    samplers = {}
    for (name, recipe), folder in zip(rows.items(), folders):
        what = getattr(recipe, "training", recipe)
        params = next((result for known, result in fitted if known == what), None)
        if params is None:
            params = recipe.fit(data, key, Path(workdir) / folder, **loop_options)
            fitted.append((what, params))
        samplers[name] = recipe.sampler(params, data.skeleton)
    return samplers


def table_evaluator(table: TableDataset, real: Mapping[str, MotionDataset], data_root: str | None = None
                    ) -> Recognizer | None:
    """The table's evaluator, trained or read from its cache, after checking what would make the table
    meaningless: the protocol's duration against the real sets (before the evaluator trains) and the
    evaluator's classes against theirs. Call it before training the rows, so a bad table fails first. None for
    a table without one (FID_a alone)."""
    check_real_sets(real, table.protocol)
    if table.evaluator is None:
        return None
    recognizer, _ = trained_recognizer(table.evaluator, data_root=data_root)
    check_evaluator(recognizer, real)
    return recognizer


def score_rows(key: jax.Array, samplers: Mapping[str, Sampler], real: Mapping[str, MotionDataset],
               recognizer: Recognizer | None, protocol: ProtocolConfig, *, mesh: Mesh | None = None,
               person_recognizer: Recognizer | None = None) -> dict[str, dict[str, list[float]]]:
    """Score ``samplers`` with ``recognizer`` (:func:`table_evaluator`) under ``protocol`` (generation and
    recogniser passes sharded on ``mesh`` when given; FID_a with a ``person_recognizer``); rows in the
    protocol's metric names, the Real row last."""
    rows = evaluate(key, samplers, recognizer, real, protocol, mesh=mesh, person_recognizer=person_recognizer)
    return {**{name: rows[name] for name in samplers}, "Real": rows["Real"]}


def paper_columns(rows: Mapping[str, Mapping[str, Any]], columns: Mapping[str, str] = ACTOR_COLUMNS
                  ) -> dict[str, dict[str, np.ndarray]]:
    """Rows in the protocol's metric names -> the paper's ``columns`` (in their order; metrics in
    :data:`PERCENT` × 100). Metrics the paper has no column for are dropped."""
    return {name: {column: 100 * np.asarray(cells[metric]) if metric in PERCENT else np.asarray(cells[metric])
                   for metric, column in columns.items() if metric in cells}
            for name, cells in rows.items()}


def side_by_side(tables: Mapping[str, Mapping[str, Mapping[str, Any]]]) -> dict[str, dict[str, Any]]:
    """Tables of several datasets, ``{label: {row: {column: cell}}}``, as one: row ``r`` holds every
    dataset's cells of ``r`` under columns prefixed with the dataset's label (``"UESTC FID_test"``); rows in
    first-seen order."""
    rows: dict[str, dict[str, Any]] = {}
    for label, table in tables.items():
        for name, cells in table.items():
            rows.setdefault(name, {}).update({f"{label} {column}": cell for column, cell in cells.items()})
    return rows


def reported_row(numbers: Mapping[str, Sequence[float | None]], columns: Mapping[str, str] = ACTOR_COLUMNS
                 ) -> dict[str, float]:
    """A row of a paper's table, ``{dataset label: values}`` with the values in the paper's column order
    (``columns``; FID_test only where the stand-in has a test split; None where the paper prints no number),
    as cells under dataset-prefixed columns, laid out as :func:`side_by_side` does."""
    cells = {}
    for label, values in numbers.items():
        names = [c for m, c in columns.items() if m != "FID_test" or STAND_INS[label].test_split]
        if len(values) != len(names):
            raise ValueError(f"numbers[{label!r}]: expected {len(names)} values ({', '.join(names)}), "
                             f"got {len(values)}")
        cells.update({f"{label} {column}": value for column, value in zip(names, values) if value is not None})
    return cells


def interleave_reported(rows: Mapping[str, Mapping[str, Any]], reported: Mapping[str, Mapping[str, Any]],
                        order: Sequence[str]) -> dict[str, dict[str, Any]]:
    """The table in the paper's row ``order``: each measured row, then the paper's numbers for that row as
    ``"<row> (reported)"`` (also for rows the paper has and this table does not measure)."""
    table = {}
    for row in order:
        if row in rows:
            table[row] = rows[row]
        if row in reported:
            table[f"{row} (reported)"] = reported[row]
    return table


@dataclasses.dataclass(frozen=True)
class TableDataset:
    """One dataset of a table: its column prefix (the paper's name, ``"NTU-13"``), the data, the evaluator
    and the protocol it is scored with; for motions of several persons, optionally the one-person recogniser
    of FID_a (``person_evaluator``, :func:`~jaxmotion.evaluation.protocol.evaluate`'s ``person_recognizer``,
    reading the data's skeleton: :meth:`~jaxmotion.models.recognition.Recognizer.reading`). ``evaluator=None``:
    FID_a alone."""

    label: str
    data: TableData
    evaluator: RecognizerTraining | None
    protocol: ProtocolConfig
    person_evaluator: RecognizerTraining | None = None


#: The cpu profile's protocol unless an experiment sizes its own: 5 repetitions of up to 1 000 motions.
CPU_PROTOCOL = ProtocolConfig(repetitions=5, max_real=1000)
#: The smoke profile's: 2 repetitions of 40 motions.
SMOKE_PROTOCOL = ProtocolConfig(repetitions=2, max_real=40, chunk=40)


def table_dataset(label: str, profile: str, *, cpu_protocol: ProtocolConfig = CPU_PROTOCOL,
                  paper_protocol: ProtocolConfig = ProtocolConfig.actor(), evaluator: str | None = None,
                  smoke_protocol: ProtocolConfig = SMOKE_PROTOCOL) -> TableDataset:
    """The embedded stand-in of the paper dataset ``label`` (a key of :data:`STAND_INS`) in ``profile``:
    its standard evaluator (or ``evaluator``, an evaluator name: ODMO scores UESTC with its own GRU) in that
    profile (none if the stand-in has none); smoke: 80 clips and ``smoke_protocol``; cpu: ``cpu_protocol``;
    paper: ``paper_protocol``."""
    if label not in STAND_INS:
        raise ValueError(f"label: expected one of {sorted(STAND_INS)}, got {label!r}")
    stand_in = STAND_INS[label]
    data = TableData(stand_in.dataset, count=80 if profile == "smoke" else None, test_split=stand_in.test_split)
    protocol = {"smoke": smoke_protocol, "cpu": cpu_protocol, "paper": paper_protocol}.get(profile)
    if protocol is None:
        raise ValueError(f"profile: expected smoke, cpu or paper, got {profile!r}")
    name = evaluator or stand_in.evaluator
    return TableDataset(label, data, None if name is None else evaluator_spec(name, profile), protocol)


#: What :func:`run_table` hands its ``pictures`` hook: the dataset, its rows' trained samplers, its train split.
PicturesHook = Callable[[TableDataset, Mapping[str, Sampler], MotionDataset], None]


def run_table(rows: Mapping[str, Recipe], table: TableDataset, *, workdir: str | Path, train_key: jax.Array,
              eval_key: jax.Array, data_root: str | None = None, columns: Mapping[str, str] = ACTOR_COLUMNS,
              mesh: Mesh | None = None, pictures: PicturesHook | None = None) -> dict[str, dict[str, np.ndarray]]:
    """A table on one dataset: load it, train every row (:func:`fit_rows` in ``workdir``), score them
    together (:func:`score_rows`); rows in the paper's ``columns``, the Real row last. ``mesh``: train and
    evaluate data-parallel on it (None: one device). ``pictures``: called once the rows are scored, to draw
    what they generate."""
    real = real_sets(table.data, data_root)
    recognizer = table_evaluator(table, real, data_root)  # before any row trains
    person = (None if table.person_evaluator is None
              else trained_recognizer(table.person_evaluator, data_root=data_root)[0].reading(real["train"].skeleton))
    samplers = fit_rows(rows, real["train"], train_key, workdir, mesh=mesh)
    scored = paper_columns(score_rows(eval_key, samplers, real, recognizer, table.protocol, mesh=mesh,
                                      person_recognizer=person), columns)
    if pictures is not None:
        pictures(table, samplers, real["train"])
    return scored


def run_tables(tables: Sequence[TableDataset], rows_of: Callable[[TableDataset], Mapping[str, Recipe]], *,
               workdir: str | Path, key: Callable[[str], jax.Array], data_root: str | None = None,
               columns: Mapping[str, str] = ACTOR_COLUMNS, mesh: Mesh | None = None,
               pictures: PicturesHook | None = None) -> dict[str, dict[str, Any]]:
    """A table over several datasets, side by side: on each, the rows ``rows_of(dataset)`` train in
    ``<workdir>/<slug(label)>/`` from ``key("train <label>")`` and are scored from ``key("eval <label>")``
    (``pictures``: :func:`run_table`'s hook, on each)."""
    labels = [table.label for table in tables]
    if len({slug(label) for label in labels}) != len(labels):
        raise ValueError(f"tables: labels must give distinct folder names, got {labels}")
    return side_by_side({table.label: run_table(rows_of(table), table, workdir=Path(workdir) / slug(table.label),
                                                train_key=key(f"train {table.label}"),
                                                eval_key=key(f"eval {table.label}"), data_root=data_root,
                                                columns=columns, mesh=mesh, pictures=pictures)
                         for table in tables})


#: ActFormer's smoke protocol: its settings at 3 motions per class and 2 repetitions.
ACTFORMER_SMOKE_PROTOCOL = ProtocolConfig(repetitions=2, sampling="per_class", per_class=3, chunk=64,
                                          accuracy="class_mean", class_fid=True, reference="tiles")


def actformer_table(label: str, profile: str) -> TableDataset:
    """The stand-in of ``label`` under ActFormer's protocol (:meth:`ProtocolConfig.actformer`; cpu: 5
    repetitions) with its ST-GCN evaluator; several persons add FID_a's one-person recogniser, NTU-1P's. GTA
    Combat (one class) has FID_a alone, from NTU-1P's recogniser on the 15 joints NTU and GTA share."""
    stand_in = STAND_INS[label]
    combat = stand_in.evaluator is None
    table = table_dataset(label, profile, evaluator=None if combat else stand_in.dataset + "/stgcn",
                          paper_protocol=ProtocolConfig.actformer(), cpu_protocol=ProtocolConfig.actformer(5),
                          smoke_protocol=ACTFORMER_SMOKE_PROTOCOL)
    if synthetic.VARIANTS[table.data.name].persons == 1:
        return table
    person = "synth-ntu1p/stgcn-joints15" if combat else "synth-ntu1p/stgcn"
    return dataclasses.replace(table, person_evaluator=evaluator_spec(person, profile))
