"""Motion export: BVH, AMASS-layout npz and joints npy written, read back and posed again.

Speed: every motion has at most 16 frames and 24 joints, so the exporter's conversions (padded to 16
frames) and forward kinematics on the SMPL-24 tree compile once for the whole file.
"""

import functools
import re

import jax
import numpy as np
import pytest

from jaxmotion.data import export, pack
from jaxmotion.data.motion import Motion
from jaxmotion.data.retarget import foot_contacts, foot_skating, mixamo_names
from jaxmotion.data.synthetic import generate, subject_offsets
from jaxmotion.geometry import (
    CMU_MOCAP20,
    EULER_ORDERS,
    SMPL24,
    axis_angle_to_matrix,
    euler_to_matrix,
    forward_kinematics,
    load_body_model,
    matrix_to_axis_angle,
)
from jaxmotion.progress import ENV_AFTER, ENV_EVERY

FRAMES = 16
FPS = 20.0
FK_ATOL = 1e-4  # metres: the round-trip tolerance
LEAVES = [j for j in range(SMPL24.num_joints) if j not in SMPL24.parents]


def matrices(rotations):
    """Axis-angle ``[..., 3]`` -> ``[..., 3, 3]``, on the exporter's padded shapes (nothing compiles twice)."""
    return export._rows(axis_angle_to_matrix, rotations)


def fk(rotations, translation, offsets):
    """SMPL-24 joints ``[T, 24, 3]`` of axis-angle ``[T, 24, 3]`` rotations, T <= FRAMES (padded to FRAMES,
    as the exporter pads, so that forward kinematics compiles once)."""
    count = len(rotations)
    rotations, translation = (np.pad(np.asarray(a, np.float32), [(0, FRAMES - count)] + [(0, 0)] * (a.ndim - 1),
                                     mode="edge") for a in (matrices(rotations), translation))
    joints = forward_kinematics(rotations, translation, np.asarray(offsets, np.float32), SMPL24.parents)
    return np.asarray(joints)[:count]


def normal(seed: int) -> np.ndarray:
    """``[FRAMES, 25, 3]`` float32 standard normals from ``seed`` (one shape: jax.random compiles once)."""
    return np.asarray(jax.random.normal(jax.random.PRNGKey(seed), (FRAMES, 25, 3)))


@functools.cache
def motion(seed: int, subject: int | None = 3):
    """A random SMPL-24 motion ``(rotations, translation, offsets, joints)`` with joints = FK(rotations).

    ``subject``: the bone lengths of that subject of the embedded HumanAct12 stand-in (per-subject offsets,
    as in the embedded data), or ``None`` for the SMPL-24 template.
    """
    draws = normal(seed)
    rotations, translation = 0.7 * draws[:, :24], draws[:, 24]
    offsets = SMPL24.offsets if subject is None else subject_offsets("synth-humanact12", subject)
    return rotations, translation, offsets, fk(rotations, translation, offsets)


def in_joint_order(bvh: export.BvhMotion, names):
    """A read-back BVH's arrays reordered from the file's depth-first order to ``names``' order."""
    index = [bvh.names.index(name) for name in names]
    where = {old: new for new, old in enumerate(index)}
    parents = tuple(-1 if bvh.parents[i] < 0 else where[bvh.parents[i]] for i in index)
    return parents, bvh.offsets[index], bvh.rotations[:, index]


def read_back_joints(path):
    bvh = export.load_bvh(path)
    parents, offsets, rotations = in_joint_order(bvh, SMPL24.joint_names)
    assert parents == SMPL24.parents
    return fk(rotations, bvh.translation, offsets), bvh


def elementary_rotation(axis, degrees):
    """Right-handed rotation by ``degrees`` about "X", "Y" or "Z" (column vectors), in numpy: an oracle."""
    t = np.radians(degrees)
    c, s = np.cos(t), np.sin(t)
    return {"X": np.array([[1, 0, 0], [0, c, -s], [0, s, c]]), "Y": np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]]),
            "Z": np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])}[axis]


def rodrigues(axis_angle):
    """``[..., 3]`` axis-angle -> ``[..., 3, 3]``, float64, written out (the reader borrows nothing)."""
    angle = np.linalg.norm(axis_angle, axis=-1, keepdims=True)[..., None]
    k = axis_angle / np.maximum(np.linalg.norm(axis_angle, axis=-1, keepdims=True), 1e-12)
    cross = np.zeros(k.shape[:-1] + (3, 3))
    cross[..., 0, 1], cross[..., 0, 2], cross[..., 1, 2] = -k[..., 2], k[..., 1], -k[..., 0]
    cross = cross - np.swapaxes(cross, -1, -2)
    return np.eye(3) + np.sin(angle) * cross + (1 - np.cos(angle)) * cross @ cross


def assert_same_rotations(actual, expected, atol=1e-5):
    np.testing.assert_allclose(matrices(actual), matrices(expected), rtol=0, atol=atol)


# --- rest offsets ----------------------------------------------------------------------------------------


@pytest.mark.parametrize("subject", [None, 3, 7])
def test_rest_offsets_recover_the_offsets_a_motion_was_posed_with(subject):
    rotations, _, offsets, joints = motion(0, subject)
    recovered = export.rest_offsets(rotations, joints, SMPL24.parents)
    np.testing.assert_allclose(recovered[1:], offsets[1:], rtol=0, atol=1e-5)
    assert np.all(recovered[0] == 0.0) and recovered.dtype == np.float32
    np.testing.assert_array_equal(export.rest_offsets(rotations[0], joints[0], SMPL24.parents), recovered)


def test_embedded_subject_offsets_are_not_the_template():
    # Why rest_offsets exists: the embedded data's bodies differ from SMPL24.offsets by centimetres.
    assert np.abs(subject_offsets("synth-humanact12", 3) - SMPL24.offsets).max() > 0.01


# --- BVH -------------------------------------------------------------------------------------------------


@pytest.mark.parametrize("order", EULER_ORDERS)
def test_bvh_round_trip_reproduces_joints_for_every_euler_order(tmp_path, order):
    rotations, translation, offsets, joints = motion(1)
    path = export.save_bvh(tmp_path / "m.bvh", rotations, translation, export.rest_offsets(rotations, joints,
                           SMPL24.parents), SMPL24.parents, SMPL24.joint_names, FPS, order)
    read, bvh = read_back_joints(path)
    np.testing.assert_allclose(read, joints, rtol=0, atol=FK_ATOL)
    assert bvh.orders == (order,) * 24 and bvh.fps == FPS
    assert_same_rotations(in_joint_order(bvh, SMPL24.joint_names)[2], rotations)


@pytest.mark.parametrize("order", ["ZXY", "XYZ"])
@pytest.mark.parametrize("sign", [1.0, -1.0])
def test_bvh_euler_singularities_survive_the_round_trip(tmp_path, order, sign):
    # Every joint at gimbal lock: the middle channel at +-90 degrees.
    angles = np.clip(1.5 * normal(2)[:, :24], -3.0, 3.0)
    angles[..., 1] = sign * np.pi / 2
    rotations = export._rows(lambda a: matrix_to_axis_angle(euler_to_matrix(a, order)), angles)
    _, translation, offsets, _ = motion(1)
    joints = fk(rotations, translation, offsets)
    path = export.save_bvh(tmp_path / "lock.bvh", rotations, translation, offsets, SMPL24.parents,
                           SMPL24.joint_names, FPS, order)
    read, bvh = read_back_joints(path)
    np.testing.assert_allclose(read, joints, rtol=0, atol=FK_ATOL)
    assert_same_rotations(in_joint_order(bvh, SMPL24.joint_names)[2], rotations)


def test_bvh_file_has_the_smpl_hierarchy_channels_and_frame_time(tmp_path):
    rotations, translation, offsets, _ = motion(1)
    path = export.save_bvh(tmp_path / "m.bvh", rotations, translation, offsets, SMPL24.parents,
                           SMPL24.joint_names, 30.0)
    text = path.read_text()
    assert text.startswith("HIERARCHY\nROOT pelvis\n{\n")
    assert text.count("CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation") == 1
    assert text.count("CHANNELS 3 Zrotation Xrotation Yrotation") == 23
    assert text.count("JOINT ") == 23 and text.count("End Site") == len(LEAVES) == 5
    assert f"MOTION\nFrames: {FRAMES}\nFrame Time: {1 / 30.0!r}\n" in text
    assert len(text.split("MOTION\n")[1].splitlines()) == 2 + FRAMES
    assert export.load_bvh(path).fps == pytest.approx(30.0, rel=1e-12)


def test_bvh_round_trip_keeps_any_tree_and_a_non_zero_root_offset(tmp_path):
    # A random 24-joint tree whose joint order is not depth-first, with a root OFFSET.
    rng = np.random.default_rng(0)
    order = rng.permutation(np.arange(1, 24))
    parents = [-1] * 24
    for position, joint in enumerate(order):
        parents[joint] = int(rng.choice(np.concatenate([[0], order[:position]])))
    parents, names = tuple(parents), tuple(f"j{j}" for j in range(24))
    rotations, translation, _, _ = motion(2)
    offsets = rng.normal(size=(24, 3)).astype(np.float32)
    bvh = export.load_bvh(export.save_bvh(tmp_path / "tree.bvh", rotations, translation, offsets, parents, names,
                                          FPS, "YZX"))
    read_parents, read_offsets, read_rotations = in_joint_order(bvh, names)
    assert read_parents == parents
    np.testing.assert_allclose(read_offsets, offsets, rtol=0, atol=1e-6)
    np.testing.assert_allclose(bvh.translation, translation, rtol=0, atol=1e-5)
    assert_same_rotations(read_rotations, rotations)


MIXED_ORDERS_BVH = """HIERARCHY
ROOT hips
{
  OFFSET 1.0 2.0 3.0
  CHANNELS 6 Zposition Yrotation Xposition Xrotation Yposition Zrotation
  JOINT chest
  {
    OFFSET 0 1 0
    CHANNELS 3 Xrotation Yrotation Zrotation
    End Site
    {
      OFFSET 0 0.5 0
    }
  }
}
MOTION
Frames: 2
Frame Time: 0.04
0.3 10 0.1 20 0.2 30 40 50 60
-0.3 -10 -0.1 -20 -0.2 -30 90 -90 0
"""


def test_load_bvh_reads_each_joints_own_channel_order(tmp_path):
    path = tmp_path / "mixed.bvh"
    path.write_text(MIXED_ORDERS_BVH)
    bvh = export.load_bvh(path)
    assert bvh.names == ("hips", "chest") and bvh.parents == (-1, 0) and bvh.orders == ("YXZ", "XYZ")
    assert bvh.fps == pytest.approx(25.0)
    np.testing.assert_allclose(bvh.translation, [[1.1, 2.2, 3.3], [0.9, 1.8, 2.7]], atol=1e-6)
    np.testing.assert_allclose(bvh.offsets, [[1, 2, 3], [0, 1, 0]])
    channels = [[[10, 20, 30], [40, 50, 60]], [[-10, -20, -30], [90, -90, 0]]]  # [frame][joint], channel order
    for frame, joint in np.ndindex(2, 2):
        order, angles = bvh.orders[joint], channels[frame][joint]
        expected = functools.reduce(np.matmul, [elementary_rotation(a, d) for a, d in zip(order, angles)])
        np.testing.assert_allclose(rodrigues(bvh.rotations[frame, joint]), expected, atol=1e-5)


MALFORMED = [
    ("0.3 10 0.1 20 0.2 30 40 50 60\n", "0.3 10 0.1 20 0.2 30 40 50\n", "line 19: expected 9 channel values"),
    ("0.3 10 0.1 20 0.2 30 40 50 60\n", "0.3 10 0.1 20 0.2 x 40 50 60\n", "line 19: expected numbers"),
    ("    OFFSET 0 1 0\n", "    OFFSET 0 one 0\n", "line 8: expected an OFFSET value, got 'one'"),
    ("    CHANNELS 3 Xrotation", "    CHANNELS 3 Wrotation", "line 9: unknown channel 'Wrotation'"),
    ("    CHANNELS 3 Xrotation Yrotation Zrotation", "    CHANNELS 3 Xposition Yposition Zposition",
     "line 9: joint chest: position channels are read on the root only"),
    ("  JOINT chest", "  BONE chest", "line 6: expected OFFSET, CHANNELS, JOINT, End Site or '}'"),
    ("Frames: 2", "Frames: 3", "'Frames: 3' but 2 frame lines follow"),
    ("MOTION\n", "ROOT other\n{\n}\nMOTION\n", "line 16: a second ROOT"),
    ("HIERARCHY", "HIERARCH", "line 1: expected 'HIERARCHY', got 'HIERARCH'"),
]


@pytest.mark.parametrize("old, new, message", MALFORMED)
def test_malformed_bvh_is_rejected_naming_the_line(tmp_path, old, new, message):
    path = tmp_path / "bad.bvh"
    assert old in MIXED_ORDERS_BVH
    path.write_text(MIXED_ORDERS_BVH.replace(old, new, 1))
    with pytest.raises(ValueError, match=re.escape(message)):
        export.load_bvh(path)


def test_bvh_with_non_finite_channel_values_is_rejected_naming_the_line(tmp_path):
    path = tmp_path / "nan.bvh"
    lines = MIXED_ORDERS_BVH.splitlines()
    last = len(lines) - 1
    lines[last] = " ".join(["nan"] + lines[last].split()[1:])
    path.write_text("\n".join(lines) + "\n")
    with pytest.raises(ValueError, match=f"line {last + 1}: expected finite numbers, got \\['nan'\\]"):
        export.load_bvh(path)


def test_truncated_bvh_is_an_unexpected_end_of_file(tmp_path):
    path = tmp_path / "short.bvh"
    path.write_text(MIXED_ORDERS_BVH.split("  JOINT")[0])
    with pytest.raises(ValueError, match="unexpected end of file"):
        export.load_bvh(path)


def test_save_bvh_rejects_wrong_shapes_naming_field_and_expected_shape(tmp_path):
    rotations, translation, offsets, _ = motion(1)
    args = dict(offsets=offsets, parents=SMPL24.parents, names=SMPL24.joint_names, fps=FPS)
    with pytest.raises(ValueError, match=re.escape("rotations: expected [T, 24, 3], got (60, 23, 3)")):
        export.save_bvh(tmp_path / "x.bvh", np.zeros((60, 23, 3)), np.zeros((60, 3)), **args)
    with pytest.raises(ValueError, match=re.escape("translation: expected [T, 3] = (16, 3), got (15, 3)")):
        export.save_bvh(tmp_path / "x.bvh", rotations, translation[1:], **args)
    with pytest.raises(ValueError, match=re.escape("order: expected one of")):
        export.save_bvh(tmp_path / "x.bvh", rotations, translation, **args, order="ZXZ")
    assert not (tmp_path / "x.bvh").exists()


# --- AMASS npz ---------------------------------------------------------------------------------------------


KEYS = {"smplh": ["betas", "dmpls", "gender", "mocap_framerate", "poses", "trans"],
        "smpl": ["betas", "gender", "mocap_framerate", "poses", "trans"]}


@pytest.mark.parametrize("layout, up", [("smplh", "z"), ("smpl", "y")])
def test_amass_npz_round_trip_keeps_keys_shapes_dtypes_and_joints(tmp_path, layout, up):
    rotations, translation, offsets, joints = motion(4)
    options = export.AmassOptions(layout=layout, up=up)
    path = export.save_amass_npz(tmp_path / "m.npz", rotations, translation, FPS, options)
    body = 22 if layout == "smplh" else 24
    with np.load(path) as data:
        assert sorted(data.files) == KEYS[layout]
        assert data["poses"].shape == (FRAMES, {"smplh": 156, "smpl": 72}[layout])
        assert data["poses"].dtype == data["trans"].dtype == np.float64 and data["trans"].shape == (FRAMES, 3)
        np.testing.assert_array_equal(data["betas"], np.zeros({"smplh": 16, "smpl": 10}[layout]))
        assert data["mocap_framerate"].dtype == np.float64 and float(data["mocap_framerate"]) == FPS
        assert str(data["gender"]) == "neutral"
        np.testing.assert_allclose(data["poses"][:, 3: 3 * body], rotations[:, 1:body].reshape(FRAMES, -1), atol=0)
        assert np.all(data["poses"][:, 3 * body:] == 0.0)  # SMPL+H's fingers at rest
        if layout == "smplh":
            np.testing.assert_array_equal(data["dmpls"], np.zeros((FRAMES, 8)))
    loaded, fps = export.load_amass_npz(path, up=up, offsets=offsets)
    assert fps == FPS and loaded.name == "m" and loaded.action == -1
    # SMPL's hand joints 22 and 23 are leaves: SMPL+H drops their rotations, no joint moves
    np.testing.assert_allclose(loaded.joints, joints, rtol=0, atol=FK_ATOL)
    np.testing.assert_allclose(loaded.translation, translation, rtol=0, atol=1e-6)
    assert_same_rotations(loaded.rotations[:, :body], rotations[:, :body])


def test_amass_z_up_turns_the_library_up_axis_to_z(tmp_path):
    rotations, translation, _, _ = motion(4)
    root_rest = np.array([0.001, -0.22, 0.03])
    options = export.AmassOptions(root_rest=root_rest, betas=np.ones(3), gender="female")
    path = export.save_amass_npz(tmp_path / "m.npz", np.zeros_like(rotations), translation, FPS, options)
    with np.load(path) as data:
        # R_x(+90 deg): (x, y, z) -> (x, -z, y); SMPL's trans leaves out the rest pelvis.
        np.testing.assert_allclose(data["trans"] + root_rest, translation[:, [0, 2, 1]] * [1, -1, 1], atol=1e-6)
        root = matrices(data["poses"][:, :3])
        np.testing.assert_allclose(root @ [0.0, 1.0, 0.0], np.broadcast_to([0.0, 0.0, 1.0], (FRAMES, 3)), atol=1e-6)
        np.testing.assert_array_equal(data["betas"], [1.0] * 3 + [0.0] * 13)  # padded to AMASS's 16, in order
        assert str(data["gender"]) == "female"
    loaded, _ = export.load_amass_npz(path, root_rest=root_rest)
    np.testing.assert_allclose(loaded.translation, translation, rtol=0, atol=1e-6)


# SMPL+H's kinematic tree as its model files write it (kintree_table row 0): SMPL's 22 body joints, then the
# left hand's 15 finger joints (index, middle, little, ring, thumb; 3 each, the first on the left wrist, 20),
# then the right hand's (on the right wrist, 21). Written out here, not taken from the library.
SMPLH_PARENTS = ([-1, 0, 0, 0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 9, 9, 12, 13, 14, 16, 17, 18, 19]
                 + [p for wrist, first in ((20, 22), (21, 37)) for f in range(5)
                    for p in (wrist, first + 3 * f, first + 3 * f + 1)])


def smplh_file(path, rest, *, betas_shift):
    """An SMPL+H-format model file (one vertex on each joint, J_regressor the identity, 16 betas) whose rest body
    joints are ``rest [22, 3]`` at betas = 0, fingers 3 cm apart beyond each wrist; beta 0 lifts the whole body by
    ``betas_shift`` (its rest pelvis moves with the shape, its bone lengths do not)."""
    fingers = [rest[20 + hand] + [0.03 * (1 - 2 * hand) * (1 + k % 3), 0.0, 0.01 * (k // 3)]
               for hand in (0, 1) for k in range(15)]
    vertices = np.concatenate([rest, fingers]).astype(np.float32)
    shapedirs = np.zeros((52, 3, 16), np.float32)
    shapedirs[:, :, 0] = betas_shift
    np.savez(path, v_template=vertices, shapedirs=shapedirs, posedirs=np.zeros((52, 3, 459), np.float32),
             J_regressor=np.eye(52, dtype=np.float32), weights=np.eye(52, dtype=np.float32),
             kintree_table=np.stack([np.where(np.array(SMPLH_PARENTS) < 0, 2 ** 32 - 1, SMPLH_PARENTS),
                                     np.arange(52)]).astype(np.int64))
    return path


def pose_amass_file(npz_path, model_path):
    """An independent reading: the joints ``[T, J, 3]`` (the file's world) a body model file puts where an AMASS
    file says, as SMPL does: rest joints = J_regressor (v_template + shapedirs betas); each joint's world
    transform = its parent's composed with (R_j, rest offset); the root at J_0 + trans."""
    with np.load(npz_path) as data, np.load(model_path) as model:
        parents = [int(p) if p < len(model["kintree_table"][0]) else -1 for p in model["kintree_table"][0]]
        betas = data["betas"][: model["shapedirs"].shape[-1]]
        rest = model["J_regressor"] @ (model["v_template"] + model["shapedirs"] @ betas)
        rotations = rodrigues(data["poses"].reshape(len(data["poses"]), -1, 3))
        trans = data["trans"]
    frames, joints = len(trans), len(parents)
    world_rotations, positions = np.zeros((frames, joints, 3, 3)), np.zeros((frames, joints, 3))
    for j, p in enumerate(parents):  # parents come before children in SMPL's order
        if p < 0:
            world_rotations[:, j], positions[:, j] = rotations[:, j], rest[j] + trans
        else:
            world_rotations[:, j] = world_rotations[:, p] @ rotations[:, j]
            positions[:, j] = positions[:, p] + world_rotations[:, p] @ (rest[j] - rest[p])
    return positions


@pytest.mark.parametrize("layout", ["smplh", "smpl"])
def test_amass_npz_posed_by_an_independent_reading_of_the_body_model_gives_the_motions_joints(tmp_path, layout):
    rotations, translation, offsets, joints = motion(5)
    pelvis = np.array([0.0, 0.9, 0.02])  # the model's rest pelvis at betas = 0, not the origin
    rest = fk(np.zeros((1, 24, 3)), pelvis[None], offsets)[0]
    betas = np.array([0.5, 0.0, -1.0])
    if layout == "smplh":
        model = smplh_file(tmp_path / "smplh.npz", rest[:22], betas_shift=[0.02, 0.1, -0.03])
    else:
        model = tmp_path / "smpl.npz"
        shapedirs = np.zeros((24, 3, 10), np.float32)
        shapedirs[:, :, 0] = [0.02, 0.1, -0.03]
        np.savez(model, v_template=rest.astype(np.float32), shapedirs=shapedirs, posedirs=np.zeros((24, 3, 207)),
                 J_regressor=np.eye(24), weights=np.eye(24), kintree_table=np.stack([SMPL24.parents, np.arange(24)]))
    options = export.AmassOptions.for_body(load_body_model(model), betas, layout=layout, gender="male")
    path = export.save_amass_npz(tmp_path / "m.npz", rotations, translation, FPS, options)
    posed = pose_amass_file(path, model)
    z_up = joints[..., [0, 2, 1]] * [1, -1, 1]  # the library's y up as AMASS's z up: R_x(+90 deg)
    body = 22 if layout == "smplh" else 24
    np.testing.assert_allclose(posed[:, :body], z_up[:, :body], rtol=0, atol=FK_ATOL)
    # the file read back with the same model puts the root where it was
    loaded, _ = export.load_amass_npz(path, offsets=offsets, body=load_body_model(model))
    np.testing.assert_allclose(loaded.joints, joints, rtol=0, atol=FK_ATOL)


def test_amass_options_refuse_bad_values_naming_the_field(tmp_path):
    for fields, message in [({"layout": "smplx"}, "layout: expected one of ['smplh', 'smpl'], got 'smplx'"),
                            ({"gender": "other"}, "gender: expected one of ['neutral', 'male', 'female']"),
                            ({"up": "x"}, "up: expected 'z'"), ({"betas": [np.nan]}, "betas: 1 non-finite values"),
                            ({"root_rest": [0.0, 1.0]}, "root_rest: expected [3], got (2,)")]:
        with pytest.raises(ValueError, match=re.escape(message)):
            export.AmassOptions(**fields)
    model = load_body_model(smplh_file(tmp_path / "smplh.npz", np.zeros((22, 3)), betas_shift=0.0))
    with pytest.raises(ValueError, match=re.escape("betas: the body model has 16 shape coefficients, got 17")):
        export.AmassOptions.for_body(model, np.zeros(17))
    np.savez(tmp_path / "long.npz", poses=np.zeros((2, 156)), trans=np.zeros((2, 3)), mocap_framerate=30.0,
             betas=np.r_[np.zeros(16), 1.0])  # a 17th coefficient the model cannot apply: refused, not dropped
    with pytest.raises(ValueError, match=re.escape("betas: 17 shape coefficients, non-zero past the body model's 16")):
        export.load_amass_npz(tmp_path / "long.npz", body=model)


def test_load_amass_npz_reads_smplh_poses_of_real_amass_files(tmp_path):
    rotations, translation, _, _ = motion(4)
    poses = np.concatenate([rotations[:, :22].reshape(FRAMES, 66), np.ones((FRAMES, 90))], axis=1)
    np.savez(tmp_path / "smplh.npz", poses=poses, trans=translation, betas=np.zeros(16), mocap_framerate=120.0,
             gender="male", dmpls=np.zeros((FRAMES, 8)))
    loaded, fps = export.load_amass_npz(tmp_path / "smplh.npz", up="y")
    assert fps == 120.0
    np.testing.assert_allclose(loaded.rotations[:, :22], rotations[:, :22], atol=1e-6)
    assert np.all(loaded.rotations[:, 22:] == 0.0)
    np.testing.assert_allclose(loaded.joints, fk(loaded.rotations, loaded.translation, SMPL24.offsets), atol=1e-6)


def test_load_amass_npz_names_missing_keys_and_bad_pose_widths(tmp_path):
    np.savez(tmp_path / "a.npz", poses=np.zeros((4, 72)), trans=np.zeros((4, 3)))
    with pytest.raises(ValueError, match=re.escape("missing ['mocap_framerate']")):
        export.load_amass_npz(tmp_path / "a.npz")
    np.savez(tmp_path / "b.npz", poses=np.zeros((4, 69)), trans=np.zeros((4, 3)), mocap_framerate=30.0)
    with pytest.raises(ValueError, match=re.escape("poses: expected [T, 72] (SMPL) or [T, 156] (SMPL+H), got (4, 69)")):
        export.load_amass_npz(tmp_path / "b.npz")


# --- npy ---------------------------------------------------------------------------------------------------


def test_joints_npy_round_trip_is_float32_at_the_given_path(tmp_path):
    *_, joints = motion(5)
    path = export.save_joints_npy(tmp_path / "joints", joints.astype(np.float64))
    assert path == tmp_path / "joints"  # no extension appended behind the caller's back
    loaded = np.load(path)
    assert loaded.dtype == np.float32
    np.testing.assert_array_equal(loaded, joints.astype(np.float32))


# --- export_motions ------------------------------------------------------------------------------------------


def batch(lengths=(16, 9, 5)):
    """A padded sampler-style batch of three motions; frames past each length are garbage."""
    parts = [motion(10 + n) for n in range(len(lengths))]
    out = {name: np.stack([p[i] for p in parts]) for i, name in enumerate(("rotations", "translation"))}
    out["joints"] = np.stack([p[3] for p in parts])
    for n, length in enumerate(lengths):
        for name in ("rotations", "translation", "joints"):
            out[name][n, length:] = 1e3  # padding that must not reach any file
    out["lengths"] = np.array(lengths)
    return out


@pytest.mark.parametrize("cut", ["lengths", "mask"])
def test_export_motions_writes_every_format_with_each_motions_own_frames(tmp_path, cut):
    motions = batch()
    if cut == "mask":
        motions["mask"] = np.arange(FRAMES)[None, :] < motions.pop("lengths")[:, None]
    written = export.export_motions(tmp_path / "out", motions, SMPL24, FPS)
    stems = ["0000", "0001", "0002"]
    assert written == [tmp_path / "out" / f"{s}.{f}" for s in stems for f in ("bvh", "npz", "npy")]
    for n, (stem, length) in enumerate(zip(stems, (16, 9, 5))):
        joints = motions["joints"][n, :length]
        assert np.load(tmp_path / "out" / f"{stem}.npy").shape == (length, 24, 3)
        read, bvh = read_back_joints(tmp_path / "out" / f"{stem}.bvh")
        np.testing.assert_allclose(read, joints, rtol=0, atol=FK_ATOL)
        # The npz holds no bone lengths: posed on the motion's own offsets (the BVH's), it gives the joints.
        loaded, _ = export.load_amass_npz(tmp_path / "out" / f"{stem}.npz",
                                          offsets=in_joint_order(bvh, SMPL24.joint_names)[1])
        np.testing.assert_allclose(loaded.joints, joints, rtol=0, atol=FK_ATOL)


def test_export_motions_reports_each_motion_once_progress_is_due(tmp_path, capsys, monkeypatch):
    monkeypatch.setenv(ENV_AFTER, "0")
    monkeypatch.setenv(ENV_EVERY, "0")
    export.export_motions(tmp_path / "out", batch(), SMPL24, FPS, formats=("npy",))
    lines = capsys.readouterr().err.splitlines()
    assert [line.split(" | ")[0] for line in lines] == [
        "[export] out motion 1/3  33%", "[export] out motion 2/3  67%", "[export] out motion 3/3 100%"]


def test_export_motions_of_a_dataset_uses_its_names_fps_and_each_subjects_offsets(tmp_path):
    records = []
    for n, subject in enumerate((3, 7)):
        rotations, translation, _, joints = motion(20 + n, subject)
        frames = 12 - n
        records.append(Motion(joints=joints[:frames], translation=translation[:frames], rotations=rotations[:frames],
                              action=0,
                              subject=subject, name=f"clip/{n}"))
    data = pack(records, name="toy", split="train", class_names=("a",), skeleton=SMPL24, fps=12.0)
    written = export.export_motions(tmp_path, data, formats=("bvh",))
    assert written == [tmp_path / "clip_0.bvh", tmp_path / "clip_1.bvh"]
    for path, record, subject in zip(written, records, (3, 7)):
        read, bvh = read_back_joints(path)
        assert bvh.fps == 12.0 and len(read) == record.num_frames
        np.testing.assert_allclose(in_joint_order(bvh, SMPL24.joint_names)[1][1:],
                                   subject_offsets("synth-humanact12", subject)[1:], atol=1e-5)
        np.testing.assert_allclose(read, record.joints, rtol=0, atol=FK_ATOL)


def test_export_motions_without_rotations_writes_only_npy(tmp_path):
    motions = {"joints": batch()["joints"], "lengths": np.array([16, 9, 5])}
    for fmt in ("bvh", "npz"):
        with pytest.raises(ValueError, match=rf"^{fmt}: needs rotations .* only 'npy'"):
            export.export_motions(tmp_path, motions, SMPL24, FPS, formats=(fmt, "npy"))
    assert not list(tmp_path.iterdir())  # checked before anything is written
    written = export.export_motions(tmp_path, motions, SMPL24, formats=("npy",))
    assert [np.load(p).shape[0] for p in written] == [16, 9, 5]


BAD_BATCHES = [
    ({"rotations": np.zeros((3, 16, 23, 3))}, "rotations: expected [N, T, 24, 3] = (3, 16, 24, 3), got (3, 16, 23, 3)"),
    ({"translation": np.zeros((3, 15, 3))}, "translation: expected [N, T, 3] = (3, 16, 3), got (3, 15, 3)"),
    ({"lengths": np.array([16, 17, 5])}, "lengths: expected [N] = (3,) integers in [1, T = 16]"),
    ({"lengths": None, "mask": np.ones((3, 16)) * (np.arange(16) % 2)}, "mask: expected each row to be"),
    ({"mask": np.ones((3, 16))}, "lengths and mask disagree: motion 1"),
    ({"rotations": np.full((3, 16, 24, 3), np.nan)}, "rotations: 3456 non-finite values (NaN or infinite)"),
]


@pytest.mark.parametrize("change, message", BAD_BATCHES)
def test_export_motions_rejects_bad_batches_naming_field_and_expected_shape(tmp_path, change, message):
    with pytest.raises(ValueError, match=re.escape(message)):
        export.export_motions(tmp_path, {**batch(), **change}, SMPL24, FPS)
    assert not list(tmp_path.iterdir())


def test_export_motions_rejects_npz_off_the_smpl_tree_and_unknown_formats(tmp_path):
    motions = {"joints": np.zeros((1, 4, 20, 3)), "rotations": np.zeros((1, 4, 20, 3)),
               "translation": np.zeros((1, 4, 3))}
    with pytest.raises(ValueError, match=re.escape("npz: SMPL parameters need the 24-joint SMPL tree")):
        export.export_motions(tmp_path, motions, CMU_MOCAP20, FPS, formats=("npz",))
    with pytest.raises(ValueError, match=re.escape("formats: expected a non-empty subset of ['bvh', 'npz', 'npy']")):
        export.export_motions(tmp_path, motions, CMU_MOCAP20, FPS, formats=("fbx",))
    with pytest.raises(ValueError, match=re.escape("names: expected plain file names")):
        export.export_motions(tmp_path, motions, CMU_MOCAP20, FPS, formats=("npy",), names=["../x"])


def test_export_with_mixamo_names_and_clean_feet_writes_one_cleaned_motion_in_every_format(tmp_path):
    data = generate("synth-humanact12", "train", seed=0, count=1, progress=False)  # a walk: its stance feet slide
    options = export.ExportOptions(rig="mixamo", clean_feet=True)
    export.export_motions(tmp_path, data, formats=("bvh", "npy"), options=options)
    ankles = [SMPL24.index("left_ankle"), SMPL24.index("right_ankle")]
    for motion, stem in zip(data, data.names):
        bvh = export.load_bvh(tmp_path / f"{export._UNSAFE.sub('_', stem)}.bvh")
        assert set(bvh.names) == set(mixamo_names()) and "mixamorig:LeftFoot" in bvh.names
        parents, offsets, rotations = in_joint_order(bvh, mixamo_names())
        assert parents == SMPL24.parents
        joints = np.load(tmp_path / f"{export._UNSAFE.sub('_', stem)}.npy")  # the cleaned motion's joints
        np.testing.assert_allclose(export._joints(rotations, bvh.translation, offsets, parents), joints, atol=FK_ATOL)
        np.testing.assert_allclose(joints[:, 0], motion.joints[:, 0], atol=1e-6)  # the root does not move
        contacts = foot_contacts(motion.joints[:, ankles], data.fps)
        before, after = (foot_skating(j[:, ankles], contacts, data.fps) for j in (motion.joints, joints))
        assert after < 0.1 * before


def test_export_options_refuse_what_the_skeleton_or_formats_cannot_carry(tmp_path):
    motions = {"joints": np.zeros((1, 4, 20, 3)), "rotations": np.zeros((1, 4, 20, 3)),
               "translation": np.zeros((1, 4, 3))}
    with pytest.raises(ValueError, match=re.escape("clean_feet: the legs it holds are SMPL-24's")):
        export.export_motions(tmp_path, motions, CMU_MOCAP20, FPS, formats=("npy",),
                              options=export.ExportOptions(clean_feet=True))
    with pytest.raises(ValueError, match=re.escape("rig: Mixamo's names are for the SMPL-24 tree")):
        export.export_motions(tmp_path, motions, CMU_MOCAP20, FPS, formats=("bvh",),
                              options=export.ExportOptions(rig="mixamo"))
    with pytest.raises(ValueError, match=re.escape("clean_feet: needs rotations")):
        export.export_motions(tmp_path, {"joints": np.zeros((1, 4, 24, 3))}, SMPL24, FPS, formats=("npy",),
                              options=export.ExportOptions(clean_feet=True))
    with pytest.raises(ValueError, match=re.escape("rig: expected one of ['smpl', 'mixamo'], got 'maya'")):
        export.ExportOptions(rig="maya")
    assert not list(tmp_path.iterdir())


@pytest.mark.parametrize("fmt", ["npy", "bvh"])
def test_a_later_motion_that_is_not_a_number_stops_the_export_before_any_file(tmp_path, fmt):
    motions = batch()
    clips = [Motion(joints=motions["joints"][n, :t], translation=motions["translation"][n, :t],
                    rotations=motions["rotations"][n, :t], action=0, name=f"clip{n}")
             for n, t in enumerate(motions["lengths"])]
    clips[2].joints[3, 5, 1] = np.nan  # the last motion
    data = pack(clips, name="gen", split="all", class_names=("a",), skeleton=SMPL24, fps=FPS)
    with pytest.raises(ValueError, match=re.escape("motion 'clip2': joints: 1 non-finite values")):
        export.export_motions(tmp_path, data, formats=(fmt,))
    assert not list(tmp_path.iterdir())  # all or nothing
