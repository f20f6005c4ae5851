"""The minimal training loop.

Contract, so that a resumed run is bitwise identical to an uninterrupted one:

* ``state`` is any pytree with an integer ``step`` field (e.g. ``flax.training.train_state.TrainState``,
  or a GAN state holding two optimisers); the step function increments it.
* ``step_fn(state, batch, key) -> (state, metrics)`` is pure; ``key`` is ``fold_in(loop_key, state.step)``,
  so step n draws the same numbers whether or not the run was interrupted.
* ``batch_fn(step) -> batch`` is a deterministic function of the step index (data order from explicit
  keys, e.g. a permutation drawn from ``fold_in(data_key, epoch)``), so no iterator state is saved.

Metrics are averaged over each logging interval and appended to ``metrics.jsonl``; checkpoints fall on
logging boundaries, so a resumed run rewrites exactly the lines it would have written.
"""

from __future__ import annotations

import dataclasses
import json
import sys
from collections.abc import Callable, Mapping
from pathlib import Path
from typing import Any, Protocol

import jax
import jax.numpy as jnp

from jaxmotion.train.checkpoint import Checkpointer
from jaxmotion.train.progress import Progress


class StepFn(Protocol):
    def __call__(self, state: Any, batch: Any, key: jax.Array) -> tuple[Any, Mapping[str, jax.Array]]: ...


@dataclasses.dataclass(frozen=True)
class LoopConfig:
    """How long to train and how often to log and checkpoint (``checkpoint_every`` = 0: only at the end)."""

    steps: int
    log_every: int = 50
    checkpoint_every: int = 1000
    keep_checkpoints: int = 2

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


def train(
    state: Any,
    step_fn: StepFn,
    batch_fn: Callable[[int], Any],
    *,
    key: jax.Array,
    config: LoopConfig,
    workdir: str | Path | None = None,
    progress: bool = True,
) -> Any:
    """Run ``config.steps`` steps from ``state`` (or from the latest checkpoint in ``workdir``).

    With ``workdir`` set, checkpoints go to ``workdir/checkpoints`` and averaged metrics to
    ``workdir/metrics.jsonl``; a run that finds a checkpoint resumes from it. Returns the final state.
    """
    ckpt = Checkpointer(Path(workdir) / "checkpoints", max_to_keep=config.keep_checkpoints) if workdir else None
    log_path = Path(workdir) / "metrics.jsonl" if workdir else None
    try:
        if ckpt is not None and ckpt.latest_step() is not None:
            state = ckpt.restore(state)
            print(f"resuming from the checkpoint at step {int(state.step)} in {ckpt.directory}", file=sys.stderr)
        start = int(state.step)
        if log_path is not None:
            _truncate_log(log_path, start)
        if start >= config.steps:
            return state

        # The key travels as an argument (not a closure constant) so the step compiles once per run.
        def run_step(state, batch, loop_key):
            return step_fn(state, batch, jax.random.fold_in(loop_key, state.step))

        run_step = jax.jit(run_step, donate_argnums=0)
        bar = Progress(config.steps, start) if progress else None
        totals, count = None, 0
        for step in range(start, config.steps):
            state, metrics = run_step(state, batch_fn(step), key)
            totals = metrics if totals is None else jax.tree.map(jnp.add, totals, metrics)
            count += 1
            done = step + 1
            if done % config.log_every == 0 or done == config.steps:
                means = {k: float(v) / count for k, v in totals.items()}
                if log_path is not None:
                    with log_path.open("a") as f:
                        f.write(json.dumps({"step": done, **means}) + "\n")
                if bar is not None:
                    bar.update(done, means)
                totals, count = None, 0
            if ckpt is not None and (
                done == config.steps or (config.checkpoint_every and done % config.checkpoint_every == 0)
            ):
                ckpt.save(done, state)
        if bar is not None:
            bar.close()
        return state
    finally:
        if ckpt is not None:
            ckpt.close()


def _truncate_log(path: Path, step: int) -> None:
    """Drop log lines past ``step``: they belong to work the checkpoint does not hold."""
    if not path.exists():
        return
    lines = [ln for ln in path.read_text().splitlines() if ln and json.loads(ln)["step"] <= step]
    path.write_text("".join(ln + "\n" for ln in lines))
