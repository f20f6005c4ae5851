"""Neural Marionette's single-action protocol (Tables 1 and 2, Table 4's single-action column): every test action is
generated again under its own conditions, and the generated actions are scored against the real ones.

The paper says only that a recogniser "pre-trained on BABEL-MAG" scores Acc, FID, Div, Multi-mod, ΔTraj and ΔJPE
(§5.1.2); sample counts, repetitions and which real set are unstated ([U] in MARIONETTE.md §4.2). Chosen here:

* **The test actions** (:func:`action_set`): every action of the test split with its 6 context frames and at most
  ``max_frames`` frames (the model's longest), or ``count`` of them evenly spaced over the split. Each keeps what
  MARIONET is conditioned on: the context (world frame, where it is in its take), its tags and the next action's,
  its duration and its root's ground path (followed for actions with a root-motion tag, as the trainer feeds
  them), and its label (its first tag: the evaluator's class).
* **A repetition** regenerates every test action once (Z sampled) with each row's sampler, and scores it with the
  evaluator (:mod:`jaxmotion.evaluation.recognizers`): **Acc** (the label recognised), **FID** against the real
  test actions' features (fixed: the real set is the test split itself), **Div** and **Multi-mod** (A2M's 200 and
  20 pairs: :mod:`jaxmotion.metrics.diversity`), **ΔTraj** (metres: the generated root against the followed
  paths, on the ground plane: :func:`~jaxmotion.metrics.trajectory.trajectory_error_per_sample`). Repetitions
  redraw Z and the pairs; the table gives mean ± 95% CI over them.
* **The Real row**: the test actions themselves, Acc, Div and Multi-mod (no FID, as the paper's "/").
* **ΔJPE** (``joint_error``; Table 2 names it and never defines it): each row generates every test action once
  more with Z = mu (the sampler called with ``key=None``), and the mean joint distance to the real action, in
  the world frame, in centimetres (:func:`~jaxmotion.metrics.trajectory.joint_position_error_per_sample`). One
  value per row: it has no randomness to repeat.

An **action sampler** is any function ``(key | None, conditions) -> motions``: ``conditions`` a chunk of
:attr:`ActionSet.conditions` (``context_rotations [N, K, 24, 3]``, ``context_translation [N, K, 3]``, ``tags``,
``next_tags [N, C]`` bool, ``actions [N]`` labels (for generators conditioned on one class), ``durations [N]``,
``paths [N, T, 2]``, ``follow [N]`` bool), ``motions`` a mapping with
``joints [N, T, J, 3]`` in the world frame (and what else the evaluator reads: ``rotations``, ``translation``)
for the same ``T`` frames; ``key=None`` asks for the deterministic reading (Z = mu).

Axes: N actions, K context frames, T frames (the longest action), J joints, C tags, D features.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Mapping
from typing import Any, NamedTuple

import jax
import jax.numpy as jnp
import numpy as np

from jaxmotion.config import check_at_least
from jaxmotion.data.mag_tags import root_tag_mask
from jaxmotion.data.motion import MotionDataset
from jaxmotion.data.pipeline import map_in_chunks
from jaxmotion.data.segments import CONTEXT_FRAMES
from jaxmotion.metrics.classification import accuracy, confusion_matrix
from jaxmotion.metrics.diversity import diversity, multimodality
from jaxmotion.metrics.fid import fid
from jaxmotion.metrics.trajectory import joint_position_error_per_sample, trajectory_error_per_sample
from jaxmotion.models.recognition import Recognizer
from jaxmotion.progress import phase

ActionSampler = Callable[[jax.Array | None, Mapping[str, np.ndarray]], Mapping[str, Any]]
#: The protocol's metric names -> Neural Marionette's columns (Tables 1 and 2), in the paper's order.
MARIONETTE_COLUMNS = {"FID": "FID", "accuracy": "Acc", "diversity": "Div", "multimodality": "Multi-mod",
                      "trajectory_error": "ΔTraj", "joint_error": "ΔJPE"}


@dataclasses.dataclass(frozen=True)
class ActionProtocol:
    """How the generated test actions are scored (module docstring). ``count``: test actions (None: all of them);
    ``max_frames``: the longest action kept (the generators' longest); ``chunk``: actions per sampler call;
    ``joint_error``: also ΔJPE (Table 2)."""

    repetitions: int = 10
    count: int | None = None
    max_frames: int = 120
    chunk: int = 256
    diversity_pairs: int = 200
    multimodality_pairs: int = 20
    joint_error: bool = False

    def __post_init__(self):
        check_at_least(self, 1, "repetitions", "count", "max_frames", "chunk", "diversity_pairs",
                       "multimodality_pairs")


class ActionSet(NamedTuple):
    """Test actions: what each is generated from (``conditions``, the action sampler's input) and the real action
    (``real``: ``joints [N, T, J, 3]``, ``rotations``, ``translation``, ``lengths [N]``, ``actions [N]`` labels),
    padded after each action's end with its last frame."""

    conditions: dict[str, np.ndarray]
    real: dict[str, np.ndarray]

    def __len__(self) -> int:
        return len(self.real["lengths"])


def action_set(data: MotionDataset, *, max_frames: int = 120, count: int | None = None) -> ActionSet:
    """The test actions of ``data`` (a multi-action split: takes with segments) with :data:`CONTEXT_FRAMES` frames
    before them and at most ``max_frames`` frames; ``count``: that many, evenly spaced (None: all)."""
    if data.segments is None:
        raise ValueError(f"data: {data.name}/{data.split} has no segment table; the protocol scores the actions of "
                         f"multi-action takes (synth-mag, mag)")
    if data.rotations is None:
        raise ValueError(f"data: {data.name} has joint positions only; the generators continue rotations")
    items = data.action_items(CONTEXT_FRAMES)
    keep = np.flatnonzero(items.durations <= max_frames)
    if count is not None and count < len(keep):
        keep = keep[np.round(np.linspace(0, len(keep) - 1, count)).astype(int)]
    if not len(keep):
        raise ValueError(f"data: no action of {data.name}/{data.split} has {CONTEXT_FRAMES} context frames and at "
                         f"most {max_frames} frames")
    sequences = items.data
    starts, durations = sequences.starts[keep], items.durations[keep]
    frames = int(durations.max())
    context = starts[:, None] + np.arange(CONTEXT_FRAMES)
    action = starts[:, None] + CONTEXT_FRAMES + np.minimum(np.arange(frames), durations[:, None] - 1)  # last repeats
    follow = np.any(items.tags[keep] & root_tag_mask(data.class_names), axis=1)
    lengths = durations.astype(np.int32)
    conditions = {"context_rotations": sequences.rotations[context], "context_translation": sequences.translation[context],
                  "tags": items.tags[keep], "next_tags": items.next_tags[keep],
                  "actions": sequences.actions[keep].astype(np.int32), "durations": lengths,
                  "paths": sequences.translation[action][..., [0, 2]], "follow": follow}
    real = {"joints": sequences.joints[action], "rotations": sequences.rotations[action],
            "translation": sequences.translation[action], "lengths": lengths,
            "actions": conditions["actions"]}
    return ActionSet(conditions, real)


def generate_for(sampler: ActionSampler, key: jax.Array | None, conditions: Mapping[str, np.ndarray], chunk: int,
                 on_chunk: Callable[[int, int], None] | None = None) -> dict[str, np.ndarray]:
    """``sampler`` on ``conditions`` in chunks of ``chunk`` actions (chunk i from ``fold_in(key, i)``; ``key=None``:
    Z = mu throughout), concatenated; checks that it gives world-frame joints for every action and frame."""
    frames = conditions["paths"].shape[1]

    def sample(i, part):
        motions = sampler(None if key is None else jax.random.fold_in(key, i), part)
        joints = np.shape(motions.get("joints")) if "joints" in motions else None
        if joints is None or len(joints) != 4 or joints[:2] != (len(part["durations"]), frames):
            raise ValueError(f"sampler output: expected a mapping with 'joints' [N, T, J, 3] = ({len(part['durations'])}"
                             f", {frames}, J, 3), got {joints if joints is not None else sorted(motions)}")
        return {k: v for k, v in motions.items() if k in ("joints", "rotations", "translation")}

    motions = map_in_chunks(sample, conditions, chunk, on_chunk=on_chunk)
    return {**motions, "lengths": conditions["durations"]}


def evaluate_actions(key: jax.Array, samplers: Mapping[str, ActionSampler], recognizer: Recognizer,
                     actions: ActionSet, config: ActionProtocol) -> dict[str, dict[str, list[float]]]:
    """Rows ``{"Real": {metric: [R values]}, <sampler name>: {...}}`` (module docstring): ``accuracy``, ``FID``,
    ``diversity``, ``multimodality``, ``trajectory_error`` (m) per repetition, and with ``config.joint_error`` one
    ``joint_error`` (cm). Repetition r uses ``fold_in(key, r)``; ΔJPE needs no key."""
    if "Real" in samplers:
        raise ValueError("samplers: 'Real' is the name of the real-data row; name the generator otherwise")
    labels = jnp.asarray(actions.real["actions"])
    if int(labels.max()) >= recognizer.num_classes:
        raise ValueError(f"evaluator: it recognises {recognizer.num_classes} classes, but the test actions' labels "
                         f"reach {int(labels.max())}; score them with an evaluator trained on their tags")
    conditions, classes = actions.conditions, recognizer.num_classes
    follow = np.asarray(conditions["follow"])
    rows: dict[str, dict[str, list[float]]] = {name: {} for name in ("Real", *samplers)}
    total = 1 + config.repetitions * 2 * len(samplers) + config.joint_error * len(samplers)
    with phase("[eval]", total, unit="pass") as bar:
        real_logits, real_features = recognizer(actions.real, bar.per_chunk("real test actions"))

        def scores(k: jax.Array, logits: jax.Array, features: jax.Array) -> dict[str, float]:
            k_div, k_mm = jax.random.split(k)
            return {"accuracy": float(accuracy(confusion_matrix(labels, jnp.argmax(logits, -1), classes))),
                    "diversity": float(diversity(k_div, features, config.diversity_pairs)),
                    "multimodality": float(multimodality(k_mm, features, labels, classes, config.multimodality_pairs))}

        for r in range(config.repetitions):
            rep = f"rep {r + 1}/{config.repetitions}"
            k_generate, k_score = jax.random.split(jax.random.fold_in(key, r))
            _append(rows["Real"], scores(jax.random.fold_in(k_score, 0), real_logits, real_features))
            for i, (name, sampler) in enumerate(samplers.items()):
                motions = generate_for(sampler, jax.random.fold_in(k_generate, i), conditions, config.chunk,
                                       bar.per_chunk(f"{rep} {name} generating"))
                logits, features = recognizer(motions, bar.per_chunk(f"{rep} {name} scoring"))
                metrics = scores(jax.random.fold_in(k_score, i + 1), logits, features)
                metrics["FID"] = float(fid(features, real_features))
                if follow.any():
                    errors = trajectory_error_per_sample(motions["joints"], conditions["paths"], motions["lengths"])
                    metrics["trajectory_error"] = float(np.asarray(errors)[follow].mean())
                _append(rows[name], metrics)
        if config.joint_error:
            for name, sampler in samplers.items():
                motions = generate_for(sampler, None, conditions, config.chunk, bar.per_chunk(f"{name} with Z = mu"))
                errors = joint_position_error_per_sample(motions["joints"], actions.real["joints"], motions["lengths"])
                rows[name]["joint_error"] = [100.0 * float(np.mean(errors))]
    return rows


def _append(row: dict[str, list[float]], metrics: Mapping[str, float]) -> None:
    for metric, value in metrics.items():
        row.setdefault(metric, []).append(value)
