"""The loop with two optimisers: a small hinge-loss GAN on a 2-D Gaussian (tests/toy_gan.py) moves its samples
to the target, logs its eval hook, and resumes bitwise after a SIGKILL."""

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import jax
import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).parent))
import toy_gan  # noqa: E402

from jaxmotion.train import Checkpointer  # noqa: E402

SCRIPT = Path(__file__).with_name("toy_gan.py")
REPO = Path(__file__).resolve().parents[1]


@pytest.fixture(scope="module")
def whole(tmp_path_factory):
    out = tmp_path_factory.mktemp("whole")
    toy_gan.run(out)
    return out


def test_gan_samples_move_to_the_target(whole):
    start = toy_gan.mean_distance(toy_gan.init_state(jax.random.key(0)))["mean_distance"]
    lines = [json.loads(line) for line in (whole / "metrics.jsonl").read_text().splitlines()]
    evals = [(line["step"], line["eval"]["mean_distance"]) for line in lines if "eval" in line]
    assert [step for step, _ in evals] == [100, 200, 300]
    assert start > 1.5 and evals[-1][1] < 0.25 * start, (start, evals)
    assert [line["step"] for line in lines if "eval" not in line] == [50, 100, 150, 200, 250, 300]
    state = Checkpointer(whole / "checkpoints").restore()
    assert int(state["step"]) == 300 and set(state["params"]) == {"generator", "critic"}
    assert int(state["opt_states"]["critic"][0]["count"]) == 2 * int(state["opt_states"]["generator"][0]["count"])


@pytest.mark.integration
def test_killed_gan_resumes_bitwise_equal(tmp_path, whole):
    env = {**os.environ, "PYTHONPATH": str(REPO)}
    args = [sys.executable, str(SCRIPT), "--out", str(tmp_path), "--step-sleep-s", "0.02"]
    proc = subprocess.Popen(args, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    deadline = time.monotonic() + 120
    while not (tmp_path / "checkpoints" / "100" / "commit_success.txt").exists():
        assert proc.poll() is None, "the run ended before it could be killed"
        assert time.monotonic() < deadline, "no checkpoint appeared"
        time.sleep(0.05)
    proc.send_signal(signal.SIGKILL)
    proc.wait()
    killed_at = Checkpointer(tmp_path / "checkpoints").latest_step()
    assert killed_at is not None and killed_at < 300 and not (tmp_path / "params.npz").exists()
    resumed = subprocess.run(args, env=env, check=True, capture_output=True, text=True)
    assert f"resuming from the checkpoint at step {killed_at}" in resumed.stderr
    assert (whole / "metrics.jsonl").read_bytes() == (tmp_path / "metrics.jsonl").read_bytes()
    with np.load(whole / "params.npz") as a, np.load(tmp_path / "params.npz") as b:
        assert a.files == b.files
        for name in a.files:
            np.testing.assert_array_equal(a[name], b[name])
