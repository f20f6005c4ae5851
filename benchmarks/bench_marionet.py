"""Benchmark: one MARIONET training step and one generation call, jit-compiled jaxmotion against a PyTorch peer of
the same architecture, timed in the same run.

    python benchmarks/bench_marionet.py [--repeats 3] [--only train|generate] [--gen-batch 8]
                                        [--check-batch 8] [--no-parity] [--torch-threads N]

The PyTorch peer (``benchmarks/peers/marionet_torch.py``, written from the paper and MARIONETTE.md §1.4-1.6, torch's
own ``nn.TransformerEncoder`` / ``nn.TransformerDecoder`` layers) runs when ``import torch`` works:
``pip install -e ".[bench]"`` (torch is a benchmark extra, never a runtime or test dependency). Without torch the
script says so and leaves the PyTorch columns empty.

Run it on a quiet machine: the numbers are wall times of multi-threaded CPU work, and any other job on the cores
slows them by tens of percent. Threads: XLA's defaults (every core the process may use; ``XLA_FLAGS`` printed as
XLA sees them); the peer gets ``--torch-threads``, by default 1: on the 2-core machine shared with another job,
torch's two OpenMP threads wait for each other and ran the peer 4x (training step: 30 s against 7 s) to 10x
(generation: 41 s against 4.0 s for 2 actions) slower than one thread, so one thread is the peer's faster
setting there and the conservative comparison; on a quiet machine try ``--torch-threads 2`` as well. The load
average is printed before and after.

What is timed (``float32``, CPU, the paper size: ``MarionetConfig()``, d 256, 8 heads, FF 1024, encoder 2 /
unrolling 2 / decoder 6 layers, the 32-wide path encoder, 31 tags):

* **Training step**: batch 30 (the paper's) of action items, 6 context frames then an action of 60-120 frames
  padded to 120 (a synthetic pipeline batch: axis-angle SMPL-24 rotations, translations, tags and next tags),
  forward + backward + Adam 1e-4, dropout on, Z sampled, with scheduled sampling's second pass on (the weights
  0.1 / 0.9; the schedule's share at 0.5: ``activate`` 0, ``accomplish`` 1 of 100 steps, the state at step 50,
  and a gate no first pass misses). jaxmotion: the library's step (``jaxmotion.train.marionet.marionet_step``,
  as ``train_marionet``'s loop runs it: key ``fold_in(loop key, step)``, state donated; the normalisation at the
  last context pose inside it). PyTorch: the peer's ``train_step`` on the same batch, eager (the same
  normalisation in torch, both passes, the same loss, ``backward``, ``torch.optim.Adam``).
* **Generation**: ``--gen-batch`` actions of 120 frames (full length), Z = mu, eval mode. jaxmotion:
  ``jaxmotion.models.marionet.generate`` jitted (one frame at a time through the decoder's key/value cache,
  a ``lax.scan``); PyTorch: the peer's ``generate`` under ``torch.inference_mode``, frame by frame as the paper
  describes it (every frame runs the whole causal decoder again over all the frames so far; no cache). The
  peer's work grows with the square of the length and its batch is small by default so the run stays within
  minutes on two cores.

Same weights: the peer is loaded with jaxmotion's initial parameters (``jaxmotion.nn.transformer.state_dict``
names are PyTorch's; ``load_state_dict(strict=True)``). Before timing, a parity check (dropout off, same weights)
on one variable-length batch of ``--check-batch`` actions (60-120 frames, so the padding masks matter) prints the
max |difference| of: the inputs each side makes from the pipeline batch; the teacher-forced poses in eval mode
(Z = mu); the cached ``generate`` (Z = mu) against the peer's frame-by-frame generation; and the losses of one
training step at the same inputs and noise (eps and the scheduled-sampling mix recovered from the step key as
``marionet_step`` draws them), at the initial parameters and after one Adam update of each.

Timing: jaxmotion's functions are compiled ahead of time (``jit(...).lower(...).compile()``, reported as
"compile"; PyTorch is eager and has none); each side is called twice to warm up, then the two are called
alternately ``--repeats`` times (so background load hits both alike), jaxmotion with ``block_until_ready``;
medians and min-max ranges in ms. Targets (the issue's): training step >= 1.25x the peer, generation >= 5x.
"""

from __future__ import annotations

import argparse
import dataclasses
import os
import sys
import time
from pathlib import Path

import jax
import jax.numpy as jnp
import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # runnable from a checkout without installing

from benchmarks.timing import as_loop_runs, machine_header, print_table, time_loop_step, time_pair  # noqa: E402
from jaxmotion.data.mag_tags import KINDS, TAG_NAMES  # noqa: E402
from jaxmotion.geometry.skeletons import SMPL24  # noqa: E402
from jaxmotion.models.marionet import CONTEXT, MarionetConfig, forward, generate, init_marionet  # noqa: E402
from jaxmotion.train.loop import LoopConfig  # noqa: E402
from jaxmotion.train.marionet import (MarionetTraining, marionet_inputs, marionet_state, marionet_step,  # noqa: E402
                                      sampling_share)

try:  # the PyTorch peer: pip install -e ".[bench]"
    import torch

    from benchmarks.peers import marionet_torch as peer
except ImportError:  # (an installed but broken torch raises its own error here)
    torch = peer = None

TARGET_TRAIN, TARGET_GENERATE = 1.25, 5.0
BATCH, FRAMES, MIN_FRAMES = 30, 120, 60  # the paper's batch; actions of 60-120 frames padded to 120
STEPS, START = 100, 50  # the schedule the timed steps sit in (activate 0, accomplish 1): share 0.5 at START
CONFIG = MarionetConfig()  # the paper size (supplement Table 2)
THREADS = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count()
ROOT_TAGS = np.array([KINDS[name] == "root" for name in TAG_NAMES])  # BABEL-MAG's root-motion tags


def training(config: MarionetConfig) -> MarionetTraining:
    """The paper's recipe with scheduled sampling on from the start and a gate every first pass passes, so the
    second pass always weighs in (0.1 / 0.9)."""
    return MarionetTraining(model=config, loop=LoopConfig(steps=STEPS, log_every=1, checkpoint_every=0),
                            activate=0.0, accomplish=1.0, gate=1e9)


def start_state(recipe: MarionetTraining, key: jax.Array):
    """Fresh parameters and Adam state, the step counter at ``START`` (the share of predicted poses 0.5)."""
    return marionet_state(recipe, key).replace(step=jnp.asarray(START, jnp.int32))


def synthetic_batch(key: jax.Array, batch: int, frames: int, min_frames: int | None = None) -> dict[str, jax.Array]:
    """A pipeline batch of action items: ``CONTEXT`` frames then actions of ``frames`` frames (or of lengths drawn
    in ``[min_frames, frames]``, padded with their last frame): smooth random axis-angle poses (a random heading,
    small joint angles drifting), a wandering ground path at hip height, one or two tags and next tags each."""
    k_base, k_drift, k_yaw, k_walk, k_start, k_tag, k_next, k_len = jax.random.split(key, 8)
    total = CONTEXT + frames
    lengths = (jnp.full((batch,), frames) if min_frames is None
               else jax.random.randint(k_len, (batch,), min_frames, frames + 1))
    rotations = 0.3 * jax.random.normal(k_base, (batch, 1, 24, 3)) + jnp.cumsum(
        0.02 * jax.random.normal(k_drift, (batch, total, 24, 3)), axis=1)
    yaw = jax.random.uniform(k_yaw, (batch, 1), minval=-np.pi, maxval=np.pi)
    rotations = rotations.at[:, :, 0, 1].add(yaw)
    steps = jnp.cumsum(0.02 * jax.random.normal(k_walk, (batch, total, 3)) * jnp.array([1.0, 0.1, 1.0]), axis=1)
    translation = steps + jax.random.uniform(k_start, (batch, 1, 3), minval=-1.0, maxval=1.0) * jnp.array(
        [1.0, 0.0, 1.0]) + jnp.array([0.0, 0.9, 0.0])
    real = jnp.arange(total)[None] < CONTEXT + lengths[:, None]  # [B, K + T]
    last = jnp.clip(jnp.arange(total)[None], 0, CONTEXT + lengths[:, None] - 1)  # padded with the last frame
    take = jax.vmap(lambda a, i: a[i])
    num_tags = len(TAG_NAMES)
    tags = (jax.nn.one_hot(jax.random.randint(k_tag, (batch, 2), 0, num_tags), num_tags).sum(1) > 0)
    next_tags = (jax.nn.one_hot(jax.random.randint(k_next, (batch, 2), 0, num_tags), num_tags).sum(1) > 0)
    return jax.block_until_ready({"rotations": take(rotations, last), "translation": take(translation, last),
                                  "mask": real, "tags": tags, "next_tags": next_tags})


def to_torch(tree: dict) -> dict:
    return {name: torch.from_numpy(np.array(value)) for name, value in tree.items()}


def max_difference(ours, theirs) -> tuple[float, float]:
    """``(max |Δ|, max |Δ| / max |ours|)``."""
    ours, theirs = np.asarray(ours, np.float64), np.asarray(theirs, np.float64)
    delta = float(np.abs(ours - theirs).max())
    return delta, delta / float(np.abs(ours).max())


def relative(a: float, b: float) -> float:
    return abs(a - b) / max(abs(a), 1e-30)


def model_inputs(x: dict) -> tuple:
    return x["context"], x["tags"], x["next_tags"], x["path"]


# ------------------------------------------------------------------------------------------------ parity


def step_draws(recipe: MarionetTraining, state, loop_key: jax.Array, batch: int, frames: int):
    """The noise ``marionet_step`` draws at ``state.step``: eps of Z (``forward``'s ``k_z``) and the
    scheduled-sampling mix ``[B, T - 1]``, and the share."""
    key = jax.random.fold_in(loop_key, state.step)
    k_first, k_mix, _ = jax.random.split(key, 3)
    k_z = jax.random.split(k_first, 4)[0]
    share = sampling_share(recipe, state.step)
    eps = jax.random.normal(k_z, (batch, recipe.model.width))
    mix = jax.random.bernoulli(k_mix, share, (batch, frames - 1))
    return np.array(eps), np.array(mix), float(share)


def check_parity(config: MarionetConfig, batch_size: int, k_init: jax.Array, k_loop: jax.Array) -> dict:
    """Dropout off, same weights, one variable-length batch: inputs, teacher-forced poses, generation, and the
    losses of two training steps (the second after one Adam update of each side)."""
    check = dataclasses.replace(config, encoder_dropout=0.0, unroll_dropout=0.0, decoder_dropout=0.0,
                                path_dropout=0.0)
    recipe = training(check)
    state = start_state(recipe, k_init)
    model = peer.build_peer(check, state.params)
    batch = synthetic_batch(jax.random.key(7), batch_size, FRAMES, MIN_FRAMES)
    batch_t, root_t = to_torch(batch), torch.from_numpy(ROOT_TAGS)
    x = jax.jit(marionet_inputs)(batch, jnp.asarray(ROOT_TAGS))
    x_peer = peer.marionet_inputs(batch_t, root_t)
    result = {"durations": (int(x["mask"].sum(1).min()), int(x["mask"].sum(1).max())),
              "inputs": max(max_difference(x[name], x_peer[name].numpy())[0]
                            for name in ("context", "target", "path"))}
    x_t = to_torch(x)  # the model checks read the same inputs on both sides

    ours = jax.jit(lambda p, x: forward(p, check, *model_inputs(x), x["target"], x["mask"]).poses)(state.params, x)
    theirs = peer.forward(model, *model_inputs(x_t), x_t["target"], x_t["mask"])
    result["forward"] = max_difference(ours, theirs.numpy())

    ours = jax.jit(lambda p, x: generate(p, check, *model_inputs(x), x["mask"]))(state.params, x)
    theirs = peer.generate(model, *model_inputs(x_t), x_t["mask"])
    result["generate"] = max_difference(ours, theirs.numpy())
    result["generate_frames"] = np.abs(np.asarray(ours) - theirs.numpy()).max(axis=(0, 2))  # [T]

    optimizer = peer.make_optimizer(model, recipe.learning_rate)
    skeleton = peer.Skeleton(SMPL24.parents, SMPL24.offsets)
    step = jax.jit(as_loop_runs(marionet_step(recipe, ROOT_TAGS)))
    losses = []
    for _ in range(2):
        eps, mix, share = step_draws(recipe, state, k_loop, batch_size, FRAMES)
        state, terms = step(state, batch, k_loop)
        mine = float(terms["loss"])
        theirs = float(peer.train_step(model, optimizer, batch_t, root_t, share=share, gate=recipe.gate,
                                       skeleton=skeleton, eps=torch.from_numpy(eps), mix=torch.from_numpy(mix)))
        losses.append((mine, theirs, relative(mine, theirs), float(terms["sampled share"]), float(mix.mean())))
    result["train"] = losses
    return result


# ------------------------------------------------------------------------------------------------ timing


def bench_train(repeats: int) -> dict:
    recipe = training(CONFIG)
    k_init, k_data, k_loop = jax.random.split(jax.random.key(0), 3)
    state = start_state(recipe, k_init)
    batch = synthetic_batch(k_data, BATCH, FRAMES, MIN_FRAMES)
    theirs = None
    if peer is not None:
        model = peer.build_peer(CONFIG, state.params)  # the same initial weights, copied before donation
        optimizer = peer.make_optimizer(model, recipe.learning_rate)
        batch_t, root_t = to_torch(batch), torch.from_numpy(ROOT_TAGS)
        skeleton = peer.Skeleton(SMPL24.parents, SMPL24.offsets)
        share = float(sampling_share(recipe, state.step))

        def theirs():
            peer.train_step(model, optimizer, batch_t, root_t, share=share, gate=recipe.gate, skeleton=skeleton)

    return time_loop_step(marionet_step(recipe, ROOT_TAGS), state, batch, k_loop, theirs, repeats)


def bench_generate(batch_size: int, repeats: int) -> dict:
    params = init_marionet(jax.random.key(0), CONFIG)
    x = jax.jit(marionet_inputs)(synthetic_batch(jax.random.key(1), batch_size, FRAMES), jnp.asarray(ROOT_TAGS))
    args = (*model_inputs(x), x["mask"])
    tick = time.perf_counter()
    compiled = jax.jit(lambda p, *a: generate(p, CONFIG, *a)).lower(params, *args).compile()
    compile_s = time.perf_counter() - tick
    theirs = None
    if peer is not None:
        model = peer.build_peer(CONFIG, params)
        args_t = [torch.from_numpy(np.array(a)) for a in args]

        def theirs():
            peer.generate(model, *args_t)

    result, peer_result = time_pair(lambda: jax.block_until_ready(compiled(params, *args)), theirs, repeats)
    return {**result, "peer": peer_result, "compile_s": compile_s}


# -------------------------------------------------------------------------------------------------- main


def print_parity(p: dict, check_batch: int) -> None:
    low, high = p["durations"]
    print(f"Parity (dropout off, same weights; {check_batch} actions of {low}-{high} frames padded to {FRAMES}):")
    print()
    print(f"* inputs from the pipeline batch (context, target, path), max |difference|: {p['inputs']:.1e}")
    print(f"* teacher-forced poses, Z = mu: max |difference| {p['forward'][0]:.1e} "
          f"({p['forward'][1]:.1e} of max |pose|)")
    frames = p["generate_frames"]
    print(f"* generation, cached jaxmotion vs the peer's frame-by-frame loop, Z = mu: max |difference| "
          f"{p['generate'][0]:.1e} ({p['generate'][1]:.1e} of max |pose|); by frame: "
          + ", ".join(f"{t + 1}: {frames[t]:.1e}" for t in sorted({0, 9, 29, 59, 89, high - 1})))
    print()
    print("| training step (second pass on) | loss jaxmotion | loss PyTorch | rel. diff | sampled share (jaxmotion) "
          "| mixed share |")
    print("|---|---:|---:|---:|---:|---:|")
    for name, (a, b, d, share, mixed) in zip(("initial parameters", "after one Adam step"), p["train"]):
        print(f"| {name} | {a:.7g} | {b:.7g} | {d:.1e} | {share:.2f} | {mixed:.2f} |")
    print()


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=3, help="timed calls per row and side, after two warm-up calls")
    parser.add_argument("--only", choices=("train", "generate"), default=None)
    parser.add_argument("--gen-batch", type=int, default=8, help="actions generated per call (120 frames each)")
    parser.add_argument("--check-batch", type=int, default=8, help="actions in the parity check's batch")
    parser.add_argument("--no-parity", action="store_true", help="skip the parity check")
    parser.add_argument("--torch-threads", type=int, default=1,
                        help="torch.set_num_threads for the peer (default 1: see the module docstring)")
    args = parser.parse_args()
    if min(args.repeats, args.gen_batch, args.check_batch, args.torch_threads) < 1:
        parser.error("--repeats, --gen-batch, --check-batch and --torch-threads must be >= 1")

    print(machine_header())
    print(f"XLA_FLAGS={os.environ.get('XLA_FLAGS', '') or '(unset)'} (XLA default threading, {THREADS} cores); "
          f"repeats {args.repeats}; load average before: {' '.join(f'{x:.2f}' for x in os.getloadavg())}")
    if peer is None:
        print('PyTorch peer: torch is not installed; the peer needs `pip install -e ".[bench]"` '
              "(its columns are left empty).")
    else:
        torch.set_num_threads(args.torch_threads)
        print(f"PyTorch peer: torch {torch.__version__}, {torch.get_num_threads()} thread(s), eager, float32")
    print(f"MARIONET, paper size (d {CONFIG.width}, {CONFIG.heads} heads, FF {CONFIG.ff}, layers "
          f"{CONFIG.encoder_layers} / {CONFIG.unroll_layers} / {CONFIG.decoder_layers}, path {CONFIG.path_width}, "
          f"{CONFIG.num_tags} tags)\n", flush=True)

    if peer is not None and not args.no_parity:
        k_init, _, k_loop = jax.random.split(jax.random.key(0), 3)
        print_parity(check_parity(CONFIG, args.check_batch, k_init, k_loop), args.check_batch)

    rows = []  # (name, result, target)
    if args.only in (None, "train"):
        rows.append((f"train step, batch {BATCH} x {MIN_FRAMES}-{FRAMES} frames (padded to {FRAMES}), "
                     f"second pass on", bench_train(args.repeats), TARGET_TRAIN))
    if args.only in (None, "generate"):
        rows.append((f"generate {args.gen_batch} x {FRAMES} frames, Z = mu", bench_generate(args.gen_batch,
                                                                                             args.repeats),
                     TARGET_GENERATE))

    print_table(rows)
    print(f"Load average after: {' '.join(f'{x:.2f}' for x in os.getloadavg())}")
    print("speed-up = PyTorch median / jaxmotion median. jaxmotion's step: train.marionet.marionet_step as the loop "
          "runs it (key fold_in(key, step), state donated); its generation: the cached models.marionet.generate, "
          "jitted. The peer: benchmarks/peers/marionet_torch.py, eager; its generation re-runs the causal decoder "
          "over every frame so far at each frame (the paper's loop).")


if __name__ == "__main__":
    main()
