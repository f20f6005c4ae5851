"""Running an experiment: one seed → every key, the results folder, resume checks, the command line.

An experiment module declares a frozen config dataclass with ``smoke()``, ``cpu()`` and ``paper()``
constructors and a function ``run(config, ctx) -> rows`` that trains and evaluates, where ``rows`` maps a
table row (a method) to its cells (metric name → a number, or a list of numbers over evaluation
repetitions, shown as mean ± 95% CI). Its ``main`` is one line::

    def main(argv=None):
        return experiment.main("actor_uestc", Config, run, argv, claims=CLAIMS)

``claims`` are the paper's claims from that table (:class:`~jaxmotion.evaluation.claims.Claim`), checked
on every run. Results land in ``<out>/<experiment>/<profile>/seed-<n>/``: ``config.json`` (the run
record: config, environment, inputs; :mod:`jaxmotion.provenance`), ``metrics.jsonl`` (training log),
``metrics.json`` (the same bytes for the same seed on the same machine), ``run.json`` (the session that
finished the seed: start, wall time, peak memory), ``table.md`` and ``checkpoints/``. With several seeds,
``<out>/<experiment>/<profile>/summary.json`` and ``table.md`` hold mean ± 95% CI over the seeds.
Re-running the same command resumes: finished seeds are read back, an interrupted one restarts from its
last checkpoint, and a run folder made with a different config or other inputs is refused. ``--devices``
sets the data mesh (:attr:`RunContext.mesh`), ``--export`` the formats of :meth:`RunContext.export` (and
``--npz-layout``, ``--betas``, ``--gender``, ``--body-model``, ``--rig``, ``--clean-feet`` how they are written),
``--log`` the training-log writers (:attr:`RunContext.writers`), ``--video`` MP4 videos beside the pictures of
generated motions (:attr:`RunContext.video`).
"""

from __future__ import annotations

import argparse
import contextlib
import dataclasses
import functools
import json
import shlex
import sys
import time
import zlib
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path
from typing import Any, ClassVar

import jax
import numpy as np
from jax.sharding import Mesh

from jaxmotion import config as cfglib
from jaxmotion import provenance
from jaxmotion.data.export import FORMATS as EXPORT_FORMATS
from jaxmotion.data.export import ExportOptions, export_arguments, export_motions, export_options
from jaxmotion.data.motion import MotionDataset, on_the_floor
from jaxmotion.evaluation.claims import Claim, check_all, format_claims
from jaxmotion.evaluation.recognizers import recording_evaluators
from jaxmotion.evaluation.stats import Summary, summarize
from jaxmotion.evaluation.table import format_table
from jaxmotion.recipes.tables import run_table
from jaxmotion.files import LOCK_NAME, InUseError, folder_lock, read_json, write_atomic, write_json
from jaxmotion.distributed import data_mesh, initialize_distributed, is_primary
from jaxmotion.viz.video import check_video_path
from jaxmotion.train.writers import WRITERS, WriterFactory, named_writers

Rows = Mapping[str, Mapping[str, float | Sequence[float]]]


class RunConflictError(RuntimeError):
    """The results folder holds a run made with another config or other inputs."""


@dataclasses.dataclass(frozen=True)
class RunContext:
    """Where one seed of one experiment runs, and the source of all of its randomness."""

    experiment: str
    profile: str
    seed: int
    workdir: Path
    data_root: str | None = None
    export_formats: tuple[str, ...] = ()  # --export: formats of jaxmotion.data.export for generated motions
    export_options: ExportOptions = ExportOptions()  # --npz-layout, --betas, ..., --rig, --clean-feet: how files say it
    devices: int | None = None  # --devices: the data mesh's size (None: every device of every process)
    log_writers: tuple[str, ...] = ()  # --log: training-log writers (jaxmotion.train.writers); not in the record
    video: bool = False  # --video: pictures of generated motions also as MP4 videos; not in the record

    def __post_init__(self):
        cfglib.check_seed(self.seed, "seed")  # jax.random.key(2**32) is key(0): two seeds, one run

    @functools.cached_property
    def mesh(self) -> Mesh | None:
        """The data-parallel mesh training and evaluation run on, or None on one device (the plain path)."""
        count = jax.device_count() if self.devices is None else self.devices
        return None if count == 1 else data_mesh(count)

    @functools.cached_property
    def writers(self) -> tuple[WriterFactory, ...]:
        """The ``--log`` writers every training of the run passes to the loop (``writers=ctx.writers``), next to
        ``mesh``: each opens in its training's folder. They show the training logs elsewhere and change no
        result, so the run record (:meth:`record`) leaves them out and a folder resumes with or without them."""
        return named_writers(self.log_writers)

    def runs(self, *experiments: str) -> tuple[Path, ...]:
        """The run folders of other ``experiments`` with this run's profile and seed under the same ``--out``
        (whether they exist or not); ``workdir`` is this run's :func:`seed_folder`."""
        out = self.workdir.parents[2]
        return tuple(seed_folder(out, name, self.profile, self.seed) for name in experiments)

    def key(self, stream: str) -> jax.Array:
        """An independent PRNG key per named stream (``"init"``, ``"train"``, ``"eval"``, ...).

        Derived from the seed and a stable hash of the name, so adding a stream never shifts another.
        """
        return jax.random.fold_in(jax.random.key(self.seed), zlib.crc32(stream.encode()))

    def export(self, motions: MotionDataset, name: str = "generated") -> MotionDataset:
        """Write generated ``motions`` to ``<workdir>/export/<name>/`` in the ``--export`` formats (none: do
        nothing), placed on the floor (:func:`~jaxmotion.data.motion.on_the_floor`); return them as given, so a
        call can wrap the expression that makes them."""
        if self.export_formats:
            paths = export_motions(self.workdir / "export" / name, on_the_floor(motions), formats=self.export_formats,
                                   options=self.export_options)
            print(f"[{self.experiment}] exported {len(motions)} motions as {', '.join(self.export_formats)} "
                  f"({len(paths)} files) to {self.workdir / 'export' / name}", file=sys.stderr)
        return motions

    def record(self, config: Any) -> dict[str, Any]:
        """What determines this run's results, as written to ``config.json`` (the runner adds the inputs:
        datasets and evaluators, :func:`jaxmotion.provenance.inputs`)."""
        return {
            "experiment": self.experiment,
            "profile": self.profile,
            "seed": self.seed,
            "data_root": self.data_root,
            "config_class": f"{type(config).__module__}.{type(config).__qualname__}",
            "config": cfglib.to_dict(config),
            "environment": {**provenance.environment(), "mesh_devices": 1 if self.mesh is None else self.mesh.size},
        }


class ProfileConfig:
    """Base of an experiment config built by one function of the profile name: a subclass defines
    ``for_profile(profile)`` and gets the ``smoke()``, ``cpu()`` and ``paper()`` constructors from it."""

    @classmethod
    def for_profile(cls, profile: str):
        raise NotImplementedError(f"{cls.__qualname__} must define for_profile(profile)")

    @classmethod
    def smoke(cls):
        return cls.for_profile("smoke")

    @classmethod
    def cpu(cls):
        return cls.for_profile("cpu")

    @classmethod
    def paper(cls):
        return cls.for_profile("paper")


class Sweep(ProfileConfig):
    """Base of an experiment that sweeps one field of a training over values, a table row per value (ACTOR's
    appendix ablations). A subclass is a frozen dataclass with the fields ``training`` (the recipe each row
    varies), ``table`` (a :class:`~jaxmotion.evaluation.tables.TableDataset`) and ``values``, and sets
    ``FIELD`` (a dotted path into the training), ``SMOKE_VALUES`` (the smoke profile's values) and ``SETUP``
    (profile -> ``(training, table)``); ``label(value)`` names a row. Run it with :func:`run_sweep`."""

    FIELD: ClassVar[str]
    SMOKE_VALUES: ClassVar[tuple[Any, ...]]
    SETUP: ClassVar[Callable[[str], tuple[Any, Any]]]

    def __post_init__(self):
        if not self.values:
            raise ValueError(f"values: expected at least one value of {self.FIELD}")

    @classmethod
    def for_profile(cls, profile: str):
        training, table = cls.SETUP(profile)
        return cls(training, table, cls.SMOKE_VALUES) if profile == "smoke" else cls(training, table)

    def label(self, value) -> str:
        return f"{self.FIELD} = {value}"

    def rows(self) -> dict[str, Any]:
        return {self.label(value): cfglib.replace_paths(self.training, {self.FIELD: value}) for value in self.values}


class Variants(ProfileConfig):
    """Base of an experiment whose rows each change a few fields of one training (an ablation table whose rows
    differ in different fields). A subclass is a frozen dataclass with the fields ``training`` and ``table``,
    and sets ``VARIANTS`` (row name -> ``{dotted path: value}`` into the training; ``{}``: the training
    itself), ``SETUP`` (profile -> ``(training, table)``) and optionally ``COLUMNS`` (the paper's columns,
    :func:`~jaxmotion.evaluation.tables.paper_columns`). Run it with :func:`run_sweep`."""

    VARIANTS: ClassVar[Mapping[str, Mapping[str, Any]]]
    SETUP: ClassVar[Callable[[str], tuple[Any, Any]]]

    @classmethod
    def for_profile(cls, profile: str):
        return cls(*cls.SETUP(profile))

    def rows(self) -> dict[str, Any]:
        return {name: cfglib.replace_paths(self.training, changes) for name, changes in self.VARIANTS.items()}


def run_sweep(config: Sweep | Variants, ctx: RunContext) -> Rows:
    """A :class:`Sweep`'s or :class:`Variants`' table: every row trained from the ``"train"`` key and scored
    from ``"eval"``, in the config's ``COLUMNS`` (ACTOR's by default)."""
    columns = getattr(config, "COLUMNS", None)
    return run_table(config.rows(), config.table, workdir=ctx.workdir, train_key=ctx.key("train"),
                     eval_key=ctx.key("eval"), data_root=ctx.data_root, mesh=ctx.mesh, writers=ctx.writers,
                     **({} if columns is None else {"columns": columns}))


def seed_folder(out: str | Path, experiment: str, profile: str, seed: int) -> Path:
    """Where one seed of ``experiment`` in ``profile`` runs: ``<out>/<experiment>/<profile>/seed-<n>/``."""
    return Path(out) / experiment / profile / f"seed-{seed}"


RunFn = Callable[[Any, RunContext], Rows]


def run_seed(name: str, config: Any, run_fn: RunFn, *, profile: str, seed: int, out: str | Path,
             data_root: str | None = None, claims: Sequence[Claim] = (), export_formats: Sequence[str] = (),
             export_options: ExportOptions = ExportOptions(), devices: int | None = None,
             log_writers: Sequence[str] = (), video: bool = False) -> dict[str, Any]:
    """Run (or resume, or read back) one seed; return the content of its ``metrics.json``."""
    ctx = RunContext(name, profile, seed, seed_folder(out, name, profile, seed), data_root,
                     tuple(export_formats), export_options, devices, tuple(log_writers), video)
    with (folder_lock(ctx.workdir, what="run folder") if is_primary() else contextlib.nullcontext()):
        return _run_locked(ctx, config, run_fn, claims)


def _run_locked(ctx: RunContext, config: Any, run_fn: RunFn, claims: Sequence[Claim]) -> dict[str, Any]:
    name, seed = ctx.experiment, ctx.seed
    started, clock, resumed = provenance.utc_now(), time.monotonic(), _holds_work(ctx.workdir)
    record = {**ctx.record(config), "inputs": provenance.inputs(config, ctx.data_root)}
    config_path, metrics_path = ctx.workdir / "config.json", ctx.workdir / "metrics.json"
    if config_path.exists():
        previous = read_json(config_path)
        if not isinstance(previous, dict):
            raise RunConflictError(f"{config_path} is not a run record (empty or not JSON); refusing to guess "
                                   f"what made this folder. Use another --out, or delete that folder to start over.")
        # the software and machine are recorded, not compared: a resumed run may move to a patched checkout
        changes = cfglib.diff({k: v for k, v in previous.items() if k != "environment"},
                              {k: v for k, v in record.items() if k != "environment"})
        moved = cfglib.diff(previous.get("environment", {}), record["environment"])
        if changes and not _holds_work(ctx.workdir):
            print(f"[{name}] seed {seed}: the run recorded in {config_path} never started; starting this one "
                  f"instead:\n  " + "\n  ".join(changes), file=sys.stderr)
        elif changes:
            raise RunConflictError(
                f"{ctx.workdir} holds a run with a different config or inputs; refusing to resume it.\n  "
                + "\n  ".join(changes)
                + "\nUse another --out, or delete that folder to start over."
            )
        elif moved:
            print(f"[{name}] seed {seed}: resuming in another environment:\n  " + "\n  ".join(moved), file=sys.stderr)
        finished = read_json(metrics_path)
        if isinstance(finished, dict) and "rows" in finished:
            print(f"[{name}] seed {seed}: already finished, reading {metrics_path}", file=sys.stderr)
            return finished
        if metrics_path.exists():
            print(f"[{name}] seed {seed}: {metrics_path} is unreadable (empty or cut short); evaluating again "
                  f"(finished trainings resume from their checkpoints)", file=sys.stderr)
        if not changes:
            record = previous  # keep the record of the run being resumed (its environment)
    if is_primary():
        write_json(config_path, record)
    print(f"[{name}] {ctx.profile} profile, seed {seed} -> {ctx.workdir}", file=sys.stderr)
    with recording_evaluators() as evaluators:  # the run's own, whatever else the cache holds
        rows = run_fn(config, ctx)
    if is_primary():
        write_json(ctx.workdir / provenance.SESSION_FILE, provenance.session(started, time.monotonic() - clock, resumed))
    return write_results(ctx.workdir, rows, f"{name} ({ctx.profile}, seed {seed})", claims,
                         run={"environment": ctx.record(config)["environment"],
                              "evaluators": evaluators})


def _holds_work(folder: Path) -> bool:
    """Whether a run folder holds anything a run made (a log, a checkpoint, a result) beyond its record."""
    return any(p.is_file() and p.name not in ("config.json", LOCK_NAME) for p in folder.rglob("*"))


def write_results(folder: str | Path, rows: Rows, title: str, claims: Sequence[Claim] = (), *,
                  run: Mapping[str, Any] | None = None) -> dict[str, Any]:
    """Write ``rows`` as ``table.md`` (mean ± 95% CI for repeated cells, then every claim checked) and
    ``metrics.json`` (every value with its summary, the claims' verdicts with their numbers, and ``run``:
    the environment and the evaluators used, with their cache keys and held-out accuracy) in ``folder``;
    return the ``metrics.json`` content. ``metrics.json`` is written last: in an experiment's seed folder its presence
    marks the seed as finished."""
    folder = Path(folder)
    metrics: dict[str, Any] = {"rows": {row: {col: _cell_json(v) for col, v in cells.items()}
                                        for row, cells in rows.items()}}
    metrics["claims"] = check_all(claims, metrics["rows"])
    if run is not None:
        metrics["run"] = dict(run)
    write_atomic(folder / "table.md", format_table(_table_cells(metrics), title=title) + format_claims(metrics["claims"]))
    write_json(folder / "metrics.json", metrics)
    return metrics


def aggregate_seeds(per_seed: Mapping[int, Mapping[str, Any]], claims: Sequence[Claim] = ()) -> dict[str, Any]:
    """Mean ± 95% CI over seeds of each cell's per-seed value (its mean, for repeated cells); the claims
    checked on those intervals."""
    seeds = sorted(per_seed)
    first = per_seed[seeds[0]]["rows"]
    rows = {}
    for row, cells in first.items():
        rows[row] = {}
        for col in cells:
            values = [_cell_mean(per_seed[s]["rows"][row][col]) for s in seeds]
            rows[row][col] = {**summarize(values).to_dict(), "per_seed": values}
    return {"seeds": seeds, "rows": rows, "claims": check_all(claims, rows)}


# What the library's checks raise on input it refuses (data, files, folders, values) and on a missing optional
# extra (an ImportError naming it): the command line prints their message alone; anything else is a fault and
# keeps its traceback.
CHECK_ERRORS = (ValueError, FileNotFoundError, ImportError)


def main(name: str, config_cls: type, run_fn: RunFn, argv: Sequence[str] | None = None,
         description: str | None = None, claims: Sequence[Claim] = (), exports: bool = False,
         videos: bool = False) -> dict[str, Any]:
    """The command line every experiment shares; returns the final metrics (summary for several seeds).
    ``claims``: what the paper claims from this table (checked on every run, written with the table).
    ``exports``: whether ``run_fn`` writes generated motions through :meth:`RunContext.export`; ``--export``
    is an error where it does not (it would write nothing). ``videos``: whether ``run_fn`` draws generated motions
    and, with ``--video`` (:attr:`RunContext.video`), also writes them as MP4; ``--video`` is an error elsewhere."""
    check_config_class(config_cls)
    args = _parser(name, config_cls, description).parse_args(argv)
    # Everything the command line says is checked before --print-config returns, so a printed config is one
    # that runs; only what depends on the machine (its devices, the --out folder) is checked after.
    try:
        config = cfglib.apply_overrides(getattr(config_cls, args.profile)(), args.set)
        text = cfglib.to_json(config)  # a config that cannot be recorded never trains
        seeds = _seeds(args.seed, args.seeds)
        formats = _parse_formats(args.export)
        options = export_options(args, formats)
        if formats and not exports:
            raise cfglib.ConfigError(f"--export: {name} keeps no generated motions to write; export a trained row's "
                                     "motions from its folder (jaxmotion.load_generator, then "
                                     "jaxmotion.data.export.export_motions)")
        if args.devices is not None and args.devices < 1:
            raise cfglib.ConfigError(f"--devices: expected 1 or more devices, got {args.devices}")
        log_writers = _parse_writers(args.log)
        if args.video:
            if not videos:
                raise cfglib.ConfigError(f"--video: {name} draws no generated motions; render a trained row's "
                                         "motions with python -m jaxmotion.render")
            check_video_path("generated.mp4", "--video")  # the video extra, before anything trains
    except (ValueError, ImportError) as err:  # ConfigError, and a profile constructor's own checks
        raise SystemExit(f"{name}: {err}") from None
    if args.print_config:
        print(text)
        return {}
    try:
        initialize_distributed()  # joins a multi-process run when its environment variables are set
    except ValueError as err:  # a variable that cannot be right, named
        raise SystemExit(f"{name}: {err}") from None
    if args.devices is not None and args.devices > jax.device_count():
        raise SystemExit(f"--devices: expected 1 to {jax.device_count()} (the devices JAX sees), got {args.devices}")
    out = Path(args.out)
    if out.exists() and not out.is_dir():
        raise SystemExit(f"--out: {out} is a file; expected a folder for the results (it is made if missing)")
    per_seed = {}
    for seed in seeds:
        try:
            per_seed[seed] = run_seed(name, config, run_fn, profile=args.profile, seed=seed, out=args.out,
                                      data_root=args.data_root, claims=claims,
                                      export_formats=formats, export_options=options, devices=args.devices,
                                      log_writers=log_writers, video=args.video)
        except (RunConflictError, InUseError) as err:
            raise SystemExit(f"{name}: {err}") from None
        except CHECK_ERRORS as err:
            if args.traceback:
                raise
            raise SystemExit(f"{name}: seed {seed}: {type(err).__name__}: {err}\n(--traceback shows where it was "
                             "raised)") from None
    if len(seeds) == 1:
        result = per_seed[seeds[0]]
        print(format_table(_table_cells(result), title=f"{name} ({args.profile}, seed {seeds[0]})")
              + format_claims(result.get("claims", [])))
        return result
    summary = aggregate_seeds(per_seed, claims)
    folder = Path(args.out) / name / args.profile
    table = (format_table(_table_cells(summary), title=f"{name} ({args.profile}, seeds {_seed_list(seeds)}; mean ± 95% CI)")
             + format_claims(summary["claims"]))
    write_atomic(folder / "table.md", table)
    write_json(folder / "summary.json", summary)
    print(table)
    return summary


def check_config_class(config_cls: type) -> None:
    """An experiment config is a frozen dataclass with one named constructor per profile."""
    params = getattr(config_cls, "__dataclass_params__", None)
    if params is None or not params.frozen:
        raise TypeError(f"{config_cls.__qualname__} must be a frozen dataclass (@dataclass(frozen=True))")
    missing = [p for p in cfglib.PROFILES if not callable(getattr(config_cls, p, None))]
    if missing:
        raise TypeError(f"{config_cls.__qualname__} lacks the profile constructors {missing} (classmethods)")


# --- internals -------------------------------------------------------------------------------------


def _parser(name: str, config_cls: type, description: str | None) -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog=f"python -m experiments.{name}", description=description,
                                formatter_class=argparse.RawDescriptionHelpFormatter,
                                epilog="config fields for --set (<key>: a key of a mapping the profile's config "
                                       "holds; a group of fields can also be set whole as JSON, an optional one to "
                                       "null):\n  " + "\n  ".join(cfglib.field_paths(config_cls)))
    p.add_argument("--profile", choices=cfglib.PROFILES, default="cpu",
                   help="smoke: seconds (tests); cpu: minutes on a laptop CPU; paper: the paper's settings (GPU)")
    p.add_argument("--seed", type=int, default=None, help="the one seed every PRNG key derives from (default 0)")
    p.add_argument("--seeds", help="comma-separated seeds (e.g. 0,1,2): run each, report mean ± 95%% CI")
    p.add_argument("--out", default="results", help="results root (default: results)")
    p.add_argument("--data-root", help="folder with the real dataset files (default: the embedded dataset)")
    p.add_argument("--set", action="extend", nargs="+", default=[], metavar="FIELD=VALUE",
                   help=f"override config fields, e.g. --set {_set_examples(config_cls)}".replace("%", "%%"))
    p.add_argument("--devices", type=int, default=None, metavar="N",
                   help="data-parallel over N devices (default: all of them; 1: a single device)")
    p.add_argument("--log", default="", metavar="WRITERS",
                   help=f"also show the training logs in any of {','.join(WRITERS)} (comma-separated; tensorboard: "
                        "event files in each training folder's tensorboard/); metrics.jsonl stays the record")
    p.add_argument("--export", default="", metavar="FORMATS",
                   help=f"also write generated motions as any of {','.join(EXPORT_FORMATS)} (comma-separated) "
                        "under <seed folder>/export/")
    p.add_argument("--video", action="store_true",
                   help="also write the pictures of generated motions as MP4 videos (needs jaxmotion[video]; "
                        "seconds of rendering per clip, so off by default)")
    p.add_argument("--print-config", action="store_true", help="print the resolved config as JSON and exit")
    export_arguments(p)
    p.add_argument("--traceback", action="store_true",
                   help="on an error a check raised (bad data, a folder that does not fit), show the whole "
                        "traceback instead of the message alone")
    return p


def _set_examples(config_cls: type) -> str:
    """Two overrides for ``--help`` that this experiment accepts: the first two fields of its default (cpu)
    profile's config, set to their values there."""
    leaves = list(cfglib.flatten(cfglib.to_dict(config_cls.cpu())).items())[:2]
    return " ".join(shlex.quote(f"{path}={value if isinstance(value, str) else json.dumps(value)}")
                    for path, value in leaves)


def _parse_formats(text: str) -> tuple[str, ...]:
    formats = tuple(f.strip() for f in text.split(",") if f.strip())
    unknown = [f for f in formats if f not in EXPORT_FORMATS]
    if unknown:
        raise cfglib.ConfigError(f"--export: unknown formats {unknown}; expected a comma-separated subset of "
                                 f"{','.join(EXPORT_FORMATS)}")
    return formats


def _seeds(seed: int | None, seeds: str | None) -> list[int]:
    """The seeds to run: ``--seeds 0,1,2``, or ``--seed N`` (default 0); each a valid seed."""
    if seed is not None and seeds:
        raise cfglib.ConfigError("--seed and --seeds: give one of them (--seeds 0,1,2 runs several)")
    if not seeds:
        return [cfglib.check_seed(0 if seed is None else seed, "--seed")]
    try:
        values = [int(s) for s in seeds.split(",") if s.strip()]
    except ValueError:
        raise cfglib.ConfigError(f"--seeds: expected comma-separated integers, got {seeds!r}") from None
    if not values or len(set(values)) != len(values):
        raise cfglib.ConfigError(f"--seeds: expected distinct comma-separated integers, got {seeds!r}")
    return [cfglib.check_seed(s, "--seeds") for s in values]


def _seed_list(seeds: Sequence[int]) -> str:
    return ",".join(map(str, seeds))


def _parse_writers(text: str) -> tuple[str, ...]:
    """``--log``'s writer names, each made once here: an unknown name or a missing extra stops the command
    before any training."""
    names = tuple(n.strip() for n in text.split(",") if n.strip())
    try:
        named_writers(names)
    except (ValueError, ImportError) as err:
        raise cfglib.ConfigError(f"--log: {err}") from None
    return names


def _cell_json(value: float | Sequence[float]) -> float | dict[str, Any]:
    """A number stays a number; repetitions become their summary plus the raw values."""
    if np.ndim(value) == 0:
        return float(value)
    values = [float(v) for v in np.asarray(value).ravel()]
    return {**summarize(values).to_dict(), "values": values}


def _cell_mean(cell: float | Mapping[str, Any]) -> float:
    return cell["mean"] if isinstance(cell, Mapping) else cell


def _table_cells(metrics: Mapping[str, Any]) -> dict[str, dict[str, float | Summary]]:
    def cell(c):
        return Summary.from_dict(c) if isinstance(c, Mapping) else c

    return {row: {col: cell(c) for col, c in cells.items()} for row, cells in metrics["rows"].items()}
