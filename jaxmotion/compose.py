"""One long motion from a written list of actions, by a trained Neural Marionette model (or MANN, adapted A2M).

    python -m jaxmotion.compose RUN "stand up 2s, walk 3s along 0,0 2,1 4,0, kick 1.5s, run 2s" --out motion.bvh

``RUN``: a trained generator (its folder, a row folder, or a run's seed folder with ``--row``). The actions, in
order, separated by commas (or semicolons): each is its tags (names as the model knows them, any case; several
joined by ``+``: ``sit + arm movement``), its duration (``2s`` seconds or ``45f`` frames), and optionally ``along``
and ground points ``x,z`` in metres (world frame: the character starts from a training start of the first tag,
over the origin, facing +z), the control points of the Bézier curve its root follows (four make the supplement's
cubic, two a straight line). ``--out``: ``.bvh``, ``.npz`` (AMASS layout) or ``.npy`` (joints); the segment table
(tags, first frame and end frame, whether Shadow Start or Action Revision acted) is written beside it as
``<name>.segments.json``, and a picture, ``<name>.png``: poses along the motion above its tag timeline (with
``--gif`` also ``<name>.gif`` and with ``--video`` ``<name>.mp4``: the body in 3D with the timeline's cursor; seconds
of rendering per hundred frames, so off by default; with ``--clean-feet`` every file and picture shows the cleaned
motion). An action
whose tag never followed the previous one's in training gets a warning (the paper's failure case). ``--shadow``
chooses Table 5's system: ``never`` (the pure pipeline), ``always``, or ``revision`` (Action Revision, with the
classifier ``--reviser``, trained once and cached); where Shadow Start acts, ``--smoothing`` frames blend the action
in from the pose before it (the paper's interface does so; its tables do not). An action whose path starts in a
direction none of its tag's training starts took, relative to the body, starts turned towards it (the interface's
orientation check; ``--no-orientation``: off).
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import re
import sys
from collections.abc import Callable, Sequence
from pathlib import Path

import jax
import numpy as np

from jaxmotion.data.export import export_arguments, export_motions, export_options, with_clean_feet
from jaxmotion.data.motion import MotionDataset, to_dataset
from jaxmotion.data.segments import Program, ProgramAction, Segments
from jaxmotion.evaluation.recognizers import trained_recognizer
from jaxmotion.files import write_atomic
from jaxmotion.pipelines.load import load_generator
from jaxmotion.pipelines.marionette import ContextGenerator
from jaxmotion.pipelines.multi_action import ChainOptions, bezier_path, chain_actions, joined, program_conditions
from jaxmotion.recipes.evaluators import evaluator_spec
from jaxmotion.viz.motion import take_animation, take_strip
from jaxmotion.viz.video import check_video_path

_ACTION = re.compile(r"^(?P<tags>.+?)\s+(?P<amount>\d+(?:\.\d+)?)(?P<unit>s|f)(?:\s+along\s+(?P<path>.+))?$")
_POINT = re.compile(r"^(-?\d+(?:\.\d+)?),(-?\d+(?:\.\d+)?)$")
FORMATS = {".bvh": "bvh", ".npz": "npz", ".npy": "npy"}


def canonical_tag(tag: str, tag_names: Sequence[str]) -> str:
    """The name in ``tag_names`` that ``tag`` spells (any case, any spacing); a ``ValueError`` listing the names."""
    names = {" ".join(name.lower().split()): name for name in tag_names}
    name = names.get(" ".join(tag.lower().split()))
    if name is None:
        raise ValueError(f"unknown tag {tag.strip()!r}; the model knows: {', '.join(tag_names)}")
    return name


def parse_actions(text: str, tag_names: Sequence[str], fps: float, max_frames: int) -> Program:
    """The :class:`~jaxmotion.data.segments.Program` a written list describes (module docstring); a ``ValueError``
    naming the action (its number and text) and what is wrong."""
    items = [item.strip() for item in re.split(r",\s+|;", text.strip()) if item.strip()]
    if not items:
        raise ValueError("actions: expected at least one action, e.g. \"walk 2s, kick 1.5s\"")
    actions = []
    for number, item in enumerate(items, 1):
        where = f"action {number} ({item!r})"
        match = _ACTION.match(" ".join(item.split()))
        if match is None:
            raise ValueError(f"{where}: expected '<tags> <duration>s|f [along x,z x,z ...]', e.g. 'walk 3s along "
                             f"0,0 2,1'")
        try:
            tags = [canonical_tag(tag, tag_names) for tag in match["tags"].split("+")]
        except ValueError as error:
            raise ValueError(f"{where}: tags: {error}") from None
        amount = float(match["amount"])
        frames = round(amount * fps) if match["unit"] == "s" else int(amount)
        if not 1 <= frames <= max_frames:
            raise ValueError(f"{where}: duration: expected 1 to {max_frames} frames ({max_frames / fps:g} s at "
                             f"{fps:g} fps, the model's longest action), got {frames}")
        path = None
        if match["path"] is not None:
            points = [_POINT.match(p) for p in match["path"].split()]
            if len(points) < 2 or not all(points):
                raise ValueError(f"{where}: path: expected two or more ground points 'x,z' after 'along', got "
                                 f"{match['path']!r}")
            control = np.array([[float(p[1]), float(p[2])] for p in points])
            path = tuple(map(tuple, bezier_path(control, frames).tolist()))
        actions.append(ProgramAction(tuple(tags), frames, path))
    return Program(tuple(actions))


def compose(generator: ContextGenerator, program: Program, key: jax.Array, *,
            options: ChainOptions = ChainOptions(), reviser=None, mean: bool = False, padded: bool = False,
            on_action: Callable[[int, bool, bool], None] | None = None) -> dict:
    """One motion of ``program``'s actions in order (:func:`~jaxmotion.pipelines.multi_action.chain_actions`):
    ``rotations [T, 24, 3]``, ``translation [T, 3]``, ``joints [T, 24, 3]`` and ``segments`` (per action: tags,
    first frame, end frame, ``shadowed``, ``revised``, ``turned``: degrees by which the orientation check turned its
    start). ``mean``: Z = mu for every action. ``padded``: every action
    generated at the model's longest duration (then cut), so any program reuses one compilation (a server's
    choice). ``on_action(a, shadowed, revised)``: called as each action is done."""
    k_start, k_chain = jax.random.split(key)
    conditions = program_conditions(generator, program, k_start, frames=generator.max_frames if padded else None)
    report = None if on_action is None else (lambda a, shadowed, revised: on_action(a, bool(shadowed[0]),
                                                                                      bool(revised[0])))
    chained = chain_actions(generator, None if mean else k_chain, conditions, options=options, reviser=reviser,
                            on_action=report)
    motion = joined(chained)
    ends = motion["starts"][0] + chained["lengths"][0]
    revised = chained.get("revised", np.zeros_like(chained["shadowed"]))[0]
    turned = np.rad2deg(chained.get("turned", np.zeros(chained["shadowed"].shape, np.float32))[0])
    segments = [{"tags": list(action.tags), "start": int(start), "end": int(end), "shadowed": bool(shadowed),
                 "revised": bool(again), "turned": round(float(turn), 1)} for action, start, end, shadowed, again, turn
                in zip(program.actions, motion["starts"][0], ends, chained["shadowed"][0], revised, turned)]
    frames = int(motion["lengths"][0])
    return {**{k: motion[k][0, :frames] for k in ("rotations", "translation", "joints")}, "segments": segments}


def unseen_pairs(generator: ContextGenerator, program: Program) -> list[str]:
    """A warning for each action whose first tag never followed the previous action's in the training takes (the
    paper's failure case: the chain leaves what it learnt; Fig. 11b)."""
    labels = np.argmax(program.tag_matrix(generator.class_names), axis=1)
    names, seen = generator.class_names, generator.starts.transitions
    return [f"action {a + 1} ({names[after]}) after action {a} ({names[before]}): the model never saw "
            f"{names[before]!r} followed by {names[after]!r} in training; the motion may go astray there"
            for a, (before, after) in enumerate(zip(labels[:-1], labels[1:]), 1) if not seen[before, after]]


def motion_dataset(generator: ContextGenerator, motion: dict, name: str = "composed") -> MotionDataset:
    """A composed ``motion`` (:func:`compose`) as a one-take dataset with its segment table (for pictures)."""
    frames = len(motion["joints"])
    batch = {**{k: motion[k][None] for k in ("rotations", "translation", "joints")}, "lengths": np.array([frames]),
             "actions": np.zeros(1, np.int32)}
    data = to_dataset(batch, generator.facts.skeleton, generator.class_names, generator.fps, name=name)
    tags = np.zeros((len(motion["segments"]), len(generator.class_names)), bool)
    for row, segment in enumerate(motion["segments"]):
        tags[row, [generator.class_names.index(t) for t in segment["tags"]]] = True
    count = len(tags)
    segments = Segments(np.zeros(count, np.int32), np.array([s["start"] for s in motion["segments"]], np.int32),
                        np.array([s["end"] for s in motion["segments"]], np.int32), tags,
                        np.concatenate([tags[1:], tags[-1:]]), np.full(count, -1, np.int32))
    return dataclasses.replace(data, segments=segments)


def main(argv: Sequence[str] | None = None) -> Path:
    parser = argparse.ArgumentParser(prog="python -m jaxmotion.compose", description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("run", help="a trained generator: its folder, a row folder or a run's seed folder")
    parser.add_argument("actions", help="the actions, e.g. \"stand up 2s, walk 3s along 0,0 2,1 4,0, kick 1.5s\"")
    parser.add_argument("--out", required=True, help="the motion file: .bvh, .npz (AMASS layout) or .npy (joints)")
    parser.add_argument("--row", help="the row's folder when RUN holds several generators (e.g. marionet)")
    parser.add_argument("--seed", type=int, default=0, help="draws the start and every Z (default 0)")
    parser.add_argument("--mean", action="store_true", help="Z = mu for every action (no sampling)")
    parser.add_argument("--shadow", choices=("never", "always", "revision"), default="never",
                        help="Shadow Start: never (the pure pipeline, default), always, or on Action Revision")
    parser.add_argument("--smoothing", type=int, default=6,
                        help="frames over which an action that starts from its shadow is blended in from the pose "
                             "before it (slerp; the paper's interface; default 6, 0: off)")
    parser.add_argument("--reviser", default="synth-mag/transformer-seed1",
                        help="Action Revision's classifier (an evaluator name; default synth-mag/transformer-seed1)")
    parser.add_argument("--reviser-profile", default="cpu", choices=("smoke", "cpu", "paper"),
                        help="the classifier's training profile (default cpu; trained once, then cached)")
    parser.add_argument("--no-orientation", action="store_true",
                        help="no start orientation check (on by default: an action whose path starts where its tag "
                             "never headed in training starts turned towards it, as the paper's interface does)")
    export_arguments(parser)
    parser.add_argument("--gif", action="store_true",
                        help="also write <name>.gif: the body in 3D above the tag timeline with a moving cursor")
    parser.add_argument("--video", action="store_true",
                        help="also write <name>.mp4, the same animation as a video (needs jaxmotion[video])")
    args = parser.parse_args(argv)
    out = Path(args.out)
    try:
        if out.suffix not in FORMATS:
            raise ValueError(f"--out: expected a .bvh, .npz or .npy file, got {out.name!r}")
        export = export_options(args, (FORMATS[out.suffix],))
        if args.video:
            check_video_path(out.with_suffix(".mp4"), "--video")  # the video extra, before anything is generated
        generator = load_generator(args.run, row=args.row)
        if not isinstance(generator, ContextGenerator):
            raise ValueError(f"RUN: {args.run} holds a {generator.method} generator, which does not continue a "
                             f"context; compose needs MARIONET, MANN or adapted A2M")
        program = parse_actions(args.actions, generator.class_names, generator.fps, generator.max_frames)
        for warning in unseen_pairs(generator, program):
            print(f"warning: {warning}", file=sys.stderr)
        reviser = None
        if args.shadow == "revision":
            reviser, _ = trained_recognizer(evaluator_spec(args.reviser, args.reviser_profile))
        options = ChainOptions(args.shadow, smoothing=args.smoothing, orientation=not args.no_orientation)
        motion = compose(generator, program, jax.random.key(args.seed), options=options, reviser=reviser,
                         mean=args.mean)
    except (ValueError, FileNotFoundError, ImportError) as error:
        parser.exit(2, f"{parser.prog}: error: {error}\n")
    if export.clean_feet:  # cleaned once, before the file and the pictures, so that they show one motion
        motion["rotations"], motion["joints"] = with_clean_feet(motion["rotations"], motion["translation"],
                                                                motion["joints"], generator.facts.skeleton.parents,
                                                                generator.fps)
        export = dataclasses.replace(export, clean_feet=False)
    batch = {k: motion[k][None] for k in ("rotations", "translation", "joints")}
    written = export_motions(out.parent, batch, generator.facts.skeleton, generator.fps, formats=(FORMATS[out.suffix],),
                             names=[out.stem], options=export)
    table = out.with_name(f"{out.stem}.segments.json")
    write_atomic(table, json.dumps({"fps": generator.fps, "frames": len(motion["joints"]),
                                    "segments": motion["segments"]}, indent=1).encode())
    animations = [out.with_suffix(suffix) for suffix, wanted in ((".gif", args.gif), (".mp4", args.video)) if wanted]
    pictures = [out.with_suffix(".png"), *animations]
    as_dataset = motion_dataset(generator, motion, out.stem)
    take_strip(as_dataset, 0, str(pictures[0]))
    for path in animations:
        take_animation(as_dataset, 0, str(path))
    print(f"{written[0]}: {len(motion['joints'])} frames, {len(program.actions)} actions; segments in {table}, "
          f"the tag timeline with the poses in {' and '.join(map(str, pictures))}", file=sys.stderr)
    return written[0]


if __name__ == "__main__":
    main()
