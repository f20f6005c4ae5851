"""The training loop on its own: one compilation, per-step keys, logging, checkpoint cadence, initialisation
from another run, the evaluation hook, a one-device mesh, the several-optimiser state."""

import io
import json

import chex
import jax
import jax.numpy as jnp
import numpy as np
import optax
import pytest
from flax.training.train_state import TrainState

from jaxmotion.distributed import data_mesh
from jaxmotion.train import Checkpointer, LoopConfig, MultiState, Progress, train


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
    step_fn = chex.assert_max_traces(_step_fn([]), n=1)  # a second trace raises
    train(_quadratic_state(), step_fn, _batch_fn, key=jax.random.key(0),
          config=LoopConfig(steps=12, log_every=4, checkpoint_every=8), workdir=tmp_path, progress=False)


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


def _params(state):
    return np.asarray(state.params["w"])


def test_init_from_continues_another_run_like_an_uninterrupted_one(tmp_path):
    """4 steps in one folder, then 4 more in another initialised from it == 8 steps in one run, bitwise."""
    cfg = LoopConfig(steps=8, log_every=2, checkpoint_every=4)
    key = jax.random.key(3)
    whole = train(_quadratic_state(), _step_fn([]), _batch_fn, key=key, config=cfg, workdir=tmp_path / "whole",
                  progress=False)
    train(_quadratic_state(), _step_fn([]), _batch_fn, key=key, config=LoopConfig(steps=4, log_every=2),
          workdir=tmp_path / "first", progress=False)
    second = train(_quadratic_state(), _step_fn([]), _batch_fn, key=key, config=cfg, workdir=tmp_path / "second",
                   init_from=tmp_path / "first", progress=False)
    np.testing.assert_array_equal(_params(whole), _params(second))
    assert int(second.step) == 8
    steps = [json.loads(line)["step"] for line in (tmp_path / "second" / "metrics.jsonl").read_text().splitlines()]
    assert steps == [6, 8]
    # Once the new run has a checkpoint of its own, it resumes from that one, not from init_from's.
    again = train(_quadratic_state(), _step_fn([]), _batch_fn, key=key, config=cfg, workdir=tmp_path / "second",
                  init_from=tmp_path / "first" / "checkpoints", progress=False)
    np.testing.assert_array_equal(_params(whole), _params(again))


def test_init_from_carries_the_optimiser_state(tmp_path):
    state = TrainState.create(apply_fn=None, params={"w": jnp.zeros((3,))}, tx=optax.adam(0.1))
    first = train(state, _step_fn([]), _batch_fn, key=jax.random.key(0), config=LoopConfig(steps=3, log_every=1),
                  workdir=tmp_path / "a", progress=False)
    fresh = TrainState.create(apply_fn=None, params={"w": jnp.zeros((3,))}, tx=optax.adam(0.1))
    restored = train(fresh, _step_fn([]), _batch_fn, key=jax.random.key(0), config=LoopConfig(steps=3, log_every=1),
                     init_from=tmp_path / "a", progress=False)
    assert int(restored.step) == 3
    jax.tree.map(lambda x, y: np.testing.assert_array_equal(np.asarray(x), np.asarray(y)), first.opt_state,
                 restored.opt_state)


def test_init_from_without_a_checkpoint_or_with_another_structure_is_refused(tmp_path):
    cfg = LoopConfig(steps=2, log_every=1)
    (tmp_path / "empty").mkdir()
    with pytest.raises(FileNotFoundError, match="init_from: no checkpoint under"):
        train(_quadratic_state(), _step_fn([]), _batch_fn, key=jax.random.key(0), config=cfg,
              init_from=tmp_path / "empty", progress=False)
    with pytest.raises(FileNotFoundError, match="is not a folder"):
        train(_quadratic_state(), _step_fn([]), _batch_fn, key=jax.random.key(0), config=cfg,
              init_from=tmp_path / "missing", progress=False)
    assert not (tmp_path / "missing").exists()
    train(_quadratic_state(), _step_fn([]), _batch_fn, key=jax.random.key(0), config=cfg, workdir=tmp_path / "run",
          progress=False)
    other = TrainState.create(apply_fn=None, params={"w": jnp.zeros((3,)), "b": jnp.zeros(())}, tx=optax.sgd(0.1))
    with pytest.raises(ValueError, match="does not match the state's structure"):
        train(other, _step_fn([]), _batch_fn, key=jax.random.key(0), config=LoopConfig(steps=4, log_every=1),
              init_from=tmp_path / "run", progress=False)


def _eval_fn(calls):
    def eval_fn(state):
        calls.append(int(state.step))
        return {"w_sum": jnp.sum(state.params["w"])}

    return eval_fn


def test_eval_hook_runs_every_n_steps_and_its_lines_survive_resume(tmp_path):
    cfg = LoopConfig(steps=12, log_every=2, checkpoint_every=4, eval_every=3)
    calls = []
    train(_quadratic_state(), _step_fn([]), _batch_fn, key=jax.random.key(0), config=cfg, workdir=tmp_path,
          eval_fn=_eval_fn(calls), progress=False)
    assert calls == [3, 6, 9, 12]
    reference = (tmp_path / "metrics.jsonl").read_text()
    lines = [json.loads(line) for line in reference.splitlines()]
    evals = [line for line in lines if "eval" in line]
    assert [line["step"] for line in evals] == [3, 6, 9, 12] and set(evals[0]["eval"]) == {"w_sum"}
    assert [line["step"] for line in lines if "eval" not in line] == [2, 4, 6, 8, 10, 12]
    # A kill after step 10: the checkpoint at 8 is the latest; the resumed run rewrites the same lines.
    import shutil

    shutil.rmtree(tmp_path / "checkpoints" / "12")
    with (tmp_path / "metrics.jsonl").open("w") as f:
        f.write("".join(line + "\n" for line in reference.splitlines() if json.loads(line)["step"] <= 10))
    calls.clear()
    train(_quadratic_state(), _step_fn([]), _batch_fn, key=jax.random.key(0), config=cfg, workdir=tmp_path,
          eval_fn=_eval_fn(calls), progress=False)
    assert calls == [9, 12]
    assert (tmp_path / "metrics.jsonl").read_text() == reference


def test_loop_config_rejects_a_negative_eval_interval():
    with pytest.raises(ValueError, match="eval_every must be >= 0"):
        LoopConfig(steps=10, eval_every=-1)


def test_a_step_function_that_does_not_advance_the_step_is_refused():
    def stuck(state, batch, key):
        return state, {"loss": jnp.zeros(())}

    with pytest.raises(ValueError, match="went from 0 to 0"):
        train(_quadratic_state(), stuck, _batch_fn, key=jax.random.key(0), config=LoopConfig(steps=3),
              progress=False)


def test_a_one_device_mesh_trains_bitwise_like_no_mesh(tmp_path):
    cfg = LoopConfig(steps=6, log_every=2, checkpoint_every=2)
    plain = train(_quadratic_state(), _step_fn([]), _batch_fn, key=jax.random.key(0), config=cfg,
                  workdir=tmp_path / "plain", progress=False)
    meshed = train(_quadratic_state(), _step_fn([]), _batch_fn, key=jax.random.key(0), config=cfg,
                   workdir=tmp_path / "mesh", mesh=data_mesh(1), progress=False)
    np.testing.assert_array_equal(_params(plain), _params(meshed))
    assert (tmp_path / "plain" / "metrics.jsonl").read_bytes() == (tmp_path / "mesh" / "metrics.jsonl").read_bytes()


def test_multi_state_updates_one_named_set_at_a_time():
    state = MultiState.create({"generator": {"w": jnp.ones(2)}, "critic": {"w": jnp.ones(3)}},
                              {"generator": optax.sgd(0.5), "critic": optax.adam(0.1)})
    grads = {"w": jnp.full(3, 2.0)}
    after = state.apply("critic", grads).apply("critic", grads).next_step()
    assert int(after.step) == 1 and after.names == ("generator", "critic")
    np.testing.assert_array_equal(np.asarray(after.params["generator"]["w"]), np.ones(2))
    assert int(after.opt_states["critic"][0].count) == 2  # the critic's Adam counted its own two updates
    np.testing.assert_allclose(np.asarray(after.params["critic"]["w"]), np.full(3, 0.8), rtol=1e-5)
    assert jax.tree.structure(jax.jit(lambda s: s)(after)) == jax.tree.structure(after)
    with pytest.raises(KeyError, match="no parameter set 'encoder'"):
        state.apply("encoder", grads)
    with pytest.raises(ValueError, match="one optimiser per parameter set"):
        MultiState.create({"generator": {}}, {"critic": optax.sgd(0.1)})


def test_multi_state_buffers_are_kept_replaced_by_name_and_checkpointed(tmp_path):
    state = MultiState.create({"generator": {"w": jnp.ones(2)}}, {"generator": optax.sgd(0.5)},
                              buffers={"generator": {"u": jnp.zeros(2)}})
    moved = state.with_buffer("generator", {"u": jnp.full(2, 3.0)}).apply("generator", {"w": jnp.ones(2)})
    np.testing.assert_array_equal(np.asarray(moved.buffers["generator"]["u"]), np.full(2, 3.0))
    assert jax.tree.structure(jax.jit(lambda s: s)(moved)) == jax.tree.structure(moved)
    with pytest.raises(KeyError, match="no buffer 'critic'"):
        state.with_buffer("critic", {})
    with Checkpointer(tmp_path / "ckpt") as ckpt:
        ckpt.save(1, moved)
        restored = ckpt.restore(state)
    np.testing.assert_array_equal(np.asarray(restored.buffers["generator"]["u"]), np.full(2, 3.0))
    assert MultiState.create({"g": {}}, {"g": optax.sgd(0.1)}).buffers == {}
