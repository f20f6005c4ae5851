"""Training-log writers: the training loop's records shown in other tools, beside ``metrics.jsonl``.

``metrics.jsonl`` stays the record (results and resume read it); a writer shows the same numbers elsewhere.
The loop (:func:`jaxmotion.train.loop.train`, ``writers=``) takes writer **factories**
``(folder, start_step) -> Writer``: each training run opens its own writers on its own folder (an experiment
trains many models, one folder each) once its log is truncated to ``start_step`` (0, or the checkpoint it
resumes from), hands them every record it appends to ``metrics.jsonl`` as ``write(step, scalars)``, and closes
them however training ends. The records of a resumed run's steps past ``start_step`` were also written by the
interrupted session: a writer must let them be replaced, not shown twice. Only the primary process opens writers,
and only in a run that has steps left to train.

Scalar names (:func:`record_scalars`), ours: a metrics record ``{"step": n, "loss": m}`` gives ``train/loss``;
an evaluation record ``{"step": n, "eval": {"fid": v}}`` gives ``eval/fid`` (TensorBoard groups by the prefix).

:class:`TensorBoard` writes TensorBoard event files through tensorboardX, an optional extra
(``pip install "jaxmotion[tensorboard]"``), imported only when a :class:`TensorBoard` is made.
"""

from __future__ import annotations

import dataclasses
import socket
import time
from collections.abc import Mapping, Sequence
from pathlib import Path
from types import MappingProxyType
from typing import Any, Protocol

#: Where :class:`TensorBoard` puts a training run's event files: ``<training folder>/tensorboard/``.
TENSORBOARD_FOLDER = "tensorboard"


class Writer(Protocol):
    """One training run's log in some tool: ``write`` gets each record's step and scalars, ``close`` ends it."""

    def write(self, step: int, scalars: Mapping[str, float]) -> None: ...

    def close(self) -> None: ...


class WriterFactory(Protocol):
    """Opens a :class:`Writer` for the training run in ``folder`` that starts (or resumes) at ``start_step``."""

    def __call__(self, folder: Path, start_step: int) -> Writer: ...


def record_scalars(record: Mapping[str, Any]) -> dict[str, float]:
    """A ``metrics.jsonl`` record's values under their scalar names (module docstring), its step left out."""
    if "eval" in record:
        return {f"eval/{name}": float(value) for name, value in record["eval"].items()}
    return {f"train/{name}": float(value) for name, value in record.items() if name != "step"}


def _tensorboardx():
    try:
        import tensorboardX
        from tensorboardX.proto import event_pb2, summary_pb2
    except ImportError as err:
        raise ImportError('TensorBoard logs need tensorboardX, an optional extra: pip install "jaxmotion[tensorboard]"'
                          ) from err
    return tensorboardX, event_pb2, summary_pb2


@dataclasses.dataclass(frozen=True)
class TensorBoard:
    """A :class:`WriterFactory`: TensorBoard event files in ``<folder>/tensorboard/``, so ``tensorboard --logdir
    results/<experiment>`` shows each training folder (each row of a table) as its own run.

    Each session writes a new event file whose first event marks ``start_step + 1`` as a restart: TensorBoard
    drops the steps from there on that earlier files hold (the steps an interrupted session did past its last
    checkpoint), and the resumed session writes them again. Every record is flushed to the file as it is written
    (tensorboardX's ``SummaryWriter`` queues events to a thread that ``flush()`` does not wait for, so a killed run
    could lose records of steps its checkpoint holds, which no later session writes again). Making one imports
    tensorboardX: an ImportError naming the extra if it is missing."""

    def __post_init__(self):
        _tensorboardx()

    def __call__(self, folder: Path, start_step: int) -> TensorBoardWriter:
        return TensorBoardWriter(Path(folder) / TENSORBOARD_FOLDER, start_step)


class TensorBoardWriter:
    """One session's event file in ``logdir`` (:class:`TensorBoard`)."""

    def __init__(self, logdir: Path, start_step: int):
        tensorboardx, self._event_pb2, self._summary_pb2 = _tensorboardx()
        logdir.mkdir(parents=True, exist_ok=True)
        # TensorBoard reads a folder's files in name order: the time first, as TensorFlow names them. Two sessions
        # of one start step in one second share a name; the later overwrites what the earlier wrote past that step,
        # which it purges anyway.
        name = f"events.out.tfevents.{int(time.time()):010d}.{socket.gethostname()}.{start_step}"
        self._file = tensorboardx.RecordWriter(str(logdir / name))
        self._event(file_version="brain.Event:2")
        session_log = self._event_pb2.SessionLog
        self._event(step=start_step + 1, session_log=session_log(status=session_log.START))
        self._file.flush()

    def _event(self, **fields) -> None:
        self._file.write(self._event_pb2.Event(wall_time=time.time(), **fields).SerializeToString())

    def write(self, step: int, scalars: Mapping[str, float]) -> None:
        values = [self._summary_pb2.Summary.Value(tag=name, simple_value=value) for name, value in scalars.items()]
        self._event(step=step, summary=self._summary_pb2.Summary(value=values))
        self._file.flush()

    def close(self) -> None:
        self._file.close()


#: The writers ``--log`` names (:func:`named_writers`): name -> factory class.
WRITERS = MappingProxyType({"tensorboard": TensorBoard})


def named_writers(names: Sequence[str]) -> tuple[WriterFactory, ...]:
    """The writer factories called ``names`` (keys of :data:`WRITERS`, each at most once), made now: a missing
    optional extra raises its ImportError here, before any training."""
    unknown = [name for name in names if name not in WRITERS]
    if unknown:
        raise ValueError(f"unknown writers {unknown}; expected names among: {', '.join(WRITERS)}")
    if len(set(names)) != len(names):
        raise ValueError(f"each writer at most once, got {list(names)}")
    return tuple(WRITERS[name]() for name in names)
