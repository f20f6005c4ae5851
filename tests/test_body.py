"""Tests for the SMPL-format body layer on a small hand-made model written in the SMPL format."""

import dataclasses
import pickle
import re
import sys
import types

import jax
import jax.numpy as jnp
import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from jaxmotion.geometry.body import (
    BodyModel,
    body_forward,
    body_forward_rotmats,
    load_body_model,
    rest_joints,
    root_translation,
    save_body_model,
    skinning_transforms,
)
from jaxmotion.geometry.rotations import axis_angle_to_matrix

NUM_JOINTS, NUM_VERTICES, NUM_BETAS = 4, 40, 3
FULL_TO_JOINT2, FULL_TO_ROOT = 0, 1  # vertices skinned to a single joint, for analytical checks
# Eager dispatch of every small op is slow; tests go through jit (one compile per input shape).
_forward = jax.jit(body_forward)
_forward_rotmats = jax.jit(body_forward_rotmats)


def _fixture_fields(seed: int = 0) -> dict[str, np.ndarray]:
    """A 4-joint chain along +y with vertices on a thin tube around the bones."""
    rng = np.random.default_rng(seed)
    bone_y = np.array([0.0, 0.5, 1.0, 1.5])
    y = rng.uniform(-0.1, 1.6, NUM_VERTICES)
    angle = rng.uniform(0.0, 2 * np.pi, NUM_VERTICES)
    v_template = np.stack([0.1 * np.cos(angle), y, 0.1 * np.sin(angle)], axis=-1)

    distance = np.abs(y[:, None] - bone_y[None, :])  # [V, J]
    weights = rng.uniform(0.0, 0.2, (NUM_VERTICES, NUM_JOINTS)) + np.exp(-10.0 * distance)
    weights[FULL_TO_JOINT2] = np.eye(NUM_JOINTS)[2]
    weights[FULL_TO_ROOT] = np.eye(NUM_JOINTS)[0]
    weights /= weights.sum(axis=1, keepdims=True)

    regressor = np.zeros((NUM_JOINTS, NUM_VERTICES))
    for j in range(NUM_JOINTS):
        nearest = np.argsort(distance[:, j])[:8]
        regressor[j, nearest] = rng.uniform(0.1, 1.0, nearest.size)
    regressor /= regressor.sum(axis=1, keepdims=True)

    return {
        "v_template": v_template,
        "shapedirs": 0.02 * rng.standard_normal((NUM_VERTICES, 3, NUM_BETAS)),
        "posedirs": 0.01 * rng.standard_normal((NUM_VERTICES, 3, 9 * (NUM_JOINTS - 1))),
        "J_regressor": regressor,
        "weights": weights,
        "kintree_table": np.array([[4294967295, 0, 1, 2], [0, 1, 2, 3]], dtype=np.uint32),
        "f": rng.integers(0, NUM_VERTICES, (20, 3)).astype(np.uint32),
        "bs_style": "lbs",  # official files carry extra keys; they are ignored
    }


def _write_pkl(path, fields) -> None:
    with open(path, "wb") as fh:
        pickle.dump(fields, fh, protocol=2)


def _rodrigues(aa: np.ndarray) -> np.ndarray:
    theta = np.linalg.norm(aa)
    if theta < 1e-12:
        return np.eye(3)
    k = np.array([[0, -aa[2], aa[1]], [aa[2], 0, -aa[0]], [-aa[1], aa[0], 0]]) / theta
    return np.eye(3) + np.sin(theta) * k + (1 - np.cos(theta)) * k @ k


@pytest.fixture(scope="module")
def fields():
    return _fixture_fields()


@pytest.fixture(scope="module")
def model_path(tmp_path_factory, fields):
    path = tmp_path_factory.mktemp("body") / "model.npz"
    np.savez(path, **{k: v for k, v in fields.items() if k != "bs_style"})
    return path


@pytest.fixture(scope="module")
def model(model_path):
    return load_body_model(model_path)


def _zero_pose():
    return jnp.zeros((NUM_JOINTS, 3))


def test_loaded_model_metadata(model, fields):
    assert isinstance(model, BodyModel)
    assert (model.num_vertices, model.num_joints, model.num_betas) == (NUM_VERTICES, NUM_JOINTS, NUM_BETAS)
    assert model.parents == (-1, 0, 1, 2)
    assert model.v_template.dtype == jnp.float32 and model.faces.dtype == jnp.int32
    np.testing.assert_array_equal(model.faces, fields["f"])


def test_rest_pose_reproduces_template(model, fields):
    vertices, joints = _forward(model, _zero_pose(), jnp.zeros(NUM_BETAS), jnp.zeros(3))
    np.testing.assert_allclose(vertices, fields["v_template"], atol=1e-6)
    np.testing.assert_allclose(joints, fields["J_regressor"] @ fields["v_template"], atol=1e-6)


@given(
    pose=arrays(np.float32, (NUM_JOINTS, 3), elements=st.floats(-2.0, 2.0, width=32)),
    translation=arrays(np.float32, (3,), elements=st.floats(-5.0, 5.0, width=32)),
)
def test_translation_moves_body_rigidly(model, pose, translation):
    betas = jnp.array([0.5, -1.0, 0.3])
    vertices, joints = _forward(model, pose, betas, jnp.zeros(3))
    moved_vertices, moved_joints = _forward(model, pose, betas, translation)
    np.testing.assert_allclose(moved_vertices - vertices, np.broadcast_to(translation, vertices.shape), atol=1e-5)
    np.testing.assert_allclose(moved_joints - joints, np.broadcast_to(translation, joints.shape), atol=1e-5)


@given(root_aa=arrays(np.float64, (3,), elements=st.floats(-3.0, 3.0)))
def test_root_rotation_rotates_body_about_root_joint(model, fields, root_aa):
    # Only non-root rotations drive the pose blend shapes, so the (nonzero) posedirs stay inactive.
    pose = np.zeros((NUM_JOINTS, 3), np.float32)
    pose[0] = root_aa
    translation = np.array([0.3, -0.2, 1.0])
    vertices, joints = _forward(model, pose, jnp.zeros(NUM_BETAS), translation)
    rot = _rodrigues(root_aa)
    rest_joints = fields["J_regressor"] @ fields["v_template"]
    root = rest_joints[0]
    np.testing.assert_allclose(vertices, (fields["v_template"] - root) @ rot.T + root + translation, atol=2e-5)
    np.testing.assert_allclose(joints, (rest_joints - root) @ rot.T + root + translation, atol=2e-5)


def test_single_joint_vertex_follows_its_joint_analytically(model, fields):
    rng = np.random.default_rng(1)
    pose = rng.uniform(-1.0, 1.0, (NUM_JOINTS, 3))
    betas = rng.standard_normal(NUM_BETAS)
    translation = rng.standard_normal(3)
    rigid = model.replace(posedirs=jnp.zeros_like(model.posedirs))
    vertices, joints = _forward(rigid, *(x.astype(np.float32) for x in (pose, betas, translation)))

    v_shaped = fields["v_template"] + fields["shapedirs"] @ betas
    rest = fields["J_regressor"] @ v_shaped
    rots = [_rodrigues(aa) for aa in pose]
    global_rot, position = [rots[0]], [rest[0] + translation]
    for j in range(1, NUM_JOINTS):  # the chain: parent of j is j - 1
        position.append(position[j - 1] + global_rot[j - 1] @ (rest[j] - rest[j - 1]))
        global_rot.append(global_rot[j - 1] @ rots[j])
    np.testing.assert_allclose(joints, np.stack(position), atol=1e-5)
    expected = global_rot[2] @ (v_shaped[FULL_TO_JOINT2] - rest[2]) + position[2]
    np.testing.assert_allclose(vertices[FULL_TO_JOINT2], expected, atol=1e-5)


def test_pose_blend_shapes_follow_non_root_rotations(model, fields):
    rng = np.random.default_rng(2)
    pose = rng.uniform(-1.0, 1.0, (NUM_JOINTS, 3))
    pose[0] = 0.0
    vertices, _ = _forward(model, pose.astype(np.float32), jnp.zeros(NUM_BETAS), jnp.zeros(3))
    # (R_j - I) of joints 1..J-1, row-major: the SMPL pose feature.
    feature = np.concatenate([(_rodrigues(aa) - np.eye(3)).ravel() for aa in pose[1:]])
    expected = fields["v_template"][FULL_TO_ROOT] + fields["posedirs"][FULL_TO_ROOT] @ feature
    np.testing.assert_allclose(vertices[FULL_TO_ROOT], expected, atol=1e-5)


def test_skinning_transforms_skin_the_shaped_rest_vertices_as_the_body_without_pose_correctives(model):
    rng = np.random.default_rng(3)
    rotmats = axis_angle_to_matrix(jnp.asarray(rng.uniform(-1.0, 1.0, (2, NUM_JOINTS, 3)), jnp.float32))
    betas, translation = jnp.asarray(rng.normal(size=(2, NUM_BETAS)), jnp.float32), jnp.array([0.3, 0.1, -0.2])
    rotations, shifts = skinning_transforms(model, rotmats, betas, translation)
    shaped = model.v_template + jnp.einsum("vcs,bs->bvc", model.shapedirs, betas)
    skinned = jnp.einsum("vj,bjac,bvc->bva", model.weights, rotations, shaped) + model.weights @ shifts
    flat = dataclasses.replace(model, posedirs=jnp.zeros_like(model.posedirs))
    np.testing.assert_allclose(skinned, body_forward_rotmats(flat, rotmats, betas, translation)[0], atol=1e-5)


def test_shape_blend_shapes_are_linear_and_short_betas_are_zero_padded(model, fields):
    betas = np.array([1.5, -0.7, 2.0])
    vertices, _ = _forward(model, _zero_pose(), betas.astype(np.float32), jnp.zeros(3))
    rest, _ = _forward(model, _zero_pose(), jnp.zeros(NUM_BETAS), jnp.zeros(3))
    np.testing.assert_allclose(vertices - rest, fields["shapedirs"] @ betas, atol=1e-5)
    short, _ = _forward(model, _zero_pose(), jnp.array([1.5, -0.7]), jnp.zeros(3))
    padded, _ = _forward(model, _zero_pose(), jnp.array([1.5, -0.7, 0.0]), jnp.zeros(3))
    np.testing.assert_allclose(short, padded, atol=1e-6)


def test_rest_joints_are_the_regressed_shaped_template_and_root_translation_puts_the_root_where_asked(model, fields):
    betas = np.array([1.5, -0.7, 2.0], np.float32)
    expected = fields["J_regressor"] @ (fields["v_template"] + fields["shapedirs"][..., :3] @ betas)
    np.testing.assert_allclose(rest_joints(model, betas), expected, atol=1e-5)
    _, joints = _forward(model, _zero_pose(), betas, jnp.zeros(3))
    np.testing.assert_allclose(rest_joints(model, betas), joints, atol=1e-5)
    np.testing.assert_allclose(rest_joints(model), fields["J_regressor"] @ fields["v_template"], atol=1e-5)
    root = np.array([0.3, 1.1, -2.0], np.float32)  # the library's translation: where the root joint is
    _, posed = _forward(model, _zero_pose(), betas, root_translation(model, root, betas))
    np.testing.assert_allclose(posed[0], root, atol=1e-5)


def test_leading_axes_broadcast_and_match_per_item_calls(model):
    rng = np.random.default_rng(3)
    pose = rng.uniform(-1.0, 1.0, (2, 3, NUM_JOINTS, 3)).astype(np.float32)
    betas = rng.standard_normal(NUM_BETAS).astype(np.float32)  # one shape for every frame
    translation = rng.standard_normal((3, 3)).astype(np.float32)  # broadcasts over the first axis
    vertices, joints = _forward(model, pose, betas, translation)
    assert vertices.shape == (2, 3, NUM_VERTICES, 3) and joints.shape == (2, 3, NUM_JOINTS, 3)
    for b in range(2):
        for t in range(3):
            v, j = _forward(model, pose[b, t], betas, translation[t])
            np.testing.assert_allclose(vertices[b, t], v, atol=1e-5)
            np.testing.assert_allclose(joints[b, t], j, atol=1e-5)


def test_rotmats_core_matches_axis_angle_wrapper(model):
    pose = np.random.default_rng(4).uniform(-1.0, 1.0, (NUM_JOINTS, 3)).astype(np.float32)
    rotmats = np.stack([_rodrigues(aa) for aa in pose]).astype(np.float32)
    betas, translation = jnp.array([0.5, -1.0, 0.3]), jnp.array([0.1, 0.2, 0.3])
    expected = _forward(model, pose, betas, translation)
    for got, want in zip(_forward_rotmats(model, rotmats, betas, translation), expected):
        np.testing.assert_allclose(got, want, atol=1e-5)


def test_npz_and_pkl_load_identically(tmp_path, fields, model):
    _write_pkl(tmp_path / "model.pkl", fields)
    from_pkl = load_body_model(tmp_path / "model.pkl")
    assert from_pkl.parents == model.parents
    for a, b in zip(jax.tree.leaves(from_pkl), jax.tree.leaves(model)):
        np.testing.assert_array_equal(a, b)


def test_pkl_with_sparse_regressor_and_minus_one_root(tmp_path, fields, model):
    sparse = pytest.importorskip("scipy.sparse")
    official_like = dict(fields, J_regressor=sparse.csc_matrix(fields["J_regressor"]))
    official_like["kintree_table"] = np.array([[-1, 0, 1, 2], [0, 1, 2, 3]])
    _write_pkl(tmp_path / "sparse.pkl", official_like)
    loaded = load_body_model(tmp_path / "sparse.pkl")
    assert loaded.parents == model.parents
    np.testing.assert_array_equal(loaded.joint_regressor, model.joint_regressor)


def test_save_body_model_round_trips(tmp_path, model):
    save_body_model(tmp_path / "copy.npz", model)
    copy = load_body_model(tmp_path / "copy.npz")
    assert copy.parents == model.parents
    for a, b in zip(jax.tree.leaves(copy), jax.tree.leaves(model)):
        np.testing.assert_array_equal(a, b)


def test_missing_file_names_path(tmp_path):
    path = tmp_path / "nowhere" / "SMPL_NEUTRAL.npz"
    with pytest.raises(FileNotFoundError, match="SMPL_NEUTRAL.npz"):
        load_body_model(path)


@pytest.mark.parametrize(
    ("field", "value", "message"),
    [
        ("weights", None, r"missing field 'weights'"),
        ("posedirs", np.zeros((NUM_VERTICES, 3, 26)), r"'posedirs'.*\[V, 3, 9\*\(J-1\)\] = \(40, 3, 27\)"),
        ("weights", np.zeros((NUM_VERTICES + 1, NUM_JOINTS)), r"'weights'.*\[V, J\] = \(40, 4\)"),
        ("J_regressor", np.zeros((NUM_JOINTS, NUM_VERTICES, 1)), r"'J_regressor'.*expected rank 2, \[J, V\]"),
        ("v_template", np.full((NUM_VERTICES, 3), "x"), r"'v_template'.*dtype"),
        ("kintree_table", np.array([[-1, 0, 3, 2], [0, 1, 2, 3]]), r"'kintree_table'"),
    ],
)
def test_malformed_file_raises_naming_file_and_field(tmp_path, fields, field, value, message):
    broken = {k: v for k, v in fields.items() if k != "bs_style"}
    if value is None:
        del broken[field]
    else:
        broken[field] = value
    path = tmp_path / "broken.npz"
    np.savez(path, **broken)
    with pytest.raises(ValueError, match="broken.npz") as info:
        load_body_model(path)
    assert info.match(message)


def test_unsupported_suffix_and_unreadable_files(tmp_path):
    path = tmp_path / "model.json"
    path.write_text("{}")
    with pytest.raises(ValueError, match=r"\.npz or \.pkl"):
        load_body_model(path)
    (tmp_path / "corrupt.npz").write_bytes(b"PK\x03\x04 truncated")
    with pytest.raises(ValueError, match="corrupt.npz"):
        load_body_model(tmp_path / "corrupt.npz")
    _write_pkl(tmp_path / "list.pkl", [1, 2, 3])
    with pytest.raises(ValueError, match=r"list\.pkl.*dict"):
        load_body_model(tmp_path / "list.pkl")


def test_chumpy_pickle_explains_conversion(tmp_path, fields, monkeypatch):
    # Build a pickle that references chumpy.ch.Ch, as the official files do, then hide the module.
    chumpy, chumpy_ch = types.ModuleType("chumpy"), types.ModuleType("chumpy.ch")
    ch_class = type("Ch", (), {"__module__": "chumpy.ch"})
    chumpy_ch.Ch = ch_class
    with monkeypatch.context() as patch:
        patch.setitem(sys.modules, "chumpy", chumpy)
        patch.setitem(sys.modules, "chumpy.ch", chumpy_ch)
        _write_pkl(tmp_path / "official.pkl", dict(fields, shapedirs=ch_class()))
    with pytest.raises(ImportError, match=r"official\.pkl.*chumpy.*\.npz"):
        load_body_model(tmp_path / "official.pkl")


def test_too_many_betas_and_wrong_pose_shape_raise(model):
    with pytest.raises(ValueError, match="S' <= 3"):
        _forward(model, _zero_pose(), jnp.zeros(NUM_BETAS + 1))
    with pytest.raises(ValueError, match="rotmats"):
        _forward(model, jnp.zeros((NUM_JOINTS + 1, 3)))


def test_a_concrete_mirrored_joint_rotation_is_refused(model):
    rotmats = np.tile(np.eye(3, dtype=np.float32), (NUM_JOINTS, 1, 1))
    rotmats[1, 0, 0] = -1.0
    with pytest.raises(ValueError, match=re.escape("body_forward_rotmats: rotmats: 1 of "
                                                   f"{NUM_JOINTS} matrices are not rotations; the first, at index "
                                                   "(1,), is a reflection")):
        body_forward_rotmats(model, rotmats)


def test_jit_matches_eager(model):
    rng = np.random.default_rng(5)
    args = (
        rng.uniform(-1.0, 1.0, (NUM_JOINTS, 3)).astype(np.float32),
        rng.standard_normal(NUM_BETAS).astype(np.float32),
        rng.standard_normal(3).astype(np.float32),
    )
    for got, want in zip(_forward(model, *args), body_forward(model, *args)):
        np.testing.assert_allclose(got, want, atol=1e-5)


def test_gradients_finite_at_zero_pose(model):
    def loss(pose, betas):
        vertices, joints = body_forward(model, pose, betas)
        return jnp.sum(vertices**2) + jnp.sum(joints**2)

    grad_pose, grad_betas = jax.jit(jax.grad(loss, argnums=(0, 1)))(_zero_pose(), jnp.zeros(NUM_BETAS))
    assert np.all(np.isfinite(grad_pose)) and np.all(np.isfinite(grad_betas))
    assert np.any(grad_pose != 0.0)
