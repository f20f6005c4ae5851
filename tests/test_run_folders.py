"""Run folders under hostile conditions: two processes on one folder, kills mid-write, damaged files."""

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path
from typing import NamedTuple

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from jaxmotion import experiment
from jaxmotion.files import LOCK_NAME, folder_lock, read_json, replaced_on_success, write_atomic
from jaxmotion.train import Checkpointer, LoopConfig, train

sys.path.insert(0, str(Path(__file__).parent))
import toy_experiment  # noqa: E402

TOY = Path(__file__).with_name("toy_experiment.py")
ENV = {**os.environ, "PYTHONPATH": str(Path(__file__).resolve().parents[1])}
SLOW = ["--profile", "smoke", "--set", "step_sleep_s=0.25"]


def _seed_dir(out, seed=0):
    return Path(out) / "toy" / "smoke" / f"seed-{seed}"


def _start_toy(out, *args):
    return subprocess.Popen([sys.executable, str(TOY), "--out", str(out), *args], env=ENV,
                            stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)


def _wait_for(path: Path, proc: subprocess.Popen, timeout: float = 120) -> None:
    deadline = time.monotonic() + timeout
    while not path.exists():
        assert proc.poll() is None, f"the run ended before {path} appeared: {proc.stderr.read()}"
        assert time.monotonic() < deadline, f"{path} did not appear"
        time.sleep(0.05)


# --- one process per folder ------------------------------------------------------------------------


@pytest.mark.integration
def test_a_second_run_on_a_folder_in_use_is_refused_naming_the_holder(tmp_path):
    first = _start_toy(tmp_path, *SLOW)
    try:
        _wait_for(_seed_dir(tmp_path) / "metrics.jsonl", first)
        second = subprocess.run([sys.executable, str(TOY), "--out", str(tmp_path), *SLOW], env=ENV,
                                capture_output=True, text=True)
        assert second.returncode != 0
        assert f"in use by process {first.pid} on" in second.stderr and "toy_experiment.py" in second.stderr
    finally:
        assert first.wait(timeout=300) == 0
    steps = [json.loads(line)["step"] for line in (_seed_dir(tmp_path) / "metrics.jsonl").read_text().splitlines()]
    assert steps == [10, 20, 30, 40]  # each step logged once


@pytest.mark.integration
def test_the_lock_of_a_killed_run_is_taken_over(tmp_path):
    proc = _start_toy(tmp_path, *SLOW)
    _wait_for(_seed_dir(tmp_path) / "checkpoints" / "20" / "commit_success.txt", proc)
    proc.send_signal(signal.SIGKILL)
    proc.wait()
    resumed = subprocess.run([sys.executable, str(TOY), "--out", str(tmp_path), *SLOW], env=ENV, capture_output=True,
                             text=True, check=True)
    assert f"taking over the lock left by process {proc.pid}" in resumed.stderr
    assert read_json(_seed_dir(tmp_path) / "metrics.json")["rows"]["mlp"]


@pytest.mark.integration
def test_folder_locks_are_reentrant_in_a_process_and_exclusive_across_processes(tmp_path, capsys):
    with folder_lock(tmp_path, what="test folder"):
        with folder_lock(tmp_path):  # the experiment and its loop may lock one folder
            pass
        holder = json.loads((tmp_path / LOCK_NAME).read_text())
        assert holder["pid"] == os.getpid()
        probe = ("import sys; from jaxmotion.files import folder_lock\n"
                 f"with folder_lock({str(tmp_path)!r}, what='test folder'): pass")
        other = subprocess.run([sys.executable, "-c", probe], env=ENV, capture_output=True, text=True)
        assert other.returncode != 0 and f"test folder is in use by process {os.getpid()}" in other.stderr
    assert (tmp_path / LOCK_NAME).read_text() == ""  # released, not abandoned: the next holder says nothing
    with folder_lock(tmp_path):
        pass
    assert "taking over" not in capsys.readouterr().err


@pytest.mark.integration
def test_a_waiting_lock_waits_for_the_holder(tmp_path):
    probe = ("import time; from jaxmotion.files import folder_lock\n"
             f"with folder_lock({str(tmp_path)!r}):\n"
             f"    open({str(tmp_path / 'held')!r}, 'w').close(); time.sleep(1.5)\n"
             f"    open({str(tmp_path / 'done')!r}, 'w').close()")
    holder = subprocess.Popen([sys.executable, "-c", probe], env=ENV)
    _wait_for(tmp_path / "held", holder)
    with folder_lock(tmp_path, wait=True):
        assert (tmp_path / "done").exists()
    assert holder.wait() == 0


# --- atomic results, honest "finished" --------------------------------------------------------------


def test_write_atomic_leaves_the_old_content_when_the_write_fails(tmp_path, monkeypatch):
    path = tmp_path / "metrics.json"
    write_atomic(path, "old")

    def full_disk(fd):
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(os, "fsync", full_disk)
    with pytest.raises(OSError, match="No space"):
        write_atomic(path, "new")
    assert path.read_text() == "old" and sorted(p.name for p in tmp_path.iterdir()) == ["metrics.json"]


def test_atomic_files_get_the_permissions_of_any_new_file(tmp_path):
    """mkstemp makes its files owner-only: results shared with a group would not be readable."""
    (tmp_path / "plain.txt").write_text("x")
    write_atomic(tmp_path / "atomic.txt", "x")
    with replaced_on_success(tmp_path / "video.mp4", suffix=".mp4") as temporary:
        assert temporary.suffix == ".mp4" and temporary.parent == tmp_path
        temporary.write_bytes(b"x")
    modes = {p.name: p.stat().st_mode & 0o777 for p in tmp_path.iterdir()}
    assert modes["atomic.txt"] == modes["video.mp4"] == modes["plain.txt"], modes


def test_an_empty_metrics_file_does_not_mark_the_seed_finished(tmp_path, capsys):
    first = toy_experiment.main(["--profile", "smoke", "--out", str(tmp_path)])
    (_seed_dir(tmp_path) / "metrics.json").write_text("")  # what a full disk leaves
    again = toy_experiment.main(["--profile", "smoke", "--out", str(tmp_path)])
    assert "metrics.json is unreadable" in capsys.readouterr().err
    assert again == first  # evaluated again from the finished training's checkpoint


def test_a_run_that_failed_at_start_does_not_block_the_corrected_command(tmp_path, capsys):
    def broken(config, ctx):
        raise FileNotFoundError(f"no dataset under {ctx.data_root}")

    config = toy_experiment.ToyConfig.smoke()
    with pytest.raises(FileNotFoundError):
        experiment.run_seed("toy", config, broken, profile="smoke", seed=0, out=tmp_path, data_root="/wrong")
    result = experiment.run_seed("toy", config, toy_experiment.run, profile="smoke", seed=0, out=tmp_path)
    assert "never started" in capsys.readouterr().err and result["rows"]["mlp"]
    assert read_json(_seed_dir(tmp_path) / "config.json")["data_root"] is None
    with pytest.raises(experiment.RunConflictError, match="data_root"):  # a started run is still protected
        experiment.run_seed("toy", config, broken, profile="smoke", seed=0, out=tmp_path, data_root="/wrong")


@pytest.mark.parametrize("args, message", [
    (["--seed", "4294967296"], "--seed: expected a seed from 0 to 4294967295"),
    (["--seed", "-1"], "--seed: expected a seed from 0 to 4294967295"),
    (["--seeds", "0,4294967296"], "--seeds: expected a seed from 0"),
    (["--seed", "1", "--seeds", "0,1"], "--seed and --seeds: give one of them"),
    (["--set", "lr=NaN"], "lr: expected a finite number, got nan"),
    (["--set", "lr=-Infinity"], "lr: expected a finite number, got -inf"),
    (["--set", "lr=1e999"], "lr: expected a finite number, got inf"),
])
def test_bad_seeds_and_values_are_clear_errors(tmp_path, args, message):
    with pytest.raises(SystemExit, match=message):
        toy_experiment.main(["--profile", "smoke", "--out", str(tmp_path), *args])


def test_out_naming_a_file_is_a_clear_error(tmp_path):
    (tmp_path / "results").write_text("")
    with pytest.raises(SystemExit, match="--out: .*results is a file"):
        toy_experiment.main(["--profile", "smoke", "--out", str(tmp_path / "results")])


# --- the training log and checkpoints ---------------------------------------------------------------


class Counter(NamedTuple):
    step: jax.Array
    w: jax.Array


def _counter_run(workdir, steps=6, **kwargs):
    def step_fn(state, batch, key):
        return Counter(state.step + 1, state.w + batch), {"loss": jnp.sum(state.w)}

    config = LoopConfig(steps=steps, log_every=2, checkpoint_every=2, keep_checkpoints=3)
    return train(Counter(jnp.int32(0), jnp.zeros(3)), step_fn, lambda step: jnp.full(3, float(step)), key=jnp.zeros(2, jnp.uint32),
                 config=config, workdir=workdir, progress=False, **kwargs)


def _steps(workdir):
    return [json.loads(line)["step"] for line in (workdir / "metrics.jsonl").read_text().splitlines()]


def test_a_log_line_cut_short_is_dropped_on_resume_with_a_warning(tmp_path, capsys):
    _counter_run(tmp_path, steps=4)
    with (tmp_path / "metrics.jsonl").open("a") as f:
        f.write('{"step": 6, "lo')  # killed mid-write
    _counter_run(tmp_path, steps=6)
    assert "dropping the last line" in capsys.readouterr().err
    assert _steps(tmp_path) == [2, 4, 6]


def test_a_damaged_log_line_before_the_last_is_an_error_naming_it(tmp_path):
    _counter_run(tmp_path, steps=4)
    path = tmp_path / "metrics.jsonl"
    path.write_text("garbage\n" + path.read_text())
    with pytest.raises(ValueError, match=r"metrics.jsonl, line 1: not a JSON record"):
        _counter_run(tmp_path, steps=6)


def test_a_missing_log_with_checkpoints_is_reported(tmp_path, capsys):
    _counter_run(tmp_path, steps=4)
    (tmp_path / "metrics.jsonl").unlink()
    _counter_run(tmp_path, steps=6)
    assert "metrics.jsonl is missing though the run resumes at step 4" in capsys.readouterr().err
    assert _steps(tmp_path) == [6]


def _damage_latest(checkpoints: Path, step: int) -> None:
    data = max((p for p in (checkpoints / str(step)).rglob("*") if p.is_file()), key=lambda p: p.stat().st_size)
    with data.open("r+b") as f:
        f.truncate(data.stat().st_size // 2)


def test_a_damaged_latest_checkpoint_falls_back_to_the_previous_one(tmp_path, capsys):
    whole = _counter_run(tmp_path / "whole")
    _counter_run(tmp_path / "broken", steps=4)
    _damage_latest(tmp_path / "broken" / "checkpoints", 4)
    resumed = _counter_run(tmp_path / "broken")
    err = capsys.readouterr().err
    assert "checkpoint(s) at step 4" in err and "could not be read" in err and "restored step 2" in err
    assert (tmp_path / "broken" / "checkpoints-damaged").is_dir()
    np.testing.assert_array_equal(resumed.w, whole.w)
    assert _steps(tmp_path / "broken") == [2, 4, 6]
    assert Checkpointer(tmp_path / "broken" / "checkpoints").latest_step() == 6


@pytest.mark.filterwarnings("ignore::pytest.PytestUnraisableExceptionWarning")  # orbax's reads, abandoned
def test_a_state_fitting_no_checkpoint_is_an_error_naming_the_folder_and_moves_nothing(tmp_path):
    _counter_run(tmp_path, steps=4)
    folder = tmp_path / "checkpoints"
    with pytest.raises(ValueError, match=f"no checkpoint in {folder} could be restored.* hold another state .*"
                                         f"delete {folder} to train this one from the start"):
        Checkpointer(folder).restore(Counter(jnp.int32(0), jnp.zeros(5)))
    assert Checkpointer(folder).latest_step() == 4 and not (tmp_path / "checkpoints-damaged").exists()


@pytest.mark.filterwarnings("ignore::pytest.PytestUnraisableExceptionWarning")  # orbax's reads, abandoned
def test_when_every_checkpoint_is_damaged_they_are_set_aside_and_the_run_starts_over(tmp_path, capsys):
    whole = _counter_run(tmp_path / "whole")
    _counter_run(tmp_path / "broken", steps=4)
    for step in (2, 4):
        _damage_latest(tmp_path / "broken" / "checkpoints", step)
    resumed = _counter_run(tmp_path / "broken")
    err = capsys.readouterr().err
    assert "every checkpoint in" in err and "starting over from step 0" in err
    assert sorted(p.name.split("-")[0] for p in (tmp_path / "broken" / "checkpoints-damaged").iterdir()) == ["2", "4"]
    np.testing.assert_array_equal(resumed.w, whole.w)  # from step 0 again: the same run
    assert _steps(tmp_path / "broken") == [2, 4, 6]


def test_temporary_folders_of_unfinished_saves_are_removed(tmp_path, capsys):
    _counter_run(tmp_path, steps=4)
    leftover = tmp_path / "checkpoints" / "6.orbax-checkpoint-tmp-1764612345"
    (leftover / "default").mkdir(parents=True)
    _counter_run(tmp_path, steps=6)
    assert not leftover.exists() and "left by a save that did not finish" in capsys.readouterr().err
