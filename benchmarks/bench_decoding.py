"""Benchmark: frame-by-frame generation of ACTOR's autoregressive baseline, through the key/value cache
(the library's decoding) against recomputing the causal pass for every frame (the decoding before the cache)
and against a PyTorch peer that decodes frame by frame, all timed in the same run.

    python benchmarks/bench_decoding.py [--frames 60,120,240] [--size cpu|paper] [--batch 20] [--repeats 3]
                                        [--torch-threads N]

What is timed (``float32``, CPU, eval mode, the decoder only: z given, ``batch`` sequences of full length):

* **cached**: ``jaxmotion.models.actor.decode`` without a target, jitted (what ``generate`` runs): the memory's
  cross-attention keys and values computed once, then a ``lax.scan`` over frames of
  ``jaxmotion.nn.transformer.decoder_stack_step``, each step projecting one frame and attending over the
  cached keys and values of the frames before it.
* **recomputed**: the library's decoding before the cache, rebuilt here from the public API: a
  ``fori_loop`` over frames whose step ``t`` runs one teacher-forced causal pass of all ``T`` frames
  (``decode(..., target=out)``) on the frames decoded so far and keeps its frame ``t``. Jitted.
* **PyTorch peer** (``benchmarks/peers/actor_autoregressive_torch.py``, joeynmt-style layers, eager, under
  ``torch.inference_mode``): for every frame ``t`` the decoder runs again over the frames ``0 .. t`` decoded
  so far and keeps the last output, with no cache, as a joeynmt decoder without incremental state does.
  It needs ``torch`` (``pip install -e ".[bench]"``); without it its columns stay empty.

Same weights (the peer is loaded with jaxmotion's initial parameters under joeynmt's names, ``strict=True``)
and the same z. Before timing, a parity check decodes one variable-length batch (the last third of the
frames randomly padded) on each side and prints max |difference| / max |x| of the cached output against the
recomputed one and against the peer's.

Timing (STYLE §3.12): the jitted functions are compiled ahead of time (``jit(...).lower(...).compile()``;
reported as "compile s"; PyTorch is eager and has none); each is called twice to warm up, then the three are
called in turn ``--repeats`` times (so background load hits them alike), jaxmotion with
``block_until_ready``; medians and min-max ranges in ms. The issue's target: cached >= 3x the peer at 120
frames. Threads: XLA's defaults (every core); the peer gets ``--torch-threads`` (default: as many as the
cores, as ``bench_actor.py``). On a machine other jobs load, PyTorch's OpenMP threads wait for each other:
there one thread ran the peer 4x faster than two, so pass the faster setting. Run it on a quiet machine; the
load average is printed before and after.
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

from benchmarks.timing import machine_header, time_alternately  # noqa: E402
from jaxmotion.models.actor import ActorConfig, decode, init_actor, length_mask  # noqa: E402
from jaxmotion.nn.transformer import state_dict  # noqa: E402

try:  # the PyTorch peer: pip install -e ".[bench]"
    import torch

    from benchmarks.peers import actor_autoregressive_torch as peer
except ImportError:  # (an installed but broken torch raises its own error here)
    torch = peer = None

CLASSES = 40
TARGET, TARGET_FRAMES = 3.0, 120
SIZES = {  # ACTOR's paper sizes, and the smaller ones bench_actor.py calls "cpu"
    "paper": {"width": 256, "ff": 1024, "layers": 8, "heads": 4},
    "cpu": {"width": 128, "ff": 512, "layers": 4, "heads": 4},
}
THREADS = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count()

# jaxmotion's decoder layer names -> joeynmt's (nn/transformer.py's module docstring gives the mapping)
_JOEYNMT_NAMES = {"self_attn": "trg_trg_att", "multihead_attn": "src_trg_att", "out_proj": "output_layer",
                  "norm1": "x_layer_norm", "norm2": "dec_layer_norm", "norm3": "feed_forward.layer_norm",
                  "linear1": "feed_forward.pwff_layer.0", "linear2": "feed_forward.pwff_layer.3"}


def peer_weights(decoder) -> dict[str, np.ndarray]:
    """jaxmotion's ``AutoregressiveDecoderParams`` under the peer's (joeynmt's) state-dict names."""
    weights = {"output_layer.weight": decoder.output_layer.weight}
    for name in ("embedding", "embedding_x", "layer_norm"):
        weights.update(state_dict(getattr(decoder, name), f"{name}."))
    for name, value in state_dict(decoder.layers, stacked=True).items():
        parts = [_JOEYNMT_NAMES.get(part, part) for part in name.split(".")]
        if parts[-1].startswith("in_proj_"):  # cat(q, k, v) -> three Linear layers
            kind = parts[-1].removeprefix("in_proj_")
            for part, q_k_v in zip(("q_layer", "k_layer", "v_layer"), np.split(value, 3)):
                weights[".".join([*parts[:-1], part, kind])] = q_k_v
        else:
            weights[".".join(parts)] = value
    return {name: np.array(value, np.float32, copy=True) for name, value in weights.items()}


def build_peer(config: ActorConfig, params):
    model = peer.AutoregressiveDecoderPeer(config.features, config.num_classes, dim=config.width, ff=config.ff,
                                           layers=config.layers, heads=config.heads)
    model.load_state_dict({k: torch.from_numpy(v) for k, v in peer_weights(params.decoder).items()}, strict=True)
    return model


def recomputed_decode(config: ActorConfig):
    """The decoding before the cache: frame ``t`` from a full teacher-forced causal pass on frames < t."""

    def run(params, z, actions, mask):
        def step(t, out):
            full = decode(config, params, z, actions, mask, target=out)
            return out.at[:, t].set(jax.lax.dynamic_index_in_dim(full, t, axis=1, keepdims=False))

        return jax.lax.fori_loop(0, mask.shape[1], step,
                                 jnp.zeros((*mask.shape, config.num_joints, config.channels), z.dtype))

    return run


def compiled(fn, *args) -> tuple:
    tick = time.perf_counter()
    executable = jax.jit(fn).lower(*args).compile()
    return executable, time.perf_counter() - tick


def relative_difference(a, b) -> float:
    a, b = np.asarray(a, np.float64), np.asarray(b, np.float64)
    return float(np.abs(a - b).max() / np.abs(a).max())


def bench(config: ActorConfig, params, frames: int, batch: int, repeats: int) -> dict:
    k_z, k_a, k_len = jax.random.split(jax.random.fold_in(jax.random.key(1), frames), 3)
    z = jax.random.normal(k_z, (batch, config.width))
    actions = jax.random.randint(k_a, (batch,), 0, config.num_classes)
    full = length_mask(jnp.full((batch,), frames), frames)
    cached, compile_cached = compiled(lambda p, z, a, m: decode(config, p, z, a, m), params, z, actions, full)
    recomputed, compile_recomputed = compiled(recomputed_decode(config), params, z, actions, full)

    # parity on a variable-length batch
    durations = jax.random.randint(k_len, (batch,), (2 * frames) // 3, frames + 1)
    varied = length_mask(durations, frames)
    ours = cached(params, z, actions, varied)
    parity = {"recomputed": relative_difference(ours, recomputed(params, z, actions, varied))}
    calls = [lambda: jax.block_until_ready(cached(params, z, actions, full)),
             lambda: jax.block_until_ready(recomputed(params, z, actions, full))]
    if peer is not None:
        model = build_peer(config, params)
        z_t, actions_t = torch.from_numpy(np.array(z)), torch.from_numpy(np.array(actions))
        theirs = peer.generate(model, z_t, actions_t, torch.from_numpy(np.array(durations)), frames)
        parity["peer"] = relative_difference(ours, theirs.numpy().reshape(ours.shape))
        full_t = torch.full((batch,), frames)
        calls.append(lambda: peer.generate(model, z_t, actions_t, full_t, frames))
    stats = time_alternately(calls, repeats)
    return {"cached": stats[0], "recomputed": stats[1], "peer": stats[2] if peer is not None else None,
            "compile_cached": compile_cached, "compile_recomputed": compile_recomputed, "parity": parity}


def _ms(stats: dict | None) -> tuple[str, str]:
    if stats is None:
        return "-", "-"
    return f"{stats['median']:.1f}", f"{stats['min']:.1f}-{stats['max']:.1f}"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--frames", default="60,120,240", help="comma-separated sequence lengths")
    parser.add_argument("--size", choices=tuple(SIZES), default="cpu")
    parser.add_argument("--batch", type=int, default=20)
    parser.add_argument("--repeats", type=int, default=3, help="timed calls per row and side, after two warm-up calls")
    parser.add_argument("--torch-threads", type=int, default=THREADS, help="torch.set_num_threads for the peer")
    args = parser.parse_args()
    frames_list = [int(f) for f in args.frames.split(",")]
    if args.repeats < 1 or args.batch < 1 or args.torch_threads < 1 or min(frames_list) < 1:
        parser.error("--repeats, --batch, --torch-threads and every --frames value must be >= 1")

    config = ActorConfig(num_classes=CLASSES, architecture="autoregressive", **SIZES[args.size])
    params = init_actor(jax.random.key(0), config)
    print(machine_header())
    print(f"XLA_FLAGS={os.environ.get('XLA_FLAGS', '') or '(unset)'}; repeats {args.repeats}; load average "
          f"before: {' '.join(f'{x:.2f}' for x in os.getloadavg())}")
    if peer is None:
        print('PyTorch peer: torch is not installed (`pip install -e ".[bench]"`); its columns are left empty.')
    else:
        torch.set_num_threads(args.torch_threads)
        print(f"PyTorch peer: torch {torch.__version__}, {torch.get_num_threads()} threads (XLA: its default, "
              f"{THREADS} cores), eager, float32")
    size = SIZES[args.size]
    print(f"ACTOR autoregressive decoder, {args.size} size (d {size['width']}, {size['layers']} layers, "
          f"{size['heads']} heads, FF {size['ff']}), batch {args.batch}, z given, eval mode\n")

    print("| frames | cached median ms | min-max | compile s | recomputed median ms | min-max | compile s "
          "| cached vs recomputed | PyTorch peer median ms | min-max | cached vs peer | parity vs recomputed "
          "| parity vs peer |")
    print("|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    rows = []
    for frames in frames_list:  # each row printed as soon as it is measured
        r = bench(config, params, frames, args.batch, args.repeats)
        rows.append((frames, r))
        cached, recomputed, theirs = r["cached"], r["recomputed"], r["peer"]
        cells = [str(frames), *_ms(cached), f"{r['compile_cached']:.1f}", *_ms(recomputed),
                 f"{r['compile_recomputed']:.1f}", f"{recomputed['median'] / cached['median']:.1f}x", *_ms(theirs),
                 "-" if theirs is None else f"{theirs['median'] / cached['median']:.1f}x",
                 f"{r['parity']['recomputed']:.1e}", f"{r['parity'].get('peer', float('nan')):.1e}"]
        print("| " + " | ".join(cells) + " |", flush=True)
    target_rows = [r for frames, r in rows if frames == TARGET_FRAMES and r["peer"] is not None]
    if target_rows:
        ratio = target_rows[0]["peer"]["median"] / target_rows[0]["cached"]["median"]
        print(f"\nTarget: cached >= {TARGET:g}x the peer at {TARGET_FRAMES} frames: {ratio:.1f}x, "
              f"{'met' if ratio >= TARGET else 'not met'}.")
    print(f"Load average after: {' '.join(f'{x:.2f}' for x in os.getloadavg())}")
    print("parity = max |difference| / max |x| against the cached output, on a batch with padded frames.")


if __name__ == "__main__":
    main()
