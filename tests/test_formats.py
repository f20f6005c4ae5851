"""Real-format loaders, each on a tiny fixture written in the dataset's exact file layout.

Fixtures are built in the library frame with a NumPy reference (Rodrigues + forward kinematics with the SMPL
template), moved into each dataset's source frame the way its authors' files are, written out, and loaded
back: the loaders must undo exactly that. NumPy references keep the file free of per-shape JAX compiles.
"""

import csv
import math
import pickle
import types
import warnings

import numpy as np
import pytest

from jaxmotion.data.formats import (
    REAL_LOADERS,
    cmu_mocap,
    load_cmu_mocap,
    load_cmu_mocap7,
    load_humanact12_joints,
    load_humanact12poses,
    load_ntu13,
    load_ntu13_smpl,
    load_uestc,
    ntu13,
    uestc,
)
from jaxmotion.data.formats._common import CAMERA_TO_LIBRARY, rotate_roots
from jaxmotion.geometry import CMU_MOCAP20, SMPL24, UESTC18, humanact12_to_library_frame

# Camera frame of HumanAct12 / VIBE (y down, facing -Z) <-> library frame: a 180-degree turn about X.
CAMERA = np.diag([1.0, -1.0, -1.0])
ATOL = 2e-5


# --- NumPy references ----------------------------------------------------------------------------------


def rotmat(v):
    """Rodrigues: ``[..., 3]`` rotation vectors -> ``[..., 3, 3]``."""
    v = np.asarray(v, np.float64)
    angle = np.linalg.norm(v, axis=-1)[..., None, None]
    k = np.zeros(v.shape[:-1] + (3, 3))
    k[..., 0, 1], k[..., 0, 2], k[..., 1, 2] = -v[..., 2], v[..., 1], -v[..., 0]
    k = k - np.swapaxes(k, -1, -2)
    safe = np.where(angle < 1e-12, 1.0, angle)
    return np.eye(3) + np.sin(safe) / safe * k + (1 - np.cos(safe)) / safe**2 * k @ k


def rotvec(matrix):
    """``[3, 3]`` -> rotation vector, angle in [0, pi]; near pi the axis comes from the symmetric part."""
    angle = math.acos(np.clip((np.trace(matrix) - 1) / 2, -1, 1))
    skew = np.array([matrix[2, 1] - matrix[1, 2], matrix[0, 2] - matrix[2, 0], matrix[1, 0] - matrix[0, 1]])
    if math.sin(angle) > 1e-3:
        return skew / (2 * math.sin(angle)) * angle
    if angle < 1.0:
        return skew / 2  # sin(angle) ~ angle
    outer = (matrix + np.eye(3)) / 2  # = axis axis^T at angle pi
    i = int(np.argmax(np.diag(outer)))
    axis = outer[:, i] / math.sqrt(outer[i, i])
    return (axis if axis @ skew >= 0 else -axis) * angle


def yaw(theta):
    c, s = math.cos(theta), math.sin(theta)
    return np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]])


def fk(rotations, translation):
    """Template FK: ``[T, 24, 3]`` axis-angle, ``[T, 3]`` -> ``[T, 24, 3]``."""
    local = rotmat(rotations)
    glob, pos = [None] * 24, [None] * 24
    glob[0], pos[0] = local[:, 0], np.asarray(translation, np.float64)
    for j in range(1, 24):
        p = SMPL24.parents[j]
        glob[j] = glob[p] @ local[:, j]
        pos[j] = pos[p] + glob[p] @ SMPL24.offsets[j].astype(np.float64)
    return np.stack(pos, axis=1)


def library_clip(rng, frames, root=None, bend=0.0):
    """A library-frame SMPL clip: ``(rotations [T, 24, 3], translation [T, 3], joints [T, 24, 3])``."""
    rotations = bend * rng.normal(size=(frames, 24, 3))
    rotations[:, 0] = rotvec(np.eye(3) if root is None else root)
    translation = np.array([0.1, 0.9, -0.2]) + np.arange(frames)[:, None] * np.array([0.0, 0.0, 0.03])
    return rotations, translation, fk(rotations, translation)


def with_root(rotations, matrix):
    """The same clip with its global orientation left-multiplied by ``matrix``."""
    out = rotations.copy()
    out[:, 0] = [rotvec(matrix @ r) for r in rotmat(rotations[:, 0])]
    return out


def assert_upright_facing_z(joints, skeleton, head, pelvis, left_hip, right_hip):
    up = joints[:, skeleton.index(head)] - joints[:, skeleton.index(pelvis)]
    assert np.all(up[:, 1] > 0.3)  # head well above the pelvis: +Y up
    facing = np.cross(joints[:, skeleton.index(left_hip)] - joints[:, skeleton.index(right_hip)], [0.0, 1.0, 0.0])
    assert np.all(facing[:, 2] / np.linalg.norm(facing, axis=1) > 0.99)  # +X left, so facing +Z


def assert_fk_consistent(data):
    for motion in data:
        np.testing.assert_allclose(fk(motion.rotations, motion.translation), motion.joints, atol=1e-4)


def dump(path, obj):
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_bytes(pickle.dumps(obj))


def truncate(path):
    path.write_bytes(path.read_bytes()[: len(path.read_bytes()) // 2])


def test_camera_matrix_is_the_library_frame_conversion():
    points = np.random.default_rng(0).normal(size=(5, 3)).astype(np.float32)
    np.testing.assert_allclose(points @ CAMERA_TO_LIBRARY.T, humanact12_to_library_frame(points))
    np.testing.assert_array_equal(CAMERA_TO_LIBRARY, CAMERA)


# --- HumanAct12Poses (ACTOR) ---------------------------------------------------------------------------


def write_humanact12poses(root, rng):
    """Three clips: upright at rest, bent and turned, short; returns the library-frame clips."""
    clips = [library_clip(rng, 4), library_clip(rng, 5, yaw(0.7), bend=0.3), library_clip(rng, 3, bend=0.3)]
    dump(root / "humanact12poses.pkl", {
        "poses": [with_root(r, CAMERA).reshape(-1, 72).astype(np.float32) for r, _, _ in clips],
        "joints3D": [(j @ CAMERA.T).astype(np.float32) for _, _, j in clips],
        "y": [0, 5, 11],
        "oldposes": [],
    })
    return clips


def test_humanact12poses_comes_back_in_the_library_frame(tmp_path):
    clips = write_humanact12poses(tmp_path, np.random.default_rng(0))
    data = load_humanact12poses(tmp_path)
    assert (len(data), data.split, data.skeleton, data.fps) == (3, "all", SMPL24, 20.0)
    assert list(data.actions) == [0, 5, 11] and list(data.subjects) == [-1, -1, -1]
    assert data.class_names[8] == "turn steering wheel" and list(data.lengths) == [4, 5, 3]
    assert data.joints.dtype == data.rotations.dtype == data.translation.dtype == np.float32
    for motion, (rotations, translation, joints) in zip(data, clips):
        np.testing.assert_allclose(motion.joints, joints, atol=ATOL)
        np.testing.assert_allclose(motion.translation, translation, atol=ATOL)
        np.testing.assert_allclose(rotmat(motion.rotations), rotmat(rotations), atol=ATOL)
    assert_upright_facing_z(data[0].joints, SMPL24, "head", "pelvis", "left_hip", "right_hip")
    assert_fk_consistent(data)


def test_humanact12poses_train_is_all_and_test_is_refused(tmp_path):
    write_humanact12poses(tmp_path, np.random.default_rng(0))
    train = load_humanact12poses(tmp_path / "humanact12poses.pkl", "train")
    assert train.split == "train" and np.array_equal(train.joints, load_humanact12poses(tmp_path).joints)
    with pytest.raises(ValueError, match="no test split"):
        load_humanact12poses(tmp_path, "test")


@pytest.mark.parametrize("break_it, message", [
    (lambda d: d.pop("joints3D"), r"missing key 'joints3D'"),
    (lambda d: d["poses"].__setitem__(1, np.zeros((5, 70))), r"poses\[1\]: expected .*\[T, 72\], got shape \(5, 70\)"),
    (lambda d: d["joints3D"].__setitem__(2, np.zeros((4, 24, 3))), r"joints3D\[2\]: expected .*\[3, 24, 3\]"),
    (lambda d: d["poses"].__setitem__(0, np.array([["a"] * 72] * 4)), r"poses\[0\]: .*dtype <U1"),
    (lambda d: d["y"].__setitem__(1, 12), r"y\[1\]: expected an integer class index in \[0, 12\), got 12"),
    (lambda d: d["y"].pop(), r"'y': expected a sequence of 3 items"),
])
def test_humanact12poses_malformed_pickle_names_file_and_key(tmp_path, break_it, message):
    write_humanact12poses(tmp_path, np.random.default_rng(0))
    path = tmp_path / "humanact12poses.pkl"
    data = pickle.loads(path.read_bytes())
    break_it(data)
    dump(path, data)
    with pytest.raises(ValueError, match=message) as err:
        load_humanact12poses(tmp_path)
    assert str(path) in str(err.value)


def test_humanact12poses_missing_or_truncated_file(tmp_path):
    with pytest.raises(FileNotFoundError, match=r"humanact12poses\.pkl: HumanAct12Poses pickle"):
        load_humanact12poses(tmp_path)
    write_humanact12poses(tmp_path, np.random.default_rng(0))
    truncate(tmp_path / "humanact12poses.pkl")
    with pytest.raises(ValueError, match=r"humanact12poses\.pkl: cannot unpickle"):
        load_humanact12poses(tmp_path)


# --- HumanAct12 joints (Action2Motion / ODMO) -------------------------------------------------------------


def test_humanact12_joints_labels_subjects_and_frame(tmp_path):
    rng = np.random.default_rng(1)
    names = ["P03G01R02F0010T0020A1202", "P01G01R01F0069T0143A0101", "P12G02R01F0001T0005A0402"]
    for name, frames in zip(names, (3, 4, 2)):
        np.save(tmp_path / f"{name}.npy", library_clip(rng, frames, bend=0.2)[2] @ CAMERA.T)
    (tmp_path / "humanact12.csv").write_text("motion,action_type\n")  # ODMO keeps its CSV beside the clips
    data = load_humanact12_joints(tmp_path, "train")
    assert data.names == tuple(sorted(names)) and data.rotations is None and data.skeleton is SMPL24
    assert list(data.actions) == [0, 11, 3] and list(data.subjects) == [1, 3, 12]
    assert list(data.lengths) == [4, 3, 2]
    np.testing.assert_allclose(data[0].translation, data[0].joints[:, 0])
    assert_upright_facing_z(data.joints, SMPL24, "head", "pelvis", "left_hip", "right_hip")


def test_humanact12_joints_bad_files_name_the_file(tmp_path):
    path = tmp_path / "P01G01R01F0069T0143A0101.npy"
    path.write_bytes(b"\x93NUMPY garbage")
    with pytest.raises(ValueError, match=r"A0101\.npy: cannot read HumanAct12 joint clip"):
        load_humanact12_joints(tmp_path)
    np.save(path, np.zeros((3, 18, 3)))
    with pytest.raises(ValueError, match=r"A0101\.npy: joints: expected .*\[T, 24, 3\], got shape \(3, 18, 3\)"):
        load_humanact12_joints(tmp_path)
    path.rename(tmp_path / "P01G01R01F0069T0143A1301.npy")
    with pytest.raises(ValueError, match=r"A1301\.npy: file name: coarse class 13"):
        load_humanact12_joints(tmp_path)


# --- UESTC (ACTOR) -------------------------------------------------------------------------------------------

# name, frames in the pickle, num_frames_min, library root yaw, in the train split after filtering
UESTC_VIDEOS = [
    ("a5_d0_p001_c1_color.avi", 46, 46, 0.0),  # train, side 1: no view rotation; upright at rest
    ("a7_d2_p002_c2_color.avi", 48, 46, 0.4),  # train, view 2: turned back by R_y(-pi/2); cut to 46 frames
    ("a3_d8_p001_c2_color.avi", 46, 46, 0.0),  # view 8 of side 2: dropped
    ("a0_d0_p002_c1_color.avi", 44, 50, 0.0),  # train subject, 44 < 45 frames: filtered out of train
    ("a39_d1_p003_c2_color.avi", 10, 10, 0.2),  # test subject: short clips stay
]


def write_uestc(root, rng, videos=UESTC_VIDEOS):
    """The ACTOR layout; returns per video the expected library-frame (rotations, translation, joints)."""
    (root / "info").mkdir(parents=True)
    (root / "info" / "names.txt").write_text("".join(f"{v[0]}\n" for v in videos))
    (root / "info" / "num_frames_min.txt").write_text("".join(f"{v[2]}\n" for v in videos))
    vibe, globtrans, expected = {"pose": [], "joints3d": [], "betas": []}, [], []
    for index, (name, frames, _, root_yaw) in enumerate(videos):
        view, side = int(name.split("_d")[1][0]), int(name.split("_c")[1][0])
        rotations, translation, joints = library_clip(rng, frames, yaw(root_yaw), bend=0.3 if index else 0.0)
        # What the video shows: the library clip seen from view `view` in VIBE's camera frame.
        to_source = (yaw(view * math.pi / 4) if side != 1 else np.eye(3)) @ CAMERA
        trans = rng.normal(size=(frames, 3))
        vibe_joints = rng.normal(size=(frames, 49, 3))
        vibe_joints[:, 8] = translation @ to_source.T - trans  # MidHip + globtrans = the root
        vibe["pose"].append(with_root(rotations, to_source).reshape(frames, 72).astype(np.float32))
        vibe["joints3d"].append(vibe_joints.astype(np.float32))
        vibe["betas"].append(np.zeros((frames, 10), np.float32))
        globtrans.append(trans)
        expected.append((rotations, translation, joints))
    dump(root / "vibe_cache_refined.pkl", vibe)
    dump(root / "globtrans_usez.pkl", globtrans)
    return expected


def test_uestc_train_and_test_splits_filter_and_turn_to_front_view(tmp_path):
    expected = write_uestc(tmp_path, np.random.default_rng(2))
    train, test = load_uestc(tmp_path, "train"), load_uestc(tmp_path, "test")
    assert train.names == (UESTC_VIDEOS[0][0], UESTC_VIDEOS[1][0]) and test.names == (UESTC_VIDEOS[4][0],)
    assert list(train.lengths) == [46, 46] and list(test.lengths) == [10]
    assert list(train.actions) == [5, 7] and list(test.actions) == [39]
    assert list(train.subjects) == [1, 2] and list(test.subjects) == [3]
    assert train.num_classes == 40 and train.class_names[2] == "jumping-jack" and train.fps == 30.0
    for motion, (rotations, translation, joints) in zip([*train, *test], [expected[0], expected[1], expected[4]]):
        n = motion.num_frames
        np.testing.assert_allclose(motion.translation, translation[:n], atol=1e-4)
        np.testing.assert_allclose(rotmat(motion.rotations), rotmat(rotations[:n]), atol=ATOL)
        np.testing.assert_allclose(motion.joints, joints[:n], atol=1e-4)
    assert_upright_facing_z(train[0].joints, SMPL24, "head", "pelvis", "left_hip", "right_hip")
    assert_fk_consistent(train)


def test_uestc_split_subjects_are_actors_51():
    assert len(uestc.TRAIN_SUBJECTS) == 51 and uestc.TRAIN_SUBJECTS <= set(range(1, 119))


def test_uestc_reads_class_names_file(tmp_path):
    write_uestc(tmp_path, np.random.default_rng(2), UESTC_VIDEOS[:1])
    names = [f"class {i}" for i in range(40)]
    (tmp_path / "info" / "action_classes.txt").write_text("\n".join(names) + "\n")
    assert load_uestc(tmp_path).class_names == tuple(names)
    (tmp_path / "info" / "action_classes.txt").write_text("\n".join(names[:39]))
    with pytest.raises(ValueError, match=r"action_classes\.txt: expected 40 .* got 39"):
        load_uestc(tmp_path)


def test_uestc_malformed_inputs_name_file_and_key(tmp_path):
    write_uestc(tmp_path, np.random.default_rng(2), UESTC_VIDEOS[:2])
    vibe_path = tmp_path / "vibe_cache_refined.pkl"
    vibe = pickle.loads(vibe_path.read_bytes())
    vibe["joints3d"][1] = vibe["joints3d"][1][:, :25]
    dump(vibe_path, vibe)
    message = r"vibe_cache_refined\.pkl: joints3d\[1\] \(a7_d2.*\[48, 49, 3\].*\(48, 25, 3\)"
    with pytest.raises(ValueError, match=message):
        load_uestc(tmp_path)
    del vibe["joints3d"]
    dump(vibe_path, vibe)
    with pytest.raises(ValueError, match=r"vibe_cache_refined\.pkl: missing key 'joints3d'"):
        load_uestc(tmp_path)
    (tmp_path / "info" / "num_frames_min.txt").write_text("46\n")
    with pytest.raises(ValueError, match=r"num_frames_min\.txt: expected 2 lines"):
        load_uestc(tmp_path)
    (tmp_path / "info" / "num_frames_min.txt").write_text("46\n46\n")
    (tmp_path / "globtrans_usez.pkl").unlink()
    with pytest.raises(FileNotFoundError, match=r"globtrans_usez\.pkl: UESTC translations"):
        load_uestc(tmp_path)
    with pytest.raises(ValueError, match="no split 'all'"):
        load_uestc(tmp_path, "all")


def test_uestc_unknown_subject_is_an_error(tmp_path):
    write_uestc(tmp_path, np.random.default_rng(2), [("a1_d0_p119_c1_color.avi", 46, 46, 0.0)])
    with pytest.raises(ValueError, match=r"names\.txt: line 1: 'a1_d0_p119_c1_color\.avi': expected subject"):
        load_uestc(tmp_path)


# --- NTU-13 (Action2Motion VIBE) -------------------------------------------------------------------------------

# Action2Motion's 18 joints from the SMPL template joints (+ small offsets for nose, heels and head top).
VIBE18_FROM_SMPL = [
    ("pelvis", 0), ("neck", 0), ("right_shoulder", 0), ("right_elbow", 0), ("right_wrist", 0),
    ("left_shoulder", 0), ("left_elbow", 0), ("left_wrist", 0), ("head", (0, 0, 0.1)), ("right_hip", 0),
    ("right_knee", 0), ("right_ankle", 0), ("left_hip", 0), ("left_knee", 0), ("left_ankle", 0),
    ("left_ankle", (0, -0.05, -0.05)), ("right_ankle", (0, -0.05, -0.05)), ("head", (0, 0.12, 0)),
]
NTU_FILES = ["S001C001P001R001A006.pkl", "S002C003P008R002A102.pkl", "S001C001P002R001A023.pkl"]


def write_ntu13(root, rng, files=NTU_FILES):
    """The last file has no track 1 (skipped); returns the expected library clips of the others."""
    root.mkdir(parents=True, exist_ok=True)
    (root / ntu13.LIST_FILE).write_text("\n".join(files) + "\n")
    expected = []
    for i, name in enumerate(files):
        rotations, _, joints = library_clip(rng, 3 + i, yaw(0.1 * i), bend=0.2 * i)
        vibe18 = np.stack([joints[:, SMPL24.index(n)] + np.asarray(d) for n, d in VIBE18_FROM_SMPL], axis=1)
        vibe49 = rng.normal(size=(len(joints), 49, 3))
        vibe49[:, list(ntu13.VIBE18_INDICES)] = vibe18 @ CAMERA.T
        track = {"pose": with_root(rotations, CAMERA).reshape(-1, 72), "joints3d": vibe49, "betas": np.zeros(10)}
        dump(root / name, {2 if i == len(files) - 1 else 1: track})
        expected.append((rotations, vibe18))
    return expected[:-1]


def test_ntu13_joints_labels_and_skipped_files(tmp_path):
    expected = write_ntu13(tmp_path, np.random.default_rng(3))
    with pytest.warns(UserWarning, match=r"skipped 1 of 3 files without a track 1 .*A023"):
        data = load_ntu13(tmp_path)
    assert data.names == ("S001C001P001R001A006", "S002C003P008R002A102") and data.skeleton is UESTC18
    assert list(data.actions) == [0, 12] and list(data.subjects) == [1, 8] and data.rotations is None
    assert data.class_names[12] == "side kick" and data.fps == 30.0
    for motion, (_, vibe18) in zip(data, expected):
        np.testing.assert_allclose(motion.joints, vibe18, atol=ATOL)
        np.testing.assert_allclose(motion.translation, vibe18[:, 0], atol=ATOL)
    assert_upright_facing_z(data[0].joints, UESTC18, "HeadTop", "MidHip", "LHip", "RHip")
    with pytest.warns(UserWarning):
        assert all(np.array_equal(load_ntu13(tmp_path, s).joints, data.joints) for s in ("test", "all"))


def test_ntu13_smpl_rotations_agree_with_template_joints(tmp_path):
    expected = write_ntu13(tmp_path, np.random.default_rng(3))
    with pytest.warns(UserWarning):
        data = load_ntu13_smpl(tmp_path, "test")
    assert data.skeleton is SMPL24 and list(data.actions) == [0, 12] and data.split == "test"
    for motion, (rotations, vibe18) in zip(data, expected):
        np.testing.assert_allclose(rotmat(motion.rotations), rotmat(rotations), atol=ATOL)
        np.testing.assert_allclose(motion.translation, vibe18[:, 0], atol=ATOL)  # ACTOR's root: MidHip
    assert_fk_consistent(data)


def test_ntu13_bad_inputs(tmp_path):
    write_ntu13(tmp_path, np.random.default_rng(3), ["S001C001P001R001A050.pkl", "x.pkl"])
    with pytest.raises(ValueError, match=r"A050\.pkl: file name: expected the NTU action .* got '050'"):
        load_ntu13(tmp_path)
    write_ntu13(tmp_path, np.random.default_rng(3), ["S001C001P001R001A006.pkl", "x.pkl"])
    path = tmp_path / "S001C001P001R001A006.pkl"
    obj = pickle.loads(path.read_bytes())
    obj[1]["joints3d"] = obj[1]["joints3d"][..., :2]
    dump(path, obj)
    with pytest.raises(ValueError, match=r"A006\.pkl: \[1\]\['joints3d'\]: expected .*\[T, 49, 3\]"):
        load_ntu13(tmp_path)
    truncate(path)
    with pytest.raises(ValueError, match=r"A006\.pkl: cannot unpickle"):
        load_ntu13(tmp_path)
    path.unlink()
    with pytest.raises(FileNotFoundError, match=r"A006\.pkl: VIBE output"):
        load_ntu13(tmp_path)


@pytest.mark.parametrize("content", [
    b"\x80\x02cjoblib.numpy_pickle\nNumpyArrayWrapper\n)\x81.",  # arrays stored outside the pickle stream
    b"\x78\x9c" + b"\x00" * 16,  # a zlib-compressed joblib container
])
def test_ntu13_joblib_containers_ask_for_joblib(tmp_path, content):
    try:
        import joblib  # noqa: F401
        pytest.skip("joblib is installed: it reads these files itself")
    except ImportError:
        pass
    write_ntu13(tmp_path, np.random.default_rng(3), ["S001C001P001R001A006.pkl", "x.pkl"])
    (tmp_path / "S001C001P001R001A006.pkl").write_bytes(content)
    with pytest.raises(ImportError, match=r"A006\.pkl: .*joblib.*pip install joblib"):
        load_ntu13(tmp_path)


# --- CMU mocap (Action2Motion / ODMO) -----------------------------------------------------------------------------

# A y-up 20-joint standing pose, in Action2Motion's raw units (20 per library metre).
CMU_REST = 20 * np.array([
    [0, 0.95, 0], [0, 1.25, 0], [0, 1.45, 0], [0, 1.6, 0],  # hips, thorax, neck, head
    [0.05, 1.4, 0], [0.2, 1.4, 0], [0.45, 1.4, 0], [0.7, 1.4, 0],  # left arm (+x)
    [-0.05, 1.4, 0], [-0.2, 1.4, 0], [-0.45, 1.4, 0], [-0.7, 1.4, 0],  # right arm
    [0.1, 0.9, 0], [0.1, 0.5, 0], [0.1, 0.08, 0], [0.1, 0.0, 0.12],  # left leg
    [-0.1, 0.9, 0], [-0.1, 0.5, 0], [-0.1, 0.08, 0], [-0.1, 0.0, 0.12],  # right leg
])
CMU_ROWS = [("01_01", "Climb", 5), ("86_03", "Walk", 3), ("dance-a", "Dance", 4)]


def write_cmu(root, rows=CMU_ROWS, csv_name=cmu_mocap.CLIPS_CSV):
    (root / cmu_mocap.JOINTS_DIR).mkdir(parents=True, exist_ok=True)
    with (root / csv_name).open("w", newline="") as f:
        writer = csv.writer(f)
        writer.writerow(["motion", "action_type"])
        for motion, action, frames in rows:
            writer.writerow([motion, action])
            walk = np.arange(frames)[:, None, None] * np.array([0.0, 0.0, 2.0])
            np.save(root / cmu_mocap.JOINTS_DIR / f"{motion}.npy", CMU_REST + walk)
        writer.writerow(["", ""])  # pandas drops all-empty rows; so does the loader


def test_cmu_mocap_scaled_by_twenty_in_a2m_class_order(tmp_path):
    write_cmu(tmp_path)
    data = load_cmu_mocap(tmp_path)
    assert data.names == ("01_01", "86_03", "dance-a") and list(data.lengths) == [5, 3, 4]
    assert list(data.actions) == [7, 0, 5] and list(data.subjects) == [1, 86, -1]
    assert (data.skeleton, data.fps, data.rotations, data.num_classes) == (CMU_MOCAP20, 12.0, None, 8)
    np.testing.assert_allclose(data[0].joints[0], CMU_REST / 20, atol=1e-6)
    np.testing.assert_allclose(data[0].translation[:, 2], 0.1 * np.arange(5), atol=1e-6)
    assert_upright_facing_z(data.joints, CMU_MOCAP20, "head", "hips", "left_hip", "right_hip")
    with pytest.raises(ValueError, match="no test split"):
        load_cmu_mocap(tmp_path, "test")


def test_cmu7_drops_wash_and_renumbers(tmp_path):
    write_cmu(tmp_path, [("02_01", "Run", 2), ("02_02", "Climb", 2)], cmu_mocap.CLIPS_CSV_7)
    data = load_cmu_mocap7(tmp_path, "all")
    assert data.class_names == ("Walk", "Run", "Jump", "Animal Behavior", "Dance", "Step", "Climb")
    assert list(data.actions) == [1, 6] and data.name == "cmu7"
    write_cmu(tmp_path, [("02_03", "Wash", 2)], cmu_mocap.CLIPS_CSV_7)
    with pytest.raises(ValueError, match=r"pose_clip_7class\.csv: row 2: action_type 'Wash': expected one of"):
        load_cmu_mocap7(tmp_path)


def test_cmu_bad_inputs_name_file_and_field(tmp_path):
    write_cmu(tmp_path, [("01_01", "Swim", 2)])
    with pytest.raises(ValueError, match=r"pose_clip\.csv: row 2: action_type 'Swim'"):
        load_cmu_mocap(tmp_path)
    write_cmu(tmp_path, [("01_01", "Walk", 2)])
    (tmp_path / cmu_mocap.JOINTS_DIR / "01_01.npy").write_bytes(b"not an array")
    with pytest.raises(ValueError, match=r"01_01\.npy: cannot read CMU mocap joint clip"):
        load_cmu_mocap(tmp_path)
    np.save(tmp_path / cmu_mocap.JOINTS_DIR / "01_01.npy", np.zeros((2, 21, 3)))
    with pytest.raises(ValueError, match=r"01_01\.npy: joints: expected .*\[T, 20, 3\], got shape \(2, 21, 3\)"):
        load_cmu_mocap(tmp_path)
    (tmp_path / cmu_mocap.JOINTS_DIR / "01_01.npy").unlink()
    with pytest.raises(FileNotFoundError, match=r"01_01\.npy: CMU mocap joint clip \(listed in pose_clip\.csv"):
        load_cmu_mocap(tmp_path)
    (tmp_path / cmu_mocap.CLIPS_CSV).write_text("name,action\n01_01,Walk\n")
    with pytest.raises(ValueError, match=r"pose_clip\.csv: missing column\(s\) \['motion', 'action_type'\]"):
        load_cmu_mocap(tmp_path)


def test_cmu_non_finite_joints_and_duplicate_motions_name_the_file(tmp_path):
    write_cmu(tmp_path, [("01_01", "Walk", 3)])
    clip = CMU_REST[None].repeat(3, 0)
    clip[1, 4, 2] = np.nan
    np.save(tmp_path / cmu_mocap.JOINTS_DIR / "01_01.npy", clip)
    with pytest.raises(ValueError, match=r"01_01\.npy: joints: 1 values that are not finite in float32 .*first at "
                                         r"index \(1, 4, 2\)"):
        load_cmu_mocap(tmp_path)
    clip = clip.astype(np.float64)
    clip[1, 4, 2] = 1e39  # finite in the file, infinite once stored as float32
    np.save(tmp_path / cmu_mocap.JOINTS_DIR / "01_01.npy", clip)
    with pytest.raises(ValueError, match=r"01_01\.npy: joints: 1 values that are not finite in float32 \(NaN, "
                                         r"infinite or beyond ±3.4e38\), the first at index \(1, 4, 2\): 1e\+39"):
        load_cmu_mocap(tmp_path)
    write_cmu(tmp_path, [("01_01", "Walk", 3), ("86_03", "Run", 2), ("01_01", "Walk", 3)])
    with pytest.raises(ValueError, match=r"pose_clip\.csv: motion '01_01' is listed twice \(at row 2 and row 4\)"):
        load_cmu_mocap(tmp_path)


def test_humanact12poses_non_finite_poses_name_the_file_and_clip(tmp_path):
    write_humanact12poses(tmp_path, np.random.default_rng(0))
    data = pickle.loads((tmp_path / "humanact12poses.pkl").read_bytes())
    data["poses"][1][2, 5] = np.inf
    dump(tmp_path / "humanact12poses.pkl", data)
    with pytest.raises(ValueError, match=r"humanact12poses\.pkl: poses\[1\]: 1 values that are not finite in float32"):
        load_humanact12poses(tmp_path)


def test_uestc_duplicate_video_names_are_an_error(tmp_path):
    videos = [UESTC_VIDEOS[0], UESTC_VIDEOS[1], UESTC_VIDEOS[0]]
    write_uestc(tmp_path, np.random.default_rng(2), videos)
    with pytest.raises(ValueError, match=r"names\.txt: video 'a5_d0_p001_c1_color\.avi' is listed twice "
                                         r"\(at line 1 and line 3\)"):
        load_uestc(tmp_path, "train")


def test_turning_roots_by_a_reflection_is_an_error():
    flip = np.diag([1.0, 1.0, -1.0])
    with pytest.raises(ValueError, match="rotate_roots: matrices .*2 of 2 matrices are not rotations.*reflection"):
        rotate_roots(np.zeros((2, 24, 3)), np.stack([flip, flip]))


# --- registry ------------------------------------------------------------------------------------------------


def test_real_loaders_registry_is_read_only_and_complete(tmp_path):
    assert isinstance(REAL_LOADERS, types.MappingProxyType)
    assert set(REAL_LOADERS) == {
        "humanact12", "humanact12-joints", "uestc", "ntu13", "ntu13-smpl", "cmu", "cmu7",  # ACTOR, A2M, ODMO
        "ntu1p", "ntu2p", "ntu1p-xview", "ntu2p-xview", "ntu1p-skeletons", "ntu2p-skeletons", "ntu1p-smpl",
        "combat-2p", "combat-3p", "combat-4p", "combat-5p", "babel120", "babel120-amass",  # ActFormer
        "mag",  # Neural Marionette
    }
    with pytest.raises(TypeError):
        REAL_LOADERS["extra"] = load_uestc  # type: ignore[index]
    write_cmu(tmp_path)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert len(REAL_LOADERS["cmu"](tmp_path, "train")) == 3
