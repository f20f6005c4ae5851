"""Line and scatter plots of experiment results, drawn on a matplotlib ``Figure`` (no pyplot state, no display)."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path

import numpy as np
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


def save_scatter(path: Path, points, labels, *, title: str = "") -> None:
    """Points ``[N, 2]`` coloured by integer ``labels [N]`` (one legend entry per label): e.g. latent codes
    projected to 2-D, coloured by discovered mode."""
    points, labels = np.asarray(points), np.asarray(labels)
    if points.ndim != 2 or points.shape[1] != 2 or labels.shape != (points.shape[0],):
        raise ValueError(f"points, labels: expected [N, 2] and [N], got {points.shape} and {labels.shape}")
    fig = Figure(figsize=(4.5, 4.0))
    ax = fig.subplots()
    for label in np.unique(labels):
        chosen = labels == label
        ax.scatter(points[chosen, 0], points[chosen, 1], s=8, alpha=0.7, label=f"mode {label}")
    ax.set_title(title, fontsize=9)
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=100)


def save_trajectories(path: Path, panels, *, title: str = "") -> None:
    """Top views (x right, z up the page) of root paths with their requested end points, one panel per
    ``{title: (paths [N, T, 3], ends [N, 3])}``: a path is a line from its start, its end point a cross in
    the same colour."""
    panels = dict(panels)
    fig = Figure(figsize=(4.0 * len(panels), 4.0))
    for ax, (name, (paths, ends)) in zip(fig.subplots(1, len(panels), squeeze=False)[0], panels.items(), strict=True):
        paths, ends = np.asarray(paths), np.asarray(ends)
        for i, (path_i, end) in enumerate(zip(paths, ends, strict=True)):
            line, = ax.plot(path_i[:, 0], path_i[:, 2], linewidth=1.5)
            ax.plot(end[0], end[2], marker="x", markersize=8, color=line.get_color())
        ax.plot(0, 0, marker="o", color="black")
        ax.set_aspect("equal", adjustable="datalim")
        ax.set_title(name, fontsize=9)
        ax.set_xlabel("x (m)")
        ax.set_ylabel("z (m)")
        ax.grid(alpha=0.3)
    if title:
        fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=100)
