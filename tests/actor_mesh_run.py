"""A smoke-size ACTOR training on a data mesh, run as a subprocess by the multi-device tests.

``python tests/actor_mesh_run.py --data DATA.pkl --out DIR --devices N[,M...] [--steps 20] [--step-sleep-s S]``
trains ACTOR (width 16, 1 layer, 2 heads, no dropout, AdamW 1e-3, batch 8, 20-frame windows) with the
library's loop on ``data_mesh(N)`` (0: every device; -1: no mesh), once per count given, checkpointing into
``DIR/devices-N`` and writing the final parameters there as ``params.npz`` (one process, one compilation
of the data and initialisation programs for all counts). The device count comes from ``XLA_FLAGS=--xla_force_host_platform_device_count``;
several processes join through ``JAXMOTION_COORDINATOR`` / ``JAXMOTION_NUM_PROCESSES`` /
``JAXMOTION_PROCESS_ID`` (:func:`jaxmotion.distributed.initialize_distributed`). ``DATA.pkl`` is a pickled
``MotionDataset`` (made once by the test, so no subprocess pays for generating it).
"""

from __future__ import annotations

import argparse
import pickle
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run as a script from any folder

from jaxmotion.distributed import initialize_distributed  # noqa: E402

initialize_distributed()  # before any computation; a no-op without the JAXMOTION_* variables

import jax  # noqa: E402
import numpy as np  # noqa: E402

from jaxmotion.data.pipeline import BatchSpec, make_batch_fn  # noqa: E402
from jaxmotion.models.actor import ActorConfig  # noqa: E402
from jaxmotion.distributed import data_mesh  # noqa: E402
from jaxmotion.train import LoopConfig, train  # noqa: E402
from jaxmotion.train.actor import ActorTraining, actor_state, actor_step  # noqa: E402

MODEL = dict(width=16, ff=32, layers=1, heads=2, dropout=0.0)
BATCH, WINDOW, LEARNING_RATE = 8, 20, 1e-3


def smoke_training(num_classes: int, num_joints: int, loop: LoopConfig) -> ActorTraining:
    """The smoke-size ACTOR training with ``loop``."""
    model = ActorConfig(num_classes=num_classes, num_joints=num_joints + 1, **MODEL)
    return ActorTraining(model, loop=loop, batch_size=BATCH, window=WINDOW, learning_rate=LEARNING_RATE)


def run(data, out: Path, devices: int | None, steps: int, step_sleep_s: float = 0.0, progress: bool = True):
    loop = LoopConfig(steps=steps, log_every=2, checkpoint_every=10, keep_checkpoints=10)
    training = smoke_training(data.num_classes, data.skeleton.num_joints, loop)
    k_init, k_data, k_train = jax.random.split(jax.random.key(0), 3)
    batches = make_batch_fn(data, k_data, BatchSpec(batch_size=BATCH, window=WINDOW))

    def batch_fn(step):
        time.sleep(step_sleep_s)
        return batches(step)

    mesh = None if devices == -1 else data_mesh(devices or None)
    init = jax.jit(lambda k: actor_state(training, k))(k_init)  # one program, not one per initialiser call
    state = train(init, actor_step(training, data.skeleton), batch_fn, key=k_train,
                  config=loop, workdir=out, mesh=mesh, progress=progress)
    leaves = {str(i): np.asarray(leaf) for i, leaf in enumerate(jax.tree.leaves(state.params))}
    if jax.process_index() == 0:
        np.savez(out / "params.npz", **leaves)
    return leaves


def main(argv=None):
    parser = argparse.ArgumentParser()
    parser.add_argument("--data", required=True)
    parser.add_argument("--out", required=True)
    parser.add_argument("--devices", default="0", help="comma-separated counts; 0: all devices; -1: no mesh")
    parser.add_argument("--steps", type=int, default=20)
    parser.add_argument("--step-sleep-s", type=float, default=0.0)
    args = parser.parse_args(argv)
    with open(args.data, "rb") as f:
        data = pickle.load(f)
    for devices in [int(n) for n in args.devices.split(",")]:
        run(data, Path(args.out) / f"devices-{devices}", devices, args.steps, args.step_sleep_s)


if __name__ == "__main__":
    main()


# --- for the tests that start this script ------------------------------------------------------------


def subprocess_env(host_devices: int | None, **extra: str) -> dict[str, str]:
    """The environment of a child run: ``host_devices`` CPU devices (None: XLA's default of one), the
    repository importable, this test session's compilation cache shared (children with the same XLA flags
    compile each program once between them), plus ``extra`` variables."""
    import os

    flags = [f for f in os.environ.get("XLA_FLAGS", "").split() if "xla_force_host_platform_device_count" not in f]
    if host_devices is not None:
        flags.append(f"--xla_force_host_platform_device_count={host_devices}")
    env = {**os.environ, "PYTHONPATH": str(Path(__file__).resolve().parents[1]), "XLA_FLAGS": " ".join(flags),
           "JAX_PLATFORMS": "cpu", **extra}
    cache = jax.config.jax_compilation_cache_dir
    if cache:
        min_time = jax.config.jax_persistent_cache_min_compile_time_secs
        env.update(JAX_COMPILATION_CACHE_DIR=cache, JAX_PERSISTENT_CACHE_MIN_COMPILE_TIME_SECS=str(min_time),
                   JAX_PERSISTENT_CACHE_MIN_ENTRY_SIZE_BYTES="0")
    return env


def load_params(folder: Path) -> list[np.ndarray]:
    with np.load(Path(folder) / "params.npz") as f:
        return [f[str(i)] for i in range(len(f.files))]


def free_port() -> int:
    import socket

    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]
