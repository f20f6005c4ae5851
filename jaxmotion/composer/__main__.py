"""``python -m jaxmotion.composer RUN``: serve the composer's page for a trained Neural Marionette run."""

from __future__ import annotations

import argparse
import sys
import time
from collections.abc import Sequence

from jaxmotion.composer.app import Composer
from jaxmotion.composer.server import make_server
from jaxmotion.evaluation.recognizers import trained_recognizer
from jaxmotion.geometry.body import load_body_model
from jaxmotion.pipelines.load import load_generator
from jaxmotion.recipes.evaluators import evaluator_spec


def main(argv: Sequence[str] | None = None) -> None:
    parser = argparse.ArgumentParser(
        prog="python -m jaxmotion.composer", description="Serve a web page where you draw a path, lay actions along "
        "it and watch a trained Neural Marionette model perform them (docs/composer.md).")
    parser.add_argument("run", help="a trained generator: its folder, a row folder or a run's seed folder (with --row)")
    parser.add_argument("--row", help="the row's folder when RUN holds several generators (e.g. marionet)")
    parser.add_argument("--host", default="127.0.0.1",
                        help="the address to bind (default 127.0.0.1, this machine only; 0.0.0.0 exposes it to the "
                             "network without authentication: put a reverse proxy in front)")
    parser.add_argument("--port", type=int, default=8000, help="the port (default 8000; 0: any free port)")
    parser.add_argument("--reviser", default="synth-mag/transformer-seed1",
                        help="Action Revision's classifier (an evaluator name; default synth-mag/transformer-seed1)")
    parser.add_argument("--reviser-profile", default="cpu", choices=("smoke", "cpu", "paper"),
                        help="the classifier's training profile (default cpu; trained once, then cached)")
    parser.add_argument("--no-revision", action="store_true",
                        help="no Action Revision (no classifier to train or load): Shadow Start always or never")
    parser.add_argument("--body-model", help="an SMPL-format body model file (.npz or .pkl, SMPL's 24 joints): the "
                        "page then shows the mesh (none is shipped: SMPL's licence)")
    parser.add_argument("--log", action="store_true", help="log every request to stderr")
    args = parser.parse_args(argv)
    try:
        generator = load_generator(args.run, row=args.row)
        reviser = None
        if not args.no_revision and generator.method == "marionet":
            reviser, _ = trained_recognizer(evaluator_spec(args.reviser, args.reviser_profile))
        body = None if args.body_model is None else load_body_model(args.body_model)
        composer = Composer(generator, reviser, body=body)
        server = make_server(composer, args.host, args.port, quiet=not args.log)
    except (ValueError, FileNotFoundError, OSError) as error:
        parser.exit(2, f"{parser.prog}: error: {error}\n")
    started = time.perf_counter()
    print(f"compiling {generator.method} for requests of any length ...", file=sys.stderr, flush=True)
    composer.warm_up()
    host, port = server.server_address[:2]
    print(f"ready in {time.perf_counter() - started:.1f} s: serving the composer at http://{host}:{port}/ "
          f"(Ctrl-C stops)", file=sys.stderr, flush=True)
    try:
        server.serve_forever()
    except KeyboardInterrupt:
        pass
    finally:
        server.server_close()


if __name__ == "__main__":
    main()
