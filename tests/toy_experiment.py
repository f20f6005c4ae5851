"""A tiny experiment for testing the runner: fit a 2-layer MLP to sin(3x) on [-1, 1].

Run as a script by the resume test: ``python tests/toy_experiment.py --profile smoke --out DIR``.
``step_sleep_s`` slows each step so the test can kill the process between two checkpoints.
"""

from __future__ import annotations

import dataclasses
import sys
import time
from pathlib import Path

import flax.linen as nn
import jax
import jax.numpy as jnp
import optax
from flax.training.train_state import TrainState

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run as a script from any folder

from jaxmotion import experiment  # noqa: E402
from jaxmotion.train import LoopConfig, train  # noqa: E402


@dataclasses.dataclass(frozen=True)
class ToyConfig:
    train: LoopConfig
    hidden: int = 32
    lr: float = 1e-2
    batch: int = 64
    eval_repeats: int = 4
    step_sleep_s: float = 0.0

    @classmethod
    def smoke(cls):
        return cls(train=LoopConfig(steps=40, log_every=10, checkpoint_every=20))

    @classmethod
    def cpu(cls):
        return cls(train=LoopConfig(steps=400, log_every=50, checkpoint_every=100))

    @classmethod
    def paper(cls):
        return cls(train=LoopConfig(steps=4000, log_every=100, checkpoint_every=1000), hidden=128)


class MLP(nn.Module):
    hidden: int

    @nn.compact
    def __call__(self, x):  # [B, 1] -> [B, 1]
        return nn.Dense(1)(nn.tanh(nn.Dense(self.hidden)(x)))


def _sample(key, n):  # [n, 1] inputs and targets
    x = jax.random.uniform(key, (n, 1), minval=-1.0, maxval=1.0)
    return x, jnp.sin(3.0 * x)


def run(config: ToyConfig, ctx: experiment.RunContext):
    model = MLP(config.hidden)
    params = model.init(ctx.key("init"), jnp.zeros((1, 1)))
    state = TrainState.create(apply_fn=model.apply, params=params, tx=optax.adam(config.lr))
    data_key = ctx.key("data")

    def loss_fn(params, batch):
        x, y = batch
        return jnp.mean((model.apply(params, x) - y) ** 2)

    def step_fn(state, batch, key):
        del key  # deterministic model; the loop still supplies a per-step key
        loss, grads = jax.value_and_grad(loss_fn)(state.params, batch)
        return state.apply_gradients(grads=grads), {"loss": loss}

    def batch_fn(step):
        time.sleep(config.step_sleep_s)
        return _sample(jax.random.fold_in(data_key, step), config.batch)

    state = train(state, step_fn, batch_fn, key=ctx.key("train"), config=config.train, workdir=ctx.workdir)
    eval_keys = jax.random.split(ctx.key("eval"), config.eval_repeats)
    losses = [float(loss_fn(state.params, _sample(k, 256))) for k in eval_keys]
    return {"mlp": {"eval_mse": losses, "params_l2": float(optax.tree.norm(state.params))}}


def main(argv=None):
    return experiment.main("toy", ToyConfig, run, argv)


if __name__ == "__main__":
    main()
