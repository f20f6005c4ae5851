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


WARMUP = 2  # rounds of warm-up calls before timing (see time_alternately)


def time_alternately(calls, repeats: int, warmup: int = WARMUP) -> list[dict]:
    """Each of ``calls`` (blocking) ``warmup`` times in turn, then all in turn ``repeats`` times, so background
    load hits them alike: ms stats per call, in order. Two warm-up rounds: after compilation, a jitted call's
    second run can still be several times slower than the ones after it (MARIONET's training step: 8.9 s, then
    3.5 s), as memory for its buffers is first touched."""
    for _ in range(warmup):
        for call in calls:
            call()
    times = [[] for _ in calls]
    for _ in range(repeats):
        for call, record in zip(calls, times):
            tick = time.perf_counter()
            call()
            record.append(1e3 * (time.perf_counter() - tick))
    return [_stats(record) for record in times]


def time_pair(ours, theirs, repeats: int) -> tuple[dict, dict | None]:
    """Each call (``ours`` blocks) twice to warm up, then both alternately ``repeats`` times: ms stats."""
    if theirs is None:
        return time_alternately([ours], repeats)[0], None
    return tuple(time_alternately([ours, theirs], repeats))


def as_loop_runs(step_fn):
    """A library step ``(state, batch, key)`` wrapped as ``jaxmotion.train.loop.train`` runs it: the step's key
    is ``fold_in(loop key, state.step)``."""
    return lambda state, batch, loop_key: step_fn(state, batch, jax.random.fold_in(loop_key, state.step))


def time_loop_step(step_fn, state, batch, loop_key, theirs, repeats: int) -> dict:
    """Time ``step_fn`` (:func:`as_loop_runs`' wrapper applied) jitted with the state donated, as the loop runs
    it, against ``theirs`` (or None): ``{"median", "min", "max", "peer", "compile_s"}`` in ms / s."""
    jitted = jax.jit(as_loop_runs(step_fn), donate_argnums=0)
    tick = time.perf_counter()
    compiled = jitted.lower(state, batch, loop_key).compile()
    compile_s = time.perf_counter() - tick
    first = int(state.step)  # read before the first call donates the state
    holder = [state]

    def ours():
        holder[0], metrics = compiled(holder[0], batch, loop_key)
        jax.block_until_ready((holder[0], metrics))

    result, peer_result = time_pair(ours, theirs, repeats)
    if int(holder[0].step) != first + repeats + WARMUP:  # warm-up + repeats steps, none skipped
        raise AssertionError(f"step count {int(holder[0].step)} after {repeats + WARMUP} steps")
    return {**result, "peer": peer_result, "compile_s": compile_s}


def print_table(rows) -> None:
    """The side-by-side table: rows ``(name, result, target)``, a result as :func:`time_pair` gives it."""
    print("| call | jaxmotion median ms | min-max ms | compile s | PyTorch median ms | min-max ms | speed-up "
          "| target | met |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|---|")
    for name, r, target in rows:
        p = r["peer"]
        speedup = None if p is None else p["median"] / r["median"]
        cells = [name, f"{r['median']:.1f}", f"{r['min']:.1f}-{r['max']:.1f}", f"{r['compile_s']:.1f}",
                 "-" if p is None else f"{p['median']:.1f}", "-" if p is None else f"{p['min']:.1f}-{p['max']:.1f}",
                 "-" if p is None else f"{speedup:.2f}x", f"{target:g}x",
                 "-" if p is None else ("yes" if speedup >= target else "no")]
        print("| " + " | ".join(cells) + " |")
    print()
