"""ACTOR itself through the loop: a SIGKILLed training resumes bitwise, and its loss falls."""

import json
import pickle
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).parent))
import actor_mesh_run  # noqa: E402

from jaxmotion.data.datasets import load_dataset  # noqa: E402
from jaxmotion.train import Checkpointer  # noqa: E402

SCRIPT = Path(__file__).with_name("actor_mesh_run.py")


def kill_after_checkpoint(args, env, run_dir: Path, step: int) -> int:
    """Start the script, SIGKILL it once the checkpoint of ``step`` is complete; the latest step left."""
    proc = subprocess.Popen([sys.executable, str(SCRIPT), *args], env=env, stdout=subprocess.DEVNULL,
                            stderr=subprocess.DEVNULL)
    deadline = time.monotonic() + 300
    while not (run_dir / "checkpoints" / str(step) / "commit_success.txt").exists():
        assert proc.poll() is None, "the run ended before it could be killed"
        assert time.monotonic() < deadline, "no checkpoint appeared"
        time.sleep(0.05)
    proc.send_signal(signal.SIGKILL)
    proc.wait()
    assert not (run_dir / "params.npz").exists()
    killed_at = Checkpointer(run_dir / "checkpoints").latest_step()
    assert killed_at is not None and killed_at < 20
    return killed_at


def assert_runs_bitwise_equal(whole: Path, resumed: Path) -> None:
    assert (whole / "metrics.jsonl").read_bytes() == (resumed / "metrics.jsonl").read_bytes()
    for a, b in zip(actor_mesh_run.load_params(whole), actor_mesh_run.load_params(resumed), strict=True):
        np.testing.assert_array_equal(a, b)


@pytest.fixture(scope="module")
def data_file(tmp_path_factory) -> Path:
    path = tmp_path_factory.mktemp("data") / "synth-humanact12.pkl"
    path.write_bytes(pickle.dumps(load_dataset("synth-humanact12", count=24)))
    return path


@pytest.mark.integration
def test_killed_actor_training_resumes_bitwise_and_its_loss_falls(tmp_path, data_file):
    data = pickle.loads(data_file.read_bytes())
    actor_mesh_run.run(data, tmp_path / "whole", -1, 20, progress=False)  # uninterrupted, in this process
    broken = tmp_path / "broken"
    args = ["--data", str(data_file), "--out", str(broken), "--devices", "-1", "--step-sleep-s", "0.3"]
    env = actor_mesh_run.subprocess_env(None)
    killed_at = kill_after_checkpoint(args, env, broken / "devices--1", 10)
    resumed = subprocess.run([sys.executable, str(SCRIPT), *args], env=env, check=True, capture_output=True,
                             text=True)
    assert f"resuming from the checkpoint at step {killed_at}" in resumed.stderr
    assert_runs_bitwise_equal(tmp_path / "whole", broken / "devices--1")

    losses = [json.loads(line)["loss"] for line in (tmp_path / "whole" / "metrics.jsonl").read_text().splitlines()]
    assert len(losses) == 10 and losses[-1] < 0.7 * losses[0], losses
