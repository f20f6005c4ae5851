"""Paper tables, method-agnostic: rows are samplers, scored together under one protocol.

:func:`table_evaluator` readies a dataset's evaluator (checking it and the protocol against the data first) and
:func:`score_rows` scores samplers together with it (one repetition's real draws shared by all rows). Training the
rows is the recipe layer's (:func:`jaxmotion.recipes.tables.run_table`).

Rows come back in the protocol's metric names (``accuracy``, ``FID_train``, ``FID_test``, ``diversity``,
``multimodality``); :func:`paper_columns` renames them to a paper's columns (:data:`ACTOR_COLUMNS`,
:data:`ODMO_COLUMNS`, :data:`ACTFORMER_COLUMNS`; accuracy in %). Tables that span several datasets put them :func:`side_by_side` under dataset-prefixed
columns (``"UESTC FID_tr"``); :func:`reported_row` lays a paper's printed numbers out the same way.

:class:`TableData` names the dataset a table loads and :func:`real_sets` loads it; :class:`TableDataset` adds
the evaluator and the protocol.
"""

from __future__ import annotations

import dataclasses
import re
from collections.abc import Mapping, Sequence
from typing import Any

import jax
import numpy as np
from jax.sharding import Mesh

from jaxmotion.config import check_at_least
from jaxmotion.data import synthetic
from jaxmotion.data.datasets import check_dataset_name, load_dataset, paper_dataset
from jaxmotion.data.motion import MotionDataset
from jaxmotion.evaluation.protocol import ProtocolConfig, Sampler, check_evaluator, check_real_sets, evaluate
from jaxmotion.evaluation.recognizers import RecognizerTraining, trained_recognizer
from jaxmotion.models.recognition import Recognizer


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
        check_at_least(self, 1, "count")
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
    """A folder name for a table row: ``"w/o µ/Σ tokens"`` -> ``"w-o-tokens"``; a starred name (a paper's variant
    of the unstarred row) -> ``"...-star"``."""
    text = re.sub(r"[^a-z0-9.+]+", "-", name.lower().replace("*", " star")).strip("-")
    return text or "row"


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


def paper_columns(rows: Mapping[str, Mapping[str, Any]], columns: Mapping[str, str] = ACTOR_COLUMNS,
                  percent: frozenset[str] = PERCENT) -> dict[str, dict[str, np.ndarray]]:
    """Rows in the protocol's metric names -> the paper's ``columns`` (in their order; metrics in ``percent``
    × 100: accuracy, unless the paper prints a fraction). Metrics the paper has no column for are dropped."""
    return {name: {column: 100 * np.asarray(cells[metric]) if metric in percent else np.asarray(cells[metric])
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
        names = [c for m, c in columns.items() if m != "FID_test" or paper_dataset(label).test_split]
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


