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
* ``JAXMOTION_LOCAL_DEVICES`` (optional): comma-separated local device ids this process uses,
* ``JAXMOTION_INIT_TIMEOUT`` (optional, default 60): seconds every process waits for all of them to join.

``JAXMOTION_DISTRIBUTED=auto`` instead lets ``jax.distributed.initialize()`` detect a cluster itself
(SLURM, Open MPI, Cloud TPU). On CPU the processes exchange data through gloo
(``jax_cpu_collectives_implementation``), which :func:`initialize_distributed` selects.

Start-up fails fast: the values are checked before anything starts (a ``ValueError`` naming the variable),
and a process that is not joined by all the others within ``JAXMOTION_INIT_TIMEOUT`` seconds exits with
status 1 and one line saying which variable to check: ``JAXMOTION_COORDINATOR`` when nothing answers at
that address, else ``JAXMOTION_NUM_PROCESSES`` and ``JAXMOTION_PROCESS_ID``. (XLA's own deadline, set 30 s
later, would abort the process with a C++ stack that blames another task.) Two processes with the same id
make XLA abort at once; the line each process prints before joining names the variables.

Only process 0 writes ``metrics.jsonl`` and prints progress; checkpoints are written by orbax, which
coordinates the processes itself (each writes its own shards; replicated arrays are written once), so
the run folder must be on a file system every process sees.
"""

from __future__ import annotations

import functools
import os
import socket
import sys
import threading
from collections.abc import Callable
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
ENV_INIT_TIMEOUT = "JAXMOTION_INIT_TIMEOUT"
DEFAULT_INIT_TIMEOUT_S = 60.0
# XLA aborts (a C++ check failure, not an exception) at its own deadline: ours comes first, with a message.
_XLA_GRACE_S = 30


def initialize_distributed(environ: dict[str, str] | None = None) -> bool:
    """Join a multi-process run when the environment says so (module docstring); True if it did.

    Call it first thing in an entry point, before any JAX computation. Without the variables it does
    nothing, so single-process runs are untouched. A value that cannot be right is a ``ValueError`` naming
    its variable; a run not joined within the timeout ends the process (module docstring).
    """
    env = os.environ if environ is None else environ
    auto = env.get(ENV_DISTRIBUTED, "").lower() == "auto"
    named = [name for name in (ENV_COORDINATOR, ENV_NUM_PROCESSES, ENV_PROCESS_ID) if env.get(name)]
    if not auto and not named:
        return False
    if jax.distributed.is_initialized():
        return True
    timeout = _number(env, ENV_INIT_TIMEOUT, float, DEFAULT_INIT_TIMEOUT_S)
    if auto:
        arguments, who, target = {}, f"{ENV_DISTRIBUTED}=auto: this process", "the cluster it detects"
        reason = functools.partial(str, f"the cluster's processes did not all join within {timeout:g} s "
                                        f"({ENV_INIT_TIMEOUT}); check that every task of the job started and that "
                                        "the cluster is one jax.distributed detects")
    else:
        if len(named) != 3:
            missing = sorted({ENV_COORDINATOR, ENV_NUM_PROCESSES, ENV_PROCESS_ID} - set(named))
            raise ValueError(f"initialize_distributed: {', '.join(named)} set but {', '.join(missing)} missing; a "
                             f"multi-process run needs all three (or {ENV_DISTRIBUTED}=auto)")
        coordinator = _coordinator(env[ENV_COORDINATOR])
        count = _number(env, ENV_NUM_PROCESSES, int)
        if count < 1:
            raise ValueError(f"{ENV_NUM_PROCESSES}: expected 1 or more processes, got {count}")
        index = _number(env, ENV_PROCESS_ID, int)
        if not 0 <= index < count:
            raise ValueError(f"{ENV_PROCESS_ID}: expected 0 to {count - 1} ({ENV_NUM_PROCESSES} is {count}), got "
                             f"{index}")
        arguments = dict(coordinator_address=coordinator, num_processes=count, process_id=index,
                         local_device_ids=_local_devices(env.get(ENV_LOCAL_DEVICES)))
        who, target = f"process {index} of {count}", f"the coordinator at {coordinator}"
        reason = functools.partial(_unjoined, coordinator, count, index, timeout)
    # CPU devices of different processes talk through gloo (JAX's CPU default has no cross-process
    # collectives); the setting concerns the CPU backend only, so GPU runs are unaffected.
    jax.config.update("jax_cpu_collectives_implementation", "gloo")
    print(f"[distributed] {who} joining {target} (timeout {timeout:g} s)", file=sys.stderr, flush=True)
    watchdog = threading.Timer(timeout, _give_up, args=(who, reason))
    watchdog.daemon = True
    watchdog.start()
    try:
        jax.distributed.initialize(**arguments, initialization_timeout=int(timeout) + _XLA_GRACE_S)
    finally:
        watchdog.cancel()
    return True


def _give_up(who: str, reason: Callable[[], str]) -> None:
    """The watchdog's end of a start-up that hangs in XLA (which holds no Python frame to raise into)."""
    print(f"initialize_distributed: {who}: {reason()}", file=sys.stderr, flush=True)
    os._exit(1)


def _unjoined(coordinator: str, count: int, index: int, timeout: float) -> str:
    """Why the processes did not all join: nothing at the coordinator's address, or a count or an id."""
    host, port = coordinator.rsplit(":", 1)
    if index != 0:  # process 0 serves the address itself
        try:
            socket.create_connection((host.strip("[]"), int(port)), timeout=2).close()
        except OSError as err:
            return (f"nothing answers at {ENV_COORDINATOR}={coordinator} after {timeout:g} s ({err}); check that "
                    "process 0 is running and that this is its host and a port this machine can reach")
    return (f"not all {count} processes joined the coordinator at {coordinator} within {timeout:g} s "
            f"({ENV_INIT_TIMEOUT}); check {ENV_NUM_PROCESSES} (the same in every process, and that many started) "
            f"and {ENV_PROCESS_ID} (each of 0 .. {count - 1} exactly once)")


def _number(env, name: str, kind: type, default=None):
    """``env[name]`` as ``kind`` (positive where a float: a timeout), ``default`` when unset or empty."""
    raw = env.get(name, "")
    if not raw.strip():
        return default
    try:
        value = kind(raw)
    except ValueError:
        raise ValueError(f"{name}: expected {'an integer' if kind is int else 'a number of seconds'}, got {raw!r}") \
            from None
    if kind is float and not 0 < value < float("inf"):
        raise ValueError(f"{name}: expected a positive number of seconds, got {raw!r}")
    return value


def _coordinator(raw: str) -> str:
    """``host:port`` with a port in 1 .. 65535, else a ``ValueError`` naming the variable."""
    host, _, port = raw.strip().rpartition(":")
    if not host or not port.isdigit() or not 1 <= int(port) <= 65535:
        raise ValueError(f"{ENV_COORDINATOR}: expected host:port of process 0 (a port in 1 .. 65535), got {raw!r}")
    return f"{host}:{int(port)}"


def _local_devices(raw: str | None) -> list[int] | None:
    """Comma-separated device ids ``>= 0``, each once; None when unset."""
    if not raw:
        return None
    items = [item.strip() for item in raw.split(",")]
    if not all(item.isdigit() for item in items) or len(set(items)) != len(items):
        raise ValueError(f"{ENV_LOCAL_DEVICES}: expected comma-separated device ids (integers >= 0, each once), "
                         f"got {raw!r}")
    return [int(item) for item in items]


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
