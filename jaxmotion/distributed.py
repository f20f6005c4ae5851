"""Data-parallel training and evaluation over devices and hosts, through JAX's SPMD runtime.

One mesh with one axis, ``data``, over the devices. Batches are split along their leading axis B across
it (:func:`shard_batch`); parameters and optimiser state are replicated on every device
(:func:`replicate`). A function jitted over such inputs runs as one program per device: XLA splits the
batch work and inserts the all-reduce of the gradients' batch sums, so a step computes the same numbers
as on one device, up to the order of float32 sums. Nothing else changes: the step function, the batch
function and the checkpoints are those of one device.

Several hosts (or several processes on one host): every process calls :func:`initialize_distributed`
before any other JAX call, builds the same deterministic global batch ``batch_fn(step)`` and keeps only
the rows of its own devices (:func:`shard_batch`); ``data_mesh()`` then spans the devices of every
process. The processes find each other through environment variables, read only when set:

* ``JAXMOTION_COORDINATOR``: ``host:port`` of process 0 (any free port),
* ``JAXMOTION_NUM_PROCESSES``: how many processes take part,
* ``JAXMOTION_PROCESS_ID``: this process's index, 0 .. N - 1,
* ``JAXMOTION_LOCAL_DEVICES`` (optional): comma-separated local device ids this process uses.

``JAXMOTION_DISTRIBUTED=auto`` instead lets ``jax.distributed.initialize()`` detect a cluster itself
(SLURM, Open MPI, Cloud TPU). On CPU the processes exchange data through gloo
(``jax_cpu_collectives_implementation``), which :func:`initialize_distributed` selects.

Only process 0 writes ``metrics.jsonl`` and prints progress; checkpoints are written by orbax, which
coordinates the processes itself (each writes its own shards; replicated arrays are written once), so
the run folder must be on a file system every process sees.
"""

from __future__ import annotations

import os
from typing import Any

import jax
import numpy as np
from jax.sharding import Mesh, NamedSharding, PartitionSpec

DATA_AXIS = "data"

ENV_COORDINATOR = "JAXMOTION_COORDINATOR"
ENV_NUM_PROCESSES = "JAXMOTION_NUM_PROCESSES"
ENV_PROCESS_ID = "JAXMOTION_PROCESS_ID"
ENV_LOCAL_DEVICES = "JAXMOTION_LOCAL_DEVICES"
ENV_DISTRIBUTED = "JAXMOTION_DISTRIBUTED"


def initialize_distributed(environ: dict[str, str] | None = None) -> bool:
    """Join a multi-process run when the environment says so (module docstring); True if it did.

    Call it first thing in an entry point, before any JAX computation. Without the variables it does
    nothing, so single-process runs are untouched.
    """
    env = os.environ if environ is None else environ
    auto = env.get(ENV_DISTRIBUTED, "").lower() == "auto"
    named = [name for name in (ENV_COORDINATOR, ENV_NUM_PROCESSES, ENV_PROCESS_ID) if env.get(name)]
    if not auto and not named:
        return False
    if jax.distributed.is_initialized():
        return True
    # CPU devices of different processes talk through gloo (JAX's CPU default has no cross-process
    # collectives); the setting concerns the CPU backend only, so GPU runs are unaffected.
    jax.config.update("jax_cpu_collectives_implementation", "gloo")
    if auto:
        jax.distributed.initialize()
        return True
    if len(named) != 3:
        missing = sorted({ENV_COORDINATOR, ENV_NUM_PROCESSES, ENV_PROCESS_ID} - set(named))
        raise ValueError(f"initialize_distributed: {', '.join(named)} set but {', '.join(missing)} missing; a "
                         f"multi-process run needs all three (or {ENV_DISTRIBUTED}=auto)")
    local = env.get(ENV_LOCAL_DEVICES)
    jax.distributed.initialize(
        coordinator_address=env[ENV_COORDINATOR],
        num_processes=int(env[ENV_NUM_PROCESSES]),
        process_id=int(env[ENV_PROCESS_ID]),
        local_device_ids=[int(i) for i in local.split(",")] if local else None,
    )
    return True


def data_mesh(devices: int | None = None) -> Mesh:
    """A 1-D mesh with axis ``data`` over the first ``devices`` devices (None: every device of every
    process). With several processes the mesh must span all of them (``devices`` None or the total)."""
    available = jax.devices()
    count = len(available) if devices is None else devices
    if not 1 <= count <= len(available):
        raise ValueError(f"data_mesh: asked for {devices} devices; {len(available)} are available "
                         f"({available[0].platform}); on CPU, XLA_FLAGS=--xla_force_host_platform_device_count=N "
                         f"makes N host devices")
    if jax.process_count() > 1 and count != len(available):
        raise ValueError(f"data_mesh: a {jax.process_count()}-process run uses all {len(available)} devices, "
                         f"got devices={devices}")
    return Mesh(np.asarray(available[:count]), (DATA_AXIS,))


def batch_sharding(mesh: Mesh) -> NamedSharding:
    """Leading axis split along ``data``, the rest whole."""
    return NamedSharding(mesh, PartitionSpec(DATA_AXIS))


def replicated(mesh: Mesh) -> NamedSharding:
    """The same whole array on every device of the mesh."""
    return NamedSharding(mesh, PartitionSpec())


def check_divisible(batch_size: int, mesh: Mesh, what: str = "batch size") -> None:
    """A ``ValueError`` naming both numbers unless ``batch_size`` splits evenly over the mesh."""
    devices = mesh.shape[DATA_AXIS]
    if batch_size % devices:
        raise ValueError(f"{what} {batch_size} is not divisible by the {devices} devices of the data mesh; "
                         f"use a multiple of {devices} or another device count (--devices)")


def shard_batch(batch: Any, mesh: Mesh) -> Any:
    """Place a batch (a pytree of arrays sharing a leading axis B) on ``mesh``, split along B.

    Every process passes the same global batch; each keeps the rows of its own devices. Raises a
    ``ValueError`` when B does not divide by the mesh's device count.
    """
    leaves = jax.tree.leaves(batch)
    if not leaves:
        return batch
    sizes = {np.shape(leaf)[0] if np.ndim(leaf) else None for leaf in leaves}
    if None in sizes or len(sizes) != 1:
        raise ValueError(f"shard_batch: every array of a batch needs the same leading axis B, got leading sizes "
                         f"{sorted(str(s) for s in sizes)}")
    check_divisible(sizes.pop(), mesh)
    sharding = batch_sharding(mesh)
    if jax.process_count() == 1:
        return jax.device_put(batch, sharding)
    return jax.tree.map(lambda leaf: _from_global(np.asarray(leaf), sharding), batch)


def replicate(tree: Any, mesh: Mesh) -> Any:
    """A copy of ``tree`` (a pytree of arrays, typed PRNG keys included) on every device of ``mesh``.

    With several processes every process must pass the same values (as the same seed and the same
    checkpoint give)."""
    sharding = replicated(mesh)
    if jax.process_count() == 1:
        return jax.device_put(tree, sharding)

    def put(leaf):
        if isinstance(leaf, jax.Array) and jax.dtypes.issubdtype(leaf.dtype, jax.dtypes.prng_key):
            data = _from_global(np.asarray(jax.random.key_data(leaf)), sharding)
            return jax.random.wrap_key_data(data, impl=jax.random.key_impl(leaf))
        return _from_global(np.asarray(leaf), sharding)

    return jax.tree.map(put, tree)


def _from_global(value: np.ndarray, sharding: NamedSharding) -> jax.Array:
    """A global array from the same host value on every process; each places only its devices' parts."""
    return jax.make_array_from_callback(value.shape, sharding, lambda index: value[index])


def is_primary() -> bool:
    """True in the process that writes logs and reports progress (process 0)."""
    return jax.process_index() == 0


def gather(array: Any) -> np.ndarray:
    """A (possibly sharded) array as one host array, on every process."""
    if jax.process_count() > 1 and isinstance(array, jax.Array) and not array.is_fully_addressable:
        from jax.experimental import multihost_utils

        return np.asarray(multihost_utils.process_allgather(array, tiled=True))
    return np.asarray(array)
