"""Data-parallel scaling: ACTOR paper-size training steps per second on 1, 2 and 4 devices.

ACTOR at the paper's size (d 256, 8 + 8 layers, FF 1024, 4 heads, dropout 0.1), 60-frame clips, batch 20
(the paper's; it divides by 1, 2 and 4), SMPL-24 rot6d, the library's step (``jaxmotion.train.actor.actor_step``)
wrapped as :func:`jaxmotion.train.loop.train` wraps it on a data mesh: state and key replicated, the batch
split along B, outputs replicated. Each device count runs in its own process, started with
``XLA_FLAGS=--xla_force_host_platform_device_count=N`` (on a GPU host: the first N GPUs, no flag needed).

On CPU the N "devices" are N partitions of the same cores: the table shows what splitting a step and
all-reducing its gradients costs, not a speed-up from more hardware (on 2 cores a change either way is the
scheduling of the same work, e.g. two partitions keeping both cores busier than one device's threading).
Real speed-ups need N real devices (GPUs, or hosts).

    python benchmarks/bench_scaling.py [--devices 1,2,4] [--repeats 5]
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

BATCH, FRAMES, CLASSES = 20, 60, 12


def worker(devices: int, repeats: int) -> dict:
    import jax
    import jax.numpy as jnp
    import numpy as np

    from benchmarks.timing import median_ms
    from jaxmotion.geometry.skeletons import SMPL24
    from jaxmotion.models.actor import ActorConfig
    from jaxmotion.distributed import data_mesh, replicate, shard_batch
    from jaxmotion.train import LoopConfig
    from jaxmotion.train.actor import ActorTraining, actor_state, actor_step
    from jaxmotion.distributed import replicated

    mesh = data_mesh(devices)
    training = ActorTraining(model=ActorConfig(num_classes=CLASSES), loop=LoopConfig(steps=1), batch_size=BATCH)
    k_init, k_data, k_loop = jax.random.split(jax.random.key(0), 3)
    k_rot, k_trans, k_act = jax.random.split(k_data, 3)
    batch = {"rotations": 0.3 * jax.random.normal(k_rot, (BATCH, FRAMES, SMPL24.num_joints, 3)),
             "translation": jnp.cumsum(0.01 * jax.random.normal(k_trans, (BATCH, FRAMES, 3)), axis=1),
             "actions": jax.random.randint(k_act, (BATCH,), 0, CLASSES),
             "mask": jnp.ones((BATCH, FRAMES), bool)}
    state, key, batch = replicate(actor_state(training, k_init), mesh), replicate(k_loop, mesh), shard_batch(batch, mesh)
    step_fn = actor_step(training, SMPL24)

    def run_step(state, batch, loop_key):  # as the loop runs it
        return step_fn(state, batch, jax.random.fold_in(loop_key, state.step))

    tick = time.perf_counter()
    compiled = jax.jit(run_step, donate_argnums=0, out_shardings=replicated(mesh)).lower(state, batch, key).compile()
    compile_s = time.perf_counter() - tick

    def one():
        nonlocal state
        state, terms = compiled(state, batch, key)
        jax.block_until_ready((state, terms))

    one()  # warm-up
    ms = median_ms(one, budget_s=0.0, min_repeats=repeats, max_repeats=repeats)
    assert np.isfinite(float(jax.tree.leaves(state.params)[0].ravel()[0]))
    return {"devices": devices, "platform": jax.devices()[0].platform, "compile_s": compile_s, "step_ms": ms}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--devices", default="1,2,4")
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--worker", type=int, help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.worker is not None:
        print("RESULT " + json.dumps(worker(args.worker, args.repeats)))
        return

    from benchmarks.timing import machine_header

    rows = []
    for n in [int(x) for x in args.devices.split(",")]:
        flags = [f for f in os.environ.get("XLA_FLAGS", "").split() if "host_platform_device_count" not in f]
        env = {**os.environ, "XLA_FLAGS": " ".join([*flags, f"--xla_force_host_platform_device_count={n}"])}
        out = subprocess.run([sys.executable, __file__, "--worker", str(n), "--repeats", str(args.repeats)], env=env,
                             check=True, capture_output=True, text=True).stdout
        rows.append(json.loads(next(line for line in out.splitlines() if line.startswith("RESULT "))[7:]))
    print(machine_header())
    print(f"ACTOR paper size, batch {BATCH} x {FRAMES} frames, median of {args.repeats} steps after a warm-up")
    print("| devices | rows per device | compile (s) | step (ms) | steps/s | vs 1 device |")
    print("| ---: | ---: | ---: | ---: | ---: | ---: |")
    base = rows[0]["step_ms"]
    for row in rows:
        print(f"| {row['devices']} ({row['platform']}) | {BATCH // row['devices']} | {row['compile_s']:.1f} | "
              f"{row['step_ms']:.0f} | {1e3 / row['step_ms']:.2f} | {base / row['step_ms']:.2f}x |")


if __name__ == "__main__":
    main()
