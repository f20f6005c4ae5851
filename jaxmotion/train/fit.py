"""One helper every trainer calls: a dataset, a key, a state and a step function in; a trained state out.

What the trainers used to repeat, said once: the key splits into the initialisation key, the data-order
key and the loop's per-step key (in that order, so a trainer's results do not depend on how it was
written); batches come from :func:`jaxmotion.data.pipeline.make_batch_fn` with the trainer's
:class:`~jaxmotion.data.pipeline.BatchSpec` (a :class:`~jaxmotion.data.pipeline.PairSpec` for batches of
pairs); the loop runs with the trainer's :class:`~jaxmotion.train.loop.LoopConfig`, resuming from
``workdir``'s checkpoints.

A trainer is then its config (which embeds a ``LoopConfig``), a function building the initial state from
a key, and a step function::

    state = fit(data, key, init_state=lambda k: TrainState.create(apply_fn=None, params=init(k), tx=tx),
                step_fn=step_fn, batch=BatchSpec(batch_size=20, window=60), loop=training.loop, workdir=workdir)
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import Any

import jax
import numpy as np

from jaxmotion.data.motion import MotionDataset
from jaxmotion.data.pipeline import BatchSpec, PairSpec, make_batch_fn
from jaxmotion.train.loop import LoopConfig, StepFn, train


def fit(data: MotionDataset, key: jax.Array, *, init_state: Callable[[jax.Array], Any], step_fn: StepFn,
        batch: BatchSpec | PairSpec, loop: LoopConfig, workdir: str | Path | None = None, progress: bool = True,
        labels: dict[str, np.ndarray] | None = None, **loop_options: Any) -> Any:
    """Train ``init_state(k_init)`` with ``step_fn`` on batches of ``data``; return the final state.

    ``key`` splits into ``k_init, k_data, k_train``: the initial state, the batches' order and crops, and
    the per-step keys (``fold_in(k_train, step)``). ``labels``: per-sequence arrays the batches carry too
    (:func:`~jaxmotion.data.pipeline.make_batch_fn`). ``loop_options`` go to :func:`~jaxmotion.train.loop.train`
    as they are (``mesh``, ``init_from``, ``eval_fn``, ``writers``).
    """
    k_init, k_data, k_train = jax.random.split(key, 3)
    return train(init_state(k_init), step_fn, make_batch_fn(data, k_data, batch, labels), key=k_train, config=loop,
                 workdir=workdir, progress=progress, **loop_options)
