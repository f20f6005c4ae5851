"""The training loop on its own: one compilation, per-step keys, logging, checkpoint cadence."""

import io
import json

import jax
import jax.numpy as jnp
import numpy as np
import optax
from flax.training.train_state import TrainState

from jaxmotion.train import Checkpointer, LoopConfig, Progress, train


def _quadratic_state():
    params = {"w": jnp.zeros((3,))}
    return TrainState.create(apply_fn=None, params=params, tx=optax.sgd(0.1))


def _step_fn(traces):
    def step_fn(state, batch, key):
        traces.append(1)  # runs only while tracing
        noise = jax.random.normal(key, (3,))
        loss, grads = jax.value_and_grad(lambda p: jnp.sum((p["w"] - batch) ** 2))(state.params)
        return state.apply_gradients(grads=grads), {"loss": loss, "noise": noise[0]}

    return step_fn


def _batch_fn(step):
    return jnp.full((3,), float(step % 3))


def test_train_step_traces_once(tmp_path):
    traces = []
    train(_quadratic_state(), _step_fn(traces), _batch_fn, key=jax.random.key(0),
          config=LoopConfig(steps=12, log_every=4, checkpoint_every=8), workdir=tmp_path, progress=False)
    assert len(traces) == 1


def test_step_key_depends_only_on_seed_and_step(tmp_path):
    """The logged noise of step n is fold_in(key, n - 1) whatever the run length or interruption."""
    key = jax.random.key(7)
    train(_quadratic_state(), _step_fn([]), _batch_fn, key=key,
          config=LoopConfig(steps=3, log_every=1, checkpoint_every=0), workdir=tmp_path, progress=False)
    logged = [json.loads(line)["noise"] for line in (tmp_path / "metrics.jsonl").read_text().splitlines()]
    expected = [float(jax.random.normal(jax.random.fold_in(key, s), (3,))[0]) for s in range(3)]
    np.testing.assert_allclose(logged, expected, rtol=1e-6)


def test_metrics_are_interval_means_and_checkpoints_follow_the_cadence(tmp_path):
    train(_quadratic_state(), _step_fn([]), _batch_fn, key=jax.random.key(0),
          config=LoopConfig(steps=10, log_every=5, checkpoint_every=5, keep_checkpoints=5), workdir=tmp_path,
          progress=False)
    lines = [json.loads(line) for line in (tmp_path / "metrics.jsonl").read_text().splitlines()]
    assert [line["step"] for line in lines] == [5, 10]
    # Replay the same updates eagerly to get each step's loss.
    w, losses = np.zeros(3), []
    for step in range(10):
        target = step % 3
        losses.append(float(np.sum((w - target) ** 2)))
        w = w - 0.1 * 2 * (w - target)
    np.testing.assert_allclose([lines[0]["loss"], lines[1]["loss"]], [np.mean(losses[:5]), np.mean(losses[5:])],
                               rtol=1e-5)
    ckpt = Checkpointer(tmp_path / "checkpoints")
    assert ckpt.latest_step() == 10
    np.testing.assert_allclose(np.asarray(ckpt.restore()["params"]["w"]), w, rtol=1e-5)


def test_resume_truncates_log_lines_past_the_checkpoint(tmp_path):
    cfg = LoopConfig(steps=8, log_every=2, checkpoint_every=4)
    train(_quadratic_state(), _step_fn([]), _batch_fn, key=jax.random.key(0), config=cfg, workdir=tmp_path,
          progress=False)
    reference = (tmp_path / "metrics.jsonl").read_text()
    # Simulate a kill after step 6 was logged but before the step-8 checkpoint: drop the last checkpoint.
    import shutil

    shutil.rmtree(tmp_path / "checkpoints" / "8")
    with (tmp_path / "metrics.jsonl").open("a") as f:
        f.write(json.dumps({"step": 10, "loss": -1.0}) + "\n")  # a line from beyond the checkpoint
    train(_quadratic_state(), _step_fn([]), _batch_fn, key=jax.random.key(0), config=cfg, workdir=tmp_path,
          progress=False)
    assert (tmp_path / "metrics.jsonl").read_text() == reference


def test_finished_run_is_not_trained_again(tmp_path):
    cfg = LoopConfig(steps=4, log_every=2, checkpoint_every=2)
    first = train(_quadratic_state(), _step_fn([]), _batch_fn, key=jax.random.key(0), config=cfg,
                  workdir=tmp_path, progress=False)
    traces = []
    again = train(_quadratic_state(), _step_fn(traces), _batch_fn, key=jax.random.key(0), config=cfg,
                  workdir=tmp_path, progress=False)
    assert traces == [] and int(again.step) == 4
    np.testing.assert_array_equal(np.asarray(first.params["w"]), np.asarray(again.params["w"]))


def test_progress_line_shows_step_metrics_and_eta():
    stream = io.StringIO()
    bar = Progress(total=100, stream=stream)
    bar.update(25, {"loss": 0.5})
    line = stream.getvalue()
    assert line.startswith("step 25/100 [#####---------------]  25% | loss 0.5 | ") and "ETA" in line
    assert line.endswith("\n")  # not a terminal: one line per update
