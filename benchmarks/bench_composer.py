"""Benchmark: the composer's latency, from the page's Generate to a motion it can play.

    python benchmarks/bench_composer.py [RUN] [--row marionet] [--repeats 5] [--reviser-profile cpu]

``RUN``: a trained generator (as ``python -m jaxmotion.composer`` takes it); without one, MARIONET's tiny test size,
untrained, on four takes of synth-mag (what the tests serve). The server runs in this process on a free port, as the
command runs it: the generator loaded, Action Revision's classifier loaded (trained once and cached; ``--no-revision``
leaves it out), the chain compiled once at start-up (:meth:`~jaxmotion.composer.app.Composer.warm_up`, timed as
"start-up"). Then a request of 5 actions making 10 seconds (a walk along a drawn cubic, a turn, a run along a
straight line, a kick, a wave) is sent over HTTP ``--repeats`` times for each system the server offers,
each timed from sending the request to the last byte of the streamed motion (the page then only parses the JSON and
draws): medians and min-max in ms, with the time to the first action's progress line.
"""

from __future__ import annotations

import argparse
import http.client
import json
import statistics
import sys
import threading
import time
from pathlib import Path

import jax

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # runnable from a checkout without installing

from benchmarks.timing import machine_header  # noqa: E402
from jaxmotion.composer.app import Composer  # noqa: E402
from jaxmotion.composer.server import make_server  # noqa: E402
from jaxmotion.evaluation.recognizers import trained_recognizer  # noqa: E402
from jaxmotion.pipelines.load import load_generator  # noqa: E402
from jaxmotion.recipes.evaluators import evaluator_spec  # noqa: E402

PROGRAM = [{"tags": ["Walk"], "seconds": 2.5, "path": [[0, 0], [0.5, 1.2], [1.5, 2.0], [2.5, 2.2]]},
           {"tags": ["Turn"], "seconds": 1.5}, {"tags": ["Run"], "seconds": 2.0, "path": [[2.5, 2.2], [5.0, 2.5]]},
           {"tags": ["Kick"], "seconds": 2.0}, {"tags": ["Wave Hand"], "seconds": 2.0}]


def tiny_generator():
    from jaxmotion.data import synthetic
    from jaxmotion.models.marionet import MarionetConfig, init_marionet
    from jaxmotion.pipelines.artefacts import DataFacts
    from jaxmotion.pipelines.marionette import ContextGenerator, start_bank

    takes = synthetic.generate("synth-mag", "test", seed=0, count=4, progress=False)
    config = MarionetConfig.tiny()
    params = jax.jit(init_marionet, static_argnums=1)(jax.random.key(0), config)
    return ContextGenerator(config, params, DataFacts.of(takes), start_bank(takes, per_tag=2))


def timed_request(port: int, payload: dict) -> tuple[float, float, dict]:
    """(seconds to the first action line, seconds to the end, the motion) of one generate request."""
    start = time.perf_counter()
    connection = http.client.HTTPConnection("127.0.0.1", port, timeout=600)
    connection.request("POST", "/api/generate", body=json.dumps(payload).encode())
    response = connection.getresponse()
    first, motion = None, None
    for line in response:
        event = json.loads(line)
        if event["event"] == "action" and first is None:
            first = time.perf_counter() - start
        if event["event"] == "error":
            raise RuntimeError(event["message"])
        if event["event"] == "done":
            motion = event["motion"]
    return first, time.perf_counter() - start, motion


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("run", nargs="?", help="a trained generator (default: the tests' tiny untrained one)")
    parser.add_argument("--row", help="the row's folder when RUN holds several generators (e.g. marionet)")
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--reviser-profile", default="cpu", choices=("smoke", "cpu", "paper"))
    parser.add_argument("--no-revision", action="store_true")
    args = parser.parse_args()
    print(machine_header())
    generator = load_generator(args.run, row=args.row) if args.run else tiny_generator()
    reviser = None
    if not args.no_revision:
        reviser, _ = trained_recognizer(evaluator_spec("synth-mag/transformer-seed1", args.reviser_profile),
                                        progress=False)
    composer = Composer(generator, reviser)
    start = time.perf_counter()
    composer.warm_up()
    startup = time.perf_counter() - start
    server = make_server(composer, port=0)
    threading.Thread(target=server.serve_forever, daemon=True).start()
    port = server.server_address[1]
    seconds = sum(a["seconds"] for a in PROGRAM)
    print(f"\n{generator.method}, up to {generator.max_frames} frames an action; start-up (compiling the chain "
          f"for {composer.shadow_modes[0]}): {startup:.1f} s\nrequest: {len(PROGRAM)} actions, {seconds:g} s, "
          f"{args.repeats} times per system after one untimed request\n")
    rows = []
    for mode in composer.shadow_modes:
        payload = {"actions": PROGRAM, "shadow": mode}
        timed_request(port, payload)  # a system other than the warmed-up one compiles here
        runs = [timed_request(port, {**payload, "seed": seed}) for seed in range(args.repeats)]
        firsts, totals = [1e3 * r[0] for r in runs], [1e3 * r[1] for r in runs]
        revised = sum(sum(s["revised"] for s in r[2]["segments"]) for r in runs)
        rows.append({"system": mode, "first action (ms)": f"{statistics.median(firsts):.0f}",
                     "motion received (ms)": f"{statistics.median(totals):.0f} ({min(totals):.0f}-{max(totals):.0f})",
                     "frames": runs[0][2]["frames"], "actions revised": f"{revised} of {len(PROGRAM) * len(runs)}"})
    print("| " + " | ".join(rows[0]) + " |\n|" + "---|" * len(rows[0]))
    for row in rows:
        print("| " + " | ".join(map(str, row.values())) + " |")
    server.shutdown()


if __name__ == "__main__":
    main()
