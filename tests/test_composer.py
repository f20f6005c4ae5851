"""The composer's API without a browser: requests read into programs (or refused, naming the field), every
endpoint of the server, the streamed progress, the downloads, a queued second request, and a server that keeps
serving after bad requests."""

import dataclasses
import http.client
import io
import json
import threading

import jax
import numpy as np
import pytest

from jaxmotion.composer.app import Composer, RequestError, read_request
from jaxmotion.composer.server import MAX_BODY, make_server
from jaxmotion.data import synthetic
from jaxmotion.data.export import load_bvh
from jaxmotion.geometry.body import load_body_model
from jaxmotion.models.marionet import MarionetConfig, init_marionet
from jaxmotion.pipelines.artefacts import DataFacts
from jaxmotion.pipelines.marionette import ContextGenerator, start_bank
from jaxmotion.pipelines.multi_action import ChainOptions, bezier_path

from toy_body import box_body  # noqa: E402  (tests/ is on the path)

CONFIG = MarionetConfig.tiny(max_frames=40)


@pytest.fixture(scope="module")
def generator():
    takes = synthetic.generate("synth-mag", "test", seed=0, count=4, progress=False)
    params = jax.jit(init_marionet, static_argnums=1)(jax.random.key(0), CONFIG)
    return ContextGenerator(CONFIG, params, DataFacts.of(takes), start_bank(takes, per_tag=2), max_frames=40)


@pytest.fixture(scope="module")
def served(generator, tmp_path_factory):
    body = load_body_model(box_body(tmp_path_factory.mktemp("body") / "boxes.npz"))
    composer = Composer(generator, body=body)  # no reviser: Shadow Start always or never
    composer.warm_up()
    server = make_server(composer, port=0)
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    yield composer, server.server_address[1]
    server.shutdown()
    server.server_close()


def _ask(port, method, path, body=None, headers=None):
    connection = http.client.HTTPConnection("127.0.0.1", port, timeout=120)
    data = body if isinstance(body, bytes) or body is None else json.dumps(body).encode()
    connection.request(method, path, body=data, headers=headers or {})
    response = connection.getresponse()
    return response.status, response.getheader("Content-Type"), response.read()


def _events(payload: bytes) -> list[dict]:
    return [json.loads(line) for line in payload.decode().splitlines()]


PROGRAM = {"actions": [{"tags": ["walk"], "seconds": 0.5, "path": [[0, 0], [0.3, 0.6], [0.6, 0.9], [1.0, 1.0]]},
                       {"tags": ["Run"], "frames": 12, "path": [[1, 1], [2, 1]]},
                       {"tags": ["sit", "arm movement"], "frames": 10}],
           "shadow": "always", "seed": 3}


def test_a_request_becomes_a_program_with_bezier_paths_per_frame(generator):
    request = read_request(PROGRAM, generator)
    actions = request.program.actions
    assert [a.tags for a in actions] == [("Walk",), ("Run",), ("Sit", "Arm Movement")]
    assert [a.duration for a in actions] == [15, 12, 10]  # 0.5 s at 30 fps
    np.testing.assert_allclose(actions[0].path, bezier_path(np.array(PROGRAM["actions"][0]["path"]), 15), atol=1e-6)
    np.testing.assert_allclose(actions[1].path[-1], [2, 1], atol=1e-6)
    assert actions[2].path is None and request.controls[2] is None
    assert (request.seed, request.options, request.mean) == (3, ChainOptions("always", smoothing=6, orientation=True),
                                                             False)
    assert not read_request({**PROGRAM, "orientation": False}, generator).options.orientation


@pytest.mark.parametrize("change, message", [
    ({"actions": []}, "actions: expected a list of one or more actions (the program is empty)"),
    ({"actions": [{"tags": ["dance"], "frames": 5}]}, "actions[0].tags: unknown tag 'dance'; the model knows: Walk,"),
    ({"actions": [{"tags": [], "frames": 5}]}, "actions[0].tags: expected one or more tag names"),
    ({"actions": [{"tags": ["walk", "Walk"], "frames": 5}]}, "actions[0].tags: 'Walk' given twice"),
    ({"actions": [{"tags": "kick", "seconds": 2.0}]},
     "actions[0].seconds: expected 1 to 40 frames (0.0333 to 1.33333 s at 30 fps, the model's longest action), got 60"),
    ({"actions": [{"tags": "kick", "frames": 0}]}, "actions[0].frames: expected 1 to 40 frames"),
    ({"actions": [{"tags": "kick", "frames": 2.5}]}, "actions[0].frames: expected a whole number, got 2.5"),
    ({"actions": [{"tags": "kick"}]}, "actions[0]: expected a duration as seconds or as frames"),
    ({"actions": [{"tags": "kick", "frames": 5, "seconds": 1}]}, "actions[0]: expected a duration as seconds or"),
    ({"actions": [{"tags": "walk", "frames": 5, "path": [[0, 0]]}]}, "actions[0].path: expected 2 to 64 finite ground"),
    ({"actions": [{"tags": "walk", "frames": 5, "path": [[0, 0], [float("nan"), 1]]}]}, "actions[0].path: expected"),
    ({"actions": [{"tags": "walk", "frames": 5, "speed": 2}]}, "actions[0]: unknown field 'speed'; expected frames,"),
    ({"actions": ["walk"]}, "actions[0]: expected an object"),
    ({"shadow": "sometimes"}, "shadow: expected one of revision, always, never, got \"sometimes\""),
    ({"smoothing": -1}, "smoothing: expected a whole number of frames from 0 to 40, got -1"),
    ({"seed": "1"}, "seed: expected a whole number from 0 to 2^31 - 1, got \"1\""),
    ({"mean": 1}, "mean: expected true or false, got 1"),
    ({"orientation": "yes"}, "orientation: expected true or false, got \"yes\""),
    ({"colour": "red"}, "request: unknown field 'colour'"),
])
def test_bad_requests_name_the_action_and_the_field(generator, change, message):
    with pytest.raises(RequestError) as error:
        read_request({**PROGRAM, **change}, generator)
    assert message in str(error.value) and error.value.status == 400


def test_the_page_its_files_and_the_model_are_served(served, generator):
    _, port = served
    status, kind, page = _ask(port, "GET", "/")
    assert status == 200 and kind.startswith("text/html") and b'<canvas id="view"' in page
    status, kind, script = _ask(port, "GET", "/static/composer.js")
    assert status == 200 and kind.startswith("text/javascript") and b"function bezierControls" in script
    status, _, body = _ask(port, "GET", "/api/model")
    model = json.loads(body)
    assert status == 200 and model["tags"] == list(generator.class_names) and model["max_frames"] == 40
    assert model["shadow_modes"] == ["always", "never"] and model["body"]  # no reviser here: no Action Revision
    assert model["root_tags"][model["tags"].index("Walk")] and not model["root_tags"][model["tags"].index("Kick")]
    assert np.array_equal(model["seen"], generator.starts.transitions > 0)


def test_generating_streams_each_action_then_the_motion_and_its_downloads(served):
    _, port = served
    status, kind, body = _ask(port, "POST", "/api/generate", PROGRAM)
    events = _events(body)
    assert status == 200 and kind == "application/x-ndjson"
    progress = [e for e in events if e["event"] == "action"]
    assert [(e["index"], e["of"], e["shadowed"]) for e in progress] == [(0, 3, True), (1, 3, True), (2, 3, True)]
    assert events[-1]["event"] == "done"
    motion = events[-1]["motion"]
    joints = np.array(motion["joints"]).reshape(motion["frames"], motion["joint_count"], 3)
    assert joints.shape == (37, 24, 3) and np.isfinite(joints).all()
    assert [(s["start"], s["end"], s["tags"]) for s in motion["segments"]] == [
        (0, 15, ["Walk"]), (15, 27, ["Run"]), (27, 37, ["Sit", "Arm Movement"])]
    assert motion["controls"][1] == [[1, 1], [2, 1]] and motion["controls"][2] is None
    again = _events(_ask(port, "POST", "/api/generate", PROGRAM)[2])[-1]["motion"]
    assert again["joints"] == motion["joints"] and again["id"] != motion["id"]  # deterministic from the seed
    status, _, bvh = _ask(port, "GET", motion["downloads"]["motion.bvh"])
    assert status == 200 and bvh.startswith(b"HIERARCHY")
    status, _, npy = _ask(port, "GET", motion["downloads"]["motion.npy"])
    np.testing.assert_allclose(np.load(io.BytesIO(npy)), joints, atol=1e-4)
    status, _, npz = _ask(port, "GET", motion["downloads"]["motion.npz"])
    with np.load(io.BytesIO(npz)) as data:  # SMPL+H, trans from the box body's rest pelvis (0, 0.95, 0), z up
        assert data["poses"].shape == (37, 156)
        np.testing.assert_allclose(data["trans"] + [0.0, 0.95, 0.0], joints[:, 0, [0, 2, 1]] * [1, -1, 1], atol=1e-4)
    status, _, table = _ask(port, "GET", motion["downloads"]["segments.json"])
    assert [s["end"] for s in json.loads(table)["segments"]] == [15, 27, 37]


def test_the_mesh_and_its_skinning_transforms_put_the_body_on_the_motion(served):
    """The box body's joint vertices ride rigidly on their joints and its rest joints are the template skeleton's,
    so skinned with the motion's transforms they land on the motion's joints."""
    _, port = served
    body = json.loads(_ask(port, "GET", "/api/body")[2])
    rest = np.array(body["vertices"]).reshape(-1, 3)
    joints_of, weights = np.array(body["joints"]).reshape(-1, 4), np.array(body["weights"]).reshape(-1, 4)
    assert rest.shape == (24 + 23 * 8, 3) and np.array(body["faces"]).reshape(-1, 3).max() < len(rest)
    np.testing.assert_allclose(weights.sum(axis=1), 1.0, atol=1e-3)
    motion = _events(_ask(port, "POST", "/api/generate", PROGRAM)[2])[-1]["motion"]
    skin = np.array(motion["skin"]).reshape(motion["frames"], 24, 12)
    rotations, shifts = skin[..., :9].reshape(-1, 24, 3, 3), skin[..., 9:]
    posed = np.einsum("vk,tvkab,vb->tva", weights, rotations[:, joints_of], rest) + np.einsum(
        "vk,tvka->tva", weights, shifts[:, joints_of])
    joints = np.array(motion["joints"]).reshape(motion["frames"], 24, 3)
    np.testing.assert_allclose(posed[:, :24], joints, atol=2e-4)


def test_a_body_model_must_be_on_smpls_tree_and_without_one_there_is_no_mesh(generator, tmp_path):
    with pytest.raises(RequestError, match=r"body: the server was started without a body model \(--body-model\)"):
        Composer(generator).body()
    body = load_body_model(box_body(tmp_path / "boxes.npz"))
    other = dataclasses.replace(body, parents=(-1,) + tuple(range(23)))  # a chain: not SMPL's tree
    with pytest.raises(ValueError, match="body: expected a body model on SMPL's 24-joint tree"):
        Composer(generator, body=other)


def test_downloaded_bvh_holds_the_motion(served, tmp_path):
    _, port = served
    motion = _events(_ask(port, "POST", "/api/generate", PROGRAM)[2])[-1]["motion"]
    (tmp_path / "m.bvh").write_bytes(_ask(port, "GET", motion["downloads"]["motion.bvh"])[2])
    assert load_bvh(tmp_path / "m.bvh").rotations.shape[0] == motion["frames"]


@pytest.mark.parametrize("method, path, body, headers, status, message", [
    ("POST", "/api/generate", b"{not json", None, 400, "request: the body is not JSON"),
    ("POST", "/api/generate", {"actions": [{"tags": ["dance"], "frames": 5}]}, None, 400, "unknown tag 'dance'"),
    ("POST", "/api/generate", {**PROGRAM, "shadow": "revision"}, None, 400, "shadow: 'revision' is not on offer"),
    ("POST", "/api/generate", b"x" * (MAX_BODY + 1), None, 413, f"expected at most {MAX_BODY}"),
    ("POST", "/api/other", {}, None, 404, "POST /api/other: not found"),
    ("GET", "/nothing", None, None, 404, "GET /nothing: not found"),
    ("GET", "/static/../app.py", None, None, 404, "not found"),
    ("GET", "/api/motions/m999/motion.bvh", None, None, 404, "motion 'm999': not here"),
    ("PUT", "/api/generate", b"{}", None, 405, "PUT /api/generate: expected GET"),
])
def test_bad_requests_get_a_4xx_naming_the_problem_and_the_server_goes_on(served, method, path, body, headers,
                                                                          status, message):
    _, port = served
    answer, kind, payload = _ask(port, method, path, body, headers)
    assert answer == status and kind == "application/json" and message in json.loads(payload)["error"]
    assert _ask(port, "GET", "/api/model")[0] == 200


def test_a_second_request_waits_its_turn_and_is_told(served):
    composer, port = served
    composer._lock.acquire()  # as if another request were being generated
    connection = http.client.HTTPConnection("127.0.0.1", port, timeout=120)
    connection.request("POST", "/api/generate", body=json.dumps(PROGRAM).encode())
    response = connection.getresponse()
    before = [json.loads(response.readline())]
    while before[-1]["event"] == "warning":  # tag pairs never seen come first
        before.append(json.loads(response.readline()))
    composer._lock.release()
    rest = _events(response.read())
    assert before[-1] == {"event": "queued"} and rest[-1]["event"] == "done"
    assert [e["event"] for e in rest].count("action") == 3
