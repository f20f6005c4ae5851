"""Orbax checkpoints of a training-state pytree, saved synchronously and restored from the latest step.

Saves are synchronous on purpose: a process killed right after ``save`` returns still leaves a complete
checkpoint, and orbax writes each step to a temporary folder that it renames only once complete, so a
kill during a save leaves the previous checkpoint as the latest one; opening the folder again deletes that
temporary folder. A checkpoint damaged afterwards (a file cut short by a full disk, a bad copy) is skipped
for the previous one, with a warning; when every one is damaged they are all set aside and the run starts over
(:meth:`Checkpointer.restore`, :class:`CheckpointsDamaged`).

Restores take the shardings of the state they restore into: a state replicated on a data mesh
(:mod:`jaxmotion.distributed`) comes back replicated on that mesh, whatever mesh wrote it. With several
processes every process opens the same folder and calls ``save``/``restore`` together; orbax writes each
array once and synchronises the processes itself.
"""

from __future__ import annotations

import shutil
import sys
import time
from pathlib import Path
from typing import Any

import jax
import numpy as np
import orbax.checkpoint as ocp

TMP_MARK = ".orbax-checkpoint-tmp"  # orbax writes a step to <step>.orbax-checkpoint-tmp-<n>, then renames it


class CheckpointsDamaged(FileNotFoundError):
    """No checkpoint of a folder can be read at all (damage, not a state that does not fit them); they were moved
    to ``<directory>-damaged/``, so the folder now holds none and a run starts over from step 0."""


class Checkpointer:
    """Keeps the last ``max_to_keep`` checkpoints of one run under ``directory``.

    ``read_only``: open another run's checkpoints (e.g. to initialise from them) without creating, deleting
    or writing anything there.
    """

    def __init__(self, directory: str | Path, *, max_to_keep: int = 2, read_only: bool = False):
        self.directory = Path(directory).absolute()
        self.read_only = read_only
        options = ocp.CheckpointManagerOptions(
            max_to_keep=max_to_keep, enable_async_checkpointing=False, create=not read_only, read_only=read_only
        )
        if not read_only and jax.process_index() == 0:
            self._remove_unfinished()
        self._manager = ocp.CheckpointManager(self.directory, options=options)

    def _remove_unfinished(self) -> None:
        """Delete the temporary folders of saves that a kill cut short (they are never restored)."""
        for path in sorted(self.directory.glob(f"*{TMP_MARK}*")):
            print(f"[checkpoint] removing {path}, left by a save that did not finish", file=sys.stderr)
            shutil.rmtree(path, ignore_errors=True)

    def latest_step(self) -> int | None:
        return self._manager.latest_step()

    def save(self, step: int, state: Any) -> None:
        self._manager.save(step, args=ocp.args.StandardSave(state))
        self._manager.wait_until_finished()

    def restore(self, like: Any = None, step: int | None = None) -> Any:
        """Restore ``step`` (default: the latest readable one) into the structure, shapes, dtypes and
        shardings of ``like``.

        Without ``like`` the checkpoint comes back as nested dicts and lists of arrays (for inspection).
        When the latest checkpoint cannot be read (a file cut short or damaged) but an earlier one can, the
        earlier one is restored, with a warning, and the damaged one is moved to ``<directory>-damaged/``
        (kept for inspection; a later save of its step must not find it). When none can be read:
        if they cannot be read even without ``like`` (damage), they all move there, with a warning, and
        :class:`CheckpointsDamaged` says the folder holds none now; if they can (the state does not fit them:
        another model or optimiser), the error says so and what to delete, and nothing moves.
        """
        abstract = None if like is None else jax.tree.map(ocp.utils.to_shape_dtype_struct, like)
        if step is not None:
            return self._restore(step, abstract)
        steps = sorted(self._manager.all_steps(), reverse=True)
        if not steps:
            raise FileNotFoundError(f"no checkpoint under {self.directory}")
        errors = []
        for candidate in steps:
            try:
                state = self._manager.restore(candidate, args=ocp.args.StandardRestore(abstract))
            except Exception as error:  # orbax and tensorstore raise many types for unreadable files
                errors.append((candidate, error))
                continue
            if errors:
                moved = not self.read_only and jax.process_index() == 0
                if moved:
                    self._set_aside([s for s, _ in errors])
                print(f"warning: the checkpoint(s) at step {', '.join(str(s) for s, _ in errors)} in "
                      f"{self.directory} could not be read ({_first_line(errors[0][1])}); restored step "
                      f"{candidate} instead" + (f" and moved the damaged ones to {self._damaged}" if moved else ""),
                      file=sys.stderr)
            return state
        # the first checkpoint that can be read as it was saved (no state to fit; without one, the loop just tried
        # that): none means damage
        readable = None if abstract is None else next(
            ((s, raw) for s in steps if (raw := self._read_as_saved(s)) is not None), None)
        if readable is None:
            if self.read_only or abstract is None:  # another run's (init_from), or an inspection: nothing moves
                raise ValueError(f"every checkpoint in {self.directory} is damaged (the latest, step {steps[0]}: "
                                 f"{_first_line(errors[0][1])})") from errors[0][1]
            if jax.process_index() == 0:  # every process starts over; the first moves the files
                self._set_aside(steps)
                print(f"warning: every checkpoint in {self.directory} is damaged (the latest, step {steps[0]}: "
                      f"{_first_line(errors[0][1])}); moved them to {self._damaged} and starting over from step 0",
                      file=sys.stderr)
            raise CheckpointsDamaged(f"every checkpoint in {self.directory} was damaged and set aside")
        step, saved = readable
        raise ValueError(f"no checkpoint in {self.directory} could be restored into this state; the latest (step "
                         f"{step}) differs: {_difference(saved, like) or _first_line(errors[0][1])}. They can be "
                         f"read, so they hold another state (another model, optimiser or config); delete "
                         f"{self.directory} to train this one from the start") from errors[0][1]

    def _read_as_saved(self, step: int) -> Any:
        """The checkpoint of ``step`` read as it was saved (with no state to fit), or None when it cannot be."""
        try:
            return self._manager.restore(step, args=ocp.args.StandardRestore(None))
        except Exception:  # noqa: BLE001 (orbax and tensorstore raise many types for unreadable files)
            return None

    def _restore(self, step: int, abstract: Any) -> Any:
        if step not in self._manager.all_steps():
            raise FileNotFoundError(f"no checkpoint of step {step} under {self.directory}")
        try:
            return self._manager.restore(step, args=ocp.args.StandardRestore(abstract))
        except Exception as error:
            raise ValueError(f"the checkpoint of step {step} in {self.directory} could not be restored: "
                             f"{_first_line(error)}") from error

    @property
    def _damaged(self) -> Path:
        return self.directory.with_name(self.directory.name + "-damaged")

    def _set_aside(self, steps: list[int]) -> None:
        self._damaged.mkdir(exist_ok=True)
        for step in steps:
            target = self._damaged / f"{step}-{time.strftime('%Y%m%d-%H%M%S')}"
            shutil.move(self.directory / str(step), target)
        self._manager.reload()

    def close(self) -> None:
        self._manager.close()

    def __enter__(self) -> "Checkpointer":
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


def _leaves(tree: Any) -> dict[str, tuple[tuple[int, ...], str]]:
    """``path -> (shape, dtype)`` of every array leaf, the path spelled alike for a state and a raw restore."""
    def name(key):
        return str(getattr(key, "name", getattr(key, "key", getattr(key, "idx", key))))
    leaves = {}
    for path, leaf in jax.tree_util.tree_flatten_with_path(tree)[0]:
        dtype = getattr(leaf, "dtype", None) or jax.dtypes.canonicalize_dtype(np.result_type(leaf))  # a Python int
        if not jax.dtypes.issubdtype(dtype, jax.dtypes.prng_key):  # saved as raw bits: not comparable
            leaves["/".join(name(k) for k in path)] = (tuple(np.shape(leaf)), str(dtype))
    return leaves


def _difference(saved: Any, like: Any) -> str:
    """What first differs between a checkpoint's arrays and a state's, and how many differ; "" if nothing."""
    have, want = _leaves(saved), _leaves(like)
    notes = [f"this state has {path} {list(want[path][0])}, the checkpoint none" for path in want if path not in have]
    notes += [f"the checkpoint has {path} {list(have[path][0])}, this state none" for path in have if path not in want]
    notes += [f"{path} is {list(have[path][0])} {have[path][1]} there, {list(want[path][0])} {want[path][1]} here"
              for path in want if path in have and have[path] != want[path]]
    if not notes:
        return ""
    return notes[0] + (f" (and {len(notes) - 1} more arrays differ)" if len(notes) > 1 else "")


def _first_line(error: BaseException) -> str:
    text = str(error).strip().splitlines()
    return f"{type(error).__name__}: {text[0][:200] if text else ''}"
