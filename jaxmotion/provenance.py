"""What a run was made with, for its record: the software and machine, the datasets and the evaluators.

* :func:`environment`: jaxmotion's version and git commit (when run from a checkout), Python, jax and jaxlib
  versions, the platform and device kind, the device and process counts, the CPU model and the usable CPU cores.
  The same on every run on one machine, so it may go into ``metrics.json``.
* :func:`session`: when a run started, how long it took and its peak memory; different on every run, so it goes
  into ``run.json`` beside ``metrics.json``, never into it.
* :func:`inputs`: every dataset and evaluator a config names (found by walking it: each
  :class:`~jaxmotion.evaluation.tables.TableData` and
  :class:`~jaxmotion.evaluation.recognizers.RecognizerTraining`), each with what identifies its content: an
  embedded dataset's generator version and cache file, a real dataset's resolved folder and a manifest of
  its files, an evaluator's cache key. A folder whose inputs differ from the ones it was made with is not
  resumed.

The evaluators a run used, with their held-out accuracy, are recorded as the run asks for them
(:func:`~jaxmotion.evaluation.recognizers.recording_evaluators`), not looked up in the cache afterwards.
"""

from __future__ import annotations

import dataclasses
import datetime
import functools
import importlib.metadata
import json
import platform
import resource
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import jax

from jaxmotion.data import synthetic
from jaxmotion.evaluation.recognizers import RecognizerTraining, cache_folder, data_source, usable_cpus
from jaxmotion.evaluation.tables import TableData

#: The file beside ``metrics.json`` that records the session that finished a seed (:func:`session`): it differs
#: on every run, so it is kept out of ``metrics.json``, which is the same bytes for the same seed and machine.
SESSION_FILE = "run.json"


@functools.lru_cache(maxsize=1)
def _git_commit() -> str | None:
    """The checkout's commit (with ``-dirty`` when it has uncommitted changes), or None outside a checkout."""
    root = Path(__file__).resolve().parent.parent
    try:
        commit = subprocess.run(["git", "rev-parse", "HEAD"], cwd=root, capture_output=True, text=True, timeout=10,
                                check=True).stdout.strip()
        dirty = subprocess.run(["git", "status", "--porcelain", "--untracked-files=no"], cwd=root,
                               capture_output=True, text=True, timeout=10, check=True).stdout.strip()
    except (OSError, subprocess.SubprocessError):
        return None
    return f"{commit}-dirty" if dirty else commit


def _version(package: str) -> str | None:
    try:
        return importlib.metadata.version(package)
    except importlib.metadata.PackageNotFoundError:
        return None


@functools.lru_cache(maxsize=1)
def cpu_model() -> str:
    """The CPU's model name (``/proc/cpuinfo``'s first ``model name``, else :func:`platform.processor`), or
    ``"unknown"``."""
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            field, _, value = line.partition(":")
            if field.strip() == "model name" and value.strip():
                return value.strip()
    except OSError:
        pass
    return platform.processor() or "unknown"


def environment() -> dict[str, Any]:
    """The software and machine this process runs on."""
    return {
        "jaxmotion": _version("jaxmotion"),
        "git_commit": _git_commit(),
        "python": platform.python_version(),
        "jax": jax.__version__,
        "jaxlib": _version("jaxlib"),
        "platform": jax.default_backend(),
        "device_kind": jax.devices()[0].device_kind,
        "devices": jax.device_count(),
        "local_devices": jax.local_device_count(),
        "processes": jax.process_count(),
        "cpu_model": cpu_model(),
        "cpu_threads": usable_cpus(),  # XLA's CPU reductions split over them: another count rounds differently
    }


def utc_now() -> str:
    """The current time in UTC, ISO 8601 to the second (``2026-01-31T12:00:00+00:00``)."""
    return datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds")


def peak_rss_bytes() -> int:
    """The peak resident memory so far of this process or of its largest finished child process, in bytes."""
    scale = 1 if sys.platform == "darwin" else 1024  # ru_maxrss: bytes on macOS, kilobytes on Linux
    return scale * max(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss,
                       resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss)


def session(started: str, wall_seconds: float, resumed: bool) -> dict[str, Any]:
    """The record of one session of a run (``run.json``): its start (:func:`utc_now`), its wall time, whether
    it continued work an earlier session left, and the process's peak memory at its end."""
    return {"started": started, "wall_seconds": round(wall_seconds, 1), "resumed": resumed,
            "peak_rss_bytes": peak_rss_bytes()}


def _walk(value: Any) -> Iterator[Any]:
    """Every dataclass instance inside a config, depth first."""
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        yield value
        for field in dataclasses.fields(value):
            yield from _walk(getattr(value, field.name))
    elif isinstance(value, (tuple, list)):
        for item in value:
            yield from _walk(item)


def _dataset(name: str, split: str, seed: int, count: int | None, data_root: str | None) -> dict[str, Any]:
    entry: dict[str, Any] = {"name": name, "split": split, "count": count}
    if name in synthetic.VARIANTS:
        entry.update(seed=seed, generator_version=synthetic.GENERATOR_VERSION,
                     cache_file=None if count is not None else synthetic.cache_path(name, split, seed=seed).name)
    else:
        entry.update(data_source(name, data_root))  # the resolved folder and a manifest of its files
    return entry


def _evaluator_datasets(spec: RecognizerTraining, data_root: str | None) -> list[dict[str, Any]]:
    variant = synthetic.VARIANTS.get(spec.dataset)
    held_out = (("test", spec.data_seed) if variant is None or "test" in variant.splits
                else ("train", spec.test_data_seed))
    return [_dataset(spec.dataset, "train", spec.data_seed, spec.count, data_root),
            _dataset(spec.dataset, held_out[0], held_out[1], spec.count, data_root)]


def inputs(config: Any, data_root: str | None = None) -> dict[str, Any]:
    """The datasets and evaluators ``config`` names, each identified by what determines its content."""
    datasets, evaluators = [], []
    for item in _walk(config):
        if isinstance(item, TableData):
            splits = ("train", "test") if item.test_split else ("train",)
            datasets += [_dataset(item.name, split, item.seed, item.count, data_root) for split in splits]
        elif isinstance(item, RecognizerTraining):
            evaluators.append({"name": item.name, "cache_key": cache_folder(item, data_root=data_root).name})
            datasets += _evaluator_datasets(item, data_root)
    return {"datasets": _unique(datasets), "evaluators": _unique(evaluators)}


def _unique(entries: list[dict[str, Any]]) -> list[dict[str, Any]]:
    """Entries once each, in a stable order."""
    unique = {json.dumps(e, sort_keys=True): e for e in entries}
    return [unique[k] for k in sorted(unique)]
