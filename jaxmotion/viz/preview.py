"""Look at motion datasets from the command line: grids of classes x modes (an animation, or a still of key poses),
and for multi-action datasets a whole take with its tag timeline, or the tag transition matrix
(:mod:`jaxmotion.viz.motion` draws them).

    python -m jaxmotion.viz.preview synth-humanact12 --classes 0,1,2 --out preview.gif
    python -m jaxmotion.viz.preview synth-humanact12 --classes 0,1,2 --out preview.mp4   # the video extra
    python -m jaxmotion.viz.preview synth-humanact12 --classes 0,1,2 --out preview.png --png
    python -m jaxmotion.viz.preview synth-mag --take 0 --out take.gif          # or --png for a strip
    python -m jaxmotion.viz.preview synth-mag --transitions --out transitions.png
"""

from __future__ import annotations

import argparse
from collections.abc import Sequence

from jaxmotion.viz.motion import render_grid, take_animation, take_strip, transition_heatmap
from jaxmotion.viz.scene import CAMERAS


def main(argv: Sequence[str] | None = None) -> None:
    parser = argparse.ArgumentParser(prog="python -m jaxmotion.viz.preview", description=__doc__.splitlines()[0])
    parser.add_argument("dataset", help="a synthetic variant name, e.g. synth-humanact12")
    parser.add_argument("--classes", default="0,1,2", help="comma-separated class indices")
    parser.add_argument("--out", default="preview.gif", help="a .gif or .mp4 (an animation), or with --png a .png")
    parser.add_argument("--png", action="store_true", help="save a still grid of key frames instead of an animation")
    parser.add_argument("--camera", default="auto", choices=CAMERAS,
                        help="animations: world (fixed, the paths on the ground), follow (on the root) or auto "
                             "(world for locomotion)")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--count", type=int, default=None,
                        help="generate only the first COUNT sequences (faster; enough for one per mode)")
    parser.add_argument("--split", default="train", help="the split to draw from (default: train)")
    parser.add_argument("--take", type=int, default=None,
                        help="a multi-action dataset: draw this take with its tag timeline (GIF, or --png a strip)")
    parser.add_argument("--transitions", action="store_true",
                        help="a multi-action dataset: draw the tag transition matrix (a PNG heat map)")
    args = parser.parse_args(argv)

    from jaxmotion.data import synthetic

    try:
        classes = [int(c) for c in args.classes.split(",")]
    except ValueError:
        parser.error(f"--classes: expected comma-separated class indices, got {args.classes!r}")
    try:
        data = synthetic.generate(args.dataset, args.split, seed=args.seed, count=args.count) if args.count else \
            synthetic.load(args.dataset, args.split, seed=args.seed)
        if args.transitions:
            transition_heatmap(data, args.out)
        elif args.take is not None:
            if args.png:
                take_strip(data, args.take, args.out)
            else:
                take_animation(data, args.take, args.out, camera=args.camera)
        else:
            render_grid(data, classes, args.out, still=args.png, camera=args.camera)
    except (ValueError, FileNotFoundError, ImportError) as err:  # what the checks raise: one line, as an experiment's
        raise SystemExit(f"jaxmotion.viz.preview: {err}") from None
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
