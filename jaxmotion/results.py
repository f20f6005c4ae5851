"""Results pages: run folders turned into markdown, each table beside the record of the run that made it.

    python -m jaxmotion.results results/ [--out docs/results]
    python -m jaxmotion.results results/actor_uestc/cpu/seed-0 results/odmo_modes/cpu/seed-0

Every seed folder found at or below the paths (a folder holding ``config.json`` and ``metrics.json``) is read;
the seeds of one experiment and profile make one page, ``<out>/<profile>/<experiment>.md``: for each seed its
``table.md`` as the run wrote it (claims included) and its run record (commit, versions, machine, CPU model and
cores, start, wall time, peak memory, evaluators), then the table over seeds (the profile folder's
``table.md``) where the run had several. Pages are written again from the folders on every call; a page holds
nothing typed by hand.
"""

from __future__ import annotations

import argparse
import json
from collections.abc import Iterable, Mapping, Sequence
from pathlib import Path
from typing import Any, NamedTuple

from jaxmotion.provenance import SESSION_FILE
from jaxmotion.files import write_atomic


class SeedRun(NamedTuple):
    """What one finished seed folder holds that a page shows."""

    folder: Path
    record: Mapping[str, Any]  # config.json
    metrics: Mapping[str, Any]  # metrics.json
    session: Mapping[str, Any] | None  # run.json; None for runs made before it was written
    table: str  # table.md

    @property
    def key(self) -> tuple[str, str]:
        return self.record["experiment"], self.record["profile"]


def seed_folders(paths: Iterable[str | Path]) -> list[Path]:
    """Every finished seed folder at or below ``paths`` (one holding ``config.json`` and ``metrics.json``),
    each once, sorted."""
    found = set()
    for path in map(Path, paths):
        if not path.exists():
            raise FileNotFoundError(f"paths: {path} does not exist")
        candidates = [path / "metrics.json", *path.rglob("metrics.json")]
        found.update(m.parent for m in candidates if m.is_file() and (m.parent / "config.json").is_file())
    return sorted(found)


def read_seed(folder: Path) -> SeedRun:
    """The seed folder's record, metrics, session and table; an error naming the file when one is unreadable."""
    def load(name: str) -> Any:
        try:
            return json.loads((folder / name).read_text())
        except (OSError, json.JSONDecodeError) as err:
            raise ValueError(f"{folder / name}: not readable as JSON ({err})") from None

    session = load(SESSION_FILE) if (folder / SESSION_FILE).is_file() else None
    return SeedRun(folder, load("config.json"), load("metrics.json"), session, (folder / "table.md").read_text())


def duration(seconds: float) -> str:
    """``3725.0`` -> ``"1 h 2 min 5 s"``."""
    total = round(seconds)
    hours, rest = divmod(total, 3600)
    minutes, secs = divmod(rest, 60)
    parts = [f"{hours} h" if hours else "", f"{minutes} min" if minutes else "", f"{secs} s" if secs or not total else ""]
    return " ".join(p for p in parts if p)


def gibibytes(count: int) -> str:
    return f"{count / 2**30:.1f} GiB"


def run_record(run: SeedRun) -> list[tuple[str, str]]:
    """The run record of one seed as (field, value) lines."""
    env = run.metrics.get("run", {}).get("environment") or run.record.get("environment", {})
    session = run.session
    lines = [
        ("commit", str(env.get("git_commit") or "not a git checkout")),
        ("versions", f"jaxmotion {env.get('jaxmotion')}, Python {env.get('python')}, jax {env.get('jax')}, "
                     f"jaxlib {env.get('jaxlib')}"),
        ("machine", f"{env.get('platform')} ({env.get('device_kind', 'device kind not recorded')}), "
                    f"{env.get('devices')} device(s), {env.get('processes')} process(es), "
                    f"mesh of {env.get('mesh_devices')}"),
        ("CPU", f"{env.get('cpu_model', 'model not recorded')}, {env.get('cpu_threads')} usable cores"),
    ]
    if session is None:
        lines.append(("session", f"not recorded (no {SESSION_FILE})"))
    else:
        wall = duration(session["wall_seconds"]) + (" (this session; it resumed an earlier one)"
                                                    if session["resumed"] else "")
        lines += [("started", session["started"]), ("wall time", wall),
                  ("peak memory", gibibytes(session["peak_rss_bytes"]))]
    for evaluator in run.metrics.get("run", {}).get("evaluators", []):
        accuracy = evaluator.get("held_out_accuracy")
        held_out = "not trained" if accuracy is None else f"{100 * accuracy:.1f}% held-out accuracy"
        lines.append((f"evaluator {evaluator['name']}", f"{held_out} (cache key {evaluator['cache_key']})"))
    return lines


def record_table(lines: Sequence[tuple[str, str]]) -> str:
    return "| run record | |\n| --- | --- |\n" + "".join(f"| {field} | {value} |\n" for field, value in lines)


def page(experiment: str, profile: str, runs: Sequence[SeedRun], over_seeds: str | None = None) -> str:
    """The markdown page of one experiment and profile: each seed's table and run record, then the table over
    seeds when there is one."""
    text = (f"# {experiment}, {profile} profile\n\n"
            "Made by `python -m jaxmotion.results` from the run folders; regenerate it rather than edit it.\n")
    for run in sorted(runs, key=lambda r: r.record["seed"]):
        text += f"\n{run.table.rstrip()}\n\n{record_table(run_record(run))}"
    if over_seeds is not None:
        text += f"\n{over_seeds.rstrip()}\n"
    return text


def write_pages(paths: Iterable[str | Path], out: str | Path) -> list[Path]:
    """Write one page per experiment and profile found at or below ``paths`` to ``out``; return the pages."""
    groups: dict[tuple[str, str], list[SeedRun]] = {}
    for folder in seed_folders(paths):
        run = read_seed(folder)
        groups.setdefault(run.key, []).append(run)
    if not groups:
        raise FileNotFoundError("paths: no finished seed folder (config.json and metrics.json) below them")
    written = []
    for (experiment, profile), runs in sorted(groups.items()):
        summary = runs[0].folder.parent / "table.md"  # written by a --seeds run beside its seed folders
        over_seeds = summary.read_text() if len(runs) > 1 and summary.is_file() else None
        target = Path(out) / profile / f"{experiment}.md"
        write_atomic(target, page(experiment, profile, runs, over_seeds))
        written.append(target)
    return written


def main(argv: Sequence[str] | None = None) -> list[Path]:
    parser = argparse.ArgumentParser(prog="python -m jaxmotion.results", description=__doc__.split("\n\n")[0])
    parser.add_argument("paths", nargs="+", help="results roots, experiment folders or seed folders")
    parser.add_argument("--out", default="docs/results", help="where pages go (default: docs/results)")
    args = parser.parse_args(argv)
    try:
        written = write_pages(args.paths, args.out)
    except (FileNotFoundError, ValueError) as err:
        raise SystemExit(f"jaxmotion.results: {err}") from None
    for path in written:
        print(path)
    return written


if __name__ == "__main__":
    main()

