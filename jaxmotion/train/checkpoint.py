"""Orbax checkpoints of a training-state pytree, saved synchronously and restored from the latest step.

Saves are synchronous on purpose: a process killed right after ``save`` returns still leaves a complete
checkpoint, and orbax writes each step to a temporary folder that it renames only once complete, so a
kill during a save leaves the previous checkpoint as the latest one.

Restores take the shardings of the state they restore into: a state replicated on a data mesh
(:mod:`jaxmotion.train.mesh`) comes back replicated on that mesh, whatever mesh wrote it. With several
processes every process opens the same folder and calls ``save``/``restore`` together; orbax writes each
array once and synchronises the processes itself.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import jax
import orbax.checkpoint as ocp


class Checkpointer:
    """Keeps the last ``max_to_keep`` checkpoints of one run under ``directory``.

    ``read_only``: open another run's checkpoints (e.g. to initialise from them) without creating, deleting
    or writing anything there.
    """

    def __init__(self, directory: str | Path, *, max_to_keep: int = 2, read_only: bool = False):
        self.directory = Path(directory).absolute()
        options = ocp.CheckpointManagerOptions(
            max_to_keep=max_to_keep, enable_async_checkpointing=False, create=not read_only, read_only=read_only
        )
        self._manager = ocp.CheckpointManager(self.directory, options=options)

    def latest_step(self) -> int | None:
        return self._manager.latest_step()

    def save(self, step: int, state: Any) -> None:
        self._manager.save(step, args=ocp.args.StandardSave(state))
        self._manager.wait_until_finished()

    def restore(self, like: Any = None, step: int | None = None) -> Any:
        """Restore ``step`` (default: latest) into the structure, shapes, dtypes and shardings of ``like``.

        Without ``like`` the checkpoint comes back as nested dicts and lists of arrays (for inspection).
        """
        step = self.latest_step() if step is None else step
        if step is None:
            raise FileNotFoundError(f"no checkpoint under {self.directory}")
        abstract = None if like is None else jax.tree.map(ocp.utils.to_shape_dtype_struct, like)
        return self._manager.restore(step, args=ocp.args.StandardRestore(abstract))

    def close(self) -> None:
        self._manager.close()

    def __enter__(self) -> "Checkpointer":
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()
