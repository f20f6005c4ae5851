"""Benchmark: embedded-dataset generation time per variant, and batches per second of the pipeline.

    python benchmarks/bench_data.py [--variants synth-humanact12,synth-uestc] [--batches 200]

Generation is timed from scratch (no cache), once per split. The pipeline is timed after a warm-up
call (which compiles), with ``block_until_ready``, for ACTOR's batch (20 x 60 frames, canonical frame),
ODMO's class-balanced batch (512 x 60 frames) and ActFormer's (64 x 60 frames, snake padding; on datasets
of several persons 64 x P x 60 with the persons' order shuffled, on BABEL square-root class sampling).
Prints markdown tables.
"""

from __future__ import annotations

import argparse
import os
import platform
import sys
import time
from pathlib import Path

import jax

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # runnable from a checkout without installing

from jaxmotion.data import synthetic  # noqa: E402
from jaxmotion.data.pipeline import BatchSpec, make_batch_fn  # noqa: E402

PIPELINES = {
    "ACTOR 20x60 canonical": BatchSpec(batch_size=20, window=60),
    "ACTOR 20x100 variable 60-100": BatchSpec(batch_size=20, window=100, min_length=60),
    "ODMO 512x60 balanced": BatchSpec(batch_size=512, window=60, sampling="balanced", canonical=False),
    "ActFormer 64x60 snake": BatchSpec(batch_size=64, window=60, padding="snake"),
}
ACTFORMER_PERSONS = BatchSpec(batch_size=64, window=60, padding="snake", permute_persons=True)
ACTFORMER_BABEL = BatchSpec(batch_size=64, window=60, padding="snake", sampling="sqrt")


def pipelines(data) -> dict[str, BatchSpec]:
    """The batches timed on ``data``: ActFormer's multi-person batch alone on datasets of several persons."""
    if data.persons > 1:
        return {f"ActFormer 64x{data.persons}x60 snake, persons permuted": ACTFORMER_PERSONS}
    if "babel" in data.name:
        return {**PIPELINES, "ActFormer 64x60 snake, sqrt classes": ACTFORMER_BABEL}
    return PIPELINES


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--variants", default=",".join(sorted(synthetic.VARIANTS)))
    parser.add_argument("--batches", type=int, default=200, help="batches timed per pipeline")
    args = parser.parse_args()
    print(f"jax {jax.__version__}, devices {jax.devices()}; {os.cpu_count()} logical cores; "
          f"Python {platform.python_version()}\n")

    generation, throughput = [], []
    for name in args.variants.split(","):
        for split in synthetic.VARIANTS[name].splits:
            tick = time.perf_counter()
            data = synthetic.generate(name, split)
            seconds = time.perf_counter() - tick
            mb = sum(a.nbytes for a in (data.joints, data.translation, data.rotations) if a is not None) / 2**20
            generation.append(f"| {name} | {split} | {len(data):,} | {data.joints.shape[0]:,} | {mb:.0f} | "
                              f"{seconds:.1f} |")
        for label, spec in pipelines(data).items():
            if spec.batch_size > len(data) and spec.sampling == "epoch":
                continue
            batch_fn = make_batch_fn(data, jax.random.key(0), spec)
            tick = time.perf_counter()
            jax.block_until_ready(batch_fn(0))
            compile_s = time.perf_counter() - tick
            tick = time.perf_counter()
            for step in range(1, args.batches + 1):
                out = batch_fn(step)
            jax.block_until_ready(out)
            per_s = args.batches / (time.perf_counter() - tick)
            throughput.append(f"| {name} ({split}) | {label} | {per_s:.0f} | {per_s * spec.batch_size:,.0f} | "
                              f"{compile_s:.2f} |")

    print("| variant | split | sequences | frames | MB (float32) | generation s |")
    print("|---|---|---:|---:|---:|---:|")
    print("\n".join(generation))
    print()
    print("| dataset | batch | batches/s | sequences/s | first call (compile) s |")
    print("|---|---|---:|---:|---:|")
    print("\n".join(throughput))


if __name__ == "__main__":
    main()
