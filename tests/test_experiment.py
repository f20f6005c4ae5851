"""The experiment runner: determinism, kill-and-resume, refusal to resume another config, seed sweeps."""

import json
import os
import re
import signal
import subprocess
import sys
import time
from pathlib import Path

import jax
import numpy as np
import pytest

from jaxmotion import experiment, provenance
from jaxmotion.data import export
from jaxmotion.train import Checkpointer, LoopConfig

sys.path.insert(0, str(Path(__file__).parent))
import toy_experiment  # noqa: E402

TOY = Path(__file__).with_name("toy_experiment.py")
REPO = Path(__file__).resolve().parents[1]


def _run_toy(out, *args):
    return toy_experiment.main(["--profile", "smoke", "--out", str(out), *args])


def _seed_dir(out, seed=0, profile="smoke"):
    return Path(out) / "toy" / profile / f"seed-{seed}"


def test_same_seed_same_metrics(tmp_path):
    _run_toy(tmp_path / "a")
    _run_toy(tmp_path / "b")
    for name in ["metrics.json", "metrics.jsonl", "config.json", "table.md"]:
        assert (_seed_dir(tmp_path / "a") / name).read_bytes() == (_seed_dir(tmp_path / "b") / name).read_bytes()


def test_different_seeds_differ(tmp_path):
    a = _run_toy(tmp_path, "--seed", "0")
    b = _run_toy(tmp_path, "--seed", "1")
    assert a["rows"]["mlp"]["params_l2"] != b["rows"]["mlp"]["params_l2"]


def test_run_folder_holds_the_documented_files(tmp_path):
    _run_toy(tmp_path)
    d = _seed_dir(tmp_path)
    record = json.loads((d / "config.json").read_text())
    assert record["experiment"] == "toy" and record["profile"] == "smoke" and record["seed"] == 0
    assert record["config"]["train"]["steps"] == 40
    steps = [json.loads(line)["step"] for line in (d / "metrics.jsonl").read_text().splitlines()]
    assert steps == [10, 20, 30, 40]
    assert Checkpointer(d / "checkpoints").latest_step() == 40
    assert "| mlp |" in (d / "table.md").read_text()


def test_repeated_cells_are_reported_with_interval(tmp_path):
    cell = _run_toy(tmp_path)["rows"]["mlp"]["eval_mse"]
    assert cell["n"] == 4 and len(cell["values"]) == 4
    assert cell["mean"] == pytest.approx(np.mean(cell["values"]))
    assert cell["ci95"] > 0


def test_finished_seed_is_read_back_not_retrained(tmp_path, capsys):
    first = _run_toy(tmp_path)
    mtime = (_seed_dir(tmp_path) / "metrics.json").stat().st_mtime_ns
    assert _run_toy(tmp_path) == first
    assert (_seed_dir(tmp_path) / "metrics.json").stat().st_mtime_ns == mtime
    assert "already finished" in capsys.readouterr().err


def test_resume_with_a_different_config_is_refused(tmp_path):
    _run_toy(tmp_path)
    with pytest.raises(SystemExit, match=r"different config(.|\n)*config.lr: 0.01 -> 0.02"):
        _run_toy(tmp_path, "--set", "lr=0.02")


def test_unknown_override_lists_valid_fields(tmp_path):
    with pytest.raises(SystemExit, match="unknown config field 'layers'; valid fields: train.steps"):
        _run_toy(tmp_path, "--set", "layers=3")


def test_seeds_sweep_writes_mean_and_interval(tmp_path):
    summary = _run_toy(tmp_path, "--seeds", "0,1,2")
    cell = summary["rows"]["mlp"]["params_l2"]
    per_seed = [json.loads((_seed_dir(tmp_path, s) / "metrics.json").read_text())["rows"]["mlp"]["params_l2"]
                for s in range(3)]
    assert summary["seeds"] == [0, 1, 2] and cell["per_seed"] == per_seed and cell["n"] == 3
    assert cell["mean"] == pytest.approx(np.mean(per_seed))
    assert cell["ci95"] == pytest.approx(4.3027 * np.std(per_seed, ddof=1) / np.sqrt(3), rel=1e-4)
    table = (tmp_path / "toy" / "smoke" / "table.md").read_text()
    assert "seeds 0,1,2" in table and " ± " in table


def test_named_key_streams_are_independent_and_stable(tmp_path):
    ctx = experiment.RunContext("toy", "smoke", 3, tmp_path)
    a, b = ctx.key("init"), ctx.key("train")
    assert not np.array_equal(jax.random.key_data(a), jax.random.key_data(b))
    again = experiment.RunContext("toy", "smoke", 3, tmp_path / "elsewhere").key("init")
    assert np.array_equal(jax.random.key_data(a), jax.random.key_data(again))


def test_print_config_shows_resolved_overrides(tmp_path, capsys):
    _run_toy(tmp_path, "--set", "hidden=7", "train.steps=3", "--print-config")
    printed = json.loads(capsys.readouterr().out)
    assert printed["hidden"] == 7 and printed["train"]["steps"] == 3
    assert not (tmp_path / "toy").exists()


def test_print_config_accepts_every_run_flag_and_checks_only_what_the_command_says(tmp_path, capsys):
    # the machine's devices and the --out folder are the run's business: a command printed here runs elsewhere
    (tmp_path / "file").write_text("")
    _run_toy(tmp_path / "file", "--seeds", "0,1", "--devices", "100000", "--print-config")
    assert json.loads(capsys.readouterr().out)["train"]["steps"] == 40


@pytest.mark.parametrize("args, message", [
    (["--set", "train.steps=[1]"], "toy: train.steps: expected an integer from -2**31 to 2**31 - 1 (2147483647), got [1]"),
    (["--set", 'train={"steps": "x"}'], "toy: train.steps: expected an integer from -2**31 to 2**31 - 1 (2147483647), "
                                        "got 'x'"),
    (["--set", f"train.steps={10**30}"], f"toy: train.steps: expected an integer from -2**31 to 2**31 - 1 (2147483647), "
                                         f"got {10**30}"),
    (["--set", "train=3"], "toy: 'train' is a group of fields; set one of: train.steps, "),
    (["--set", "train.steps.x=3"], "toy: unknown config field 'train.steps.x': 'train.steps' is a single value (int)"),
    (["--set", "train.log_every=7"], "toy: train: LoopConfig.checkpoint_every (20) must be a non-negative multiple"),
    (["--set", "hidden"], "toy: override 'hidden' must look like field.path=value"),
    (["--seeds", "a,b"], "toy: --seeds: expected comma-separated integers, got 'a,b'"),
])
def test_every_bad_command_line_value_is_a_one_line_exit(args, message):
    with pytest.raises(SystemExit) as exit_:
        toy_experiment.main(["--profile", "smoke", *args, "--print-config"])
    assert str(exit_.value).startswith(message) and "\n" not in str(exit_.value)


@pytest.mark.filterwarnings("ignore::pytest.PytestUnraisableExceptionWarning")  # orbax's reads, abandoned
def test_a_check_failing_inside_a_run_is_a_one_line_exit_with_the_traceback_on_request(tmp_path, monkeypatch):
    """A seed to evaluate again whose checkpoints hold another model (here: one unit wider)."""
    _run_toy(tmp_path)
    (_seed_dir(tmp_path) / "metrics.json").unlink()
    narrow = toy_experiment.MLP
    monkeypatch.setattr(toy_experiment, "MLP", lambda hidden: narrow(hidden + 1))
    folder = _seed_dir(tmp_path) / "checkpoints"
    with pytest.raises(SystemExit) as exit_:
        _run_toy(tmp_path)
    message = str(exit_.value)
    # what differs: the 3 arrays sized by the width, in the parameters and Adam's two moments
    assert re.match(re.escape(f"toy: seed 0: ValueError: no checkpoint in {folder} could be restored into this "
                              "state; the latest (step 40) differs: ")
                    + r"\S+ is \[(32, 1|1, 32|32)\] float32 there, \[(33, 1|1, 33|33)\] float32 here \(and 8 more "
                      r"arrays differ\)\. They can be read", message), message
    assert f"delete {folder} to train this one from the start" in message
    assert message.endswith("\n(--traceback shows where it was raised)") and message.count("\n") == 1
    with pytest.raises(ValueError, match="no checkpoint in .* could be restored"):
        _run_toy(tmp_path, "--traceback")


def test_help_examples_are_real_overrides_of_the_experiment(capsys):
    with pytest.raises(SystemExit):
        toy_experiment.main(["--help"])
    text = " ".join(capsys.readouterr().out.split())
    example = text.split("override config fields, e.g. --set ")[1].split(" --")[0]
    assert example == "train.steps=400 train.log_every=50"  # the cpu profile's first two fields
    toy_experiment.main(["--set", *example.split(), "--print-config"])  # the default profile's values
    assert "config fields for --set" in text and " hidden " in text


@pytest.mark.integration
def test_killed_run_resumes_bitwise_equal(tmp_path):
    """SIGKILL a training subprocess between checkpoints, rerun the same command, compare to an unbroken run."""
    args = ["--profile", "cpu", "--set", "train.steps=200", "step_sleep_s=0.01"]
    env = {**os.environ, "PYTHONPATH": str(REPO)}
    toy_experiment.main(["--out", str(tmp_path / "whole"), *args])  # the uninterrupted reference, in-process

    broken = tmp_path / "broken"
    proc = subprocess.Popen([sys.executable, str(TOY), "--out", str(broken), *args], env=env,
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    ckpt_dir = _seed_dir(broken, profile="cpu") / "checkpoints"
    deadline = time.monotonic() + 120
    while not (ckpt_dir / "100" / "commit_success.txt").exists():
        assert proc.poll() is None, "the run ended before it could be killed"
        assert time.monotonic() < deadline, "no checkpoint appeared"
        time.sleep(0.05)
    proc.send_signal(signal.SIGKILL)
    proc.wait()
    assert not (_seed_dir(broken, profile="cpu") / "metrics.json").exists()
    killed_at = Checkpointer(ckpt_dir).latest_step()
    assert killed_at is not None and killed_at < 200

    resumed = subprocess.run([sys.executable, str(TOY), "--out", str(broken), *args], check=True, env=env,
                             capture_output=True, text=True)
    # The resumed process starts at the checkpoint: it never reports a step at or before it.
    assert f"resuming from the checkpoint at step {killed_at}" in resumed.stderr
    reported = [int(line.split()[1].split("/")[0]) for line in resumed.stderr.splitlines() if line.startswith("step ")]
    assert reported and min(reported) > killed_at

    whole_dir, broken_dir = _seed_dir(tmp_path / "whole", profile="cpu"), _seed_dir(broken, profile="cpu")
    for name in ["metrics.json", "metrics.jsonl"]:
        assert (whole_dir / name).read_bytes() == (broken_dir / name).read_bytes()
    a = Checkpointer(whole_dir / "checkpoints").restore()
    b = Checkpointer(broken_dir / "checkpoints").restore()
    jax.tree.map(lambda x, y: np.testing.assert_array_equal(np.asarray(x), np.asarray(y)), a, b)


def test_loop_config_rejects_misaligned_checkpoints():
    with pytest.raises(ValueError, match="checkpoint_every .* multiple of log_every"):
        LoopConfig(steps=100, log_every=30, checkpoint_every=50)


def test_config_class_must_be_frozen_with_all_profiles():
    import dataclasses

    @dataclasses.dataclass
    class Mutable:
        x: int = 0

    @dataclasses.dataclass(frozen=True)
    class NoPaper:
        x: int = 0

        @classmethod
        def smoke(cls):
            return cls()

        cpu = smoke

    with pytest.raises(TypeError, match="frozen dataclass"):
        experiment.check_config_class(Mutable)
    with pytest.raises(TypeError, match=r"\['paper'\]"):
        experiment.check_config_class(NoPaper)
    experiment.check_config_class(toy_experiment.ToyConfig)


def test_run_record_holds_the_environment_and_resume_with_other_inputs_is_refused(tmp_path):
    result = _run_toy(tmp_path)
    path = _seed_dir(tmp_path) / "config.json"
    record = json.loads(path.read_text())
    env = record["environment"]
    assert env["jax"] == jax.__version__ and env["platform"] == "cpu" and env["devices"] >= 1
    assert env["mesh_devices"] == 1 and record["inputs"] == {"datasets": [], "evaluators": []}
    assert result["run"]["environment"] == env and result["claims"] == []
    # another dataset generator (or evaluator) behind the same config: refused, with the difference listed
    record["inputs"]["datasets"] = [{"name": "synth-uestc", "generator_version": 0}]
    path.write_text(json.dumps(record))
    (_seed_dir(tmp_path) / "metrics.json").unlink()
    with pytest.raises(SystemExit, match=r"different config or inputs(.|\n)*inputs.datasets"):
        _run_toy(tmp_path)


def test_run_json_records_the_session_and_metrics_json_holds_no_timing(tmp_path):
    _run_toy(tmp_path)
    session = json.loads((_seed_dir(tmp_path) / provenance.SESSION_FILE).read_text())
    assert set(session) == {"started", "wall_seconds", "resumed", "peak_rss_bytes"}
    assert session["started"].endswith("+00:00") and session["wall_seconds"] > 0 and not session["resumed"]
    assert session["peak_rss_bytes"] > 10 * 2**20  # a jax process holds more than 10 MiB
    metrics = (_seed_dir(tmp_path) / "metrics.json").read_text()
    assert "started" not in metrics and "wall_seconds" not in metrics and "peak_rss" not in metrics
    assert json.loads(metrics)["run"]["environment"]["cpu_model"]


def test_a_resumed_seed_records_a_resumed_session(tmp_path):
    _run_toy(tmp_path)
    (_seed_dir(tmp_path) / "metrics.json").unlink()
    _run_toy(tmp_path)
    assert json.loads((_seed_dir(tmp_path) / provenance.SESSION_FILE).read_text())["resumed"]


def test_a_changed_environment_is_reported_not_refused(tmp_path, capsys):
    _run_toy(tmp_path)
    path = _seed_dir(tmp_path) / "config.json"
    record = json.loads(path.read_text())
    record["environment"]["jax"] = "0.0.1"
    path.write_text(json.dumps(record))
    (_seed_dir(tmp_path) / "metrics.json").unlink()
    _run_toy(tmp_path)
    assert "resuming in another environment" in capsys.readouterr().err


@pytest.mark.parametrize("args, message", [(["--devices", "0"], "--devices: expected 1 or more devices, got 0"),
                                           (["--devices", "0", "--print-config"], "--devices: expected 1 or more"),
                                           (["--devices", "100000"], "--devices: expected 1 to"),
                                           (["--export", "fbx"], "--export: unknown formats"),
                                           (["--export", "fbx", "--print-config"], "--export: unknown formats"),
                                           # the toy generates nothing: --export would write nothing
                                           (["--export", "npy", "--print-config"], "toy: --export: toy keeps no "
                                                                                  "generated motions to write"),
                                           (["--seeds", "0,0", "--print-config"], "--seeds: expected distinct"),
                                           (["--export", "bvh", "--betas", "1", "--print-config"],
                                            "--body-model: they say what npz files hold; the formats written are bvh"),
                                           (["--video", "--print-config"], "toy: --video: toy draws no generated"),
                                           (["--export", "npz", "--betas", "a", "--print-config"],
                                            "--betas: expected comma-separated numbers")])
def test_bad_devices_and_export_formats_are_clear_errors(tmp_path, args, message):
    with pytest.raises(SystemExit, match=message):
        _run_toy(tmp_path, *args)


def test_the_run_context_exports_generated_motions_in_the_requested_formats(tmp_path):
    from jaxmotion.data import Motion, pack
    from jaxmotion.geometry import SMPL24, axis_angle_to_matrix, forward_kinematics

    rotations = 0.2 * np.asarray(jax.random.normal(jax.random.key(0), (2, 5, 24, 3)))
    joints = np.asarray(forward_kinematics(axis_angle_to_matrix(rotations), np.zeros((2, 5, 3)), SMPL24.offsets,
                                           SMPL24.parents))
    data = pack([Motion(joints=j, translation=np.zeros((5, 3), np.float32), rotations=r, action=0, name=f"m{i}")
                 for i, (j, r) in enumerate(zip(joints.astype(np.float32), rotations.astype(np.float32)))],
                name="gen", split="generated", class_names=("a",), skeleton=SMPL24, fps=20.0)
    ctx = experiment.RunContext("toy", "smoke", 0, tmp_path, export_formats=("bvh", "npy"))
    assert ctx.export(data) is data
    assert sorted(p.name for p in (tmp_path / "export" / "generated").iterdir()) == [
        "m0.bvh", "m0.npy", "m1.bvh", "m1.npy"]
    female = experiment.RunContext("toy", "smoke", 0, tmp_path / "npz", export_formats=("npz",),
                                   export_options=export.ExportOptions(export.AmassOptions(layout="smpl", betas=(1.0,),
                                                                                         gender="female")))
    female.export(data)
    with np.load(tmp_path / "npz" / "export" / "generated" / "m0.npz") as written:
        assert written["poses"].shape == (5, 72) and str(written["gender"]) == "female" and written["betas"][0] == 1
    silent = experiment.RunContext("toy", "smoke", 0, tmp_path / "none")
    silent.export(data)
    assert not (tmp_path / "none").exists()
