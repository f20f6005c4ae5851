"""Timing helpers shared by the benchmark scripts."""

from __future__ import annotations

import os
import platform
import statistics
import time
from pathlib import Path

import jax
import numpy as np


def median_ms(fn, budget_s: float, min_repeats: int = 5, max_repeats: int = 500) -> float:
    """Median wall time of ``fn()`` in ms, repeating until ``budget_s`` is spent (within the repeat bounds)."""
    times: list[float] = []
    start = time.perf_counter()
    while len(times) < min_repeats or (len(times) < max_repeats and time.perf_counter() - start < budget_s):
        tick = time.perf_counter()
        fn()
        times.append(time.perf_counter() - tick)
    return 1e3 * statistics.median(times)


def cpu_model() -> str:
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown CPU"


def machine_header() -> str:
    """Two lines naming the software and the device, printed above every benchmark table."""
    return (f"jax {jax.__version__}, numpy {np.__version__}, devices {jax.devices()}\n"
            f"CPU: {cpu_model()}, {os.cpu_count()} logical cores; Python {platform.python_version()}")


def _stats(times: list[float]) -> dict:
    return {"median": statistics.median(times), "min": min(times), "max": max(times)}


def time_pair(ours, theirs, repeats: int) -> tuple[dict, dict | None]:
    """Each call (``ours`` blocks) once to warm up, then both alternately ``repeats`` times: ms stats."""
    ours()
    if theirs is not None:
        theirs()
    times_ours, times_theirs = [], []
    for _ in range(repeats):
        tick = time.perf_counter()
        ours()
        times_ours.append(1e3 * (time.perf_counter() - tick))
        if theirs is not None:
            tick = time.perf_counter()
            theirs()
            times_theirs.append(1e3 * (time.perf_counter() - tick))
    return _stats(times_ours), (_stats(times_theirs) if theirs is not None else None)
