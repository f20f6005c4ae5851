"""Training-log writers: TensorBoard's event files read back equal metrics.jsonl step by step, a resumed run shows
each step once, a custom writer receives exactly the log's records and is closed whatever happens, ``--log``."""

import json
import shutil
import struct
import sys
from pathlib import Path

import jax
import jax.numpy as jnp
import numpy as np
import optax
import pytest
from flax.training.train_state import TrainState
from tensorboardX.proto.event_pb2 import Event, SessionLog
from tensorboardX.record_writer import masked_crc32c

from jaxmotion import experiment
from jaxmotion.train import LoopConfig, TensorBoard, train
from jaxmotion.train.writers import TENSORBOARD_FOLDER, named_writers

sys.path.insert(0, str(Path(__file__).parent))
import toy_experiment  # noqa: E402

CONFIG = LoopConfig(steps=8, log_every=2, checkpoint_every=4, eval_every=4)


def _state():
    return TrainState.create(apply_fn=None, params={"w": jnp.zeros((3,))}, tx=optax.sgd(0.1))


def _step_fn(state, batch, key):
    loss, grads = jax.value_and_grad(lambda p: jnp.sum((p["w"] - batch) ** 2))(state.params)
    return state.apply_gradients(grads=grads), {"loss": loss, "noise": jax.random.normal(key, ())}


def _batch_fn(step):
    return jnp.full((3,), float(step % 3))


def _eval_fn(state):
    return {"w_sum": jnp.sum(state.params["w"])}


def _train(workdir, writers, config=CONFIG, batch_fn=_batch_fn):
    return train(_state(), _step_fn, batch_fn, key=jax.random.key(0), config=config, workdir=workdir,
                 eval_fn=_eval_fn, writers=writers, progress=False)


def _log(workdir):
    return [json.loads(line) for line in (Path(workdir) / "metrics.jsonl").read_text().splitlines()]


def _logged_scalars(records):
    """(name, step, value) of every number in metrics.jsonl records, under the documented names."""
    out = []
    for record in records:
        if "eval" in record:
            out += [(f"eval/{name}", record["step"], value) for name, value in record["eval"].items()]
        else:
            out += [(f"train/{name}", record["step"], value) for name, value in record.items() if name != "step"]
    return out


def _events(logdir):
    """Every event of a TensorBoard folder's files in the order TensorBoard reads them (file names sorted),
    the TFRecord framing and its checksums checked."""
    files = sorted(Path(logdir).glob("events.out.tfevents.*"))
    assert files, f"no event files in {logdir}"
    for path in files:
        data, offset = path.read_bytes(), 0
        while offset < len(data):
            header = data[offset:offset + 8]
            (length,) = struct.unpack("<Q", header)
            assert struct.unpack("<I", data[offset + 8:offset + 12])[0] == masked_crc32c(header)
            body = data[offset + 12:offset + 12 + length]
            assert struct.unpack("<I", data[offset + 12 + length:offset + 16 + length])[0] == masked_crc32c(body)
            yield Event.FromString(body)
            offset += 16 + length


def _scalars(events):
    return [(value.tag, event.step, value.simple_value) for event in events for value in event.summary.value]


def _shown(logdir):
    """The scalars TensorBoard shows: a session-start event at step s drops what earlier events logged at steps
    from s on (its purge of a restarted run's orphaned steps)."""
    shown = []
    for event in _events(logdir):
        if event.HasField("session_log") and event.session_log.status == SessionLog.START:
            shown = [scalar for scalar in shown if scalar[1] < event.step]
        shown += _scalars([event])
    return shown


def _assert_same(shown, logged):
    assert [(name, step) for name, step, _ in shown] == [(name, step) for name, step, _ in logged]
    np.testing.assert_allclose([v for *_, v in shown], [v for *_, v in logged], rtol=1e-6)  # float32 in the file


def test_tensorboard_scalars_equal_the_training_log_step_by_step(tmp_path):
    _train(tmp_path, [TensorBoard()])
    logged = _logged_scalars(_log(tmp_path))
    assert {name for name, *_ in logged} == {"train/loss", "train/noise", "eval/w_sum"}
    _assert_same(_shown(tmp_path / TENSORBOARD_FOLDER), logged)
    assert len(list((tmp_path / TENSORBOARD_FOLDER).iterdir())) == 1


def test_a_run_killed_past_its_checkpoint_shows_each_step_once_after_resuming(tmp_path):
    _train(tmp_path, [TensorBoard()])
    reference = _log(tmp_path)
    # a kill after step 8 was logged but before its checkpoint: the resumed run redoes steps 5 to 8
    shutil.rmtree(tmp_path / "checkpoints" / "8")
    _train(tmp_path, [TensorBoard()])
    assert _log(tmp_path) == reference
    everything = _scalars(_events(tmp_path / TENSORBOARD_FOLDER))
    assert [step for name, step, _ in everything if name == "train/loss"] == [2, 4, 6, 8, 6, 8]  # on disk: twice
    _assert_same(_shown(tmp_path / TENSORBOARD_FOLDER), _logged_scalars(reference))


def test_a_run_continued_with_more_steps_shows_each_step_once(tmp_path):
    _train(tmp_path, [TensorBoard()], config=LoopConfig(steps=4, log_every=2, checkpoint_every=4, eval_every=4))
    _train(tmp_path, [TensorBoard()])
    shown = _shown(tmp_path / TENSORBOARD_FOLDER)
    assert [step for name, step, _ in shown if name == "train/loss"] == [2, 4, 6, 8]
    _assert_same(shown, _logged_scalars(_log(tmp_path)))


class _Collector:
    """A writer factory keeping what each writer it opens is given."""

    def __init__(self):
        self.opened, self.written, self.closed = [], [], 0

    def __call__(self, folder, start_step):
        self.opened.append((folder, start_step))
        return self

    def write(self, step, scalars):
        self.written.append((step, dict(scalars)))

    def close(self):
        self.closed += 1


def _as_written(records):
    """What a writer should be given for ``records``: (step, {name: value}) per record."""
    return [(record["step"], {name: value for name, _, value in _logged_scalars([record])}) for record in records]


def test_a_custom_writer_receives_exactly_the_log_records_and_only_the_redone_ones_on_resume(tmp_path):
    first = _Collector()
    _train(tmp_path, [first])
    records = _log(tmp_path)
    assert first.opened == [(tmp_path, 0)] and first.closed == 1
    assert first.written == _as_written(records)
    shutil.rmtree(tmp_path / "checkpoints" / "8")
    again = _Collector()
    _train(tmp_path, [again])
    assert again.opened == [(tmp_path, 4)] and again.closed == 1
    assert again.written == _as_written([r for r in records if r["step"] > 4])
    finished = _Collector()
    _train(tmp_path, [finished])
    assert finished.opened == []  # nothing left to train: no writer opened


def test_writers_are_closed_when_training_raises(tmp_path):
    def failing(step):
        if step == 5:
            raise RuntimeError("data gone")
        return _batch_fn(step)

    collector = _Collector()
    with pytest.raises(RuntimeError, match="data gone"):
        _train(tmp_path, [collector, TensorBoard()], batch_fn=failing)
    assert collector.closed == 1 and [step for step, _ in collector.written] == [2, 4, 4]
    assert [step for name, step, _ in _shown(tmp_path / TENSORBOARD_FOLDER) if name == "train/loss"] == [2, 4]


def test_writers_need_a_workdir_and_only_the_primary_process_opens_them(tmp_path, monkeypatch):
    with pytest.raises(ValueError, match="writers: a training log needs a folder"):
        _train(None, [_Collector()])
    monkeypatch.setattr("jaxmotion.train.loop.is_primary", lambda: False)
    collector = _Collector()
    _train(tmp_path, [collector])
    assert collector.opened == []


def test_a_missing_tensorboardx_is_an_import_error_naming_the_extra(monkeypatch):
    monkeypatch.setitem(sys.modules, "tensorboardX", None)  # import tensorboardX now raises ImportError
    with pytest.raises(ImportError, match=r'pip install "jaxmotion\[tensorboard\]"'):
        TensorBoard()
    with pytest.raises(SystemExit, match=r'--log: TensorBoard logs need tensorboardX.*jaxmotion\[tensorboard\]'):
        toy_experiment.main(["--profile", "smoke", "--log", "tensorboard", "--print-config"])


@pytest.mark.parametrize("text, message", [
    ("nope", "toy: --log: unknown writers ['nope']; expected names among: tensorboard"),
    ("tensorboard,tensorboard", "toy: --log: each writer at most once, got ['tensorboard', 'tensorboard']"),
])
def test_bad_log_writers_are_one_line_exits_naming_the_flag_and_the_choices(text, message):
    with pytest.raises(SystemExit) as exit_:
        toy_experiment.main(["--profile", "smoke", "--log", text, "--print-config"])
    assert str(exit_.value) == message


def test_the_run_context_gives_the_named_writers_and_keeps_them_out_of_the_record(tmp_path):
    plain = experiment.RunContext("toy", "smoke", 0, tmp_path)
    logged = experiment.RunContext("toy", "smoke", 0, tmp_path, log_writers=("tensorboard",))
    assert plain.writers == () and logged.writers == named_writers(["tensorboard"]) == (TensorBoard(),)
    config = toy_experiment.ToyConfig.smoke()
    assert logged.record(config) == plain.record(config)


def _run_with_writers(config, ctx):
    state = train(_state(), _step_fn, _batch_fn, key=ctx.key("train"), config=config.train,
                  workdir=ctx.workdir / "model", writers=ctx.writers, progress=False)
    return {"toy": {"w_sum": float(jnp.sum(state.params["w"]))}}


def test_log_tensorboard_through_the_command_line_and_a_folder_made_without_it_is_read_back(tmp_path):
    def main(out, *args):
        return experiment.main("toylog", toy_experiment.ToyConfig, _run_with_writers,
                               ["--profile", "smoke", "--out", str(out), *args])

    main(tmp_path / "a", "--log", "tensorboard")
    model = experiment.seed_folder(tmp_path / "a", "toylog", "smoke", 0) / "model"
    _assert_same(_shown(model / TENSORBOARD_FOLDER), _logged_scalars(_log(model)))
    first = main(tmp_path / "b")
    assert main(tmp_path / "b", "--log", "tensorboard") == first  # the same record: read back, not refused
