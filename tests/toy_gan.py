"""A small GAN on a 2-D toy distribution: the loop with two optimisers (:class:`MultiState`).

Generator and critic are 2-layer MLPs; the loss is the hinge loss of ActFormer's code (critic:
``relu(1 - D(real)) + relu(1 + D(fake))``, generator: ``-D(fake)``); every step makes ``N_CRITIC`` critic
updates, each on its own real batch, then one generator update. The target is a Gaussian at ``TARGET_MEAN``
with standard deviation ``TARGET_STD``; generated samples start near the origin. The eval hook logs the
distance from the generated samples' mean to the target's every ``eval_every`` steps.

Run as a script by the kill-and-resume test: ``python tests/toy_gan.py --out DIR [--step-sleep-s S]``
(final parameters in ``DIR/params.npz``).
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import flax.linen as nn
import jax
import jax.numpy as jnp
import numpy as np
import optax

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run as a script from any folder

from jaxmotion.train import LoopConfig, MultiState, train  # noqa: E402

TARGET_MEAN = jnp.array([2.0, -1.0])
TARGET_STD = 0.3
N_CRITIC, BATCH, LATENT = 2, 64, 2
LOOP = LoopConfig(steps=300, log_every=50, checkpoint_every=100, eval_every=100)


class MLP(nn.Module):
    hidden: int
    out: int

    @nn.compact
    def __call__(self, x):  # [B, in] -> [B, out]
        return nn.Dense(self.out)(nn.leaky_relu(nn.Dense(self.hidden)(x), 0.2))


generator, critic = MLP(32, 2), MLP(32, 1)


def init_state(key: jax.Array) -> MultiState:
    k_g, k_c = jax.random.split(key)
    params = {"generator": generator.init(k_g, jnp.zeros((1, LATENT))), "critic": critic.init(k_c, jnp.zeros((1, 2)))}
    adam = optax.adam(1e-3, b1=0.5, b2=0.9)
    return MultiState.create(params, {"generator": adam, "critic": adam})


def sample(params, key: jax.Array, n: int) -> jax.Array:  # [n, 2]
    return generator.apply(params, jax.random.normal(key, (n, LATENT)))


def step_fn(state: MultiState, batch: jax.Array, key: jax.Array):
    """``batch``: ``N_CRITIC`` real batches ``[N_CRITIC, B, 2]``."""
    keys = jax.random.split(key, N_CRITIC + 1)

    def critic_loss(c_params, g_params, real, k):
        fake = jax.lax.stop_gradient(sample(g_params, k, BATCH))
        return jnp.mean(nn.relu(1.0 - critic.apply(c_params, real))) + jnp.mean(nn.relu(1.0 + critic.apply(c_params, fake)))

    for i in range(N_CRITIC):
        d_loss, grads = jax.value_and_grad(critic_loss)(state.params["critic"], state.params["generator"], batch[i],
                                                        keys[i])
        state = state.apply("critic", grads)

    def generator_loss(g_params):
        return -jnp.mean(critic.apply(state.params["critic"], sample(g_params, keys[-1], BATCH)))

    g_loss, grads = jax.value_and_grad(generator_loss)(state.params["generator"])
    return state.apply("generator", grads).next_step(), {"critic_loss": d_loss, "generator_loss": g_loss}


def batch_fn(step: int, data_key: jax.Array = jax.random.key(1)) -> jax.Array:
    noise = jax.random.normal(jax.random.fold_in(data_key, step), (N_CRITIC, BATCH, 2))
    return TARGET_MEAN + TARGET_STD * noise


def mean_distance(state: MultiState) -> dict[str, float]:
    """Distance from the mean of 1 000 generated samples (fixed noise) to the target's mean."""
    fake = sample(state.params["generator"], jax.random.key(2), 1000)
    return {"mean_distance": float(jnp.linalg.norm(fake.mean(0) - TARGET_MEAN))}


def run(out: Path | None, step_sleep_s: float = 0.0, progress: bool = False) -> MultiState:
    def slow_batch_fn(step):
        time.sleep(step_sleep_s)
        return batch_fn(step)

    state = train(init_state(jax.random.key(0)), step_fn, slow_batch_fn, key=jax.random.key(3), config=LOOP,
                  workdir=out, eval_fn=mean_distance, progress=progress)
    if out is not None:
        np.savez(Path(out) / "params.npz", *[np.asarray(x) for x in jax.tree.leaves(state)])
    return state


if __name__ == "__main__":
    parser = argparse.ArgumentParser()
    parser.add_argument("--out", required=True)
    parser.add_argument("--step-sleep-s", type=float, default=0.0)
    args = parser.parse_args()
    run(Path(args.out), args.step_sleep_s, progress=True)
