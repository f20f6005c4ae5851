"""Pictures of generated motions from any method's sampler (ACTOR's Figure 5, ActFormer's Figure 5).

A sampler is the evaluation protocol's ``(key, actions [N], durations [N]) -> motions`` callable
(:data:`~jaxmotion.evaluation.protocol.Sampler`), so one function draws every generator's output, one person
or several.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import jax
import numpy as np

from jaxmotion.data.motion import MotionDataset, on_the_floor, to_dataset
from jaxmotion.data.preview import render_grid
from jaxmotion.evaluation.protocol import Sampler
from jaxmotion.geometry.skeletons import Skeleton
from jaxmotion.progress import phase


def generation_grid(sampler: Sampler, key: jax.Array, skeleton: Skeleton, class_names: Sequence[str], fps: float,
                    actions: int | Sequence[int], path: str | Path, *, per_action: int = 3, duration: int = 60,
                    still: bool = False) -> MotionDataset:
    """Save a grid of generated motions, one row per action (``actions``: a list of class indices, or a count
    meaning the first ones), ``per_action`` ``duration``-frame samples per row, rendered by
    :func:`~jaxmotion.data.preview.render_grid`: an animated GIF, or with ``still`` a PNG of key poses (several
    persons drawn together, each in its own colours). Returns the generated motions (mode k = sample k), placed
    on the floor (:func:`~jaxmotion.data.motion.on_the_floor`)."""
    actions = list(range(actions)) if isinstance(actions, int) else [int(a) for a in actions]
    if not actions:
        raise ValueError("actions: expected at least one action (a count >= 1 or a non-empty list)")
    if any(not 0 <= a < len(class_names) for a in actions):
        raise ValueError(f"actions: expected class indices in [0, {len(class_names)}), got {actions}")
    if per_action < 1 or duration < 1:
        raise ValueError(f"per_action, duration: expected >= 1, got {per_action}, {duration}")
    labels = np.repeat(np.asarray(actions, np.int32), per_action)
    durations = np.full(labels.shape, duration, np.int32)
    with phase("[pictures]", 1, unit="call") as bar:  # one call, compiled for this shape: seconds
        motions = {k: np.asarray(v) for k, v in sampler(key, labels, durations).items()}
        bar.advance(note=f"{len(labels)} motions")
    samples = tuple(f"sample {k + 1}" for k in range(per_action))
    data = on_the_floor(to_dataset({**motions, "lengths": durations, "actions": labels}, skeleton, class_names, fps,
                                   name="generated", modes=np.arange(len(labels), dtype=np.int32) % per_action,
                                   names=tuple(f"{class_names[a]} {k % per_action + 1}" for k, a in enumerate(labels)),
                                   mode_names=(samples,) * len(class_names)))
    render_grid(data, actions, str(path), still=still)
    return data
