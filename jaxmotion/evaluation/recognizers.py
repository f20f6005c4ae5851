"""The evaluators: train a recogniser on a dataset once, cache it, and hand it to every evaluation.

A :class:`RecognizerTraining` says everything that determines an evaluator (dataset and its seed, the
network, the optimiser, the number of steps, the seed). :func:`trained_recognizer` returns the evaluator
for it: read from the cache when it was trained before, otherwise trained now (resuming from the
cache folder's last checkpoint if an earlier attempt was interrupted) and then cached. The cache folder
is ``<cache>/recognizers/<dataset>-<architecture>-<hash of the spec>/`` (``<cache>`` = ``$JAXMOTION_CACHE``
or ``~/.cache/jaxmotion``) and holds the orbax checkpoints, the training log and ``recognizer.json`` with
the spec and the held-out accuracy.

The papers' evaluators on the embedded data, in each profile, are :mod:`jaxmotion.recipes.evaluators`'.

Held-out data: the dataset's ``test`` (or ``val``) split where it has one (synth-uestc, UESTC, the
NTU-120 and BABEL stand-ins); otherwise, for the embedded datasets, the same generator run with
``test_data_seed`` (new subjects and new sequences).
"""

from __future__ import annotations

import contextlib
import contextvars
import dataclasses
import hashlib
import json
import os
import sys
from collections.abc import Iterator
from pathlib import Path
from typing import Any, Literal

import jax
import jax.numpy as jnp
import numpy as np
import optax

from jaxmotion import config as cfglib
from jaxmotion.cache import cache_root
from jaxmotion.data import synthetic
from jaxmotion.data.datasets import check_dataset_name, load_dataset
from jaxmotion.data.motion import SKELETONS, MotionDataset
from jaxmotion.data.pipeline import BatchSpec, epoch_windows
from jaxmotion.evaluation.protocol import check_evaluator
from jaxmotion.geometry.skeletons import Skeleton
from jaxmotion.metrics.classification import accuracy, confusion_matrix
from jaxmotion.models.recognition import (
    Recognizer,
    RecognizerConfig,
    apply_recognizer,
    init_recognizer,
    recognizer_inputs,
)
from jaxmotion.files import folder_lock, read_json, write_json
from jaxmotion.progress import phase
from jaxmotion.train.checkpoint import Checkpointer
from jaxmotion.distributed import is_primary
from jaxmotion.train.fit import fit
from jaxmotion.train.loop import CHECKPOINT_FOLDER, LoopConfig
from jaxmotion.train.state import TrainState


@dataclasses.dataclass(frozen=True)
class RecognizerTraining:
    """Everything that determines one evaluator.

    ``count``: train on the first ``count`` sequences only (smoke runs). ``test_count``: held-out
    accuracy on at most this many clips (a random subset; ACTOR's protocol keeps 3 000).
    ``input_noise``: standard deviation of Gaussian noise added to the network's inputs during training
    (not a reference setting). The embedded data's hinge joints (knees, elbows) turn about one axis only
    and its hands and feet never turn, so without it a third of the ST-GCN's rot6d channels have zero
    variance, its input BatchNorm divides them by sqrt(1e-5), and a generator's smallest error there
    outweighs the whole motion. Real estimates (VIBE) have noise in every channel.
    ``trains_on``: ``train`` (the train split, held out the other) or ``held_out`` (ActFormer's rule: the
    evaluator learns on the other split, NTU's xsub test or BABEL's val, and is checked on the train split
    whose windows are the generators' reference). ``permute_persons``: shuffle the persons of every training
    window (ActFormer's two-person evaluator, which reads them in order). ``optimizer``: ``adam`` (AdamW
    with ``weight_decay``) or ``sgd`` (ActFormer's recognition recipe: SGD with Nesterov momentum 0.9, the
    weight decay added to the gradient, ``learning_rate`` times 0.1 at each of ``decay_steps``).
    """

    dataset: str
    recognizer: RecognizerConfig
    loop: LoopConfig
    batch_size: int = 64
    window: int = 60
    learning_rate: float = 1e-3
    weight_decay: float = 0.0
    data_seed: int = 0
    test_data_seed: int = 1
    count: int | None = None
    test_count: int | None = 3000
    seed: int = 0
    input_noise: float = 0.0
    trains_on: Literal["train", "held_out"] = "train"
    permute_persons: bool = False
    optimizer: Literal["adam", "sgd"] = "adam"
    decay_steps: tuple[int, ...] = ()

    def __post_init__(self):
        check_dataset_name(self.dataset, "RecognizerTraining.dataset")
        if self.trains_on not in ("train", "held_out"):
            raise ValueError(f"RecognizerTraining.trains_on: expected 'train' or 'held_out', got {self.trains_on!r}")
        if self.optimizer not in ("adam", "sgd"):
            raise ValueError(f"RecognizerTraining.optimizer: expected 'adam' or 'sgd', got {self.optimizer!r}")
        if self.loop.steps < 1:
            raise ValueError(f"RecognizerTraining.loop.steps: expected >= 1, got {self.loop.steps}")
        cfglib.check_at_least(self, 1, "batch_size", "window", "count", "test_count")
        if self.input_noise < 0:
            raise ValueError(f"RecognizerTraining.input_noise must be >= 0, got {self.input_noise}")

    @property
    def name(self) -> str:
        """The evaluator's name (:data:`jaxmotion.recipes.evaluators.EVALUATORS`):
        ``<dataset>/<architecture>[-joints15][-seed<n>]`` (a seed other than 0: the same recipe trained apart)."""
        topology = "" if self.recognizer.topology == "own" else f"-{self.recognizer.topology}"
        seed = "" if self.seed == 0 else f"-seed{self.seed}"
        return f"{self.dataset}/{self.recognizer.architecture}{topology}{seed}"


# --- data ------------------------------------------------------------------------------------------


def training_data(spec: RecognizerTraining, data_root: str | None = None) -> MotionDataset:
    """What the evaluator learns on: the train split, or with ``trains_on="held_out"`` the other one."""
    if spec.trains_on == "held_out":
        return _other_split(spec, data_root)
    return _train_split(spec, data_root)


def held_out_data(spec: RecognizerTraining, data_root: str | None = None) -> MotionDataset:
    """What the evaluator is checked on: the split :func:`training_data` does not use."""
    if spec.trains_on == "held_out":
        return _train_split(spec, data_root)
    return _other_split(spec, data_root)


def _actions(data: MotionDataset) -> MotionDataset:
    """A multi-action dataset (takes with segments: synth-mag, mag) as its actions, each labelled with its first
    tag (an intention, else the body state: body parts ride on states and are not classes of their own); any
    other dataset as it is."""
    return data if data.segments is None else data.action_items(context=0).data


def _train_split(spec: RecognizerTraining, data_root: str | None) -> MotionDataset:
    return _actions(load_dataset(spec.dataset, "train", seed=spec.data_seed, data_root=data_root, count=spec.count))


def embedded_held_out_split(dataset: str) -> str | None:
    """The embedded ``dataset``'s held-out split (``test``, else ``val``), ``None`` if it has only ``train``."""
    return next((s for s in ("test", "val") if s in synthetic.VARIANTS[dataset].splits), None)


def _other_split(spec: RecognizerTraining, data_root: str | None) -> MotionDataset:
    """The dataset's test (or val) split, or for embedded datasets without one, a fresh draw with
    ``test_data_seed``."""
    if spec.dataset in synthetic.VARIANTS:
        split = embedded_held_out_split(spec.dataset)
        if split is not None:
            return _actions(load_dataset(spec.dataset, split, seed=spec.data_seed, count=spec.count))
        return _actions(load_dataset(spec.dataset, "train", seed=spec.test_data_seed, count=spec.count))
    return _actions(load_dataset(spec.dataset, "test", data_root=data_root, count=spec.count))


def _batch_spec(spec: RecognizerTraining, canonical: bool) -> BatchSpec:
    return BatchSpec(batch_size=spec.batch_size, window=spec.window, canonical=canonical,
                     permute_persons=spec.permute_persons)


# --- training --------------------------------------------------------------------------------------


def train_recognizer(spec: RecognizerTraining, workdir: str | Path | None, *, data_root: str | None = None,
                     data: MotionDataset | None = None, progress: bool = True, **loop_options) -> Recognizer:
    """Train the evaluator ``spec`` (resuming from ``workdir``'s checkpoints) and return it; the key is
    ``jax.random.key(spec.seed)``, ``loop_options`` go to the loop (``mesh``, ``eval_fn``).

    ``data``: train on this set instead of ``spec.dataset`` (ACTOR's recognition and augmentation use
    cases train the same recipe on real, denoised or generated motions)."""
    data = training_data(spec, data_root) if data is None else data
    net = spec.recognizer
    skeleton, num_classes = data.skeleton, data.num_classes

    def step_fn(state, batch, key):
        if spec.input_noise:  # without noise the keys stay as they were before the option existed
            k_noise, key = jax.random.split(key)

        def loss_fn(params):
            x = recognizer_inputs(net, skeleton, batch)
            if spec.input_noise:
                x = x + spec.input_noise * jax.random.normal(k_noise, x.shape, x.dtype)
            (logits, _), updates = apply_recognizer(net, skeleton, num_classes,
                                                    {"params": params, "batch_stats": state.buffers}, x,
                                                    batch["lengths"], train=True, key=key)
            loss = optax.softmax_cross_entropy_with_integer_labels(logits, batch["actions"]).mean()
            return loss, (updates.get("batch_stats", state.buffers), logits)

        (loss, (batch_stats, logits)), grads = jax.value_and_grad(loss_fn, has_aux=True)(state.params)
        state = state.apply_gradients(grads).replace(buffers=batch_stats)
        return state, {"loss": loss, "accuracy": jnp.mean(jnp.argmax(logits, -1) == batch["actions"])}

    state = fit(data, jax.random.key(spec.seed),
                init_state=lambda k: _initial_state(spec, k, skeleton, num_classes, data.persons),
                step_fn=step_fn, batch=_batch_spec(spec, net.canonical), loop=spec.loop, workdir=workdir,
                progress=progress, **loop_options)
    return _recognizer(spec, data.skeleton, data.class_names, state)


def _initial_state(spec: RecognizerTraining, key: jax.Array, skeleton: Skeleton, num_classes: int,
                   persons: int = 1) -> TrainState:
    variables = init_recognizer(key, spec.recognizer, skeleton, num_classes, spec.window, persons)
    tx = recognizer_optimizer(spec)
    return TrainState.create(variables["params"], tx, variables.get("batch_stats", {}))


def recognizer_optimizer(spec: RecognizerTraining) -> optax.GradientTransformation:
    """The optimiser ``spec`` names (see :class:`RecognizerTraining`)."""
    if spec.optimizer == "sgd":
        rate = optax.piecewise_constant_schedule(spec.learning_rate, {int(s): 0.1 for s in spec.decay_steps})
        # PyTorch's SGD: the decay joins the gradient before the momentum
        return optax.chain(optax.add_decayed_weights(spec.weight_decay), optax.sgd(rate, momentum=0.9, nesterov=True))
    if spec.weight_decay:
        return optax.adamw(spec.learning_rate, weight_decay=spec.weight_decay)
    return optax.adam(spec.learning_rate)


def _recognizer(spec: RecognizerTraining, skeleton: Skeleton, class_names: tuple[str, ...],
                state: TrainState) -> Recognizer:
    variables = {"params": state.params}
    if spec.recognizer.architecture != "gru":
        variables["batch_stats"] = state.buffers
    return Recognizer(spec.recognizer, skeleton, tuple(class_names), variables)


def evaluate_recognizer(recognizer: Recognizer, data: MotionDataset, key: jax.Array, *, window: int,
                        count: int | None = None) -> dict[str, Any]:
    """Accuracy and confusion matrix on one window of each of ``count`` random clips of ``data``, which must
    have the recogniser's classes (:func:`~jaxmotion.evaluation.protocol.check_evaluator`)."""
    check_evaluator(recognizer, {data.split: data})
    count = len(data) if count is None else min(count, len(data))
    windows = epoch_windows(data, key, BatchSpec(batch_size=1, window=window, canonical=recognizer.config.canonical),
                            count)
    with phase("[evaluator] held-out", 1, unit="pass") as bar:
        logits, _ = recognizer(windows, bar.per_chunk(f"{count} clips"))
    confusion = confusion_matrix(jnp.asarray(windows["actions"]), jnp.argmax(logits, -1), recognizer.num_classes)
    return {"accuracy": float(accuracy(confusion)), "confusion": np.asarray(confusion).tolist(), "clips": count}


# --- cache -----------------------------------------------------------------------------------------


# Part of every cache key: bump it when a change to training or evaluation code changes what a spec trains.
CACHE_VERSION = 4  # 4: checkpoints hold the library's TrainState (non-trained state as `buffers`)


def cache_folder(spec: RecognizerTraining, cache_dir: str | Path | None = None, data_root: str | None = None) -> Path:
    """Where the evaluator ``spec`` is kept. The hash covers the spec, what it trains on (embedded data: the
    generator version; real data: the folder's resolved path and a manifest of its files) and what else
    changes the trained weights (:func:`training_machine`)."""
    text = json.dumps({"spec": _cache_spec(spec), "source": data_source(spec.dataset, data_root),
                       "machine": training_machine(), "version": CACHE_VERSION}, sort_keys=True)
    digest = hashlib.sha256(text.encode()).hexdigest()[:12]
    return cache_root(cache_dir) / "recognizers" / f"{spec.dataset}-{spec.recognizer.architecture}-{digest}"


# Fields added after evaluators were first cached, with their defaults: at those values they stay out of the
# cache key, so the evaluators trained before they existed are found again.
_LATER_FIELDS = {("trains_on",): "train", ("permute_persons",): False, ("optimizer",): "adam", ("decay_steps",): [],
                 ("recognizer", "persons"): "average", ("recognizer", "topology"): "own", ("recognizer", "heads"): 4}


def _cache_spec(spec: RecognizerTraining) -> dict[str, Any]:
    out = cfglib.to_dict(spec)
    for path, default in _LATER_FIELDS.items():
        *parents, name = path
        holder = out
        for parent in parents:
            holder = holder[parent]
        if holder.get(name) == default:
            del holder[name]
    return out


def data_source(dataset: str, data_root: str | Path | None) -> dict[str, Any]:
    """What identifies a dataset's content: an embedded one's generator version; a real one's folder (resolved,
    so two spellings of one folder agree and one spelling of two folders does not) and every file under it
    (relative path, size, modification time)."""
    if dataset in synthetic.VARIANTS:
        return {"generator_version": synthetic.GENERATOR_VERSION}
    if data_root is None:
        return {"data_root": None}
    root = Path(data_root).resolve()
    files = sorted((str(p.relative_to(root)), p.stat().st_size, p.stat().st_mtime_ns)
                   for p in root.rglob("*") if p.is_file())
    manifest = hashlib.sha256(json.dumps(files).encode()).hexdigest()
    return {"data_root": str(root), "files": len(files), "manifest": manifest}


def training_machine() -> dict[str, Any]:
    """What of the machine changes a training's floating-point result: the backend and device kind and, on
    CPU, the number of cores this process may use (XLA splits its reductions over them, so one core and two
    round differently)."""
    device = jax.devices()[0]
    machine = {"backend": device.platform, "device_kind": device.device_kind}
    if device.platform == "cpu":
        machine["cpu_threads"] = usable_cpus()
    return machine


def usable_cpus() -> int:
    """The CPU cores this process may run on (its affinity, e.g. under ``taskset``), else all of them."""
    return len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count() or 1


# The evaluators handed out inside a `recording_evaluators` block (None outside one): what a run used, so that its
# results name those and nothing else the cache happens to hold. A context variable, scoped by the block.
_USED: contextvars.ContextVar[list[dict[str, Any]] | None] = contextvars.ContextVar("evaluators_used", default=None)


@contextlib.contextmanager
def recording_evaluators() -> Iterator[list[dict[str, Any]]]:
    """Within the block, each evaluator :func:`trained_recognizer` hands out is added to the yielded list as
    ``{name, cache_key, held_out_accuracy, held_out_clips}`` (once each, sorted when the block ends)."""
    used: list[dict[str, Any]] = []
    token = _USED.set(used)
    try:
        yield used
    finally:
        _USED.reset(token)
        unique = {json.dumps(entry, sort_keys=True): entry for entry in used}
        used[:] = [unique[key] for key in sorted(unique)]


def _note_used(spec: RecognizerTraining, folder: Path, record: dict[str, Any]) -> None:
    if (used := _USED.get()) is not None:
        used.append({"name": spec.name, "cache_key": folder.name, "held_out_accuracy": record["held_out"]["accuracy"],
                     "held_out_clips": record["held_out"]["clips"]})


def trained_recognizer(spec: RecognizerTraining, *, cache_dir: str | Path | None = None,
                       data_root: str | None = None, progress: bool = True) -> tuple[Recognizer, dict[str, Any]]:
    """The evaluator ``spec`` and its ``recognizer.json`` record (spec, held-out accuracy), trained on
    first use and read from the cache afterwards. A second process asking for an evaluator that one is
    training waits for it, then reads it."""
    folder = cache_folder(spec, cache_dir, data_root)
    with folder_lock(folder, what="evaluator cache", wait=True) if is_primary() else contextlib.nullcontext():
        record = read_json(folder / "recognizer.json")
        if record is not None:
            skeleton = SKELETONS[record["skeleton"]]
            persons = record.get("persons", 1)  # records before several persons had one
            # shapes only: initialising the network eagerly took 10 s of a smoke run's silent start
            like = jax.eval_shape(lambda: _initial_state(spec, jax.random.key(0), skeleton, len(record["class_names"]),
                                                         persons))
            with Checkpointer(folder / CHECKPOINT_FOLDER) as ckpt:
                state = ckpt.restore(like)
            _note_used(spec, folder, record)
            return _recognizer(spec, skeleton, record["class_names"], state), record
        held_out_set = held_out_data(spec, data_root)  # before training: a dataset without one fails now
        print(f"[evaluator] training {spec.name} ({spec.loop.steps} steps) once; cached in {folder}", file=sys.stderr)
        recognizer = train_recognizer(spec, folder, data_root=data_root, progress=progress)
        held_out = evaluate_recognizer(recognizer, held_out_set, jax.random.key(spec.seed + 1),
                                       window=spec.window, count=spec.test_count)
        record = {"spec": cfglib.to_dict(spec), "class_names": list(recognizer.class_names),
                  "skeleton": recognizer.skeleton.name, "persons": held_out_set.persons, "held_out": held_out,
                  "machine": training_machine()}
        print(f"[evaluator] {spec.name}: held-out accuracy {100 * held_out['accuracy']:.1f}% on "
              f"{held_out['clips']} clips", file=sys.stderr)
        if is_primary():
            write_json(folder / "recognizer.json", record)  # written last: its presence marks the evaluator finished
        _note_used(spec, folder, record)
        return recognizer, record
