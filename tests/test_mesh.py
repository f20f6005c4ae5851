"""Data-parallel training and evaluation: the mesh helpers, ACTOR on 4 host devices against 1, kill and
resume on 4 devices, and two processes of 2 devices each against one process of 4.

Multi-device runs are subprocesses with ``XLA_FLAGS=--xla_force_host_platform_device_count=N`` (a process
fixes its device count when JAX starts); they share this session's compilation cache.
"""

import socket
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).parent))
import actor_mesh_run  # noqa: E402
from test_actor_resume import SCRIPT, assert_runs_bitwise_equal, data_file, kill_after_checkpoint  # noqa: E402, F401

from jaxmotion.distributed import data_mesh, initialize_distributed  # noqa: E402

CHECKS = Path(__file__).with_name("mesh_checks.py")
# Adam's steps are ~lr whatever the gradient's size, so float32 sums in another order can move a parameter
# whose gradient is near zero by up to lr per step; measured differences are ~5e-5 after 20 steps.
ATOL, RTOL = 5e-4, 1e-3


def test_distributed_set_up_is_a_no_op_without_its_variables():
    assert initialize_distributed({}) is False
    assert data_mesh().shape == {"data": 1}  # this process: one CPU device


def test_distributed_set_up_names_the_missing_variables():
    with pytest.raises(ValueError, match="JAXMOTION_NUM_PROCESSES, JAXMOTION_PROCESS_ID missing"):
        initialize_distributed({"JAXMOTION_COORDINATOR": "127.0.0.1:1234"})


@pytest.mark.parametrize("variables, message", [
    ({"JAXMOTION_COORDINATOR": "127.0.0.1"}, "JAXMOTION_COORDINATOR: expected host:port of process 0"),
    ({"JAXMOTION_COORDINATOR": "127.0.0.1:70000"}, "JAXMOTION_COORDINATOR: .*a port in 1 .. 65535"),
    ({"JAXMOTION_NUM_PROCESSES": "two"}, "JAXMOTION_NUM_PROCESSES: expected an integer, got 'two'"),
    ({"JAXMOTION_NUM_PROCESSES": "0"}, "JAXMOTION_NUM_PROCESSES: expected 1 or more processes, got 0"),
    ({"JAXMOTION_PROCESS_ID": "2"}, r"JAXMOTION_PROCESS_ID: expected 0 to 1 \(JAXMOTION_NUM_PROCESSES is 2\), got 2"),
    ({"JAXMOTION_LOCAL_DEVICES": "0,0"}, "JAXMOTION_LOCAL_DEVICES: expected comma-separated device ids"),
    ({"JAXMOTION_INIT_TIMEOUT": "-5"}, "JAXMOTION_INIT_TIMEOUT: expected a positive number of seconds"),
])
def test_distributed_set_up_names_the_variable_that_cannot_be_right(variables, message):
    env = {"JAXMOTION_COORDINATOR": "127.0.0.1:1234", "JAXMOTION_NUM_PROCESSES": "2", "JAXMOTION_PROCESS_ID": "1",
           **variables}
    with pytest.raises(ValueError, match=message):
        initialize_distributed(env)


def _free_port():
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return probe.getsockname()[1]


def test_a_process_not_joined_in_time_exits_naming_the_variable_to_check():
    """Process 1 with nothing at the coordinator's address, and a process 0 waiting for a second process that
    never starts: each exits with status 1 and one line after JAXMOTION_INIT_TIMEOUT (XLA alone would wait
    300 s, then abort blaming another task)."""
    code = "from jaxmotion.distributed import initialize_distributed; initialize_distributed()"
    procs = {
        index: subprocess.Popen([sys.executable, "-c", code], stderr=subprocess.PIPE, text=True,
                                env=actor_mesh_run.subprocess_env(1, JAXMOTION_COORDINATOR=f"127.0.0.1:{_free_port()}",
                                                                  JAXMOTION_NUM_PROCESSES="2",
                                                                  JAXMOTION_PROCESS_ID=str(index),
                                                                  JAXMOTION_INIT_TIMEOUT="2"))
        for index in (0, 1)}
    errors = {index: proc.communicate(timeout=60)[1] for index, proc in procs.items()}
    assert [procs[i].returncode for i in (0, 1)] == [1, 1], errors
    assert "process 1 of 2: nothing answers at JAXMOTION_COORDINATOR=127.0.0.1:" in errors[1]
    assert "process 0 of 2: not all 2 processes joined the coordinator" in errors[0]
    assert "check JAXMOTION_NUM_PROCESSES (the same in every process" in errors[0]
    assert all("Check failure" not in text for text in errors.values())


@pytest.mark.integration
def test_mesh_helpers_and_protocol_passes_on_four_devices():
    """Sharding and replication, the divisibility error, and map_in_chunks / generate / Recognizer on a mesh
    giving the one-device numbers (tests/mesh_checks.py)."""
    result = subprocess.run([sys.executable, str(CHECKS)], env=actor_mesh_run.subprocess_env(4),
                            capture_output=True, text=True)
    assert result.returncode == 0, result.stderr[-3000:]
    assert "mesh checks passed" in result.stdout


@pytest.fixture(scope="module")
def four_device_runs(tmp_path_factory, data_file):  # noqa: F811
    """ACTOR smoke training, 20 steps, on meshes of 1 and of 4 devices, in one 4-device process."""
    out = tmp_path_factory.mktemp("runs")
    subprocess.run([sys.executable, str(SCRIPT), "--data", str(data_file), "--out", str(out), "--devices", "1,4"],
                   env=actor_mesh_run.subprocess_env(4), check=True, capture_output=True)
    return out


@pytest.mark.integration
def test_actor_on_four_devices_matches_one_device(four_device_runs):
    one = actor_mesh_run.load_params(four_device_runs / "devices-1")
    four = actor_mesh_run.load_params(four_device_runs / "devices-4")
    for a, b in zip(one, four, strict=True):
        np.testing.assert_allclose(a, b, rtol=RTOL, atol=ATOL)
    assert any(not np.array_equal(a, b) for a, b in zip(one, four))  # really another program


@pytest.mark.integration
def test_actor_on_four_devices_reruns_and_resumes_bitwise(tmp_path, data_file, four_device_runs):  # noqa: F811
    """A second 4-device run, SIGKILLed after its step-10 checkpoint and restarted, ends bitwise equal to the
    first (rerun determinism and resume onto the mesh in one)."""
    args = ["--data", str(data_file), "--out", str(tmp_path), "--devices", "4", "--step-sleep-s", "0.3"]
    env = actor_mesh_run.subprocess_env(4)
    killed_at = kill_after_checkpoint(args, env, tmp_path / "devices-4", 10)
    resumed = subprocess.run([sys.executable, str(SCRIPT), *args], env=env, check=True, capture_output=True,
                             text=True)
    assert f"resuming from the checkpoint at step {killed_at}" in resumed.stderr
    assert_runs_bitwise_equal(four_device_runs / "devices-4", tmp_path / "devices-4")


@pytest.mark.integration
def test_two_processes_of_two_devices_match_one_process_of_four(tmp_path, data_file, four_device_runs):  # noqa: F811
    """Two processes on 127.0.0.1 (gloo CPU collectives), one shared run folder (orbax writes the checkpoints
    of both), against the one-process 4-device run."""
    shared = {"JAXMOTION_COORDINATOR": f"127.0.0.1:{actor_mesh_run.free_port()}", "JAXMOTION_NUM_PROCESSES": "2"}
    args = [sys.executable, str(SCRIPT), "--data", str(data_file), "--out", str(tmp_path), "--devices", "0"]
    procs = [subprocess.Popen(args, env=actor_mesh_run.subprocess_env(2, **shared, JAXMOTION_PROCESS_ID=str(i)),
                              stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True) for i in range(2)]
    try:
        logs = [p.communicate(timeout=600)[0] for p in procs]
    finally:
        for p in procs:
            p.kill()
    assert [p.returncode for p in procs] == [0, 0], "\n".join(log[-2000:] for log in logs)
    two = actor_mesh_run.load_params(tmp_path / "devices-0")
    four = actor_mesh_run.load_params(four_device_runs / "devices-4")
    for a, b in zip(two, four, strict=True):
        np.testing.assert_allclose(a, b, rtol=RTOL, atol=ATOL)
    assert sorted(p.name for p in (tmp_path / "devices-0" / "checkpoints").iterdir()) == ["10", "20"]
