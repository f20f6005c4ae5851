"""Benchmark: one ActFormer training iteration and the protocol's generation call, jit-compiled jaxmotion
against a PyTorch peer of the same architecture, timed in the same run.

    python benchmarks/bench_actformer.py [--repeats 5] [--batch 64 [32 ...]] [--only train|generate]
                                         [--per-class 100] [--baseline-threads N] [--peer-device cpu|cuda]
                                         [--precision highest|default] [--out PATH]

The PyTorch peer (``benchmarks/peers/actformer_torch.py``, written from FACTS.md §5 and jaxmotion's docstrings)
runs when ``import torch`` works: ``pip install -e ".[bench]"`` (torch is a benchmark extra, never a runtime or
test dependency). Without torch the script says so and leaves the PyTorch columns empty. ``--out PATH`` also
writes the header, the arguments, and each row's parity check and timings as JSON (rewritten after each part).

Devices: jaxmotion runs on JAX's default backend (the first device: a GPU when jax has its CUDA plugin and sees
one); the peer on ``--peer-device`` (default ``cuda`` when ``torch.cuda.is_available()``, else ``cpu``): its
models, optimisers, inputs and its own random draws live there, and on CUDA each timed peer call ends with
``torch.cuda.synchronize()`` so that its wall time covers the GPU work (jaxmotion's calls block on their
results). The header names the JAX backend and device and the peer's device. On a GPU machine, from the
repository root: ``PYTHONPATH=. python3 benchmarks/bench_actformer.py --out results.json``, or
``benchmarks/device_actformer.sh`` (writes the table and the JSON under ``$OUT``).

Precision: both sides compute in float32. jaxmotion leaves the matmul precision of its models to XLA's default
(only a few calls, such as the spectral-norm power iterations and the GP prior, ask for ``Precision.HIGHEST``),
which on GPUs may use TF32 for float32 dots and convolutions. ``--precision highest`` (the default) runs
everything under ``jax.default_matmul_precision("highest")`` and, for a CUDA peer, sets
``torch.backends.cuda.matmul.allow_tf32`` and ``torch.backends.cudnn.allow_tf32`` to False: full float32 on both
sides. ``--precision default`` leaves XLA's default and turns both TF32 flags on, roughly the same trade. A CPU
peer's precision settings are left at PyTorch's defaults (full float32).

On CPU, run it on a quiet machine: the numbers are wall times of multi-threaded CPU work, and any other job on
the cores slows them by tens of percent. Threads: XLA's defaults (its CPU client uses every core available to the
process; no thread flags are set here; ``XLA_FLAGS`` are printed as XLA sees them, including the YNN-fusion
workaround that importing jaxmotion adds on jaxlib 0.10); PyTorch gets the same core count
(``torch.set_num_threads``), or ``--baseline-threads``. Expect several minutes: a training iteration is five
generator passes and nine critic passes over 64 two-person clips, and the step compiles twice (the timed
batch and the parity batch).

What is timed (``float32``, the authors' NTU-2P configuration: ``GeneratorConfig(num_classes=26,
persons=2)``, i.e. 25 joints x 3 channels, 60 frames, width 8 per joint = 200, depth 2 (two I-Former +
T-Former pairs), 8 heads, MLP ratio 2, spectral norm, ``skeleton`` output; critic base 32 channels, 6 channels
per node (2 persons x 3) plus the motion flow, NTU-25 adjacencies from ``critic_graphs``; 1 358 075 and
5 174 593 parameters):

* **Training iteration**: ``--batch`` clips (default 64, the authors'; every size given is a row), 4 critic
  updates, each on its own real batch and fresh fakes, then 1 generator update; hinge loss; Adam 2e-4, betas
  (0, 0.999); every training forward moves its spectral-norm power iterations. jaxmotion: the library's own
  step (``jaxmotion.train.actformer.actformer_step`` on ``actformer_state``, as ``train_actformer``'s loop runs
  it: key ``fold_in(loop key, step)``, state donated), fed one pipeline batch (``make_batch_fn`` with
  ``ActFormerTraining.batch``, 4 x B snake-padded 60-frame windows, on ``load_dataset("synth-ntu2p",
  count=...)``); the step turns the joints into root + unit limb vectors and draws its GP latents and fake labels
  itself. PyTorch: the peer's ``train_iteration``, eager, on the same real windows already in the generator's
  representation (``real_batches``, computed once outside the timing: the authors' feeder also delivers
  prepared features, and this spares the peer work that jaxmotion's step does), drawing its latents
  (``torch.randn`` through the same GP factors) and labels itself.
* **Generation**: ``--per-class`` (100, the protocol's) clips for each of the 26 classes = 2 600 two-person
  clips of 60 frames, eval mode (the stored power-iteration vectors), from given GP latents. jaxmotion:
  ``models.actformer.generate`` jitted over all rows at once, and the pipeline's ``generate_motions`` (latents
  drawn per row, chunks of 256, joints rebuilt from the limb vectors, host arrays out, as the protocol's sampler
  calls it); PyTorch: the peer's ``generate`` over all rows under ``torch.inference_mode``. The power-iteration
  vectors are those after five training-mode generator passes (as after one training iteration), not the random
  start vectors, whose tiny sigmas blow the raw root joint up to ~1e3.

Same weights: the peer is loaded with jaxmotion's parameters and power-iteration vectors
(``actformer_torch.generator_state_dict`` / ``critic_state_dict`` of the pytrees, ``load_state_dict(strict=True)``
into ``torch.nn.utils.spectral_norm``'s ``weight_orig`` / ``weight_u`` / ``weight_v``). Parity, checked before
timing on a batch of ``CHECK_BATCH`` (16) at the same architecture:

* generator outputs (eval mode, the same latents, labels and vectors; max |Δ| over all outputs, and over the
  raw root joint relative to its largest value) and critic scores (eval mode, jaxmotion's state after one
  iteration loaded afresh, on real and generated clips; max |Δ| / max |score|);
* one critic loss and one generator loss with their gradients at the initial state on the same inputs (the
  first real batch and fakes from the latents the step draws for its first critic update and for its
  generator update), computed as ``actformer_step`` computes them: the losses' relative difference, and
  ``max |Δ grad| / max |grad|`` and ``‖Δ grad‖ / ‖grad‖`` over each network's parameters;
* one full training iteration from the identical initial state on the same real windows, the peer fed the
  latents and fake labels the jax step draws, reproduced from the step's key as ``actformer_step`` draws them
  (``split(fold_in(loop key, step), 5)``, then ``k_z, k_y = split(key_i)``, ``randint(k_y, [B], 0, 26)``,
  ``sample_latents(k_z)``): the last critic loss (after three critic updates) and the generator loss (after
  four), with relative differences, and the largest parameter difference after the iteration. Adam with
  β₁ = 0 moves every parameter by ~±lr · sign(g) on its first step, so parameters whose gradient is of the
  order of Adam's eps or of rounding (measured: the query and key rows of the first I-Former, which attends
  over two nearly identical person tokens) move by up to 2·lr = 4e-4 apart: in the runs made, the critic loss
  after three updates still agreed to ~1e-6 relative, the generator loss after four to ~1e-4 (the critic's
  conv4 and down3 weights differ most). The gradient check above is the exact one (~1e-6).

Timing: jaxmotion's step and ``generate`` are compiled ahead of time (``jit(...).lower(...).compile()``;
reported as "compile"); ``generate_motions`` jits on its first call, whose time (trace + compile + one run) is
reported instead. PyTorch is eager and has none. Each side is called twice to warm up, then the sides are called
alternately ``--repeats`` times (so background load hits both alike), jaxmotion with ``block_until_ready``, a
CUDA peer with ``torch.cuda.synchronize()``; the table gives medians and min-max ranges.
"""

from __future__ import annotations

import argparse
import contextlib
import json
import os
import sys
import time
from pathlib import Path

import jax
import jax.numpy as jnp
import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # runnable from a checkout without installing

from benchmarks.timing import as_loop_runs, machine_header, print_table, time_loop_step, time_pair
from jaxmotion.data.datasets import load_dataset
from jaxmotion.data.pipeline import make_batch_fn
from jaxmotion.models.actformer import GeneratorConfig, generate
from jaxmotion.models.actformer_critic import critic
from jaxmotion.pipelines.actformer import ActFormerGenerator, generate_motions
from jaxmotion.train.actformer import ActFormerTraining, actformer_state, actformer_step, critic_graphs, real_batches
from jaxmotion.models.actformer_prior import latent_factors, sample_latents
from jaxmotion.train.loop import LoopConfig

try:  # the PyTorch peer: pip install -e ".[bench]"
    import torch

    from benchmarks.peers import actformer_torch as peer
except ImportError:  # (an installed but broken torch raises its own error here)
    torch = peer = None

TARGET_TRAIN, TARGET_GENERATE = 1.5, 1.5
DATASET = "synth-ntu2p"
CHECK_BATCH = 16  # the parity batch (clips per critic update)
PARITY_ROWS = 256  # generated clips compared
WARM_PASSES = 5  # training-mode generator passes that move the start vectors before generation
CONFIG = GeneratorConfig(num_classes=26, persons=2)  # the authors' NTU-2P generator (the defaults otherwise)
# XLA's CPU client runs on every core the process may use; PyTorch is given the same number of threads.
THREADS = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count()
PEER_DEVICE = "cpu"  # where the peer's models and inputs live: set once by main from --peer-device


# --------------------------------------------------------------------------------------------- helpers


def relative(a: float, b: float) -> float:
    return abs(a - b) / max(abs(a), 1e-30)


def training(batch_size: int) -> ActFormerTraining:
    """The library's recipe (authors' defaults: critic base 32, n_critic 4, hinge, Adam 2e-4 (0, 0.999))."""
    return ActFormerTraining(generator=CONFIG, loop=LoopConfig(steps=1), batch_size=batch_size)


def pipeline_batch(data, recipe: ActFormerTraining, key: jax.Array) -> dict:
    """One pipeline batch of the recipe: ``n_critic · B`` windows (step 0 of ``make_batch_fn``)."""
    return jax.block_until_ready(make_batch_fn(data, key, recipe.batch)(0))


def to_torch(x):
    """A host copy of ``x`` as a tensor on the peer's device."""
    return torch.from_numpy(np.array(x)).to(PEER_DEVICE)


def to_numpy(t) -> np.ndarray:
    """A peer tensor (on any device) as a host array."""
    return t.detach().cpu().numpy()


def synchronised(fn):
    """``fn`` for timing: on CUDA, followed by ``torch.cuda.synchronize()`` so the wall time covers the GPU work;
    on CPU, ``fn`` itself."""
    if PEER_DEVICE != "cuda":
        return fn

    def call():
        fn()
        torch.cuda.synchronize()

    return call


def build_peers(recipe: ActFormerTraining, graphs, params: dict, buffers: dict):
    """Generator, critic and their Adams holding copies of jaxmotion's parameters and vectors, on the peer's
    device (parameters, power-iteration vectors and adjacency buffers)."""
    generator = peer.load_jaxmotion(peer.Generator(CONFIG.num_classes),
                                    peer.generator_state_dict(params["generator"], buffers["generator"]))
    critic_t = peer.load_jaxmotion(peer.Critic(graphs, CONFIG.num_classes, channels=recipe.critic.channels,
                                               base_channels=recipe.critic_base_channels),
                                   peer.critic_state_dict(params["critic"], buffers["critic"]))
    generator, critic_t = generator.to(PEER_DEVICE), critic_t.to(PEER_DEVICE)  # before the optimisers
    return generator, critic_t, peer.make_optimizers(generator, critic_t, recipe.learning_rate, recipe.betas)


def step_draws(recipe: ActFormerTraining, key: jax.Array) -> tuple[np.ndarray, np.ndarray]:
    """What ``actformer_step`` draws from its key: latents ``[N + 1, B, T, Z]`` and fake labels ``[N + 1, B]``,
    row ``i`` for critic update ``i``, the last for the generator update."""
    factors = latent_factors(recipe.model)
    latents, labels = [], []
    for k in jax.random.split(key, recipe.n_critic + 1):
        k_z, k_y = jax.random.split(k)
        labels.append(jax.random.randint(k_y, (recipe.batch_size,), 0, CONFIG.num_classes))
        latents.append(sample_latents(recipe.model, factors, k_z, recipe.batch_size))
    return np.array(jnp.stack(latents)), np.array(jnp.stack(labels))


# ---------------------------------------------------------------------------------------------- parity


def jax_losses(recipe: ActFormerTraining, graphs, params: dict, buffers: dict, real, real_labels, draws):
    """One critic loss and one generator loss with their gradients, as ``actformer_step`` computes them, from
    the same starting vectors: ``(d_loss, d_grads), (g_loss, g_grads)``."""
    g_cfg, c_cfg = recipe.generator, recipe.critic
    latents, labels = draws

    def critic_loss(c_params):
        fake, _ = generate(g_cfg, params["generator"], buffers["generator"], latents[0], labels[0], train=True)
        real_score, c_sn = critic(c_cfg, graphs, c_params, buffers["critic"], real, real_labels, train=True)
        fake_score, _ = critic(c_cfg, graphs, c_params, c_sn, jax.lax.stop_gradient(fake), labels[0], train=True)
        return jnp.mean(jax.nn.relu(1.0 - real_score)) + jnp.mean(jax.nn.relu(1.0 + fake_score))

    def generator_loss(g_params):
        fake, _ = generate(g_cfg, g_params, buffers["generator"], latents[-1], labels[-1], train=True)
        score, _ = critic(c_cfg, graphs, params["critic"], buffers["critic"], fake, labels[-1], train=True)
        return -jnp.mean(score)

    return (jax.jit(jax.value_and_grad(critic_loss))(params["critic"]),
            jax.jit(jax.value_and_grad(generator_loss))(params["generator"]))


def peer_losses(recipe: ActFormerTraining, graphs, params: dict, buffers: dict, real, real_labels, draws):
    """The same two losses and gradients from fresh peers (a training forward moves the vectors in place):
    ``(d_loss, {name: grad}), (g_loss, {name: grad})``."""
    latents, labels = (to_torch(a) for a in draws)
    grads = lambda model: {name: to_numpy(p.grad) for name, p in model.named_parameters()}  # noqa: E731
    generator, critic_t, _ = build_peers(recipe, graphs, params, buffers)
    with torch.no_grad():
        fake = generator(latents[0], labels[0])
    d_loss = (torch.relu(1.0 - critic_t(to_torch(real), to_torch(real_labels))).mean()
              + torch.relu(1.0 + critic_t(fake, labels[0])).mean())
    d_loss.backward()
    critic_grads = grads(critic_t)
    generator, critic_t, _ = build_peers(recipe, graphs, params, buffers)
    critic_t.requires_grad_(False)
    g_loss = -critic_t(generator(latents[-1], labels[-1]), labels[-1]).mean()
    g_loss.backward()
    return (d_loss.item(), critic_grads), (g_loss.item(), grads(generator))


def gradient_difference(ours: dict, theirs: dict) -> tuple[float, float]:
    """``max |Δ| / max |g|`` and ``‖Δ‖ / ‖g‖`` over every parameter of a network (names: the peer's)."""
    delta = np.concatenate([np.ravel(np.asarray(ours[name]) - g) for name, g in theirs.items()])
    g = np.concatenate([np.ravel(np.asarray(ours[name])) for name in theirs])
    return float(np.abs(delta).max() / np.abs(g).max()), float(np.linalg.norm(delta) / np.linalg.norm(g))


def max_parameter_difference(state, generator, critic_t) -> float:
    """Largest |Δ| over every parameter of both networks after training each side."""
    pairs = [(peer.generator_state_dict(state.params["generator"], state.buffers["generator"]), generator),
             (peer.critic_state_dict(state.params["critic"], state.buffers["critic"]), critic_t)]
    return max(float(np.abs(np.asarray(arrays[name]) - to_numpy(p)).max())
               for arrays, model in pairs for name, p in model.named_parameters())


def check_scores(recipe: ActFormerTraining, graphs, state, motions, labels) -> float:
    """Critic scores in eval mode with ``state``'s weights and vectors loaded afresh: max |Δ| / max |score|."""
    _, critic_t, _ = build_peers(recipe, graphs, state.params, state.buffers)
    ours, _ = critic(recipe.critic, graphs, state.params["critic"], state.buffers["critic"], motions, labels)
    theirs = to_numpy(peer.score(critic_t, to_torch(motions), to_torch(labels)))
    return float(np.abs(np.asarray(ours) - theirs).max() / np.abs(np.asarray(ours)).max())


def check_train_parity(data, graphs, parents, k_init: jax.Array, k_loop: jax.Array) -> dict:
    """Losses and gradients at the initial state, then one full iteration of each side from it."""
    recipe = training(CHECK_BATCH)
    state = actformer_state(recipe, graphs, k_init)
    batch = pipeline_batch(data, recipe, jax.random.key(7))
    reals, labels = real_batches(recipe, batch, parents)
    draws = step_draws(recipe, jax.random.fold_in(k_loop, state.step))
    (d_ours, d_grad), (g_ours, g_grad) = jax_losses(recipe, graphs, state.params, state.buffers, reals[0],
                                                    labels[0], draws)
    (d_theirs, d_grad_t), (g_theirs, g_grad_t) = peer_losses(recipe, graphs, state.params, state.buffers,
                                                             reals[0], labels[0], draws)
    gradients = {"critic": (float(d_ours), d_theirs, relative(float(d_ours), d_theirs),
                            *gradient_difference(peer.critic_state_dict(d_grad, state.buffers["critic"]), d_grad_t)),
                 "generator": (float(g_ours), g_theirs, relative(float(g_ours), g_theirs),
                               *gradient_difference(peer.generator_state_dict(g_grad, state.buffers["generator"]),
                                                    g_grad_t))}

    generator, critic_t, optimizers = build_peers(recipe, graphs, state.params, state.buffers)
    state, metrics = jax.jit(as_loop_runs(actformer_step(recipe, graphs, parents)))(state, batch, k_loop)
    d_theirs, g_theirs = peer.train_iteration(generator, critic_t, optimizers, to_torch(reals), to_torch(labels),
                                              latents=to_torch(draws[0]), fake_labels=to_torch(draws[1]))
    d_ours, g_ours = float(metrics["critic_loss"]), float(metrics["generator_loss"])
    iteration = {"critic": (d_ours, float(d_theirs), relative(d_ours, float(d_theirs))),
                 "generator": (g_ours, float(g_theirs), relative(g_ours, float(g_theirs))),
                 "parameters": max_parameter_difference(state, generator, critic_t)}
    fakes, _ = generate(CONFIG, state.params["generator"], state.buffers["generator"], jnp.asarray(draws[0][0]),
                        jnp.asarray(draws[1][0]))
    scores = {"real": check_scores(recipe, graphs, state, reals[0], labels[0]),
              "generated": check_scores(recipe, graphs, state, fakes, jnp.asarray(draws[1][0]))}
    return {"gradients": gradients, "iteration": iteration, "scores": scores}


def check_generate_parity(params, spectral, generator, z, labels) -> tuple[float, float]:
    """The first rows through both generators: max |Δ| over all outputs, and max |Δ root| / max |root|."""
    rows = slice(0, PARITY_ROWS)
    ours = np.asarray(generate(CONFIG, params, spectral, z[rows], labels[rows])[0])
    theirs = to_numpy(peer.generate(generator, to_torch(z[rows]), to_torch(labels[rows])))
    root = ours[..., 0, :]
    return float(np.abs(ours - theirs).max()), float(np.abs(root - theirs[..., 0, :]).max() / np.abs(root).max())


# ------------------------------------------------------------------------------------------------ rows


def bench_train(data, graphs, parents, batch_size: int, repeats: int, parity: bool) -> dict:
    recipe = training(batch_size)
    k_init, k_data, k_loop = jax.random.split(jax.random.key(0), 3)
    state = actformer_state(recipe, graphs, k_init)
    batch = pipeline_batch(data, recipe, k_data)

    theirs, check = None, None
    if peer is not None:
        if parity:
            check = check_train_parity(data, graphs, parents, k_init, k_loop)
        generator, critic_t, optimizers = build_peers(recipe, graphs, state.params, state.buffers)  # before donation
        reals, labels = (to_torch(a) for a in real_batches(recipe, batch, parents))
        factors = to_torch(latent_factors(recipe.model))

        def peer_iteration():
            peer.train_iteration(generator, critic_t, optimizers, reals, labels, factors=factors,
                                 num_classes=CONFIG.num_classes)

        theirs = synchronised(peer_iteration)

    step_fn = actformer_step(recipe, graphs, parents)
    return {**time_loop_step(step_fn, state, batch, k_loop, theirs, repeats), "parity": check}


def warm_state(recipe: ActFormerTraining, graphs):
    """The initial state with the generator's vectors moved by ``WARM_PASSES`` training-mode passes."""
    state = actformer_state(recipe, graphs, jax.random.key(0))
    params, spectral = state.params["generator"], state.buffers["generator"]
    z = sample_latents(recipe.model, latent_factors(recipe.model), jax.random.key(1), 2)
    move = jax.jit(lambda spectral: generate(CONFIG, params, spectral, z, jnp.zeros(2, jnp.int32), train=True)[1])
    for _ in range(WARM_PASSES):
        spectral = move(spectral)
    return state.with_buffer("generator", spectral)


def bench_generate(data, graphs, per_class: int, repeats: int) -> tuple[dict, dict]:
    """Two rows: the jitted ``generate`` over every row at once, and ``generate_motions``."""
    recipe = training(1)
    state = warm_state(recipe, graphs)
    params, spectral = state.params["generator"], state.buffers["generator"]
    labels = jnp.repeat(jnp.arange(CONFIG.num_classes, dtype=jnp.int32), per_class)
    z = jax.block_until_ready(sample_latents(recipe.model, latent_factors(recipe.model), jax.random.key(3), len(labels)))

    def sample(params, spectral, z, labels):
        return generate(CONFIG, params, spectral, z, labels)[0]

    tick = time.perf_counter()
    compiled = jax.jit(sample).lower(params, spectral, z, labels).compile()
    compile_s = time.perf_counter() - tick
    theirs, check = None, None
    if peer is not None:
        generator, _, _ = build_peers(recipe, graphs, state.params, state.buffers)
        check = check_generate_parity(params, spectral, generator, z, labels)
        z_t, labels_t = to_torch(z), to_torch(labels)

        def peer_generate():
            peer.generate(generator, z_t, labels_t)

        theirs = synchronised(peer_generate)

    direct, peer_result = time_pair(lambda: jax.block_until_ready(compiled(params, spectral, z, labels)), theirs,
                                    repeats)

    fitted = ActFormerGenerator.trained_on(recipe.model, state.params["generator"], state.buffers["generator"], data)
    actions, key = np.asarray(labels), jax.random.key(4)
    tick = time.perf_counter()  # jits on its first call: trace + compile + one run
    generate_motions(fitted, key, actions)
    first_s = time.perf_counter() - tick
    pipeline, _ = time_pair(lambda: generate_motions(fitted, key, actions), None, repeats)
    return ({**direct, "peer": peer_result, "parity": check, "compile_s": compile_s},
            {**pipeline, "peer": peer_result, "parity": None, "compile_s": first_s})


# -------------------------------------------------------------------------------------------------- main


def print_parity(rows) -> None:
    print("Parity:")
    print()
    if all(r["parity"] is None for _, r, _ in rows):
        print("(not checked: no PyTorch peer)")
    for name, r, _ in rows:
        p = r["parity"]
        if isinstance(p, dict):
            print(f"* {name}: parity batch {CHECK_BATCH} clips per critic update, same weights, vectors, real windows, "
                  "latents and fake labels")
            print("| | loss jaxmotion | loss PyTorch | rel. diff | grad max abs diff / max abs | grad ‖Δ‖ / ‖g‖ |")
            print("|---|---:|---:|---:|---:|---:|")
            for part, (a, b, d, gmax, gnorm) in p["gradients"].items():
                print(f"| {part} loss at the initial state | {a:.7g} | {b:.7g} | {d:.1e} | {gmax:.1e} | {gnorm:.1e} |")
            for part, label in (("critic", "last critic loss of one iteration (3 updates in)"),
                                ("generator", "generator loss of one iteration (4 critic updates in)")):
                a, b, d = p["iteration"][part]
                print(f"| {label} | {a:.7g} | {b:.7g} | {d:.1e} | | |")
            print(f"After the iteration: max |Δ parameter| = {p['iteration']['parameters']:.1e} (Adam's first steps "
                  "are ±lr = 2e-4 where a gradient is rounding-sized). Critic scores, eval mode, jaxmotion's state "
                  f"after the iteration: max |Δ| / max |score| = {p['scores']['real']:.1e} (real clips), "
                  f"{p['scores']['generated']:.1e} (generated clips)")
        elif isinstance(p, tuple):
            print(f"* {name}: the first {PARITY_ROWS} clips through both generators, same latents, labels and "
                  f"vectors: max |Δ| = {p[0]:.1e}; raw root joint max |Δ| / max |root| = {p[1]:.1e}")
    print()


def parity_json(p):
    """A row's parity check with named fields (None when not checked)."""
    if isinstance(p, dict):
        losses = ("jaxmotion", "pytorch", "relative_difference")
        return {"batch": CHECK_BATCH,
                "gradients": {part: dict(zip(losses + ("grad_max_abs_diff_over_max_abs", "grad_norm_diff_over_norm"),
                                             values)) for part, values in p["gradients"].items()},
                "iteration": {**{part: dict(zip(losses, p["iteration"][part])) for part in ("critic", "generator")},
                              "max_abs_parameter_difference": p["iteration"]["parameters"]},
                "critic_scores_max_abs_diff_over_max_abs": p["scores"]}
    if isinstance(p, tuple):
        return {"rows": PARITY_ROWS, "max_abs_difference": p[0], "root_max_abs_diff_over_max_abs": p[1]}
    return None


def write_json(path: Path, header: list[str], args, rows) -> None:
    """The header, the arguments, and every row's parity check and timings (ms; compile in s)."""
    def timings(r):
        return None if r is None else {k: r[k] for k in ("median", "min", "max")}

    doc = {"header": header, "args": {k: str(v) if isinstance(v, Path) else v for k, v in vars(args).items()},
           "rows": [{"call": name, "jaxmotion_ms": timings(r), "compile_s": r["compile_s"],
                     "pytorch_ms": timings(r["peer"]),
                     "speedup": None if r["peer"] is None else r["peer"]["median"] / r["median"], "target": target,
                     "parity": parity_json(r["parity"])} for name, r, target in rows]}
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps(doc, indent=1, default=float) + "\n")


def main() -> None:
    global PEER_DEVICE
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=5, help="timed calls per row and side, after two warm-up calls")
    parser.add_argument("--batch", type=int, nargs="+", default=[64],
                        help="clips per critic update (one row each; the authors' is 64)")
    parser.add_argument("--only", choices=("train", "generate"), default=None)
    parser.add_argument("--per-class", type=int, default=100, help="generated clips per class (26 classes)")
    parser.add_argument("--baseline-threads", type=int, default=THREADS,
                        help="threads for PyTorch (torch.set_num_threads); default: the cores XLA uses")
    parser.add_argument("--peer-device", choices=("cpu", "cuda"), default=None,
                        help="where the PyTorch peer runs; default: cuda if torch.cuda.is_available(), else cpu")
    parser.add_argument("--precision", choices=("default", "highest"), default="highest",
                        help="float32 matmul precision: highest (jax.default_matmul_precision('highest'), PyTorch "
                             "TF32 off on CUDA) or default (XLA's default, PyTorch TF32 on on CUDA)")
    parser.add_argument("--out", type=Path, default=None, help="also write the parity and timing rows as JSON here")
    args = parser.parse_args()
    if args.repeats < 1 or min(args.batch) < 1 or args.per_class < 1:
        parser.error("--repeats, --batch and --per-class must be >= 1")
    cuda = peer is not None and torch.cuda.is_available()
    if args.peer_device is None:
        args.peer_device = "cuda" if cuda else "cpu"
    elif args.peer_device == "cuda" and not cuda:
        parser.error("--peer-device cuda: " + ("torch is not installed" if peer is None
                                               else "torch.cuda.is_available() is False"))
    PEER_DEVICE = args.peer_device
    precision = (contextlib.nullcontext() if args.precision == "default"
                 else jax.default_matmul_precision(args.precision))
    with precision:  # read when each function is traced: covers every jit and op below
        run(args)


def run(args) -> None:
    device = jax.devices()[0]
    header = [machine_header(),
              # No thread settings for XLA: its defaults. jaxmotion's import may add its YNN-fusion workaround.
              f"XLA_FLAGS={os.environ.get('XLA_FLAGS', '') or '(unset)'} (no thread flags: XLA default threading, "
              f"{THREADS} cores); repeats {args.repeats}; load average {os.getloadavg()[0]:.1f} at the start",
              f"jaxmotion: JAX backend {jax.default_backend()}, device {device.device_kind} (platform "
              f"{device.platform}), float32, matmul precision "
              + ("'highest' (jax.default_matmul_precision: full float32 dots and convolutions)"
                 if args.precision == "highest" else
                 "XLA's default (on GPUs it may use TF32 for float32 dots and convolutions)")]
    if peer is None:
        header.append('PyTorch peer: torch is not installed; the peer needs `pip install -e ".[bench]"` '
                      "(its columns are left empty).")
    else:
        torch.set_num_threads(args.baseline_threads)
        torch.manual_seed(0)
        threads = (f"{torch.get_num_threads()} threads (torch.set_num_threads"
                   + (", as many as XLA's cores" if args.baseline_threads == THREADS else "") + ")")
        if PEER_DEVICE == "cuda":
            tf32 = args.precision == "default"
            torch.backends.cuda.matmul.allow_tf32 = torch.backends.cudnn.allow_tf32 = tf32
            header.append(f"PyTorch peer: torch {torch.__version__}, device cuda ({torch.cuda.get_device_name()}), "
                          f"{threads}, eager, float32, TF32 {'on' if tf32 else 'off'} "
                          f"(torch.backends.cuda.matmul.allow_tf32 = torch.backends.cudnn.allow_tf32 = {tf32}); "
                          "each timed call ends with torch.cuda.synchronize()")
        else:
            header.append(f"PyTorch peer: torch {torch.__version__}, device cpu, {threads}, eager, float32")
    print("\n".join(header))
    print()

    recipe = training(max(args.batch))
    windows = recipe.n_critic * max(args.batch)  # an epoch-sampled batch needs that many clips
    data = load_dataset(DATASET, count=max(windows, 2 * CONFIG.num_classes))
    if (data.skeleton.num_joints, data.persons, data.num_classes) != (CONFIG.joints, CONFIG.persons,
                                                                      CONFIG.num_classes):
        raise SystemExit(f"{DATASET}: expected {CONFIG.joints} joints, {CONFIG.persons} persons and "
                         f"{CONFIG.num_classes} classes")
    parents = data.skeleton.parents
    graphs = critic_graphs(recipe, parents)

    rows = []  # (name, result, target)

    def save() -> None:  # after each part, so that a run cut short still leaves its finished rows
        if args.out is not None:
            write_json(args.out, header, args, rows)

    if args.only in (None, "train"):
        for i, batch_size in enumerate(args.batch):
            rows.append((f"train iteration (4 critic + 1 generator), {batch_size} x 2 x 60",
                         bench_train(data, graphs, parents, batch_size, args.repeats, parity=i == 0), TARGET_TRAIN))
            save()
    if args.only in (None, "generate"):
        n = args.per_class * CONFIG.num_classes
        direct, pipeline = bench_generate(data, graphs, args.per_class, args.repeats)
        rows.append((f"generate {n} x 2 x 60 (generate, jit)", direct, TARGET_GENERATE))
        rows.append((f"generate {n} x 2 x 60 (generate_motions)", pipeline, TARGET_GENERATE))
        save()

    print_parity(rows)
    print_table(rows)
    print(f"Load average at the end: {os.getloadavg()[0]:.1f}")
    print("Notes:")
    print("* speed-up = PyTorch median / jaxmotion median; targets from the issue.")
    print("* compile s: ahead-of-time compilation for the step and the jitted generate; for generate_motions, the "
          "first call (trace + compile + one run).")
    print("* The generate_motions row repeats the PyTorch times of the row above (the same peer call; the peer "
          "neither draws the latents nor rebuilds joints).")


if __name__ == "__main__":
    main()
