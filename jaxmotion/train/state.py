"""Training states: one optimiser (:class:`TrainState`) or several named parameter sets, each with its own
optimiser (:class:`MultiState`, a GAN's generator + critic).

Both keep the non-trained state a model carries (BatchNorm running statistics, spectral-norm power-iteration
vectors) as ``buffers``, checkpointed with the parameters and never touched by the optimiser.

:class:`TrainState` is ``step``, ``params``, ``opt_state`` and ``buffers`` with the optimiser static;
``apply_gradients`` counts the step. :class:`MultiState` is a pytree like ``flax.training.train_state.TrainState``: ``step``, ``params``,
``opt_states`` and ``buffers`` (untrained state: spectral-norm vectors) are its leaves (checkpointed, replicated
on a data mesh), the optimisers are static. The
loop needs only its ``step``; one loop step is whatever the step function makes of it, e.g. ActFormer's
``n_critic`` critic updates, each on its own batch, then one generator update::

    state = MultiState.create({"generator": g_params, "critic": c_params},
                              {"generator": optax.adam(1e-4), "critic": optax.adam(4e-4)})

    def step_fn(state, batch, key):                         # batch["real"]: [n_critic, B, ...]
        for i in range(n_critic):
            grads = jax.grad(critic_loss)(state.params["critic"], state.params["generator"], batch["real"][i], ...)
            state = state.apply("critic", grads)
        grads = jax.grad(generator_loss)(state.params["generator"], state.params["critic"], ...)
        return state.apply("generator", grads).next_step(), metrics

``apply`` updates one set and leaves ``step`` alone; ``next_step`` counts the loop step (exactly once per
step function call: the loop checks). Each optimiser keeps its own update count in its state.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import jax
import jax.numpy as jnp
import optax
from flax import struct


class TrainState(struct.PyTreeNode):
    """``step`` (updates done), ``params``, ``opt_state`` and ``buffers`` (non-trained state, ``{}`` when the
    model has none); the optimiser ``tx`` is static."""

    step: jax.Array
    params: Any
    opt_state: Any
    tx: optax.GradientTransformation = struct.field(pytree_node=False)
    buffers: Any = struct.field(default_factory=dict)

    @classmethod
    def create(cls, params: Any, tx: optax.GradientTransformation, buffers: Any = None) -> TrainState:
        """Step 0 and ``tx``'s fresh state for ``params``."""
        return cls(step=jnp.zeros((), jnp.int32), params=params, opt_state=tx.init(params), tx=tx,
                   buffers={} if buffers is None else buffers)

    def apply_gradients(self, grads: Any) -> TrainState:
        """One optimiser update with ``grads`` (same structure as ``params``), one step later."""
        updates, opt_state = self.tx.update(grads, self.opt_state, self.params)
        return self.replace(step=self.step + 1, params=optax.apply_updates(self.params, updates),
                            opt_state=opt_state)


class MultiState(struct.PyTreeNode):
    """``step`` (loop steps done), ``params`` and ``opt_states`` keyed by set name; ``optimizers`` static."""

    step: jax.Array
    params: dict[str, Any]
    opt_states: dict[str, Any]
    optimizers: tuple[tuple[str, optax.GradientTransformation], ...] = struct.field(pytree_node=False)
    buffers: dict[str, Any] = struct.field(default_factory=dict)

    @classmethod
    def create(cls, params: Mapping[str, Any], optimizers: Mapping[str, optax.GradientTransformation],
               buffers: Mapping[str, Any] | None = None) -> MultiState:
        """Step 0 and a fresh optimiser state per set; ``params`` and ``optimizers`` name the same sets.
        ``buffers``: state that is kept and checkpointed but not trained (spectral-norm power-iteration
        vectors, running statistics), by name."""
        if set(params) != set(optimizers) or not params:
            raise ValueError(f"MultiState.create: params name the sets {sorted(params)} but optimizers name "
                             f"{sorted(optimizers)}; give one optimiser per parameter set")
        names = tuple(params)  # the order given, also the checkpoint's
        return cls(
            step=jnp.zeros((), jnp.int32),
            params={name: params[name] for name in names},
            opt_states={name: optimizers[name].init(params[name]) for name in names},
            optimizers=tuple((name, optimizers[name]) for name in names),
            buffers=dict(buffers or {}),
        )

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(name for name, _ in self.optimizers)

    def optimizer(self, name: str) -> optax.GradientTransformation:
        for known, tx in self.optimizers:
            if known == name:
                return tx
        raise KeyError(f"MultiState: no parameter set {name!r}; the sets are {list(self.names)}")

    def apply(self, name: str, grads: Any) -> MultiState:
        """One optimiser update of the set ``name`` with ``grads`` (same structure as its parameters);
        the other sets and ``step`` are unchanged."""
        tx = self.optimizer(name)
        updates, opt_state = tx.update(grads, self.opt_states[name], self.params[name])
        return self.replace(params={**self.params, name: optax.apply_updates(self.params[name], updates)},
                            opt_states={**self.opt_states, name: opt_state})

    def with_buffer(self, name: str, value: Any) -> MultiState:
        """The same state with buffer ``name`` replaced (e.g. the moved power-iteration vectors)."""
        if name not in self.buffers:
            raise KeyError(f"MultiState: no buffer {name!r}; the buffers are {sorted(self.buffers)}")
        return self.replace(buffers={**self.buffers, name: value})

    def next_step(self) -> MultiState:
        """The same state one loop step later (call once at the end of a step function)."""
        return self.replace(step=self.step + 1)
