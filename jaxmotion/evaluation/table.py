"""Markdown tables of results: rows (methods) × columns (metrics), cells a number or mean ± CI."""

from __future__ import annotations

from collections.abc import Mapping

from jaxmotion.evaluation.stats import Summary

Cell = float | Summary


def format_table(rows: Mapping[str, Mapping[str, Cell]], *, digits: int = 3, title: str | None = None) -> str:
    """Render ``{row: {column: cell}}`` as a markdown table; columns keep first-seen order."""
    columns: list[str] = []
    for cells in rows.values():
        columns.extend(c for c in cells if c not in columns)
    lines = [f"### {title}", ""] if title else []
    lines.append("| | " + " | ".join(columns) + " |")
    lines.append("| --- |" + " --- |" * len(columns))
    for name, cells in rows.items():
        rendered = [_cell(cells[c], digits) if c in cells else "–" for c in columns]
        lines.append(f"| {name} | " + " | ".join(rendered) + " |")
    return "\n".join(lines) + "\n"


def _cell(cell: Cell, digits: int) -> str:
    if isinstance(cell, Summary):
        return cell.format(digits)
    return f"{float(cell):.{digits}f}"
