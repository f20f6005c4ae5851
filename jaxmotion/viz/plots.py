"""Line plots of experiment results, drawn on a matplotlib ``Figure`` (no pyplot state, no display)."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path

from matplotlib.figure import Figure


def save_curves(path: Path, x: Sequence[float], panels: Mapping[str, Mapping[str, Sequence[float]]], *,
                xlabel: str, marks: Sequence[float] = ()) -> None:
    """One panel per ``{y label: {curve label: values over x}}``, dashed vertical lines at ``marks``."""
    fig = Figure(figsize=(4.5 * len(panels), 3.4))
    for ax, (ylabel, curves) in zip(fig.subplots(1, len(panels), squeeze=False)[0], panels.items(), strict=True):
        for label, values in curves.items():
            ax.plot(x, values, marker="o", label=label)
        for mark in marks:
            ax.axvline(mark, color="grey", linestyle="--", linewidth=1)
        ax.set_xlabel(xlabel)
        ax.set_ylabel(ylabel)
        ax.grid(alpha=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(path, dpi=100)
