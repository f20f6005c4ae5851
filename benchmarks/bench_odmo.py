"""Benchmark: one ODMO training step, one sampling call and mode discovery, jit-compiled jaxmotion against a
PyTorch peer of the same architecture (and, for mode discovery, scikit-learn as the authors call it), timed
in the same run.

    python benchmarks/bench_odmo.py [--repeats 5] [--batch 512 [64 32 ...]] [--only train|generate|modes]
                                    [--per-class 250] [--codes 600] [--baseline-threads N] [--breakdown]

The PyTorch peer (``benchmarks/peers/odmo_torch.py``, written from the paper, FACTS.md §6 and jaxmotion's
docstrings) runs when ``import torch`` works: ``pip install -e ".[bench]"`` (torch is a benchmark extra, never
a runtime or test dependency); the mode-discovery baseline needs scikit-learn (the ``test`` extra). Without
one of them the script says so and leaves its columns empty.

Run it on a quiet machine: the numbers are wall times of multi-threaded CPU work, and any other job on the
cores slows them by tens of percent. Threads: XLA's defaults (its CPU client uses every core available to
the process; no thread flags are set here; ``XLA_FLAGS`` are printed as XLA sees them, including the
YNN-fusion workaround that importing jaxmotion adds on jaxlib 0.10); PyTorch (``torch.set_num_threads``) and
scikit-learn (BLAS and OpenMP, through ``threadpoolctl``) get the same core count, or ``--baseline-threads``.
Measured on the 2-core machine: scikit-learn's loop runs 2.5x faster on one thread than on two even when the
machine is quiet (its k-means and BLAS calls are too small to split), and on oversubscribed cores both
baselines' spinning OpenMP threads degrade 3-30x where XLA's degrade ~2x; ``--baseline-threads 1`` is then
the conservative comparison. ``taskset -c 0 python benchmarks/bench_odmo.py`` gives every side one core.

What is timed (``float32``, CPU, HumanAct12 sizes: ``ODMOConfig.humanact12()``, 24 joints, 12 classes, 60
frames, code 20):

* **Training step**: ``--batch`` pairs (default 512, the paper's; every size given is a row) of 60-frame
  windows, both halves through the autoencoder in train mode, the pair loss at ``ODMOLossConfig()``'s
  defaults, backward, global-norm clipping at 1, Adam 1e-3. jaxmotion: the library's own step
  (``jaxmotion.train.odmo.odmo_step`` on ``odmo_state``, as ``train_odmo``'s loop runs it: key
  ``fold_in(loop key, step)``, state donated), fed one pipeline pair batch (``make_batch_fn`` with
  ``ODMOTraining.batch``'s ``PairSpec`` on ``load_dataset("synth-humanact12", count=240)``). PyTorch: the
  peer's ``train_step`` on the same batch, eager (both halves concatenated for the LSTMs and the decoder
  loop, split only for BatchNorm; the decoder's constant condition share computed once per sequence, as
  jaxmotion's ``decode_motion`` does).
* **Sampling**: ``--per-class`` (250, the protocol's HumanAct12 count) codes per class x 12 classes = 3 000
  motions from given codes, classes and end roots, no teacher forcing. jaxmotion: ``models.odmo.generate``
  jitted over all rows at once, and the pipeline's ``generate_from_codes`` (host arrays in and out, in its
  default chunks of 2 048 rows); PyTorch: the peer's ``generate`` over all rows in eval mode under
  ``torch.inference_mode``.
* **Mode discovery** for every class: 12 classes of ~``--codes`` 20-dimensional codes (counts vary by ±10%
  between classes), each class drawn from its own mixture of 2-4 Gaussians (a stand-in for a trained code
  bank; the means a standard normal draw each, ~6 apart, spreads 0.2-0.6 per axis). jaxmotion:
  ``jaxmotion.mixtures.discover_modes_batched`` (the code's rule; one jitted call per k = 3, 4, ... fits every
  class whose rule has not broken yet, until none is left). scikit-learn: the authors' loop, per class for k = 3..9
  ``GaussianMixture(n_components=k, n_init=5, init_params="kmeans", random_state=0).fit_predict`` and
  ``silhouette_score``, stopping at the first ``S_k < 0.95 · S_{k−1}`` (k − 1 chosen, 9 if none), then the
  final fit at the chosen k.

Same weights, same loss: the peer is loaded with jaxmotion's initial parameters and running statistics
(``jaxmotion.models.odmo.state_dict`` names are the authors'; ``load_state_dict(strict=True)`` with
``num_batches_tracked`` added). Before timing, a parity check runs both steps on one 32-pair pipeline batch
with the same reparameterisation noise and teacher-forcing mask, both recovered from the step key exactly as
``odmo_step`` draws them (``k_tf, k_z = split(fold_in(loop key, step))``; ``ε = normal(k_z, [2B, Z])``;
``bernoulli(k_tf, rate, [2, T])`` per decoder step and half), with a teacher-forcing rate of 0.5 so that both
decoder paths run; it prints the two losses and their relative difference at the initial parameters and after
one update of each (which checks the gradients, the clipping and Adam), and the BatchNorm running statistics
after the first step (after the second they also carry the update of the biases in front of each BatchNorm,
whose gradient is zero up to rounding, so that Adam's first step moves them by ±lr with a sign set by
rounding noise: ~1e-3 relative, in both implementations alike, and invisible to the loss). Sampling is
checked on the same codes (max |Δ| / max |x| of the poses); mode discovery prints the k each side chose per
class next to the number of Gaussians the class was drawn from (the two use different random draws, so they
need not agree everywhere).

Timing: jaxmotion's step and ``generate`` are compiled ahead of time (``jit(...).lower(...).compile()``;
reported as "compile"); ``generate_from_codes`` and ``discover_modes_batched`` jit on their first call, whose
time (trace + compile + one run) is reported instead. PyTorch and scikit-learn have none. Each side is called
twice to warm up, then the sides are called alternately ``--repeats`` times (so background load hits both
alike), jaxmotion with ``block_until_ready``; the table gives medians and min-max ranges.

``--breakdown`` adds a table of where a step's time goes: forward, and forward + backward, of each network
alone (encoder, trajectory generator, motion generator) on both sides at the first ``--batch``.
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path

import jax
import jax.numpy as jnp
import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # runnable from a checkout without installing

from benchmarks.timing import machine_header, time_loop_step, time_pair
from jaxmotion.data.datasets import load_dataset
from jaxmotion.data.pipeline import make_batch_fn
from jaxmotion.mixtures import MODE_KS, choose_k, discover_modes_batched
from jaxmotion.models.odmo import ODMOConfig, generate, state_dict
from jaxmotion.pipelines.odmo import generate_from_codes
from jaxmotion.train.loop import LoopConfig
from jaxmotion.train.odmo import ODMOTraining, TeacherForcing, odmo_state, odmo_step

try:  # the PyTorch peer: pip install -e ".[bench]"
    import torch

    from benchmarks.peers import odmo_torch as peer
except ImportError:  # (an installed but broken torch raises its own error here)
    torch = peer = None

try:  # the mode-discovery baseline
    from sklearn.metrics import silhouette_score
    from sklearn.mixture import GaussianMixture
except ImportError:
    GaussianMixture = silhouette_score = None

TARGET_TRAIN, TARGET_GENERATE, TARGET_MODES = 1.5, 1.5, 2.0
DATASET, DATASET_COUNT = "synth-humanact12", 240
CHECK_BATCH, CHECK_RATE = 32, 0.5  # the parity batch (pairs) and its teacher-forcing rate
CODE_DIM = 20
CONFIG = ODMOConfig.humanact12()
# XLA's CPU client runs on every core the process may use; PyTorch is given the same number of threads.
THREADS = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count()


# --------------------------------------------------------------------------------------------- helpers


def relative(a: float, b: float) -> float:
    return abs(a - b) / max(abs(a), 1e-30)


def training(batch_size: int, teacher_forcing: TeacherForcing | None = None) -> ODMOTraining:
    """The library's recipe at HumanAct12 sizes with ``batch_size`` pairs (default teacher-forcing schedule)."""
    return ODMOTraining(model=CONFIG, batch_size=batch_size, loop=LoopConfig(steps=1),
                        teacher_forcing=TeacherForcing() if teacher_forcing is None else teacher_forcing)


def pair_batch(data, recipe: ODMOTraining, key: jax.Array) -> dict:
    """One pipeline pair batch (step 0 of ``make_batch_fn`` with the recipe's ``PairSpec``)."""
    return jax.block_until_ready(make_batch_fn(data, key, recipe.batch)(0))


def to_torch(tree):
    if isinstance(tree, dict):
        return {name: to_torch(value) for name, value in tree.items()}
    return torch.from_numpy(np.array(tree))


def build_peer(params, stats):
    """The peer at HumanAct12 sizes holding a copy of jaxmotion's parameters and running statistics."""
    model = peer.ODMOPeer(CONFIG.num_joints, CONFIG.num_classes, CONFIG.num_frames, CONFIG.code_dim)
    return peer.load_jaxmotion(model, state_dict(params, stats))  # copies, before any donation


def step_noise(recipe: ODMOTraining, step: jax.Array, key: jax.Array, pairs: int):
    """What ``odmo_step`` draws from its key: ``ε [2B, Z]`` and the teacher-forcing mask ``[T, 2B]``."""
    k_tf, k_z = jax.random.split(key)
    rate = recipe.teacher_forcing.rate(step)
    draws = jax.random.bernoulli(k_tf, rate, (2, recipe.model.num_frames))
    eps = jax.random.normal(k_z, (2 * pairs, recipe.model.code_dim), jnp.float32)
    return np.array(eps), np.array(jnp.repeat(draws.T, pairs, axis=1))


# ---------------------------------------------------------------------------------------------- parity


def max_stats_difference(stats, model) -> float:
    """max |Δ| / max |value| over the four running-statistics vectors of jaxmotion and the peer."""
    fc = model.LMPencoder.fc
    pairs = [(stats.bn1.running_mean, fc[1].running_mean), (stats.bn1.running_var, fc[1].running_var),
             (stats.bn4.running_mean, fc[4].running_mean), (stats.bn4.running_var, fc[4].running_var)]
    return max(float(np.abs(np.asarray(a) - b.numpy()).max() / np.abs(np.asarray(a)).max()) for a, b in pairs)


def check_train_parity(data, k_init: jax.Array, k_loop: jax.Array) -> dict:
    """Both steps on one batch with the same weights, noise and teacher-forcing masks: the losses at the
    initial parameters and after one update of each, and the running statistics after the first step."""
    recipe = training(CHECK_BATCH, TeacherForcing(start=CHECK_RATE, end=CHECK_RATE))
    state = odmo_state(recipe, k_init)
    batch = pair_batch(data, recipe, jax.random.key(7))
    model = build_peer(state.params, state.buffers)
    optimizer = peer.make_optimizer(model, recipe.learning_rate)
    step_fn = odmo_step(recipe)
    step = jax.jit(lambda state, batch, loop_key: step_fn(state, batch, jax.random.fold_in(loop_key, state.step)))
    batch_t = to_torch(batch)
    losses, forced, stats_diff = [], [], None
    for _ in range(2):
        eps, mask = step_noise(recipe, state.step, jax.random.fold_in(k_loop, state.step), CHECK_BATCH)
        forced.append(float(mask.mean()))
        state, terms = step(state, batch, k_loop)
        ours = float(terms["loss"])
        theirs = float(peer.train_step(model, optimizer, batch_t, eps=torch.from_numpy(eps),
                                       teacher_mask=torch.from_numpy(mask), clip_norm=recipe.clip_norm))
        losses.append((ours, theirs, relative(ours, theirs)))
        if stats_diff is None:  # after the first step: the statistics of the initial parameters
            stats_diff = max_stats_difference(state.buffers, model)
    return {"initial": losses[0], "updated": losses[1], "stats": stats_diff, "forced": forced}


def check_generate_parity(params, model, codes, actions, ends) -> float:
    """max |Δ poses| / max |poses| between the two samplers on the same codes (the first 256 rows)."""
    rows = slice(0, 256)
    ours = np.asarray(generate(CONFIG, params, codes[rows], actions[rows], ends[rows])["poses"])
    theirs = peer.generate(model, *(torch.from_numpy(np.array(a[rows])) for a in (codes, actions, ends)))["poses"]
    return float(np.abs(ours - theirs.numpy()).max() / np.abs(ours).max())


# ------------------------------------------------------------------------------------------------ rows


def bench_train(data, pairs: int, repeats: int, parity: bool) -> dict:
    recipe = training(pairs)
    k_init, k_data, k_loop = jax.random.split(jax.random.key(0), 3)
    state = odmo_state(recipe, k_init)
    batch = pair_batch(data, recipe, k_data)
    step_fn = odmo_step(recipe)  # the library's step, as train_odmo's loop builds it
    theirs, check = None, None
    if peer is not None:
        if parity:
            check = check_train_parity(data, k_init, k_loop)
        model = build_peer(state.params, state.buffers)  # the same initial weights, copied before donation
        optimizer = peer.make_optimizer(model, recipe.learning_rate)
        batch_t = to_torch(batch)
        rate = float(recipe.teacher_forcing.rate(0))

        def theirs():
            peer.train_step(model, optimizer, batch_t, rate=rate, clip_norm=recipe.clip_norm)

    return {**time_loop_step(step_fn, state, batch, k_loop, theirs, repeats), "parity": check}


def sampling_inputs(per_class: int):
    """Codes ``[N, Z]`` (per-class offsets plus noise, the scale of a trained bank's), classes ``[N]`` (class
    order, ``per_class`` each) and end roots ``[N, 3]``."""
    k_code, k_centre, k_end = jax.random.split(jax.random.key(3), 3)
    n = per_class * CONFIG.num_classes
    actions = jnp.repeat(jnp.arange(CONFIG.num_classes, dtype=jnp.int32), per_class)
    centres = 2.0 * jax.random.normal(k_centre, (CONFIG.num_classes, CONFIG.code_dim))
    codes = centres[actions] + 0.3 * jax.random.normal(k_code, (n, CONFIG.code_dim))
    ends = jax.random.normal(k_end, (n, 3)) * jnp.array([1.0, 0.05, 1.0])
    return jax.block_until_ready((codes, actions, ends))


def bench_generate(per_class: int, repeats: int) -> tuple[dict, dict]:
    """Two rows: the jitted ``generate`` over every row at once, and ``generate_from_codes``."""
    recipe = training(1)
    state = odmo_state(recipe, jax.random.key(0))
    params = state.params
    codes, actions, ends = sampling_inputs(per_class)

    def sample(params, codes, actions, ends):
        return generate(CONFIG, params, codes, actions, ends)

    theirs, check = None, None
    if peer is not None:
        model = build_peer(params, state.buffers)
        check = check_generate_parity(params, model, codes, actions, ends)
        inputs_t = [torch.from_numpy(np.array(a)) for a in (codes, actions, ends)]

        def theirs():
            peer.generate(model, *inputs_t)

    tick = time.perf_counter()
    compiled = jax.jit(sample).lower(params, codes, actions, ends).compile()
    compile_s = time.perf_counter() - tick
    result, peer_result = time_pair(lambda: jax.block_until_ready(compiled(params, codes, actions, ends)),
                                    theirs, repeats)
    direct = {**result, "peer": peer_result, "parity": check, "compile_s": compile_s}

    host = [np.asarray(a) for a in (codes, actions, ends)]
    tick = time.perf_counter()  # generate_from_codes jits on its first call: trace + compile + one run
    generate_from_codes(params, CONFIG, *host)
    first_s = time.perf_counter() - tick
    result, _ = time_pair(lambda: generate_from_codes(params, CONFIG, *host), None, repeats)
    # the peer's times from the alternating run above are shown again on this row for the ratio
    pipeline = {**result, "peer": peer_result, "parity": None, "compile_s": first_s}
    return direct, pipeline


def mode_codes(per_class: int, seed: int = 0) -> tuple[np.ndarray, np.ndarray, list[np.ndarray], list[int]]:
    """Per class ~``per_class`` (±10%) codes of ``CODE_DIM`` dims from a mixture of 2-4 Gaussians (means
    drawn from N(0, I), so ~6 apart; per-axis spreads 0.2-0.6; Dirichlet(4) weights): padded ``[C, M, Z]``, ``mask
    [C, M]``, the unpadded per-class arrays and each class's number of Gaussians."""
    rng = np.random.default_rng(seed)
    c = CONFIG.num_classes
    counts = rng.integers(int(0.9 * per_class), int(1.1 * per_class) + 1, c)
    width = int(counts.max())
    padded = np.zeros((c, width, CODE_DIM), np.float32)
    mask = np.zeros((c, width), bool)
    per, truth = [], []
    for i in range(c):
        k = int(rng.integers(2, 5))
        weights = rng.dirichlet(np.full(k, 4.0))
        means = rng.normal(0.0, 1.0, (k, CODE_DIM))
        which = rng.choice(k, counts[i], p=weights)
        scales = rng.uniform(0.2, 0.6, (k, CODE_DIM))
        x = (means[which] + rng.normal(0.0, 1.0, (counts[i], CODE_DIM)) * scales[which]).astype(np.float32)
        padded[i, :counts[i]], mask[i, :counts[i]] = x, True
        per.append(x)
        truth.append(k)
    return padded, mask, per, truth


def sklearn_modes(per_class: list[np.ndarray], n_init: int = 5) -> list[int]:
    """The authors' loop: per class, k = 3..9 until the silhouette drops below 0.95 of the previous one,
    then the final fit at the chosen k. Returns the chosen k per class."""
    chosen = []
    ks = list(MODE_KS["code"])
    for x in per_class:
        k_best, previous = ks[-1], None
        for k in ks:
            labels = GaussianMixture(n_components=k, n_init=n_init, init_params="kmeans",
                                     random_state=0).fit_predict(x)
            score = silhouette_score(x, labels)
            if previous is not None and score < 0.95 * previous:
                k_best = k - 1
                break
            previous = score
        GaussianMixture(n_components=k_best, n_init=n_init, init_params="kmeans", random_state=0).fit(x)
        chosen.append(k_best)
    return chosen


def bench_breakdown(data, pairs: int, repeats: int) -> list[tuple[str, dict, dict | None]]:
    """Where a training step's time goes: forward, and forward + backward (gradients of the parameters for
    the sum of squares of the network's output), of each network on the ``2B`` sequences of a step, both
    sides, alternately: the encoder (train mode, BatchNorm per half), the trajectory generator (code, class,
    true end root), the motion generator (trajectory encoder over the true root path, then the decoder loop
    with a teacher-forcing mask of rate ½). What is left of a step is the loss, the clipping and Adam."""
    from jaxmotion.models.odmo import (
        decode_motion,
        encode,
        flatten_poses,
        integrate,
        trajectory_velocities,
    )

    recipe = training(pairs)
    state = odmo_state(recipe, jax.random.key(0))
    params, stats = state.params, state.buffers
    batch = pair_batch(data, recipe, jax.random.key(1))
    poses = flatten_poses(jnp.concatenate([batch["first"]["joints"], batch["second"]["joints"]]))
    actions = jnp.concatenate([batch["first"]["actions"], batch["second"]["actions"]])
    k_code, k_mask = jax.random.split(jax.random.key(2))
    code = 0.3 * jax.random.normal(k_code, (2 * pairs, CONFIG.code_dim))
    mask = jnp.repeat(jax.random.bernoulli(k_mask, 0.5, (CONFIG.num_frames, 2)), pairs, axis=1)
    end, path = poses[:, -1, :3], poses[..., :3]

    def encoder(params):
        mu, logvar, _ = encode(CONFIG, params, stats, poses, train=True, groups=2)
        return jnp.square(mu).sum() + jnp.square(logvar).sum()

    def trajectory(params):
        return jnp.square(integrate(trajectory_velocities(params, code, actions, end, CONFIG))).sum()

    def motion(params):
        return jnp.square(decode_motion(params, code, actions, path, CONFIG, teacher=poses, teacher_mask=mask)).sum()

    parts = {"encoder": encoder, "trajectory generator": trajectory, "motion generator": motion}
    theirs = {}
    if peer is not None:
        model = build_peer(params, stats)
        model.train()
        p_t, a_t, c_t, m_t = (torch.from_numpy(np.array(a)) for a in (poses, actions, code, mask))
        end_t, path_t = p_t[:, -1, :3], p_t[..., :3]
        theirs = {"encoder": lambda: sum(v.square().sum() for v in model.LMPencoder(p_t, 2)),
                  "trajectory generator": lambda: peer.integrate(model.tgenerator(c_t, a_t, end_t)).square().sum(),
                  "motion generator": lambda: model.mgenerator(c_t, a_t, path_t, teacher=p_t,
                                                               teacher_mask=m_t).square().sum()}
    rows = []
    for name, fn in parts.items():
        forward_ = jax.jit(fn).lower(params).compile()
        backward_ = jax.jit(jax.grad(fn)).lower(params).compile()
        peer_forward = peer_backward = None
        if name in theirs:
            def peer_forward(fn_t=theirs[name]):
                with torch.no_grad():
                    fn_t()

            def peer_backward(fn_t=theirs[name]):
                model.zero_grad(set_to_none=True)
                fn_t().backward()

        fwd = time_pair(lambda f=forward_: jax.block_until_ready(f(params)), peer_forward, repeats)
        bwd = time_pair(lambda f=backward_: jax.block_until_ready(f(params)), peer_backward, repeats)
        rows.append((name, {"forward": fwd[0], "backward": bwd[0]},
                     None if peer is None else {"forward": fwd[1], "backward": bwd[1]}))
    return rows


def bench_modes(per_class: int, repeats: int, threads: int) -> dict:
    padded, mask, per, truth = mode_codes(per_class)
    x, m = jnp.asarray(padded), jnp.asarray(mask)
    key = jax.random.key(0)  # the code's random_state=0, as class_modes keys it

    def ours():
        return discover_modes_batched(key, x, m, rule="code", n_init=5)

    tick = time.perf_counter()  # jits on its first call: trace + compile + one run
    found = ours()
    first_s = time.perf_counter() - tick
    ours_k = [int(k) for k in found.k]
    # the rule on the returned silhouettes agrees with the returned k
    assert ours_k == [choose_k(row, found.ks, rule="code") for row in np.asarray(found.silhouettes)]
    theirs, theirs_k = None, None
    if GaussianMixture is not None:
        from threadpoolctl import threadpool_limits  # a scikit-learn dependency

        with threadpool_limits(threads):
            theirs_k = sklearn_modes(per)

        def theirs():
            with threadpool_limits(threads):
                sklearn_modes(per)

    result, base = time_pair(lambda: jax.block_until_ready(ours().labels), theirs, repeats)
    return {**result, "peer": base, "compile_s": first_s,
            "parity": {"jaxmotion": ours_k, "sklearn": theirs_k, "truth": truth,
                       "counts": mask.sum(1).tolist()}}


# -------------------------------------------------------------------------------------------------- main


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=5, help="timed calls per row and side, after two warm-up calls")
    parser.add_argument("--batch", type=int, nargs="+", default=[512],
                        help="training-step batch sizes in pairs (one row each; the paper's is 512)")
    parser.add_argument("--only", choices=("train", "generate", "modes"), default=None)
    parser.add_argument("--per-class", type=int, default=250, help="sampled motions per class (12 classes)")
    parser.add_argument("--codes", type=int, default=600, help="codes per class for mode discovery (±10%%)")
    parser.add_argument("--breakdown", action="store_true",
                        help="also time each network's forward and forward + backward at the first --batch")
    parser.add_argument("--baseline-threads", type=int, default=THREADS,
                        help="threads for PyTorch (torch.set_num_threads) and scikit-learn (threadpoolctl: BLAS "
                             "and OpenMP); default: the cores XLA uses")
    args = parser.parse_args()
    if args.repeats < 1 or min(args.batch) < 2 or args.per_class < 1 or args.codes < 20:
        parser.error("--repeats >= 1, --batch >= 2, --per-class >= 1 and --codes >= 20 are required")

    print(machine_header())
    # No thread settings for XLA: its defaults. jaxmotion's import may add its YNN-fusion workaround.
    print(f"XLA_FLAGS={os.environ.get('XLA_FLAGS', '') or '(unset)'} (no thread flags: XLA default threading, "
          f"{THREADS} cores); repeats {args.repeats}; load average {os.getloadavg()[0]:.1f} at the start")
    if peer is None:
        print('PyTorch peer: torch is not installed; the peer needs `pip install -e ".[bench]"` '
              "(its columns are left empty).")
    else:
        torch.set_num_threads(args.baseline_threads)
        print(f"PyTorch peer: torch {torch.__version__}, {torch.get_num_threads()} threads (torch.set_num_threads"
              + (", as many as XLA's cores" if args.baseline_threads == THREADS else "") + "), eager, float32")
    if GaussianMixture is None:
        print("scikit-learn is not installed: the mode-discovery baseline is left empty.")
    else:
        import sklearn

        print(f"scikit-learn {sklearn.__version__}, BLAS and OpenMP limited to {args.baseline_threads} threads "
              "(threadpoolctl)")
    print()

    rows = []  # (name, result, target, baseline name)
    data = None
    if args.only in (None, "train") or args.breakdown:
        data = load_dataset(DATASET, count=DATASET_COUNT)
        if (data.skeleton.num_joints, data.num_classes) != (CONFIG.num_joints, CONFIG.num_classes):
            raise SystemExit(f"{DATASET}: expected {CONFIG.num_joints} joints and {CONFIG.num_classes} classes")
    if args.only in (None, "train"):
        for i, pairs in enumerate(args.batch):
            rows.append((f"train step, {pairs} pairs x 60", bench_train(data, pairs, args.repeats, parity=i == 0),
                         TARGET_TRAIN, "PyTorch"))
    if args.only in (None, "generate"):
        n = args.per_class * CONFIG.num_classes
        direct, pipeline = bench_generate(args.per_class, args.repeats)
        rows.append((f"sample {n} x 60 (generate, jit)", direct, TARGET_GENERATE, "PyTorch"))
        rows.append((f"sample {n} x 60 (generate_from_codes)", pipeline, TARGET_GENERATE, "PyTorch"))
    if args.only in (None, "modes"):
        rows.append((f"mode discovery, 12 classes x ~{args.codes} x {CODE_DIM}",
                     bench_modes(args.codes, args.repeats, args.baseline_threads), TARGET_MODES, "scikit-learn"))

    print("Parity:")
    print()
    for name, r, _, _ in rows:
        p = r["parity"]
        if isinstance(p, dict) and "initial" in p:
            (a0, b0, d0), (a1, b1, d1) = p["initial"], p["updated"]
            print(f"* {name}: parity batch {CHECK_BATCH} pairs, teacher-forcing rate {CHECK_RATE} (forced share "
                  f"{p['forced'][0]:.2f} / {p['forced'][1]:.2f}), same ε and masks")
            print("| | loss jaxmotion | loss PyTorch | rel. diff |")
            print("|---|---:|---:|---:|")
            print(f"| initial parameters | {a0:.7g} | {b0:.7g} | {d0:.1e} |")
            print(f"| after one clipped Adam step of each | {a1:.7g} | {b1:.7g} | {d1:.1e} |")
            print(f"BatchNorm running statistics after the first step: max |Δ| / max |value| = {p['stats']:.1e}")
        elif isinstance(p, float):
            print(f"* {name}: the same 256 codes through both samplers, max |Δ poses| / max |poses| = {p:.1e}")
        elif isinstance(p, dict) and "truth" in p:
            agree = "-" if p["sklearn"] is None else sum(a == b for a, b in zip(p["jaxmotion"], p["sklearn"]))
            print(f"* {name}: codes per class {p['counts']}")
            print(f"  Gaussians drawn from: {p['truth']}")
            print(f"  k chosen, jaxmotion:    {p['jaxmotion']}")
            print(f"  k chosen, scikit-learn: {p['sklearn']} (same k for {agree} of 12 classes)")
    print()

    print("| call | jaxmotion median ms | min-max ms | compile s | baseline | baseline median ms | min-max ms "
          "| speed-up | target | met |")
    print("|---|---:|---:|---:|---|---:|---:|---:|---:|---|")
    for name, r, target, base in rows:
        p = r["peer"]
        speedup = None if p is None else p["median"] / r["median"]
        cells = [name, f"{r['median']:.1f}", f"{r['min']:.1f}-{r['max']:.1f}", f"{r['compile_s']:.1f}", base,
                 "-" if p is None else f"{p['median']:.1f}", "-" if p is None else f"{p['min']:.1f}-{p['max']:.1f}",
                 "-" if p is None else f"{speedup:.2f}x", f"{target:g}x",
                 "-" if p is None else ("yes" if speedup >= target else "no")]
        print("| " + " | ".join(cells) + " |")
    print()
    if args.breakdown:
        pairs = args.batch[0]
        print(f"Breakdown of a training step, {pairs} pairs ({2 * pairs} sequences) x 60 frames; median ms "
              "(min-max), each network alone, sum-of-squares output loss:")
        print()
        print("| network | jaxmotion forward | jaxmotion fwd + bwd | PyTorch forward | PyTorch fwd + bwd |")
        print("|---|---:|---:|---:|---:|")
        fmt = lambda r: f"{r['median']:.0f} ({r['min']:.0f}-{r['max']:.0f})"
        for name, ours, theirs in bench_breakdown(data, pairs, args.repeats):
            cells = [name, fmt(ours["forward"]), fmt(ours["backward"])]
            cells += ["-", "-"] if theirs is None else [fmt(theirs["forward"]), fmt(theirs["backward"])]
            print("| " + " | ".join(cells) + " |")
        print()
    print(f"Load average at the end: {os.getloadavg()[0]:.1f}")
    print("Notes:")
    print("* speed-up = baseline median / jaxmotion median; targets from the issue (step and sampling against "
          "PyTorch, mode discovery against scikit-learn).")
    print("* compile s: ahead-of-time compilation for the step and the jitted generate; for generate_from_codes "
          "and mode discovery, the first call (trace + compile + one run).")
    print("* The generate_from_codes row repeats the PyTorch times of the row above (the same peer call).")


if __name__ == "__main__":
    main()
