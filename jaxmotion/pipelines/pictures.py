"""Pictures of generated motions from any method's sampler (ACTOR's Figure 5, ActFormer's Figure 5), and Neural
Marionette's Figures 5 and 6 from a trained context model (:func:`marionette_pictures`).

A sampler is the evaluation protocol's ``(key, actions [N], durations [N]) -> motions`` callable
(:data:`~jaxmotion.evaluation.protocol.Sampler`), so one function draws every generator's output, one person
or several.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence
from pathlib import Path

import jax
import numpy as np

from jaxmotion.data.motion import MotionDataset, concatenate, on_the_floor, to_dataset
from jaxmotion.evaluation.protocol import Sampler
from jaxmotion.geometry.skeletons import Skeleton
from jaxmotion.progress import phase
from jaxmotion.viz.motion import render_grid
from jaxmotion.viz.video import render_video


def generation_grid(sampler: Sampler, key: jax.Array, skeleton: Skeleton, class_names: Sequence[str], fps: float,
                    actions: int | Sequence[int], path: str | Path, *, per_action: int = 3, duration: int = 60,
                    still: bool = False, video: bool = False) -> MotionDataset:
    """Save a grid of generated motions, one row per action (``actions``: a list of class indices, or a count
    meaning the first ones), ``per_action`` ``duration``-frame samples per row, rendered by
    :func:`~jaxmotion.viz.motion.render_grid`: an animation as ``path``'s suffix says (``.gif``, or ``.mp4`` with
    the ``video`` extra), or with ``still`` a PNG of key poses (several persons drawn together, each in its own
    colours); ``video``: also ``path`` with the suffix ``.mp4``, the same motions animated (the ``video`` extra).
    Returns the generated motions (mode k = sample k), placed on the floor
    (:func:`~jaxmotion.data.motion.on_the_floor`)."""
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
    if video:
        render_grid(data, actions, Path(path).with_suffix(".mp4"))
    return data


#: Neural Marionette's Figure 5: eight generated actions and their durations (seconds).
FIGURE5 = (("Jump", 1.13), ("Crossing Limbs", 1.90), ("Stand Up", 2.47), ("Kick", 1.67),
           ("Walk Upward/Downward", 1.33), ("Stretch", 2.70), ("Sit Down", 3.00), ("Move Something", 2.73))


def marionette_pictures(generator, key: jax.Array, folder: str | Path, *, video: bool = False) -> list[Path]:
    """Neural Marionette's Figures 5 and 6 from a trained context model (:class:`~jaxmotion.pipelines.marionette.
    ContextGenerator`), as PNG strips of key poses in ``folder``: ``figure5.png``, the eight actions of
    :data:`FIGURE5` with the paper's durations (Z sampled; tags the training data never started are left out), and
    ``figure6.png``, controllability: one action (Throw, Z = mu) beside Z sampled twice, a longer duration, another
    start and another tag (Punch), each changing one thing. Two generations in all. ``video``: also ``figure5.mp4`` and
    ``figure6.mp4``, the same actions animated side by side (the ``video`` extra)."""
    folder = Path(folder)
    names, starts, fps = generator.class_names, generator.starts.counts, generator.fps
    started = [tag for tag in names if starts[names.index(tag)]]
    base = "Throw" if "Throw" in started else max(started, key=lambda t: starts[names.index(t)])
    other = "Punch" if base != "Punch" else "Kick"
    b = names.index(base)
    first = (generator.starts.rotations[b, 0], generator.starts.translation[b, 0])
    alternative = next((c for c in range(len(names)) if starts[c] and c != b), b)
    second = (generator.starts.rotations[alternative, starts[alternative] - 1],
              generator.starts.translation[alternative, starts[alternative] - 1])
    frames = min(60, generator.max_frames)
    longer = min(int(1.5 * frames), generator.max_frames)
    figure5 = [(tag, min(max(round(seconds * fps), 1), generator.max_frames)) for tag, seconds in FIGURE5
               if tag in started]
    k_sampled, k_mean = jax.random.split(key)
    sampled = generator.actions(k_sampled, [t for t, _ in figure5] + [base, base],
                                [d for _, d in figure5] + [frames, frames],
                                contexts=[None] * len(figure5) + [first] * 2)
    mean = generator.actions(k_mean, [base, base, base, other], [frames, longer, frames, frames],
                             contexts=[first, first, second, first], mean=True)
    labels5 = [f"{tag} {d / fps:.2f} s" for tag, d in figure5]
    labels6 = [f"{base} (Z = mu)", f"{base}, Z sampled", f"{base}, Z sampled again", f"{base}, {longer} frames",
               f"{base}, another start", f"{other} (another tag)"]
    n5 = len(figure5)
    paths = []
    for name, motions, labels in (("figure5.png", sampled.subset(range(n5)), labels5),
                                  ("figure6.png", concatenate([mean.subset([0]), sampled.subset([n5, n5 + 1]),
                                                               mean.subset([1, 2, 3])], split="generated"), labels6)):
        rows = dataclasses.replace(motions, class_names=tuple(labels), actions=np.arange(len(labels), dtype=np.int32),
                                   modes=np.zeros(len(labels), np.int32), mode_names=())
        render_grid(rows, range(len(labels)), str(folder / name), still=True)
        paths.append(folder / name)
        if video:
            paths.append(render_video(folder / f"{Path(name).stem}.mp4", rows, columns=4))
    return paths
