"""The evaluation protocol: a generator's metric row, and the "Real" row, over R repetitions.

Every paper scores a generator the same way, with different numbers (each paper's evaluation code): draw a set of
real motions, generate motions for the same action labels, pass both through the recogniser, and compute
accuracy, FID against the real features, diversity and multimodality; repeat R times with fresh draws
and report mean ± 95% CI. The numbers are data (:class:`ProtocolConfig`, part of each experiment's config):

* ACTOR (:meth:`ProtocolConfig.actor`): 20 repetitions; each shuffles the real set and keeps up to 3 000
  clips, and generates one motion per kept clip, with its label, 60 frames long.
* ODMO (:meth:`ProtocolConfig.odmo`): 10 repetitions of N generated motions per class (400 CMU, 250
  HumanAct12, 200 UESTC) against N class-balanced real windows per class, and n-APD (``n_apd``: each
  set's per-class APD over that of the repetition's reference real draw, ×100; the real windows are in
  the recogniser's frame, canonical or not, and generated motions as the sampler gives them).
* ActFormer (:meth:`ProtocolConfig.actformer`): 100 generated motions per class against a fixed real
  reference, the train split cut into non-overlapping windows (``reference="tiles"``, 64 frames as the
  code; the paper's "all 60 frames": ``reference_window=60``); accuracy is the mean per-class recall
  (``accuracy="class_mean"``), and besides the whole-set FID (FID_w) the mean of the per-class FIDs
  (``class_fid``: ``FIDm_<name>``); for several persons, FID_a from a one-person recogniser's features
  max-pooled over the persons (``evaluate(..., person_recognizer=...)``: ``FIDa_<name>``, and
  ``FIDam_<name>`` per class). The paper reports one set (``repetitions=1``); repetitions redraw the
  generated motions and the Real row's windows against the same reference. GTA Combat has one class and no
  recogniser of its own: there the one-person recogniser alone is given (``recognizer=None``) and the rows
  hold FID_a only.

The "Real" row is computed the same way as a generator's: a second, independent draw of the reference
real set (ACTOR's "gt2") plays the generator's part, so its FID measures how far two real samples lie
apart, its accuracy is the recogniser's on real motions, and its diversity/multimodality are the data's.
The real sets are named (``{"train": ..., "test": ...}``) and the FID against each is reported under
its name (``FID_train``, ``FID_test``); labels, accuracy and the Real row use the first set, the
reference. A paper's column names are a separate mapping (:mod:`jaxmotion.evaluation.tables`).

:func:`evaluate` returns rows ``{row: {metric: [R values]}}``, the form an experiment's ``run`` returns;
the runner writes them to ``table.md`` and ``metrics.json`` (outside an experiment:
``jaxmotion.experiment.write_results(folder, rows, title)``).

A sampler is any function ``(key, actions [N], durations [N]) -> motions``, where ``motions`` is a mapping
with ``joints [N, T, J, 3]`` (library frame, metres) and whatever else the recogniser reads
(``rotations [N, T, J, 3]`` axis-angle for rot6d recognisers, ``translation``, ``lengths``).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Mapping
from typing import Any, Literal, NamedTuple

import jax
import jax.numpy as jnp
import numpy as np
from jax.sharding import Mesh

from jaxmotion.config import check_at_least
from jaxmotion.data.motion import MotionDataset
from jaxmotion.distributed import replicate
from jaxmotion.data.pipeline import BatchSpec, class_windows, epoch_windows, map_in_chunks, tiled_windows
from jaxmotion.metrics.apd import n_apd
from jaxmotion.metrics.classification import accuracy, confusion_matrix, mean_class_recall
from jaxmotion.metrics.diversity import diversity, multimodality
from jaxmotion.metrics.fid import aggregate_persons, fid, fid_class_mean
from jaxmotion.models.recognition import Recognizer
from jaxmotion.progress import phase

Motions = Mapping[str, Any]
Sampler = Callable[[jax.Array, jax.Array, jax.Array], Motions]


@dataclasses.dataclass(frozen=True)
class ProtocolConfig:
    """How a paper evaluates (see the module docstring).

    ``sampling``: ``per_real_clip`` (one generated motion per real clip, up to ``max_real`` clips) or
    ``per_class`` (``per_class`` generated motions and real windows per class). ``duration``: frames of
    generated motions and real windows. ``chunk``: sequences generated per sampler call. ``n_apd``: also
    score ODMO's n-APD (:func:`jaxmotion.metrics.apd.n_apd`) against the reference real draw.
    ``accuracy``: ``overall`` (correct / all: ACTOR, ODMO) or ``class_mean`` (mean per-class recall:
    ActFormer). ``class_fid``: also the mean of the per-class FIDs (``FIDm_<name>``). ``reference``:
    ``draw`` (each repetition draws the real sets as ``sampling`` says) or ``tiles`` (ActFormer: every clip
    cut into non-overlapping windows of ``reference_window`` frames, once; generated motions per class).
    """

    repetitions: int = 20
    sampling: Literal["per_real_clip", "per_class"] = "per_real_clip"
    max_real: int = 3000
    per_class: int = 100
    duration: int = 60
    diversity_pairs: int = 200
    multimodality_pairs: int = 20
    chunk: int = 500
    n_apd: bool = False
    accuracy: Literal["overall", "class_mean"] = "overall"
    class_fid: bool = False
    reference: Literal["draw", "tiles"] = "draw"
    reference_window: int = 64

    def __post_init__(self):
        check_at_least(self, 1, "repetitions", "max_real", "per_class", "duration", "diversity_pairs",
                       "multimodality_pairs", "chunk", "reference_window")
        for name, allowed in (("sampling", ("per_real_clip", "per_class")), ("accuracy", ("overall", "class_mean")),
                              ("reference", ("draw", "tiles"))):
            if getattr(self, name) not in allowed:
                raise ValueError(f"ProtocolConfig.{name}: expected one of {allowed}, got {getattr(self, name)!r}")
        if self.reference == "tiles" and self.sampling != "per_class":
            raise ValueError("ProtocolConfig.reference: 'tiles' generates per class; set sampling='per_class'")

    @classmethod
    def actor(cls) -> ProtocolConfig:
        return cls()

    @classmethod
    def odmo(cls, per_class: int) -> ProtocolConfig:
        return cls(repetitions=10, sampling="per_class", per_class=per_class, n_apd=True)

    @classmethod
    def actformer(cls, repetitions: int = 1) -> ProtocolConfig:
        return cls(repetitions=repetitions, sampling="per_class", per_class=100, accuracy="class_mean",
                   class_fid=True, reference="tiles")


def real_windows(data: MotionDataset, key: jax.Array, config: ProtocolConfig, canonical: bool) -> dict[str, np.ndarray]:
    """One repetition's draw of real motions from ``data`` (``config.duration`` frames each)."""
    spec = BatchSpec(batch_size=1, window=config.duration, canonical=canonical)
    if config.sampling == "per_class":
        return class_windows(data, key, spec, config.per_class)
    return epoch_windows(data, key, spec, min(config.max_real, len(data)))


def generate(sampler: Sampler, key: jax.Array, actions: np.ndarray, duration: int, chunk: int,
             mesh: Mesh | None = None, on_chunk: Callable[[int, int], None] | None = None) -> dict[str, np.ndarray]:
    """Call ``sampler`` on ``actions [N]`` in chunks of ``chunk`` (the last one padded, so the sampler sees
    one shape) and concatenate; chunk i uses ``fold_in(key, i)``. ``mesh``: split each chunk over a data
    mesh's devices (:func:`jaxmotion.data.pipeline.map_in_chunks`); ``None``: one device. ``on_chunk``:
    progress, as ``map_in_chunks`` calls it."""
    if mesh is not None:
        key = replicate(key, mesh)

    def sample(i, part):
        durations = jnp.full(part.shape, duration, jnp.int32, device=None if mesh is None else part.sharding)
        motions = sampler(jax.random.fold_in(key, i), jnp.asarray(part), durations)
        if "joints" not in motions:
            raise ValueError(f"sampler output: expected a mapping with 'joints' [N, T, J, 3], got keys {sorted(motions)}")
        return dict(motions)

    return map_in_chunks(sample, np.asarray(actions, np.int32), chunk, mesh=mesh, on_chunk=on_chunk)


class Reference(NamedTuple):
    """A real set's recogniser features ``[M, D]`` (``None`` without a recogniser), their ``actions [M]``, and
    for FID_a the one-person recogniser's features max-pooled over persons ``[M, D']`` (``None`` without one)."""

    features: jax.Array | None
    actions: jax.Array
    person_features: jax.Array | None = None


def person_features(recognizer: Recognizer, motions: Motions, on_chunk: Callable[[int, int], None] | None = None
                    ) -> jax.Array:
    """FID_a's features: each person of ``motions`` (``joints [N, P, T, J, 3]``, and ``translation`` /
    ``rotations`` alike) through a one-person ``recognizer``, channel-wise max over the persons -> ``[N, D]``."""
    joints = np.asarray(motions["joints"])
    if joints.ndim != 5:
        raise ValueError(f"motions['joints']: FID_a needs motions of several persons [N, P, T, J, 3], got "
                         f"shape {joints.shape}")
    n, p = joints.shape[:2]
    rows = {k: np.asarray(motions[k]).reshape(n * p, *np.shape(motions[k])[2:])
            for k in ("joints", "translation", "rotations") if motions.get(k) is not None}
    if motions.get("lengths") is not None:
        rows["lengths"] = np.repeat(np.asarray(motions["lengths"]), p)
    _, features = recognizer(rows, on_chunk)
    return aggregate_persons(jnp.reshape(features, (n, p, -1)))


def reference_features(recognizer: Recognizer | None, motions: Motions, person_recognizer: Recognizer | None = None,
                       on_chunk: Callable[[int, int], None] | None = None) -> Reference:
    """A real set's :class:`Reference` (``motions``: a batch dict with ``actions``; ``on_chunk``: progress of
    each recogniser's pass)."""
    pooled = None if person_recognizer is None else person_features(person_recognizer, motions, on_chunk)
    features = None if recognizer is None else recognizer(motions, on_chunk)[1]
    return Reference(features, jnp.asarray(motions["actions"]), pooled)


def score(key: jax.Array, recognizer: Recognizer | None, motions: Motions, actions: np.ndarray,
          references: Mapping[str, Reference], config: ProtocolConfig, real: Motions | None = None,
          person_recognizer: Recognizer | None = None, num_classes: int | None = None,
          on_chunk: Callable[[int, int], None] | None = None) -> dict[str, float]:
    """The metrics of one set of motions made for ``actions [N]``: accuracy (``config.accuracy``),
    ``FID_<name>`` against each named :class:`Reference`, with ``config.class_fid`` the class-mean
    ``FIDm_<name>``, with a ``person_recognizer`` FID_a (``FIDa_<name>``, ``FIDam_<name>`` per class), then
    diversity, multimodality, and with ``config.n_apd`` the n-APD against the ``real`` motions (a batch dict
    with ``joints`` and ``actions``). ``recognizer=None``: FID_a (and n-APD) only; ``num_classes``, the data's
    class count, is then required. ``on_chunk``: progress of each recogniser's pass."""
    if recognizer is None and (person_recognizer is None or num_classes is None):
        raise ValueError("recognizer: without one, score needs a person_recognizer and num_classes (FID_a only)")
    actions = jnp.asarray(actions)
    classes = recognizer.num_classes if recognizer is not None else num_classes
    out, features = {}, None
    if recognizer is not None:
        logits, features = recognizer(motions, on_chunk)
        confusion = confusion_matrix(actions, jnp.argmax(logits, -1), classes)
        out["accuracy"] = float((mean_class_recall if config.accuracy == "class_mean" else accuracy)(confusion))
    pooled = None if person_recognizer is None else person_features(person_recognizer, motions, on_chunk)
    for name, reference in references.items():
        if features is not None:
            out[f"FID_{name}"] = float(fid(features, reference.features))
            if config.class_fid:
                out[f"FIDm_{name}"] = float(fid_class_mean(features, actions, reference.features,
                                                           reference.actions, classes))
        if pooled is not None:
            if reference.person_features is None:
                raise ValueError(f"references[{name!r}]: FID_a needs the real set's person features")
            out[f"FIDa_{name}"] = float(fid(pooled, reference.person_features))
            if config.class_fid:
                out[f"FIDam_{name}"] = float(fid_class_mean(pooled, actions, reference.person_features,
                                                            reference.actions, classes))
    if features is not None:
        k_div, k_mm = jax.random.split(key)
        out["diversity"] = float(diversity(k_div, features, config.diversity_pairs))
        out["multimodality"] = float(multimodality(k_mm, features, actions, classes, config.multimodality_pairs))
    if config.n_apd:
        if real is None:
            raise ValueError("real: n-APD needs the real motions it normalises by")
        out["n_apd"] = float(n_apd(jnp.asarray(motions["joints"]), actions, jnp.asarray(real["joints"]),
                                   jnp.asarray(real["actions"]), classes))
    return out


def check_real_sets(real: Mapping[str, MotionDataset], config: ProtocolConfig) -> None:
    """Refuse a duration longer than every clip of a real set: every real window would be mostly padding."""
    for name, data in real.items():
        longest = int(data.lengths.max()) if len(data) else 0
        if config.duration > longest:
            raise ValueError(f"protocol.duration: {config.duration} frames is longer than every clip of the real "
                             f"set {name!r} ({data.name}; the longest has {longest}); choose at most {longest}")


def check_evaluator(recognizer: Recognizer, real: Mapping[str, MotionDataset]) -> None:
    """Refuse an evaluator trained on other classes than a real set's: its accuracy and FID would mean nothing."""
    for name, data in real.items():
        if data.num_classes != recognizer.num_classes:
            raise ValueError(f"evaluator: it recognises {recognizer.num_classes} classes, but the real set {name!r} "
                             f"({data.name}) has {data.num_classes}; score a dataset with an evaluator trained on "
                             f"its classes")


def evaluate(key: jax.Array, samplers: Mapping[str, Sampler], recognizer: Recognizer | None,
             real: Mapping[str, MotionDataset], config: ProtocolConfig,
             mesh: Mesh | None = None, person_recognizer: Recognizer | None = None
             ) -> dict[str, dict[str, list[float]]]:
    """Rows ``{"Real": {metric: [R values]}, <sampler name>: {...}}`` over ``config.repetitions``.

    ``real``: named real sets, the first being the reference (labels, accuracy, the Real row). Every
    sampler is scored against the same real draws in a repetition (with ``config.reference="tiles"``, the
    same tiled windows in all: each class present gets ``config.per_class`` generated motions, and the Real
    row is a class-balanced draw of the reference set's windows). Repetition r uses ``fold_in(key, r)``.
    ``person_recognizer``: a one-person recogniser for FID_a on motions of several persons; with
    ``recognizer=None`` the rows hold FID_a alone (a dataset no recogniser knows the classes of).
    ``mesh``: generation and the recogniser's passes split their chunks over a
    data mesh's devices (same numbers up to float32 sums); ``None``: one device.

    Progress: a long evaluation prints ``[eval] pass 5/14 ... | rep 2/5 ACTOR generating | ... | ETA 1m20s``
    lines on stderr, a pass being one generation or one recogniser's pass over a set, advanced per chunk
    (:func:`jaxmotion.progress.phase`: ``JAXMOTION_PROGRESS_AFTER`` seconds of silence first, 10 by default).
    """
    if not real:
        raise ValueError("real: expected at least one named real dataset")
    if "Real" in samplers:
        raise ValueError("samplers: 'Real' is the name of the real-data row; name the generator otherwise")
    check_real_sets(real, config)
    if recognizer is None and person_recognizer is None:
        raise ValueError("recognizer: expected a recogniser, or a person_recognizer for FID_a alone")
    if recognizer is not None:
        check_evaluator(recognizer, real)

    def on_mesh(r: Recognizer | None) -> Recognizer | None:
        return r if mesh is None or r is None or r.mesh is not None else dataclasses.replace(r, mesh=mesh)

    recognizer, person_recognizer = on_mesh(recognizer), on_mesh(person_recognizer)
    canonical = (recognizer or person_recognizer).config.canonical
    rows: dict[str, dict[str, list[float]]] = {name: {} for name in ("Real", *samplers)}
    reference_name = next(iter(real))
    tiles = config.reference == "tiles"
    passes = (recognizer is not None) + (person_recognizer is not None)  # recogniser passes over one set
    total = (len(real) * passes * (1 if tiles else config.repetitions)
             + config.repetitions * (len(samplers) + (1 + len(samplers)) * passes))
    with phase("[eval]", total, unit="pass") as bar:
        if tiles:
            draws = {name: tiled_windows(data, config.reference_window) for name, data in real.items()}
            references = {name: reference_features(recognizer, draw, person_recognizer,
                                                   bar.per_chunk(f"{name} reference"))
                          for name, draw in draws.items()}
            present = np.unique(draws[reference_name]["actions"])
            actions = np.repeat(present, config.per_class).astype(np.int32)
        for r in range(config.repetitions):
            rep = f"rep {r + 1}/{config.repetitions}"
            k_real, k_again, k_score, k_generate = jax.random.split(jax.random.fold_in(key, r), 4)
            if not tiles:
                draws = {name: real_windows(data, jax.random.fold_in(k_real, i), config, canonical)
                         for i, (name, data) in enumerate(real.items())}
                references = {name: reference_features(recognizer, draw, person_recognizer,
                                                       bar.per_chunk(f"{rep} {name} reference"))
                              for name, draw in draws.items()}
                actions = draws[reference_name]["actions"]
            second = real_windows(real[reference_name], k_again, config, canonical)
            sets = {"Real": (second, second["actions"])}
            for i, (name, sampler) in enumerate(samplers.items()):
                sets[name] = (generate(sampler, jax.random.fold_in(k_generate, i), actions, config.duration,
                                       config.chunk, mesh, bar.per_chunk(f"{rep} {name} generating")), actions)
            for i, (name, (motions, labels)) in enumerate(sets.items()):
                metrics = score(jax.random.fold_in(k_score, i), recognizer, motions, labels, references, config,
                                draws[reference_name], person_recognizer, real[reference_name].num_classes,
                                bar.per_chunk(f"{rep} {name} scoring"))
                for metric, value in metrics.items():
                    rows[name].setdefault(metric, []).append(value)
    return rows
