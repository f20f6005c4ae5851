"""``python -m jaxmotion.results``: run folders become one markdown page per experiment and profile, each table
beside its run record."""

import json
import sys
from pathlib import Path

import pytest

from jaxmotion import results

sys.path.insert(0, str(Path(__file__).parent))
import toy_experiment  # noqa: E402


@pytest.fixture(scope="module")
def toy_runs(tmp_path_factory):
    out = tmp_path_factory.mktemp("results")
    toy_experiment.main(["--profile", "smoke", "--seeds", "0,1", "--out", str(out)])
    return out


def test_a_results_root_gives_one_page_per_experiment_and_profile_with_each_seeds_table_and_record(toy_runs, tmp_path):
    written = results.main([str(toy_runs), "--out", str(tmp_path)])
    assert written == [tmp_path / "smoke" / "toy.md"]
    text = written[0].read_text()
    seed = toy_runs / "toy" / "smoke" / "seed-0"
    assert (seed / "table.md").read_text().rstrip() in text  # the run's own table, claims included
    assert text.count("| run record | |") == 2 and "### toy (smoke, seeds 0,1; mean ± 95% CI)" in text
    environment = json.loads((seed / "metrics.json").read_text())["run"]["environment"]
    session = json.loads((seed / "run.json").read_text())
    for value in (environment["git_commit"] or "not a git checkout", environment["cpu_model"],
                  f"{environment['cpu_threads']} usable cores", f"jax {environment['jax']}", session["started"]):
        assert value in text
    assert "wall time |" in text and "peak memory |" in text and "GiB" in text


def test_a_seed_folder_alone_gives_its_page_without_the_table_over_seeds(toy_runs, tmp_path):
    results.write_pages([toy_runs / "toy" / "smoke" / "seed-1"], tmp_path)
    text = (tmp_path / "smoke" / "toy.md").read_text()
    assert "### toy (smoke, seed 1)" in text and "seed 0)" not in text and "mean ± 95% CI)" not in text


def test_pages_are_the_same_bytes_from_the_same_folders(toy_runs, tmp_path):
    first = results.write_pages([toy_runs], tmp_path / "a")[0].read_bytes()
    assert results.write_pages([toy_runs], tmp_path / "b")[0].read_bytes() == first


def test_a_run_without_run_json_says_its_session_is_not_recorded(toy_runs, tmp_path):
    seed = toy_runs / "toy" / "smoke" / "seed-0"
    copy = tmp_path / "old" / "seed-0"
    copy.mkdir(parents=True)
    for name in ("config.json", "metrics.json", "table.md"):
        (copy / name).write_bytes((seed / name).read_bytes())
    results.write_pages([copy], tmp_path / "pages")
    assert "| session | not recorded (no run.json) |" in (tmp_path / "pages" / "smoke" / "toy.md").read_text()


def test_a_folder_without_runs_is_an_error_naming_it(tmp_path):
    with pytest.raises(SystemExit, match="no finished seed folder"):
        results.main([str(tmp_path), "--out", str(tmp_path / "pages")])
    with pytest.raises(SystemExit, match="missing.*does not exist"):
        results.main([str(tmp_path / "missing")])


@pytest.mark.parametrize("seconds, text", [(0, "0 s"), (59.6, "1 min"), (3725, "1 h 2 min 5 s"), (7200, "2 h")])
def test_durations_read_as_hours_minutes_seconds(seconds, text):
    assert results.duration(seconds) == text
