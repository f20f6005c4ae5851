"""Trained generators as artefacts: what generation needs, written beside a run's checkpoints and read back
without the training data, the optimiser state or the experiment that made it.

A generator folder holds two files:

* ``generator.json``: the method (``"actor"``, ``"a2m"``, ``"odmo"``, ``"actformer"``), the model config as data
  with its importable type (``"jaxmotion.models.actor.ActorConfig"``), the skeleton (name, joints, parents, rest
  offsets), the class names and frame rate of the data it learnt, and the method's scalar settings;
* ``arrays.npz``: every array generation reads (parameters, non-trained state such as BatchNorm statistics or
  spectral-norm vectors, derived arrays such as ODMO's code bank or ActFormer's mean bone lengths), one entry per
  pytree leaf under its path (``params/encoder/layers/0/w``).

Both are written atomically (a temporary file renamed), ``arrays.npz`` first: a folder whose ``generator.json``
parses is complete. Reading rebuilds each pytree on a template the method makes from its config
(``jax.eval_shape`` of its initialiser), so a file of another architecture is refused with the first path that
does not fit.

Every method's generator (:class:`Generator`) has ``generate(key, actions, durations)`` returning a
:class:`~jaxmotion.data.motion.MotionDataset` placed on the floor (:func:`~jaxmotion.data.motion.on_the_floor`), ``sampler()`` (the
evaluation protocol's sampler, the motions as the method writes them) and ``save(folder)``;
:func:`jaxmotion.pipelines.load.load_generator` opens any of them.
"""

from __future__ import annotations

import dataclasses
import importlib
import io
import json
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any, Protocol

import jax
import jax.numpy as jnp
import numpy as np

from jaxmotion import config as cfglib
from jaxmotion.data.motion import SKELETONS, MotionDataset, on_the_floor, to_dataset
from jaxmotion.files import write_atomic, write_json
from jaxmotion.geometry.skeletons import Skeleton

RECORD = "generator.json"
ARRAYS = "arrays.npz"
FORMAT = 1  # the layout of the two files; bump it when it changes

Sampler = Any  # (key, actions [N], durations [N]) -> motions (jaxmotion.evaluation.protocol.Sampler)


class Generator(Protocol):
    """A trained generator of one method (see the module docstring)."""

    method: str
    skeleton: Skeleton
    class_names: tuple[str, ...]
    fps: float

    def generate(self, key: jax.Array | int, actions: Sequence[int], durations: Sequence[int] | None = None
                 ) -> MotionDataset: ...

    def sampler(self) -> Sampler: ...

    def save(self, folder: str | Path) -> Path: ...


class SamplingGenerator:
    """What every method's generator shares: the data facts' views and :meth:`generate` through the method's
    protocol sampler. A subclass is a frozen dataclass with the fields ``facts`` and ``frames`` (the default
    duration) and defines ``sampler()``, ``save(folder)`` and ``load(artefact)``."""

    facts: DataFacts
    frames: int

    @property
    def skeleton(self) -> Skeleton:
        return self.facts.skeleton

    @property
    def class_names(self) -> tuple[str, ...]:
        return self.facts.class_names

    @property
    def fps(self) -> float:
        return self.facts.fps

    def generate(self, key: jax.Array | int, actions: Sequence[int], durations: Sequence[int] | None = None
                 ) -> MotionDataset:
        """One motion per ``actions[n]`` (``durations[n]`` frames, default :attr:`frames`), row n drawn from
        ``fold_in(key, n)``, as the library's motion record placed on the floor. ``key``:
        a jax.random key or an int seed."""
        actions = np.asarray(actions, np.int32).reshape(-1)
        if actions.size == 0:
            raise ValueError("actions: expected at least one class id, got none")
        durations = (np.full(actions.shape, self.frames, np.int32) if durations is None
                     else np.asarray(durations, np.int32).reshape(-1))
        motions = self.sampler()(as_key(key), actions, durations)
        return motion_records(motions, self.facts, self.method)


class ParamsGenerator(SamplingGenerator):
    """A generator that is its model config and parameters (ACTOR, Action2Motion): a subclass is a frozen dataclass
    with the fields ``model``, ``params``, ``facts`` and ``frames``, sets ``method`` and ``init`` (the model's
    ``init(key, config) -> params``, whose shapes rebuild the saved parameters) and defines ``sampler()``."""

    model: Any
    params: Any
    init: Any  # staticmethod(init(key, config) -> params)

    def save(self, folder: str | Path) -> Path:
        return save_artefact(folder, self.method, self.model, self.facts, {"params": self.params},
                             {"frames": self.frames})

    @classmethod
    def load(cls, artefact: Artefact) -> ParamsGenerator:
        template = jax.eval_shape(lambda k: cls.init(k, artefact.model), jax.random.key(0))
        return cls(artefact.model, artefact.tree("params", template), artefact.facts, artefact.settings["frames"])


class ArtefactError(ValueError):
    """A generator folder that is missing, incomplete or of another architecture."""


@dataclasses.dataclass(frozen=True)
class DataFacts:
    """What a generator knows of the data it learnt: the skeleton its motions use, the class names its action
    ids index and the frame rate."""

    skeleton: Skeleton
    class_names: tuple[str, ...]
    fps: float

    @classmethod
    def of(cls, data: MotionDataset) -> DataFacts:
        return cls(data.skeleton, tuple(data.class_names), float(data.fps))


def as_key(key: jax.Array | int, where: str = "key") -> jax.Array:
    """A typed PRNG key from a key (typed or raw ``uint32[2]``) or an int seed."""
    if isinstance(key, (int, np.integer)) and not isinstance(key, bool):
        if not 0 <= int(key) < 2**32:
            raise ValueError(f"{where}: expected a seed from 0 to 2**32 - 1 or a jax.random key, got {key}")
        return jax.random.key(int(key))
    if isinstance(key, jax.Array) and jnp.issubdtype(key.dtype, jax.dtypes.prng_key) and key.shape == ():
        return key
    if isinstance(key, (jax.Array, np.ndarray)) and key.dtype == np.uint32 and key.shape == (2,):
        return jax.random.wrap_key_data(jnp.asarray(key))
    raise ValueError(f"{where}: expected an int seed or one jax.random key, got {type(key).__name__} "
                     f"{getattr(key, 'shape', '')}")


def motion_records(motions: Mapping[str, Any], facts: DataFacts, method: str) -> MotionDataset:
    """A sampler's batch dict as the library's motion record, placed on the floor
    (:func:`~jaxmotion.data.motion.on_the_floor`)."""
    return on_the_floor(to_dataset(motions, facts.skeleton, facts.class_names, facts.fps, name=method,
                                   split="generated"))


# --- writing -------------------------------------------------------------------------------------------


def save_artefact(folder: str | Path, method: str, model: Any, facts: DataFacts, trees: Mapping[str, Any],
                  settings: Mapping[str, Any] | None = None) -> Path:
    """Write a generator folder: ``model`` (a config dataclass), the data ``facts``, the pytrees ``trees`` (name
    -> pytree of arrays) and JSON ``settings``; returns the folder."""
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    flat = {}
    for name, tree in trees.items():
        flat.update(_flatten(tree, name))
    buffer = io.BytesIO()
    np.savez(buffer, **flat)
    write_atomic(folder / ARRAYS, buffer.getvalue())
    record = {"format": FORMAT, "method": method,
              "model": {"type": f"{type(model).__module__}.{type(model).__qualname__}", "config": cfglib.to_dict(model)},
              "skeleton": _skeleton_record(facts.skeleton), "class_names": list(facts.class_names), "fps": facts.fps,
              "settings": dict(settings or {})}
    write_json(folder / RECORD, record)  # last: its presence marks the folder complete
    return folder


def _flatten(tree: Any, prefix: str) -> dict[str, np.ndarray]:
    leaves = jax.tree_util.tree_flatten_with_path(tree)[0]
    return {_path(prefix, path): np.asarray(leaf) for path, leaf in leaves}


def _path(prefix: str, path: tuple) -> str:
    parts = [prefix]
    for entry in path:
        for attr in ("name", "key", "idx"):
            if hasattr(entry, attr):
                parts.append(str(getattr(entry, attr)))
                break
    return "/".join(parts)


def _skeleton_record(skeleton: Skeleton) -> dict[str, Any]:
    return {"name": skeleton.name, "joint_names": list(skeleton.joint_names), "parents": list(skeleton.parents),
            "offsets": None if skeleton.offsets is None else np.asarray(skeleton.offsets).tolist()}


# --- reading -------------------------------------------------------------------------------------------


@dataclasses.dataclass(frozen=True)
class Artefact:
    """A generator folder read back: its record, model config, data facts and flat arrays."""

    folder: Path
    method: str
    model: Any
    facts: DataFacts
    settings: Mapping[str, Any]
    arrays: Mapping[str, np.ndarray]

    def tree(self, name: str, template: Any) -> Any:
        """The pytree ``name`` rebuilt on ``template``'s structure: leaves with a shape (arrays, shape-dtype structs)
        are checked against it and cast to its dtype; other leaves (``0``) take the stored array as it is."""
        leaves, treedef = jax.tree_util.tree_flatten_with_path(template)
        values = []
        for path, like in leaves:
            key = _path(name, path)
            if key not in self.arrays:
                raise ArtefactError(f"{self.folder / ARRAYS}: no array {key!r}; the file was written for another "
                                    f"architecture than {type(self.model).__name__}")
            value = self.arrays[key]
            if not hasattr(like, "shape"):  # a template of any size (a code bank, mixtures): take it as stored
                values.append(value)
                continue
            if value.shape != tuple(like.shape):
                raise ArtefactError(f"{self.folder / ARRAYS}: {key!r} has shape {value.shape}, the model expects "
                                    f"{tuple(like.shape)}")
            values.append(jnp.asarray(value, like.dtype))
        return jax.tree_util.tree_unflatten(treedef, values)

    def array(self, name: str) -> np.ndarray:
        if name not in self.arrays:
            raise ArtefactError(f"{self.folder / ARRAYS}: no array {name!r}")
        return self.arrays[name]


def read_artefact(folder: str | Path) -> Artefact:
    """Read a generator folder written by :func:`save_artefact`; errors name what is missing."""
    folder = Path(folder)
    record_path = folder / RECORD
    if not record_path.is_file():
        raise ArtefactError(f"{folder}: no {RECORD}; not a finished generator folder (a run writes it when its "
                            f"training ends)")
    try:
        record = json.loads(record_path.read_text())
    except (OSError, json.JSONDecodeError) as err:
        raise ArtefactError(f"{record_path}: unreadable ({err})") from None
    if record.get("format") != FORMAT:
        raise ArtefactError(f"{record_path}: format {record.get('format')!r}; this jaxmotion reads format {FORMAT}")
    if not (folder / ARRAYS).is_file():
        raise ArtefactError(f"{folder}: {RECORD} without {ARRAYS}; the folder is incomplete")
    with np.load(folder / ARRAYS) as npz:
        arrays = {name: npz[name] for name in npz.files}
    model = _config_from(record["model"], record_path)
    facts = DataFacts(_skeleton_from(record["skeleton"]), tuple(record["class_names"]), float(record["fps"]))
    return Artefact(folder, record["method"], model, facts, record.get("settings", {}), arrays)


def _config_from(model: Mapping[str, Any], where: Path) -> Any:
    module_name, _, name = model["type"].rpartition(".")
    if not module_name.startswith("jaxmotion."):
        raise ArtefactError(f"{where}: model type {model['type']!r} is not a jaxmotion config")
    try:
        cls = getattr(importlib.import_module(module_name), name)
    except (ImportError, AttributeError):
        raise ArtefactError(f"{where}: model type {model['type']!r} cannot be imported from this jaxmotion") from None
    return cfglib.from_dict(cls, model["config"])


def _skeleton_from(record: Mapping[str, Any]) -> Skeleton:
    """The library's skeleton of that name when the record matches it (so motions compare as that skeleton),
    else a skeleton built from the record."""
    offsets = None if record["offsets"] is None else np.asarray(record["offsets"], np.float32)
    known = SKELETONS.get(record["name"])
    if (known is not None and list(known.parents) == list(record["parents"])
            and (offsets is None) == (known.offsets is None)
            and (offsets is None or np.array_equal(np.asarray(known.offsets, np.float32), offsets))):
        return known
    return Skeleton(record["name"], tuple(record["joint_names"]), tuple(record["parents"]), offsets)
