"""Benchmark: Neural Marionette's chain (``jaxmotion.pipelines.multi_action.chain_actions``), programs of 20
actions generated at once, as the pure pipeline, with Shadow Start on every action, and with Action Revision.

    python benchmarks/bench_chain.py [--programs 64] [--actions 20] [--frames 40] [--repeats 3] [--size cpu|paper]

What is timed (CPU, float32): ``--programs`` programs of ``--actions`` actions of ``--frames`` frames each (the
issue's 64 x 20 x ~40), one call of ``chain_actions`` (every action one jitted step over all programs: normalise the
context, generate frame by frame through the decoder's key/value cache, back to the world frame, the next context),
with Z sampled. MARIONET at the cpu profile's size (``--size paper``: the supplement's) with fresh parameters: the
time does not depend on what the weights learnt, only on how many actions Action Revision regenerates. Rows:

* **pure**: ``ChainOptions("never")``;
* **SS always**: ``ChainOptions("always")`` (Eq. 6 for every action: nearest begin poses of the tag among synth-mag's
  training actions, least squares, normalisation);
* **AR, all revised**: ``ChainOptions("revision")`` with a revision classifier (the evaluator's Transformer at the
  cpu size, fresh parameters) whose answers are replaced by wrong ones, so every action is classified and generated
  again: the worst case (a trained classifier on a trained model regenerates a share of them: the Revised column
  of ``marionet_revision``).

There is no peer: no other implementation of the system exists (the PyTorch peer of ``bench_marionet.py`` times
MARIONET's own generation, cached against frame-by-frame). Each row is called once to compile (reported), then
``--repeats`` times; medians and min-max in seconds, and actions per second.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import jax
import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # runnable from a checkout without installing

from benchmarks.timing import machine_header, time_alternately  # noqa: E402
from jaxmotion.data.datasets import load_dataset  # noqa: E402
from jaxmotion.models.marionet import MarionetConfig, init_marionet  # noqa: E402
from jaxmotion.models.recognition import Recognizer, RecognizerConfig, init_recognizer  # noqa: E402
from jaxmotion.pipelines.artefacts import DataFacts  # noqa: E402
from jaxmotion.pipelines.marionette import ContextGenerator, start_bank  # noqa: E402
from jaxmotion.pipelines.multi_action import ChainOptions, chain_actions  # noqa: E402
from jaxmotion.recipes.marionette import marionet_training  # noqa: E402


class AlwaysWrong:
    """A revision classifier that runs a real recogniser, then answers a class other than every action's tag."""

    def __init__(self, recognizer: Recognizer, tags: np.ndarray):
        self.recognizer, self.tags, self.num_classes = recognizer, tags, recognizer.num_classes
        self.calls = 0

    def __call__(self, motions, on_chunk=None):
        logits, features = self.recognizer(motions)
        jax.block_until_ready(logits)  # the classifier's work is part of the cost; its answer is replaced
        wrong = (np.argmax(self.tags[:, self.calls % self.tags.shape[1]], axis=-1) + 1) % self.num_classes
        self.calls += 1  # the chain asks once per action, in order
        return np.eye(self.num_classes)[wrong], features


def conditions(data, programs: int, actions: int, frames: int, seed: int = 0) -> dict[str, np.ndarray]:
    """Programs whose actions are training actions' tags (first tags), ``frames`` frames each, no path, starting
    from real contexts."""
    rng = np.random.default_rng(seed)
    items = data.action_items(6)
    picks = rng.integers(0, len(items), (programs, actions))
    tags = items.tags[picks]
    context = items.data.starts[picks[:, 0], None] + np.arange(6)
    return {"context_rotations": items.data.rotations[context], "context_translation": items.data.translation[context],
            "tags": tags, "next_tags": np.concatenate([tags[:, 1:], tags[:, -1:]], axis=1),
            "durations": np.full((programs, actions), frames, np.int32),
            "paths": np.zeros((programs, actions, frames, 2), np.float32),
            "follow": np.zeros((programs, actions), bool)}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--programs", type=int, default=64)
    parser.add_argument("--actions", type=int, default=20)
    parser.add_argument("--frames", type=int, default=40)
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--size", choices=("cpu", "paper"), default="cpu")
    args = parser.parse_args()
    print(machine_header())
    data = load_dataset("synth-mag", "train")
    model = marionet_training(args.size).model if args.size == "cpu" else MarionetConfig()
    params = jax.jit(init_marionet, static_argnums=1)(jax.random.key(0), model)
    generator = ContextGenerator(model, params, DataFacts.of(data), start_bank(data), max_frames=120)
    net = RecognizerConfig.transformer()
    recognizer = Recognizer(net, data.skeleton, tuple(data.class_names),
                            init_recognizer(jax.random.key(1), net, data.skeleton, data.num_classes))
    c = conditions(data, args.programs, args.actions, args.frames)
    count = args.programs * args.actions
    rows = {"pure": (ChainOptions("never"), None), "SS always": (ChainOptions("always"), None),
            "AR, all revised": (ChainOptions("revision"), AlwaysWrong(recognizer, c["tags"]))}
    calls, compile_s = [], {}
    for name, (options, reviser) in rows.items():
        def call(options=options, reviser=reviser):
            return chain_actions(generator, jax.random.key(2), c, options=options, reviser=reviser)

        tick = time.perf_counter()
        call()
        compile_s[name] = time.perf_counter() - tick
        calls.append(call)
    print(f"\n{args.programs} programs x {args.actions} actions x {args.frames} frames, MARIONET {args.size} size "
          f"(d {model.width}, decoder {model.decoder_layers} layers)\n")
    print("| chain | first call s (compile) | median s | min-max s | actions / s |")
    print("|---|---:|---:|---:|---:|")
    for (name, _), stats in zip(rows.items(), time_alternately(calls, args.repeats)):
        seconds = stats["median"] / 1e3
        print(f"| {name} | {compile_s[name]:.1f} | {seconds:.2f} | {stats['min'] / 1e3:.2f}-{stats['max'] / 1e3:.2f} "
              f"| {count / seconds:.0f} |")


if __name__ == "__main__":
    main()
