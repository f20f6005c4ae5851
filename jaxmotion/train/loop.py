"""The minimal training loop.

Contract, so that a resumed run is bitwise identical to an uninterrupted one:

* ``state`` is any pytree with an integer ``step`` field (e.g. ``flax.training.train_state.TrainState``,
  or a GAN state holding two optimisers); the step function increments it.
* ``step_fn(state, batch, key) -> (state, metrics)`` is pure; ``key`` is ``fold_in(loop_key, state.step)``,
  so step n draws the same numbers whether or not the run was interrupted.
* ``batch_fn(step) -> batch`` is a deterministic function of the step index (data order from explicit
  keys, e.g. a permutation drawn from ``fold_in(data_key, epoch)``), so no iterator state is saved.

Metrics are averaged over each logging interval and appended to ``metrics.jsonl`` as
``{"step": n, <metric>: mean, ...}``; checkpoints fall on logging boundaries, so a resumed run rewrites
exactly the lines it would have written.

Options:

* ``eval_fn(state) -> {name: float}`` runs after every ``config.eval_every``-th step (0: never; the last
  step too only when it is such a multiple) and adds a line ``{"step": n, "eval": {name: value}}`` after
  that step's metrics line. It must be a deterministic function of the state (fixed keys, fixed data),
  so a resumed run, which drops every line past its checkpoint and redoes those steps, writes the same
  lines as an uninterrupted one.
* ``init_from``: another run's folder (or its ``checkpoints/`` folder) whose latest checkpoint, optimiser
  state included, starts a run whose ``workdir`` holds no checkpoint yet. The step counter continues
  from that checkpoint's step, so ``config.steps`` stays the total (a 2 000-step run fine-tuned for 200
  more has ``steps=2200``); once the new run has checkpoints of its own it resumes from those.
* ``mesh``: a data mesh (:func:`jaxmotion.distributed.data_mesh`). State and key are replicated on it,
  every batch is split along its leading axis (which must divide by the device count), and the step
  compiles as one SPMD program; checkpoints restore onto the mesh. ``None`` (default): one device, as
  before. With several processes, only process 0 writes ``metrics.jsonl`` and shows progress.
* ``writers``: writer factories (:mod:`jaxmotion.train.writers`, e.g. TensorBoard's). Process 0 opens each on
  ``workdir`` with the step it starts from (once the log is truncated there, and only if steps are left),
  hands it every record it appends to ``metrics.jsonl``, and closes it however training ends. They need a
  ``workdir``: without one they are refused.
"""

from __future__ import annotations

import contextlib
import dataclasses
import json
import sys
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path
from typing import Any, Protocol

import jax
import jax.numpy as jnp

from jax.sharding import Mesh

from jaxmotion.files import folder_lock, write_atomic
from jaxmotion.train.checkpoint import Checkpointer, CheckpointsDamaged
from jaxmotion.train.writers import Writer, WriterFactory, record_scalars
from jaxmotion.distributed import is_primary, replicate, replicated, shard_batch
from jaxmotion.progress import Progress

#: A training folder's checkpoints live in ``<workdir>/CHECKPOINT_FOLDER/`` (orbax, one folder per step).
CHECKPOINT_FOLDER = "checkpoints"
#: The training log in a run folder: one JSON line per ``log_every`` steps (the loss terms' means) and per evaluation.
TRAINING_LOG = "metrics.jsonl"


class StepFn(Protocol):
    def __call__(self, state: Any, batch: Any, key: jax.Array) -> tuple[Any, Mapping[str, jax.Array]]: ...


@dataclasses.dataclass(frozen=True)
class LoopConfig:
    """How long to train and how often to log and checkpoint (``checkpoint_every`` = 0: only at the end),
    and how often to call the evaluation hook (``eval_every`` = 0: never)."""

    steps: int
    log_every: int = 50
    checkpoint_every: int = 1000
    keep_checkpoints: int = 2
    eval_every: int = 0

    def __post_init__(self):
        if self.steps < 0:
            raise ValueError(f"LoopConfig.steps must be >= 0, got {self.steps}")
        if self.log_every < 1:
            raise ValueError(f"LoopConfig.log_every must be >= 1, got {self.log_every}")
        if self.checkpoint_every < 0 or self.checkpoint_every % self.log_every:
            raise ValueError(
                f"LoopConfig.checkpoint_every ({self.checkpoint_every}) must be a non-negative multiple of "
                f"log_every ({self.log_every}), so that a resumed run logs exactly what an uninterrupted one does"
            )
        if self.keep_checkpoints < 1:
            raise ValueError(f"LoopConfig.keep_checkpoints must be >= 1, got {self.keep_checkpoints}")
        if self.eval_every < 0:
            raise ValueError(f"LoopConfig.eval_every must be >= 0 (0: never), got {self.eval_every}")


def train(
    state: Any,
    step_fn: StepFn,
    batch_fn: Callable[[int], Any],
    *,
    key: jax.Array,
    config: LoopConfig,
    workdir: str | Path | None = None,
    progress: bool = True,
    mesh: Mesh | None = None,
    init_from: str | Path | None = None,
    eval_fn: Callable[[Any], Mapping[str, float]] | None = None,
    writers: Sequence[WriterFactory] = (),
) -> Any:
    """Run ``config.steps`` steps from ``state`` (or from the latest checkpoint in ``workdir``, or else
    from ``init_from``'s); see the module docstring for ``mesh``, ``init_from``, ``eval_fn`` and ``writers``.

    With ``workdir`` set, checkpoints go to ``workdir/checkpoints`` and averaged metrics to
    ``workdir/metrics.jsonl``; a run that finds a checkpoint resumes from it. Returns the final state.
    """
    if workdir is None:
        if writers:
            raise ValueError("writers: a training log needs a folder; got writers but workdir=None")
        return _train(state, step_fn, batch_fn, key, config, None, progress, mesh, init_from, eval_fn, ())
    with folder_lock(workdir, what="training folder") if is_primary() else contextlib.nullcontext():
        return _train(state, step_fn, batch_fn, key, config, Path(workdir), progress, mesh, init_from, eval_fn,
                      writers)


def _train(state, step_fn, batch_fn, key, config, workdir, progress, mesh, init_from, eval_fn, writers):
    ckpt = Checkpointer(workdir / CHECKPOINT_FOLDER, max_to_keep=config.keep_checkpoints) if workdir else None
    primary = is_primary()
    log_path = workdir / TRAINING_LOG if workdir and primary else None
    cleanup = contextlib.ExitStack()  # the checkpointer and the writers, closed however training ends
    if ckpt is not None:
        cleanup.callback(ckpt.close)
    try:
        if mesh is not None:
            state, key = replicate(state, mesh), replicate(key, mesh)
        resumed = ckpt is not None and ckpt.latest_step() is not None
        if resumed:
            try:
                state = ckpt.restore(state)
                _report(f"resuming from the checkpoint at step {int(state.step)} in {ckpt.directory}")
            except CheckpointsDamaged:  # set aside with a warning: the run starts over
                resumed = False
        if not resumed and init_from is not None:
            state = _restore_from(init_from, state)
        start = int(state.step)
        if log_path is not None:
            _truncate_log(log_path, start, resumed=resumed)
        if start >= config.steps:
            return state
        opened: list[Writer] = ([cleanup.enter_context(contextlib.closing(factory(workdir, start)))
                                 for factory in writers] if log_path is not None else [])

        # The key travels as an argument (not a closure constant) so the step compiles once per run.
        def run_step(state, batch, loop_key):
            return step_fn(state, batch, jax.random.fold_in(loop_key, state.step))

        if mesh is None:
            run_step, place = jax.jit(run_step, donate_argnums=0), lambda batch: batch
        else:
            run_step = jax.jit(run_step, donate_argnums=0, out_shardings=replicated(mesh))
            place = lambda batch: shard_batch(batch, mesh)  # noqa: E731
        bar = Progress(config.steps, start) if progress and primary else None
        totals, count = None, 0
        for step in range(start, config.steps):
            state, metrics = run_step(state, place(batch_fn(step)), key)
            if step == start and int(state.step) != step + 1:
                raise ValueError(f"step_fn: the state's step went from {step} to {int(state.step)}; a step "
                                 f"function advances it by exactly 1 (per-step keys and resume depend on it)")
            totals = metrics if totals is None else jax.tree.map(jnp.add, totals, metrics)
            count += 1
            done = step + 1
            if done % config.log_every == 0 or done == config.steps:
                means = {k: float(v) / count for k, v in totals.items()}
                _append(log_path, opened, {"step": done, **means})
                if bar is not None:
                    bar.update(done, means)
                totals, count = None, 0
            if eval_fn is not None and config.eval_every and done % config.eval_every == 0:
                values = {k: float(v) for k, v in eval_fn(state).items()}
                _append(log_path, opened, {"step": done, "eval": values})
                if bar is not None:
                    bar.message(f"eval at step {done}: " + " | ".join(f"{k} {v:.4g}" for k, v in values.items()))
            if ckpt is not None and (
                done == config.steps or (config.checkpoint_every and done % config.checkpoint_every == 0)
            ):
                ckpt.save(done, state)
        if bar is not None:
            bar.close()
        return state
    finally:
        cleanup.close()


def _restore_from(init_from: str | Path, like: Any) -> Any:
    """The latest checkpoint of another run (its folder or its ``checkpoints/``), into ``like``'s form."""
    folder = Path(init_from)
    if (folder / CHECKPOINT_FOLDER).is_dir():
        folder = folder / CHECKPOINT_FOLDER
    if not folder.is_dir():
        raise FileNotFoundError(f"init_from: {init_from} is not a folder")
    source = Checkpointer(folder, read_only=True)
    try:
        step = source.latest_step()
        if step is None:
            raise FileNotFoundError(f"init_from: no checkpoint under {folder}")
        try:
            state = source.restore(like, step)
        except Exception as error:  # orbax raises several types for a tree that does not fit
            raise ValueError(f"init_from: the checkpoint at step {step} in {folder} does not match the "
                             f"state's structure (another model or optimiser?): {error}") from error
    finally:
        source.close()
    _report(f"initialised from the checkpoint at step {step} in {folder}")
    return state


def _report(message: str) -> None:
    if is_primary():
        print(message, file=sys.stderr)


def _append(path: Path | None, writers: Sequence[Writer], record: Mapping[str, Any]) -> None:
    if path is not None:
        with path.open("a") as f:
            f.write(json.dumps(record) + "\n")
        for writer in writers:
            writer.write(record["step"], record_scalars(record))


def _truncate_log(path: Path, step: int, *, resumed: bool) -> None:
    """Drop log lines past ``step``: they belong to work the checkpoint does not hold. A last line cut short
    (a kill mid-write) is dropped with a warning; a damaged line before it is an error naming the line."""
    if not path.exists():
        if resumed and step > 0:
            _report(f"warning: {path} is missing though the run resumes at step {step}: the log starts at "
                    f"step {step}; the lines of the steps before are lost")
        return
    lines = path.read_text().splitlines()
    kept = []
    for number, line in enumerate(lines, 1):
        if not line.strip():
            continue
        try:
            record = json.loads(line)
        except ValueError:
            if number == len(lines):
                _report(f"warning: dropping the last line of {path}, cut short by an interrupted write: {line[:80]!r}")
                continue
            raise ValueError(f"{path}, line {number}: not a JSON record ({line[:80]!r}); the training log is "
                             f"damaged; repair or delete that line") from None
        if record["step"] <= step:
            kept.append(line)
    write_atomic(path, "".join(ln + "\n" for ln in kept))
