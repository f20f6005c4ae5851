"""A paper's claims about its tables, as data, checked against the measured rows.

A :class:`Claim` says that one row's value in a column is lower (``"<"``) or higher (``">"``) than another
row's: ``Claim("ACTOR", "<", "GRU", "FID_tr")`` reads "ACTOR's FID_tr is lower than the GRU's". Each
experiment declares the claims its paper makes from that table; :func:`check` marks each one against the
table's cells:

* **holds**: the two 95% intervals do not overlap and the order is the claimed one;
* **does not hold**: the intervals do not overlap and the order is the other one;
* **inconclusive**: the intervals overlap (or the means are equal);
* **not measured**: a row or column is missing from the table (a row the run did not train).

A cell is a number, a summary with ``mean`` and ``ci95`` (the half-width of the 95% interval;
:class:`~jaxmotion.evaluation.stats.Summary`) or a list of repetition values (summarised here); a single
value is a point, its own interval.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Iterable, Mapping, Sequence
from typing import Any, Literal

import numpy as np

from jaxmotion.evaluation.stats import summarize

VERDICTS = ("holds", "does not hold", "inconclusive", "not measured")


@dataclasses.dataclass(frozen=True)
class Claim:
    """``row_a``'s ``column`` is ``op`` (``"<"`` lower, ``">"`` higher) than ``row_b``'s. ``source``: where the
    paper says so (section, table, a few words)."""

    row_a: str
    op: Literal["<", ">"]
    row_b: str
    column: str
    source: str = ""

    def __post_init__(self):
        if self.op not in ("<", ">"):
            raise ValueError(f"Claim.op: expected '<' or '>', got {self.op!r}")
        if self.row_a == self.row_b:
            raise ValueError(f"Claim: compares row {self.row_a!r} with itself")

    def __str__(self) -> str:
        return f"{self.row_a} {self.op} {self.row_b} on {self.column}"


def interval(cell: Any) -> tuple[float, float, float]:
    """``(mean, low, high)`` of a cell: a number, a list of repetition values, or a mapping with ``mean`` and
    ``ci95``."""
    if isinstance(cell, Mapping):
        mean, half = float(cell["mean"]), cell.get("ci95")
    elif np.ndim(cell) == 0:
        mean, half = float(cell), None
    else:
        summary = summarize([float(v) for v in np.asarray(cell).ravel()])
        mean, half = summary.mean, summary.ci95
    half = 0.0 if half is None or math.isnan(half) else float(half)  # one value: a point
    return mean, mean - half, mean + half


def check(claim: Claim, rows: Mapping[str, Mapping[str, Any]]) -> dict[str, Any]:
    """The verdict on ``claim`` from the table ``rows`` (``{row: {column: cell}}``), with the numbers."""
    out: dict[str, Any] = {"claim": str(claim), "row_a": claim.row_a, "op": claim.op, "row_b": claim.row_b,
                           "column": claim.column, "source": claim.source}
    cells = [rows.get(row, {}).get(claim.column) for row in (claim.row_a, claim.row_b)]
    if any(cell is None for cell in cells):
        return {**out, "verdict": "not measured"}
    (mean_a, low_a, high_a), (mean_b, low_b, high_b) = (interval(cell) for cell in cells)
    out.update(a={"mean": mean_a, "low": low_a, "high": high_a}, b={"mean": mean_b, "low": low_b, "high": high_b})
    if high_a < low_b:
        verdict = "holds" if claim.op == "<" else "does not hold"
    elif high_b < low_a:
        verdict = "holds" if claim.op == ">" else "does not hold"
    else:
        verdict = "inconclusive"
    return {**out, "verdict": verdict}


def check_all(claims: Iterable[Claim], rows: Mapping[str, Mapping[str, Any]]) -> list[dict[str, Any]]:
    return [check(claim, rows) for claim in claims]


def format_claims(results: Sequence[Mapping[str, Any]], digits: int = 2) -> str:
    """The checked claims as a markdown list: verdict, the claim, both intervals, the paper's source."""
    if not results:
        return ""
    lines = ["", "Claims of the paper, checked on this run (95% intervals):", ""]
    for r in results:
        numbers = ""
        if "a" in r:
            a, b = r["a"], r["b"]
            numbers = (f": {r['row_a']} {a['mean']:.{digits}f} [{a['low']:.{digits}f}, {a['high']:.{digits}f}], "
                       f"{r['row_b']} {b['mean']:.{digits}f} [{b['low']:.{digits}f}, {b['high']:.{digits}f}]")
        source = f" ({r['source']})" if r.get("source") else ""
        lines.append(f"- **{r['verdict']}**: {r['claim']}{numbers}{source}")
    return "\n".join(lines) + "\n"
