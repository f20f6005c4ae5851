"""Loaders of the datasets ActFormer uses, each on tiny fixtures written in the real layout.

NTU RGB+D 120 (the Kinect ``.skeleton`` files and ActFormer's prepared h5), GTA Combat, NTURecon-1P and BABEL
(from AMASS + BABEL's json, and ActFormer's prepared h5). Fixtures start from known library-frame poses, are
moved into each source frame (Kinect camera space, GTA's and AMASS's z-up worlds) and encoded the way the
authors' scripts encode them (NumPy references here), written out, and loaded back.
"""

import inspect
import json
import math
import re
import sys
import warnings

import numpy as np
import pytest

from jaxmotion.data.formats import (
    REAL_LOADERS,
    load_babel120,
    load_babel120_amass,
    load_gta_combat,
    load_ntu_prepared,
    load_ntu_recon,
    load_ntu_skeletons,
)
from jaxmotion.data.formats import babel, gta_combat, ntu120_files
from jaxmotion.data.formats.ntu120 import (
    MUTUAL_CLASS_NAMES,
    SINGLE_CLASS_NAMES,
    XSUB_TRAIN_SUBJECTS,
    fill_missing,
    gaussian_smooth,
)
from jaxmotion.data.formats.ntu120_files import NTU_AVGLENGTH, prepare_skeleton, read_skeleton
from jaxmotion.geometry import GTA22, NTU25, SMPL24

KINECT = np.diag([-1.0, 1.0, -1.0])  # Kinect camera space <-> library frame: 180 degrees about Y (self-inverse)
Z_UP = np.array([[1.0, 0, 0], [0, 0, 1], [0, -1, 0]])  # z-up (GTA, AMASS) -> y-up: R_x(-90 degrees)


# --- NumPy references --------------------------------------------------------------------------------------------


def rotmat(v):
    """Rodrigues: ``[..., 3]`` -> ``[..., 3, 3]``."""
    v = np.asarray(v, np.float64)
    angle = np.linalg.norm(v, axis=-1)[..., None, None]
    k = np.zeros(v.shape[:-1] + (3, 3))
    k[..., 0, 1], k[..., 0, 2], k[..., 1, 2] = -v[..., 2], v[..., 1], -v[..., 0]
    k = k - np.swapaxes(k, -1, -2)
    safe = np.where(angle < 1e-12, 1.0, angle)
    return np.eye(3) + np.sin(safe) / safe * k + (1 - np.cos(safe)) / safe**2 * k @ k


def rotvec(matrix):
    """A rotation matrix (angle < pi) -> rotation vector."""
    angle = math.acos(np.clip((np.trace(matrix) - 1) / 2, -1, 1))
    skew = np.array([matrix[2, 1] - matrix[1, 2], matrix[0, 2] - matrix[2, 0], matrix[1, 0] - matrix[0, 1]])
    return skew / 2 if angle < 1e-9 else skew / (2 * math.sin(angle)) * angle


def yaw(theta):
    c, s = math.cos(theta), math.sin(theta)
    return np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]])


def fk(rotations, translation):
    """SMPL template FK: ``[T, 24, 3]`` axis-angle, ``[T, 3]`` -> ``[T, 24, 3]``."""
    local = rotmat(rotations)
    glob, pos = [None] * 24, [None] * 24
    glob[0], pos[0] = local[:, 0], np.asarray(translation, np.float64)
    for j in range(1, 24):
        p = SMPL24.parents[j]
        glob[j] = glob[p] @ local[:, j]
        pos[j] = pos[p] + glob[p] @ SMPL24.offsets[j].astype(np.float64)
    return np.stack(pos, axis=1)


def limb_encode(joints, parents):
    """ActFormer's skeleton representation: ``[P, T, J, 3]`` -> ``[P, T, J, 3]`` (root minus the mean root over
    frames and persons, then unit limb vectors with the + 1e-4 guard)."""
    out = np.empty_like(joints)
    for child, parent in enumerate(parents):
        if parent >= 0:
            d = joints[..., child, :] - joints[..., parent, :]
            out[..., child, :] = d / (np.linalg.norm(d, axis=-1, keepdims=True) + 1e-4)
    out[..., 0, :] = joints[..., 0, :] - joints[..., 0, :].mean(axis=(0, 1))
    return out


def limb_decode(vectors, parents, lengths):
    """Rebuild joints from the root along the tree."""
    out = np.zeros_like(vectors)
    out[..., 0, :] = vectors[..., 0, :]
    done = {0}
    while len(done) < len(parents):
        for child, parent in enumerate(parents):
            if child not in done and parent in done:
                out[..., child, :] = out[..., parent, :] + vectors[..., child, :] * lengths[child]
                done.add(child)
    return out


def to_channels(vectors):
    """``[P, T, J, 3]`` -> ActFormer's float32 ``(3P, J, T)``, channel 3p + c."""
    p, t, j, _ = vectors.shape
    return np.ascontiguousarray(vectors.transpose(0, 3, 2, 1).reshape(3 * p, j, t)).astype(np.float32)


def bone_lengths(joints, parents):
    return np.array([0.0] + [np.linalg.norm(joints[c] - joints[p]) for c, p in enumerate(parents) if p >= 0])


def rot6d(rotations):
    """``[T, J, 3]`` axis-angle -> ``[T, J, 6]``, the first two matrix rows."""
    return rotmat(rotations)[..., :2, :].reshape(*rotations.shape[:-1], 6)


def smpl_channels(rotations, translation):
    """``(rotations [T, 24, 3], translation [T, 3])`` -> ActFormer's float32 ``(6, 25, T)``."""
    row = np.concatenate([translation, np.zeros_like(translation)], axis=1)[:, None]
    return np.ascontiguousarray(np.concatenate([rot6d(rotations), row], axis=1).transpose(2, 1, 0)).astype(np.float32)


def with_root(rotations, matrix):
    out = rotations.copy()
    out[:, 0] = [rotvec(matrix @ r) for r in rotmat(rotations[:, 0])]
    return out


def assert_upright_facing_z(joints, skeleton, head, pelvis, left_hip, right_hip):
    up = joints[..., skeleton.index(head), :] - joints[..., skeleton.index(pelvis), :]
    assert np.all(up[..., 1] > 0.3)  # +Y up
    side = joints[..., skeleton.index(left_hip), :] - joints[..., skeleton.index(right_hip), :]
    facing = np.cross(side, [0.0, 1.0, 0.0])  # +X is the left, so facing = left x up
    assert np.all(facing[..., 2] / np.linalg.norm(facing, axis=-1) > 0.99)


@pytest.fixture
def h5py():
    return pytest.importorskip("h5py")


def write_h5(h5py, path, arrays):
    path.parent.mkdir(parents=True, exist_ok=True)
    with h5py.File(path, "w") as f:
        for key, value in arrays.items():
            f.create_dataset(key, data=value)


def parent_matrix(parents):
    """ActFormer's ``parent`` matrix: ``[p, c] = 1``, the root its own parent."""
    m = np.zeros((len(parents), len(parents)), np.float32)
    m[0, 0] = 1
    for c, p in enumerate(parents):
        if p >= 0:
            m[p, c] = 1
    return m


def write_adjacency(h5py, path, parents, lengths, **extra):
    write_h5(h5py, path, {"parent": parent_matrix(parents), "adjacency": np.ones((len(parents),) * 2, np.float32),
                          "avglength": np.asarray(lengths, np.float32), **extra})


# --- NTU-25 poses -----------------------------------------------------------------------------------------------

_NTU_LEFT = {  # library frame: facing +Z, left at +X
    "shoulder": (0.17, 1.46, 0.0), "elbow": (0.19, 1.22, -0.01), "wrist": (0.20, 0.99, 0.02),
    "hand": (0.20, 0.92, 0.03), "hand_tip": (0.20, 0.86, 0.05), "thumb": (0.17, 0.93, 0.07),
    "hip": (0.08, 0.97, 0.0), "knee": (0.09, 0.63, 0.02), "ankle": (0.09, 0.29, -0.01), "foot": (0.09, 0.24, 0.10),
}
_NTU_MID = {"spine_base": (0, 1.0, 0), "spine_mid": (0, 1.28, 0.01), "spine_shoulder": (0, 1.49, 0),
            "neck": (0, 1.56, 0.01), "head": (0, 1.68, 0.03)}


def ntu_rest():
    rows = dict(_NTU_MID)
    for part, (x, y, z) in _NTU_LEFT.items():
        rows[f"left_{part}"], rows[f"right_{part}"] = (x, y, z), (-x, y, z)
    return np.array([rows[n] for n in NTU25.joint_names], np.float64)


def ntu_person(frames, offset, turn=0.0, spin=0.0):
    """``[T, 25, 3]`` library-frame joints: the rest pose turned by ``turn + spin t`` about Y, moved to
    ``offset`` (and sliding 2 cm per frame along x)."""
    rest = ntu_rest() - [0, 1.0, 0]
    return np.stack([rest @ yaw(turn + spin * t).T + np.asarray(offset) + [0.02 * t, 1.0, 0] for t in range(frames)])


# --- NTU .skeleton files --------------------------------------------------------------------------------------


def skeleton_text(frames):
    """``frames``: per frame a list of ``(bodyID, [25, 3] Kinect positions)`` -> the ``.skeleton`` text."""
    lines = [str(len(frames))]
    for bodies in frames:
        lines.append(str(len(bodies)))
        for body_id, xyz in bodies:
            lines += [f"{body_id} 0 1 1 1 1 0 0.01 -0.02 2", "25"]
            lines += [f"{x:.7f} {y:.7f} {z:.7f} 250.1 200.2 1000.3 500.4 0.9 0.1 0.2 0.3 2" for x, y, z in xyz]
    return "\n".join(lines) + "\n"


def write_skeleton(root, name, frames):
    path = root / "skeletons" / f"{name}.skeleton"
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(skeleton_text(frames))
    return path


def kinect(joints):
    return joints @ KINECT.T


ACTFORMER_NAMES = ("ntu1p", "ntu2p", "ntu1p-xview", "ntu2p-xview", "ntu1p-skeletons", "ntu2p-skeletons", "ntu1p-smpl",
                   "combat-2p", "combat-3p", "combat-4p", "combat-5p", "babel120", "babel120-amass")


def test_registry_has_the_actformer_datasets_under_their_stand_in_names(tmp_path, h5py):
    assert set(ACTFORMER_NAMES) <= set(REAL_LOADERS)
    for name in ACTFORMER_NAMES:
        assert list(inspect.signature(REAL_LOADERS[name]).parameters)[:2] == ["root", "split"]
        with pytest.raises(ValueError, match=r"no split 'nope'; expected one of \('train', '(test|val)'"):
            REAL_LOADERS[name](tmp_path, "nope")


def test_kinect_and_z_up_turns_are_proper_rotations():
    for m in (ntu120_files.KINECT_TO_LIBRARY, gta_combat.GTA_TO_LIBRARY, babel.AMASS_TO_LIBRARY):
        np.testing.assert_allclose(m @ m.T, np.eye(3), atol=1e-12)
        assert np.linalg.det(m) == pytest.approx(1.0)
    np.testing.assert_array_equal(ntu120_files.KINECT_TO_LIBRARY, KINECT)
    np.testing.assert_array_equal(gta_combat.GTA_TO_LIBRARY @ [0, 0, 1], [0, 1, 0])  # z up -> y up
    np.testing.assert_array_equal(babel.AMASS_TO_LIBRARY, Z_UP)


ONE_PERSON = "S001C001P001R001A001"  # xsub train (P001), xview test (C001)


def write_ntu_raw(root):
    """One-person clips and distractors; returns the library-frame joints of the kept standing person."""
    person = ntu_person(6, (0.2, 0.0, -3.0))[:1].repeat(6, axis=0)  # standing still, 3 m in front of the sensor
    assert np.all(kinect(person)[:, 0, 2] > 2.9)  # depth away from the sensor
    assert np.all(kinect(person)[:, NTU25.index("left_hip"), 0] < kinect(person)[:, NTU25.index("right_hip"), 0])
    spurious = kinect(ntu_person(6, (1.5, 0.0, -4.0)))
    frames = [[("72057594037927936", kinect(person)[t])] + ([("72057594037927937", spurious[t])] if t in (2, 3) else [])
              for t in range(6)]
    write_skeleton(root, ONE_PERSON, frames)
    turned = kinect(ntu_person(4, (0, 0, -2.5), turn=0.5))
    write_skeleton(root, "S001C002P003R001A061", [[("9", turned[t])] for t in range(4)])  # test subject, camera 2
    write_skeleton(root, "S001C001P001R001A050", [[("9", turned[t])] for t in range(4)])  # a two-person action
    write_skeleton(root, "S001C003P001R002A002", [[("9", turned[t])] for t in range(4)])  # listed missing
    write_skeleton(root, "S001C001P002R001A003", [[] for _ in range(3)])  # no body: skipped with a warning
    (root / "ntu_rgb120_missings.txt").write_text("S001C003P001R002A002\nS017C003P020R002A060\n")
    return person


def test_skeleton_reader_reads_bodies_in_order_of_appearance(tmp_path):
    write_ntu_raw(tmp_path)
    clip = read_skeleton(tmp_path / "skeletons" / f"{ONE_PERSON}.skeleton")
    assert clip.num_frames == 6 and [b.body_id for b in clip.bodies] == ["72057594037927936", "72057594037927937"]
    assert list(clip.bodies[1].frames) == [2, 3] and clip.bodies[0].joints.shape == (6, 25, 12)
    np.testing.assert_allclose(clip.bodies[0].joints[0, 0, 3:], [250.1, 200.2, 1000.3, 500.4, 0.9, 0.1, 0.2, 0.3, 2])
    np.testing.assert_allclose(clip.bodies[0].info[0], [0, 1, 1, 1, 1, 0, 0.01, -0.02, 2])


def test_ntu1p_skeletons_frame_labels_and_xsub_split(tmp_path):
    person = write_ntu_raw(tmp_path)
    with pytest.warns(UserWarning, match=r"skipped 1 clips with fewer than 1 bodies .*S001C001P002R001A003"):
        train = REAL_LOADERS["ntu1p-skeletons"](tmp_path, "train")
    test = load_ntu_skeletons(tmp_path, "test")
    assert (train.name, train.persons, train.skeleton, train.fps, train.rotations) == (
        "ntu1p-skeletons", 1, NTU25, 30.0, None)
    assert train.names == (ONE_PERSON,) and test.names == ("S001C002P003R001A061",)
    assert list(train.actions) == [0] and list(test.actions) == [49]  # A061 is ActFormer's label 49
    assert list(train.subjects) == [1] and list(test.subjects) == [3]
    assert train.class_names == SINGLE_CLASS_NAMES and len(train.class_names) == 94
    # the spurious body (2 detections) is dropped; a still pose stays exactly itself through the smoothing
    np.testing.assert_allclose(train[0].joints, person, atol=1e-6)
    np.testing.assert_allclose(train[0].translation, person[:, 0], atol=1e-6)
    assert_upright_facing_z(train[0].joints, NTU25, "head", "spine_base", "left_hip", "right_hip")
    np.testing.assert_allclose(train[0].translation[0], [0.2, 1.0, -3.0], atol=1e-6)  # in front: at -Z


def test_ntu_skeletons_xview_uses_cameras_2_and_3(tmp_path):
    write_ntu_raw(tmp_path)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        train = load_ntu_skeletons(tmp_path, "train", benchmark="xview")
        test = load_ntu_skeletons(tmp_path, "test", benchmark="xview")
    assert train.name == "ntu1p-skeletons-xview"
    assert train.names == ("S001C002P003R001A061",)  # C003 is listed missing
    assert test.names == (ONE_PERSON,)
    assert ntu120_files.XVIEW_TRAIN_CAMERAS == {2, 3} and len(XSUB_TRAIN_SUBJECTS) == 53


TWO_PERSON = "S002C001P004R001A050"  # xsub train (P004), label 0


def write_two_person_clip(root):
    """12 frames, 3 bodies. Q: first seen (frame 0), 8 detections with a gap at 4..7; P: from frame 2 on, 10
    detections; R: frames 1-2 only. Kept: P and Q, listed Q first. Returns the Kinect joints of Q and P."""
    q = kinect(ntu_person(12, (-0.5, 0.0, -3.0), turn=0.3, spin=0.05))
    p = kinect(ntu_person(12, (0.5, 0.0, -3.2), turn=math.pi, spin=-0.02))
    r = kinect(ntu_person(12, (2.0, 0.0, -5.0)))
    frames = []
    for t in range(12):
        bodies = [("100", q[t])] if t not in (4, 5, 6, 7) else []
        bodies += [("300", r[t])] if t in (1, 2) else []
        bodies += [("200", p[t])] if t >= 2 else []
        frames.append(bodies)
    return write_skeleton(root, TWO_PERSON, frames), q, p


def test_two_person_preparation_keeps_the_most_detected_bodies_and_fills_gaps(tmp_path):
    path, q, p = write_two_person_clip(tmp_path)
    clip = read_skeleton(path)
    assert [b.body_id for b in clip.bodies] == ["100", "300", "200"]
    code = prepare_skeleton(clip, 2, sigma=None)
    linear = prepare_skeleton(clip, 2, rule="linear", sigma=None)
    assert code.shape == (2, 12, 25, 3)
    np.testing.assert_allclose(code[1, :2], p[[2, 2]], atol=1e-6)  # before the first detection: its copy
    np.testing.assert_allclose(code[1, 2:], p[2:], atol=1e-6)
    for t in (0, 1, 2, 3, 8, 9, 10, 11):
        np.testing.assert_allclose(code[0, t], q[t], atol=1e-6)
    np.testing.assert_allclose(code[0, 4], 0.8 * q[3] + 0.2 * q[8], atol=1e-6)  # ActFormer writes frame a + 1 ...
    np.testing.assert_array_equal(code[0, 5:8], 0.0)  # ... and leaves the rest of the gap at zero
    for t in (4, 5, 6, 7):
        w = (t - 3) / 5
        np.testing.assert_allclose(linear[0, t], (1 - w) * q[3] + w * q[8], atol=1e-6)
    smoothed = prepare_skeleton(clip, 2)
    np.testing.assert_allclose(smoothed, gaussian_smooth(code, 3.0, axis=1), atol=1e-12)
    assert prepare_skeleton(clip, 4) is None  # fewer bodies than asked for: skipped
    detected = np.isin(np.arange(12), [0, 1, 2, 3, 8, 9, 10, 11])
    np.testing.assert_allclose(code[0], fill_missing(np.where(detected[:, None, None], q, 0), detected), atol=1e-6)


def test_ntu2p_skeletons_output_two_persons_in_the_library_frame(tmp_path):
    _, q, p = write_two_person_clip(tmp_path)
    write_skeleton(tmp_path, "S002C001P004R001A120", [[("1", q[t])] for t in range(5)])  # one body: skipped
    write_skeleton(tmp_path, "S002C001P004R001A001", [[("1", q[t])] for t in range(5)])  # one-person action
    (tmp_path / "ntu_rgb120_missings.txt").write_text("")
    with pytest.warns(UserWarning, match=r"fewer than 2 bodies .*A120"):
        data = REAL_LOADERS["ntu2p-skeletons"](tmp_path, "train")
    assert (data.name, data.persons, data.names, list(data.actions)) == ("ntu2p-skeletons", 2, (TWO_PERSON,), [0])
    assert data.class_names == MUTUAL_CLASS_NAMES and data.joints.shape == (12, 2, 25, 3)
    clip = prepare_skeleton(read_skeleton(tmp_path / "skeletons" / f"{TWO_PERSON}.skeleton"), 2)
    np.testing.assert_allclose(data[0].joints, clip @ KINECT.T, atol=1e-6)
    np.testing.assert_allclose(data[0].translation, data[0].joints[:, :, 0], atol=0)
    turned_back = data[0].joints[1] @ np.diag([-1.0, 1.0, -1.0])  # P stands turned by pi about Y: facing -Z
    assert_upright_facing_z(turned_back[:3], NTU25, "head", "spine_base", "left_hip", "right_hip")
    with pytest.warns(UserWarning, match="fewer than 2 bodies"):
        linear = load_ntu_skeletons(tmp_path, "train", persons=2, rule="linear")
    assert not np.allclose(linear.joints, data.joints, atol=1e-3)  # the gap rule reaches the output
    assert len(load_ntu_skeletons(tmp_path, "test", persons=2)) == 0


def _truncated(text):
    return text[: text.index("250.1", len(text) // 2)]


@pytest.mark.parametrize("edit, message", [
    (_truncated, r"line \d+: joints of body \d of frame \d: expected 25 more line\(s\), got the end of the file"),
    (lambda s: s.replace("\n25\n", "\n24\n", 1), r"line 4: numJoint of body 0 of frame 0: expected 25, got 24"),
    (lambda s: s.replace(" 0.3 2\n", " 0.3\n", 1), r"line 5: joints of body 0 of frame 0 \(line 1 of 25\): expected"),
    (lambda s: "six\n" + s.split("\n", 1)[1], r"line 1: numFrame: expected an integer >= 0, got 'six'"),
    (lambda s: s.replace("0 1 1 1 1 0", "0 1 1 1", 1), r"line 3: body info of body 0 of frame 0: expected 10 values"),
    (lambda s: s + "1\n", r"expected the end of the file after numFrame = 6 frames"),
])
def test_malformed_skeleton_names_file_line_and_field(tmp_path, edit, message):
    write_ntu_raw(tmp_path)
    path = tmp_path / "skeletons" / f"{ONE_PERSON}.skeleton"
    path.write_text(edit(path.read_text()))
    with pytest.raises(ValueError, match=message) as err:
        read_skeleton(path)
    assert str(path) in str(err.value)
    with pytest.raises(ValueError, match=message):
        load_ntu_skeletons(tmp_path, "train")


def test_bad_skeleton_names_and_missing_inputs(tmp_path):
    write_ntu_raw(tmp_path)
    (tmp_path / "skeletons" / "S001C001P001R001A121.skeleton").write_text("0\n")
    with pytest.raises(ValueError, match=r"A121\.skeleton: file name: expected SsssCcccPpppRrrrAaaa"):
        load_ntu_skeletons(tmp_path, "train")
    (tmp_path / "ntu_rgb120_missings.txt").unlink()
    with pytest.raises(FileNotFoundError, match=r"ntu_rgb120_missings\.txt: NTU list of samples"):
        load_ntu_skeletons(tmp_path, "train")
    with pytest.raises(ValueError, match=r"no split 'val'"):
        load_ntu_skeletons(tmp_path, "val")
    with pytest.raises(ValueError, match=r"benchmark: expected 'xsub' or 'xview'"):
        load_ntu_skeletons(tmp_path, "train", benchmark="xset")


# --- ActFormer's prepared NTU h5 -------------------------------------------------------------------------------


def ntu_prepared_clip(persons, frames, seed):
    """Library-frame joints ``[P, T, 25, 3]`` and ActFormer's stored ``(3P, 25, T)`` of them."""
    people = [ntu_person(frames, (0.8 * k - 0.4, 0.0, -3.0 - 0.3 * k), turn=math.pi * k + 0.1 * seed, spin=0.07)
              for k in range(persons)]
    joints = np.stack(people)
    return joints, to_channels(limb_encode(kinect(joints), NTU25.parents))


def test_ntu1p_prepared_labels_round_trip_and_frame(tmp_path, h5py):
    keys = {"S001C001P001R001A001": 5, "S001C001P001R001A050": 4, "S002C001P004R001A094": 3}
    clips = {key: ntu_prepared_clip(1, frames, i) for i, (key, frames) in enumerate(keys.items())}
    write_h5(h5py, tmp_path / "data1p" / "xsub.train.h5", {k: v for k, (_, v) in clips.items()})
    lengths = bone_lengths(ntu_rest(), NTU25.parents)  # the fixture's own bones: the rebuild is exact
    write_adjacency(h5py, tmp_path / "ntu_adjacency.h5", NTU25.parents, lengths, root=np.float32(0))
    data = REAL_LOADERS["ntu1p"](tmp_path, "train")
    assert (data.name, data.split, data.persons, data.skeleton, data.fps) == ("ntu1p", "train", 1, NTU25, 30.0)
    assert data.names == tuple(keys) and list(data.actions) == [0, 49, 93] and list(data.subjects) == [1, 1, 4]
    assert list(data.lengths) == [5, 4, 3] and data.rotations is None and data.class_names == SINGLE_CLASS_NAMES
    for motion, (joints, stored) in zip(data, clips.values()):
        centred = joints[0] - joints[0, :, 0].mean(axis=0)  # ActFormer stores the root minus its mean
        np.testing.assert_allclose(motion.joints, centred, atol=1e-3)  # unit vectors carry a 1e-4 guard
        vectors = stored.reshape(1, 3, 25, -1).transpose(0, 3, 2, 1)[0].astype(np.float64) @ KINECT.T
        np.testing.assert_allclose(motion.joints, limb_decode(vectors, NTU25.parents, lengths), atol=1e-5)
        np.testing.assert_allclose(motion.translation, motion.joints[:, 0])
    assert_upright_facing_z(data[0].joints[:1], NTU25, "head", "spine_base", "left_hip", "right_hip")


def test_ntu_prepared_without_adjacency_uses_actformer_lengths(tmp_path, h5py):
    _, stored = ntu_prepared_clip(1, 3, 0)
    write_h5(h5py, tmp_path / "data1p" / "xview.test.h5", {"S001C001P001R001A002": stored})
    data = REAL_LOADERS["ntu1p-xview"](tmp_path, "test")
    assert data.name == "ntu1p-xview" and list(data.actions) == [1]
    lengths = np.linalg.norm(data.joints - data.joints[:, [max(p, 0) for p in NTU25.parents]], axis=-1)
    np.testing.assert_allclose(lengths, np.broadcast_to(NTU_AVGLENGTH, lengths.shape), atol=2e-4)
    assert NTU_AVGLENGTH[1] == pytest.approx(0.2805, abs=5e-5) and len(NTU_AVGLENGTH) == 25


def test_ntu2p_prepared_keeps_flip_copies_as_stored(tmp_path, h5py):
    joints, stored = ntu_prepared_clip(2, 4, 0)
    flipped = np.concatenate([stored[3:], stored[:3]])
    _, other = ntu_prepared_clip(2, 3, 1)
    write_adjacency(h5py, tmp_path / "ntu_adjacency.h5", NTU25.parents, bone_lengths(ntu_rest(), NTU25.parents))
    write_h5(h5py, tmp_path / "data2p" / "xsub.train.h5", {
        "S001C001P001R001A001": stored, "S001C001P001R001A001-flip": flipped, "S003C002P008R001A026": other})
    data = REAL_LOADERS["ntu2p"](tmp_path, "train")
    assert (data.persons, data.joints.shape[1:], data.class_names) == (2, (2, 25, 3), MUTUAL_CLASS_NAMES)
    assert data.names == ("S001C001P001R001A001", "S001C001P001R001A001-flip", "S003C002P008R001A026")
    assert list(data.actions) == [0, 0, 25] and list(data.subjects) == [1, 1, 8]
    np.testing.assert_allclose(data[1].joints, data[0].joints[::-1], atol=1e-6)  # persons swapped
    centred = joints - joints[:, :, 0].mean(axis=(0, 1))
    np.testing.assert_allclose(data[0].joints, centred, atol=1e-3)  # unit vectors carry a 1e-4 guard
    assert_upright_facing_z(data[0].joints[0, :1], NTU25, "head", "spine_base", "left_hip", "right_hip")
    assert REAL_LOADERS["ntu2p-xview"] is not REAL_LOADERS["ntu2p"]


@pytest.mark.parametrize("arrays, message", [
    ({"S001C001P001R001A001": np.zeros((6, 25, 4), np.float32)},
     r"'S001C001P001R001A001': expected a real numeric array of shape \[3, 25, T\], got shape \(6, 25, 4\)"),
    ({"S001C001P001R001A095": np.zeros((3, 25, 4), np.float32)},
     r"key 'S001C001P001R001A095': class id 095 minus 1: expected an integer class index in \[0, 94\), got 94"),
    ({"clip7": np.zeros((3, 25, 4), np.float32)}, r"key 'clip7': expected 'A' and 3 digits"),
    ({"S001C001P001R001A001": np.full((3, 25, 2), np.nan, np.float32)},
     r"'S001C001P001R001A001': 150 values that are not finite in float32"),
])
def test_ntu_prepared_malformed_h5_names_file_and_key(tmp_path, h5py, arrays, message):
    path = tmp_path / "data1p" / "xsub.test.h5"
    write_h5(h5py, path, arrays)
    with pytest.raises(ValueError, match=message) as err:
        load_ntu_prepared(tmp_path, "test")
    assert str(path) in str(err.value)


@pytest.mark.parametrize("scale, norm", [(0.0, "0"), (1.5, "1.498")])
def test_ntu_prepared_limb_vectors_that_are_not_unit_vectors_are_refused(tmp_path, h5py, scale, norm):
    _, stored = ntu_prepared_clip(1, 3, 0)
    stored[:, 12, 2] *= scale  # joint 12's limb vector at frame 2: collapsed or stretched
    path = tmp_path / "data1p" / "xsub.train.h5"
    write_h5(h5py, path, {"S001C001P001R001A001": stored})
    with pytest.raises(ValueError, match=re.escape(
            f"{path}: 'S001C001P001R001A001': 1 limb vectors are not unit vectors; the first, person 0, frame 2, "
            f"joint 12 ({NTU25.joint_names[12]}), has norm {norm}")):
        load_ntu_prepared(tmp_path)


def test_ntu_adjacency_file_is_checked(tmp_path, h5py):
    _, stored = ntu_prepared_clip(1, 3, 0)
    write_h5(h5py, tmp_path / "data1p" / "xsub.train.h5", {"S001C001P001R001A001": stored})
    path = tmp_path / "ntu_adjacency.h5"
    write_h5(h5py, path, {"parent": parent_matrix(NTU25.parents)})
    with pytest.raises(ValueError, match=r"ntu_adjacency\.h5: missing key 'avglength' \(found: \['parent'\]\)"):
        load_ntu_prepared(tmp_path)
    write_adjacency(h5py, path, GTA22.parents, np.ones(22))
    with pytest.raises(ValueError, match=r"ntu_adjacency\.h5: 'avglength': expected .* \[25\], got shape \(22,\)"):
        load_ntu_prepared(tmp_path)
    collapsed = np.array(NTU_AVGLENGTH)
    collapsed[7] = 0.0
    write_adjacency(h5py, path, NTU25.parents, collapsed)
    with pytest.raises(ValueError, match=r"ntu_adjacency\.h5: 'avglength': expected a positive bone length for every "
                                         r"joint but the root, got 0\.0 at joint 7 \(left_hand\)"):
        load_ntu_prepared(tmp_path)
    bad = list(NTU25.parents)
    bad[3] = 20
    write_adjacency(h5py, path, tuple(bad), NTU_AVGLENGTH)
    with pytest.raises(ValueError, match=r"'parent': joint 3: expected parent 2 \(the NTU-25"):
        load_ntu_prepared(tmp_path)
    path.write_bytes(b"not an hdf5 file")
    with pytest.raises(ValueError, match=r"ntu_adjacency\.h5: cannot read .* as HDF5"):
        load_ntu_prepared(tmp_path)
    path.unlink()
    with pytest.raises(FileNotFoundError, match=r"data1p.xsub\.test\.h5: ActFormer's prepared NTU 1P clips not found"):
        load_ntu_prepared(tmp_path, "test")


def test_missing_h5py_says_how_to_install(tmp_path, monkeypatch):
    monkeypatch.setitem(sys.modules, "h5py", None)  # import h5py now raises ImportError
    for name in ("ntu1p", "combat-2p", "ntu1p-smpl", "babel120"):
        with pytest.raises(ImportError, match=r'needs h5py, an optional extra: pip install -e "\.\[h5\]"'):
            REAL_LOADERS[name](tmp_path, "train")


# --- GTA Combat ------------------------------------------------------------------------------------------------

_GTA_POSE = {  # library frame: facing +Z, left at +X (JTA's sides)
    "pelvis": (0, 1.0, 0), "spine3": (0, 1.1, 0.01), "spine2": (0, 1.2, 0.02), "spine1": (0, 1.3, 0.01),
    "spine0": (0, 1.4, 0), "neck": (0, 1.5, 0), "head_center": (0, 1.6, 0.02), "head_top": (0, 1.72, 0.01),
    "left_clavicle": (0.05, 1.48, 0), "left_shoulder": (0.18, 1.46, 0), "left_elbow": (0.2, 1.2, -0.02),
    "left_wrist": (0.21, 0.96, 0.03), "left_hip": (0.1, 0.95, 0), "left_knee": (0.1, 0.54, 0.03),
    "left_ankle": (0.1, 0.12, 0),
}


def gta_rest():
    rows = {}
    for name, (x, y, z) in _GTA_POSE.items():
        rows[name] = (x, y, z)
        if name.startswith("left_"):
            rows["right_" + name[5:]] = (-x, y, z)
    return np.array([rows[n] for n in GTA22.joint_names], np.float64)


def gta_clip(persons, frames, seed):
    rest = gta_rest() - [0, 1.0, 0]
    joints = np.stack([np.stack([rest @ yaw(2 * math.pi * k / persons + 0.1 * t + seed).T + [k, 1.0, 0.5 * seed]
                                 for t in range(frames)]) for k in range(persons)])
    z_up = joints @ Z_UP  # library -> GTA's z-up world (the inverse turn)
    assert np.all(z_up[..., GTA22.index("head_top"), 2] > z_up[..., 0, 2] + 0.5)
    return joints, to_channels(limb_encode(z_up, GTA22.parents))


def test_gta_combat_persons_label_round_trip_and_up_axis(tmp_path, h5py):
    lengths = bone_lengths(gta_rest(), GTA22.parents)
    write_adjacency(h5py, tmp_path / "gta_adjacency.h5", GTA22.parents, lengths)
    clips = {"000017": gta_clip(3, 4, 0), "000003": gta_clip(3, 2, 1)}
    write_h5(h5py, tmp_path / "gta_combat_3p.h5", {k: v for k, (_, v) in clips.items()})
    write_h5(h5py, tmp_path / "gta_combat_2p.h5", {"a": gta_clip(2, 3, 0)[1]})
    data = REAL_LOADERS["combat-3p"](tmp_path, "train")
    assert (data.name, data.persons, data.skeleton, data.class_names, data.fps) == (
        "combat-3p", 3, GTA22, ("combat",), 30.0)
    assert data.names == ("000003", "000017") and list(data.actions) == [0, 0]  # the file's key order
    assert data.joints.shape == (6, 3, 22, 3) and list(data.subjects) == [-1, -1]
    for motion in data:
        joints = clips[motion.name][0]
        np.testing.assert_allclose(motion.joints, joints - joints[:, :, 0].mean(axis=(0, 1)), atol=2e-3)
    assert_upright_facing_z(data[1].joints[0, :1], GTA22, "head_top", "pelvis", "left_hip", "right_hip")
    assert np.all(data.joints[..., GTA22.index("head_top"), 1] > data.joints[..., 0, 1] + 0.5)  # +Y up
    assert np.array_equal(load_gta_combat(tmp_path, "test", persons=3).joints, data.joints)  # no held-out file
    assert REAL_LOADERS["combat-2p"](tmp_path, "all").persons == 2


def test_gta_combat_requires_its_adjacency_file_and_checks_shapes(tmp_path, h5py):
    write_h5(h5py, tmp_path / "gta_combat_4p.h5", {"a": gta_clip(3, 3, 0)[1]})
    with pytest.raises(FileNotFoundError, match=r"gta_adjacency\.h5: .*'avglength'.*no published constant"):
        REAL_LOADERS["combat-4p"](tmp_path, "train")
    write_h5(h5py, tmp_path / "gta_adjacency.h5", {"parent": parent_matrix(GTA22.parents)})
    with pytest.raises(ValueError, match=r"gta_adjacency\.h5: missing key 'avglength'"):
        REAL_LOADERS["combat-4p"](tmp_path, "train")
    write_adjacency(h5py, tmp_path / "gta_adjacency.h5", GTA22.parents, bone_lengths(gta_rest(), GTA22.parents))
    with pytest.raises(ValueError, match=r"gta_combat_4p\.h5: 'a': expected .* \[12, 22, T\], got shape \(9, 22, 3\)"):
        REAL_LOADERS["combat-4p"](tmp_path, "train")
    with pytest.raises(ValueError, match=r"persons: expected one of \(2, 3, 4, 5\)"):
        load_gta_combat(tmp_path, persons=6)
    assert REAL_LOADERS["combat-5p"].__name__ == "load_combat_5p"


# --- NTURecon-1P ------------------------------------------------------------------------------------------------


def smpl_clip(rng, frames, root=None, bend=0.3):
    """Library-frame SMPL rotations ``[T, 24, 3]`` and a de-meaned translation ``[T, 3]``."""
    rotations = bend * rng.normal(size=(frames, 24, 3))
    rotations[:, 0] = rotvec(np.eye(3) if root is None else root)
    translation = np.array([0.1, 0.0, -0.2]) + np.arange(frames)[:, None] * np.array([0.0, 0.01, 0.03])
    return rotations, translation - translation.mean(axis=0)


def assert_same_rotations(actual, expected):
    np.testing.assert_allclose(rotmat(actual), rotmat(expected), atol=2e-5)


def test_ntu_recon_rotations_translation_and_template_joints(tmp_path, h5py):
    rng = np.random.default_rng(0)
    clips = {"S001C001P001R001A001": smpl_clip(rng, 4, bend=0.0), "S001C001P002R001A094": smpl_clip(rng, 3)}
    write_h5(h5py, tmp_path / "data_1p" / "xsub.train.h5", {k: smpl_channels(*v) for k, v in clips.items()})
    write_h5(h5py, tmp_path / "data_1p" / "xsub.test.h5", {"S001C001P003R001A050": smpl_channels(*smpl_clip(rng, 2))})
    data = REAL_LOADERS["ntu1p-smpl"](tmp_path, "train")
    assert (data.name, data.skeleton, data.fps, data.persons) == ("ntu1p-smpl", SMPL24, 30.0, 1)
    assert data.names == tuple(clips) and list(data.actions) == [0, 93] and list(data.subjects) == [1, 2]
    assert data.class_names == SINGLE_CLASS_NAMES and data.class_names[49] == "put on headphone"
    for motion, (rotations, translation) in zip(data, clips.values()):
        assert_same_rotations(motion.rotations, rotations)
        np.testing.assert_allclose(motion.translation, translation, atol=1e-6)
        np.testing.assert_allclose(motion.joints, fk(motion.rotations, motion.translation), atol=1e-5)
    assert_upright_facing_z(data[0].joints, SMPL24, "head", "pelvis", "left_hip", "right_hip")
    test = load_ntu_recon(tmp_path, "test")
    assert list(test.actions) == [49] and list(test.subjects) == [3]
    with pytest.raises(ValueError, match=r"no split 'val'.*cross-subject split only"):
        load_ntu_recon(tmp_path, "val")


def test_ntu_recon_malformed_rot6d_and_shape(tmp_path, h5py):
    path = tmp_path / "data_1p" / "xsub.train.h5"
    write_h5(h5py, path, {"S001C001P001R001A001": np.zeros((6, 25, 2), np.float32)})
    with pytest.raises(ValueError, match=r"xsub\.train\.h5: 'S001C001P001R001A001': frame 0, joint 0: expected rot6d"):
        load_ntu_recon(tmp_path, "train")
    write_h5(h5py, path, {"S001C001P001R001A001": np.zeros((6, 24, 2), np.float32)})
    with pytest.raises(ValueError, match=r"'S001C001P001R001A001': expected .* \[6, 25, T\], got shape \(6, 24, 2\)"):
        load_ntu_recon(tmp_path, "train")


# --- BABEL: ActFormer's prepared h5 ---------------------------------------------------------------------------

AMASS_UPRIGHT = Z_UP.T  # AMASS global orientation of a body standing upright (SMPL's y-up body turned z-up)


def label_map(count=150):
    names = [f"category {i}" for i in range(count)]
    for index, name in ((0, "walk"), (3, "turn"), (13, "jump"), (119, "slide"), (149, "flail arms")):
        if index < count:
            names[index] = name
    return {name: i for i, name in enumerate(names)}


def test_babel120_prepared_frame_labels_and_splits(tmp_path, h5py):
    rng = np.random.default_rng(1)
    clips = {"5e3c1d0a_l00_A001": smpl_clip(rng, 4, bend=0.0), "9b2f77e1_l03_A120": smpl_clip(rng, 3)}
    stored = {k: smpl_channels(with_root(r, AMASS_UPRIGHT), t @ Z_UP) for k, (r, t) in clips.items()}
    write_h5(h5py, tmp_path / "train120.h5", stored)
    write_h5(h5py, tmp_path / "val120.h5", {"0aa_l00_A013": stored["9b2f77e1_l03_A120"]})
    data = REAL_LOADERS["babel120"](tmp_path, "train")
    assert (data.name, data.skeleton, data.fps, data.num_classes) == ("babel120", SMPL24, 30.0, 120)
    # without a label-map file, BABEL's own category names
    assert data.class_names[0] == "walk" and data.class_names[119] == "sudden movement"
    assert data.names == tuple(clips) and list(data.actions) == [0, 119]
    for motion, (rotations, translation) in zip(data, clips.values()):
        assert_same_rotations(motion.rotations, rotations)
        np.testing.assert_allclose(motion.translation, translation, atol=1e-6)
        np.testing.assert_allclose(motion.joints, fk(motion.rotations, motion.translation), atol=1e-5)
    assert_upright_facing_z(data[0].joints, SMPL24, "head", "pelvis", "left_hip", "right_hip")
    (tmp_path / "action_label_2_idx.json").write_text(json.dumps(label_map()))
    val, test = load_babel120(tmp_path, "val"), load_babel120(tmp_path, "test")
    assert val.split == "val" and test.split == "test" and val.names == test.names == ("0aa_l00_A013",)
    assert val.class_names[13] == "jump" and list(val.actions) == [12] and len(val.class_names) == 120
    with pytest.raises(ValueError, match=r"'train' reads|expected one of \('train', 'val', 'test'\)"):
        load_babel120(tmp_path, "all")
    (tmp_path / "action_label_2_idx.json").write_text(json.dumps(label_map(100)))
    with pytest.raises(ValueError, match=r"action_label_2_idx\.json: expected the category indices 0..119 .* "
                                         r"missing 20: \[100, 101"):
        load_babel120(tmp_path, "val")


def test_babel120_prepared_wrong_shape_names_file_and_key(tmp_path, h5py):
    write_h5(h5py, tmp_path / "train120.h5", {"seg_l00_A001": np.zeros((9, 25, 3), np.float32)})
    with pytest.raises(ValueError, match=r"train120\.h5: 'seg_l00_A001': expected .*\[6, 25, T\], got shape \(9"):
        load_babel120(tmp_path, "train")


# --- BABEL: AMASS + BABEL json ---------------------------------------------------------------------------------


@pytest.mark.parametrize("frames", [1, 2, 3, 7, 40, 241])
@pytest.mark.parametrize("rate", [120.0, 100.0, 60.0, 59.94, 30.0, 24.0])
def test_cubic_resampling_matches_scipy_zoom(frames, rate):
    ndimage = pytest.importorskip("scipy.ndimage")
    x = np.random.default_rng(frames).normal(size=(frames, 4))
    expected = ndimage.zoom(x, [30.0 / rate, 1])
    out = babel.resample_cubic(x, babel.zoomed_frames(frames, 30.0 / rate))
    assert out.shape == expected.shape
    np.testing.assert_allclose(out, expected, atol=1e-9)  # the same spline: rounding differences only


def test_cubic_resampling_keeps_the_samples():
    x = np.random.default_rng(0).normal(size=(9, 2))
    np.testing.assert_allclose(babel.resample_cubic(x, 9), x, atol=1e-12)  # an interpolating spline
    line = np.linspace(0, 8, 9)[:, None] * [1.0, -2.0]
    np.testing.assert_allclose(babel.resample_cubic(line, 5), line[::2], atol=1e-12)
    assert babel.zoomed_frames(25, 0.5) == 12 and babel.zoomed_frames(27, 0.5) == 14  # round half to even


def amass_motion(rng, frames):
    """AMASS-like arrays: SMPL-H ``poses [T, 156]`` (upright body, small bends), ``trans [T, 3]`` (z-up)."""
    poses = 0.2 * rng.normal(size=(frames, 156))
    poses[:, :3] = rotvec(AMASS_UPRIGHT) + 0.01 * np.arange(frames)[:, None]
    trans = np.stack([0.02 * np.arange(frames), np.sin(np.arange(frames) / 5), 0.9 + 0.0 * np.arange(frames)], 1)
    return poses, trans


SEQ_FRAME_ANN = {
    "feat_p": "CMU/CMU/01/01_01_poses.npz", "dur": 0.4,
    "seq_ann": {"labels": [{"seg_id": "s-all", "act_cat": ["walk"]}]},
    "frame_ann": {"labels": [
        {"seg_id": "seg-jump", "act_cat": ["jump"], "start_t": 0.0, "end_t": 0.2},  # frames [0, 6)
        {"seg_id": "seg-walk", "act_cat": ["walk", "turn", "walk"], "start_t": 0.1, "end_t": 0.5},  # [3, 12)
        {"seg_id": "seg-none", "act_cat": None, "start_t": 0.0, "end_t": 0.4},
        {"seg_id": "seg-flail", "act_cat": ["flail arms", "not a category"], "start_t": 0.0, "end_t": 0.4},
        {"seg_id": "seg-slide", "act_cat": ["slide"], "start_t": 0.39, "end_t": 0.4},  # [11, 12)
        {"seg_id": "seg-empty", "act_cat": ["walk"], "start_t": 0.4, "end_t": 0.41},  # past the end: dropped
    ]},
}
SEQ_SEQ_ANN = {
    "feat_p": "BMLrub/BMLrub/rub001/0001_treadmill_norm_poses.npz", "dur": 0.33,
    "seq_ann": {"labels": [{"seg_id": "whole", "act_cat": ["turn"]}, {"seg_id": "other", "act_cat": None}]},
    "frame_ann": None,
}


def write_babel_raw(root, rng):
    motions = {}
    for sequence, frames, rate in ((SEQ_FRAME_ANN, 24, 60.0), (SEQ_SEQ_ANN, 40, 120.0)):
        path = root / "amass" / "rawdata" / sequence["feat_p"].split("/", 1)[1]
        path.parent.mkdir(parents=True, exist_ok=True)
        poses, trans = amass_motion(rng, frames)
        np.savez(path, poses=poses, trans=trans, mocap_framerate=np.array(rate), gender=np.array("male"),
                 betas=np.zeros(16), dmpls=np.zeros((frames, 8)))
        motions[sequence["feat_p"]] = (poses, trans, rate)
    (root / "babel_v1.0_release").mkdir()
    (root / "babel_v1.0_release" / "train.json").write_text(json.dumps({"11": SEQ_FRAME_ANN, "12": SEQ_SEQ_ANN}))
    (root / "babel_v1.0_release" / "val.json").write_text(json.dumps({"20": SEQ_SEQ_ANN}))
    (root / "action_label_2_idx.json").write_text(json.dumps(label_map()))
    return motions


BABEL_KEYS = ("seg-jump_l00_A014", "seg-slide_l04_A120", "seg-walk_l01_A001", "seg-walk_l01_A004", "whole_l00_A004")


def test_babel_amass_segments_labels_and_frame(tmp_path):
    motions = write_babel_raw(tmp_path, np.random.default_rng(2))
    data = REAL_LOADERS["babel120-amass"](tmp_path, "train")
    assert (data.name, data.skeleton, data.fps, data.persons) == ("babel120-amass", SMPL24, 30.0, 1)
    assert data.names == BABEL_KEYS  # key order; a segment per category; dropped: no category, >= 120, empty
    assert list(data.actions) == [13, 119, 0, 3, 3] and list(data.lengths) == [6, 1, 9, 9, 10]
    assert data.class_names[0] == "walk" and data.class_names[119] == "slide"
    assert np.all(data.rotations[:, 22:] == 0)  # SMPL's hands: the 6 zeros after SMPL-H's 66 body values
    for motion in data:
        np.testing.assert_allclose(motion.translation.mean(axis=0), 0, atol=1e-6)  # de-meaned per segment
        np.testing.assert_allclose(motion.joints, fk(motion.rotations, motion.translation), atol=1e-5)
    np.testing.assert_allclose(data[2].joints, data[3].joints, atol=1e-6)  # a multi-category label, duplicated
    assert_upright_facing_z(data[0].joints[:1], SMPL24, "head", "pelvis", "left_hip", "right_hip")
    # translation: AMASS z-up -> y-up; the overlapping segment starts from frames the first one de-meaned
    poses, trans, _ = motions[SEQ_FRAME_ANN["feat_p"]]
    resampled = babel.resample_cubic(trans, 12)
    working = resampled.copy()
    working[0:6] -= working[0:6].mean(axis=0)
    code = working[3:12] - working[3:12].mean(axis=0)
    independent = resampled[3:12] - resampled[3:12].mean(axis=0)
    np.testing.assert_allclose(data[2].translation, code @ Z_UP.T, atol=1e-6)
    other = load_babel120_amass(tmp_path, "train", overlap="independent")
    np.testing.assert_allclose(other[2].translation, independent @ Z_UP.T, atol=1e-6)
    np.testing.assert_allclose(other[0].joints, data[0].joints)  # not overlapping an earlier segment: the same
    val, test = load_babel120_amass(tmp_path, "val"), load_babel120_amass(tmp_path, "test")
    assert val.names == test.names == ("whole_l00_A004",) and test.split == "test"


def test_babel_amass_matches_actformer_prepared_h5(tmp_path, h5py):
    """The raw path against ActFormer's pipeline rebuilt with scipy's zoom, written as train120.h5."""
    ndimage = pytest.importorskip("scipy.ndimage")
    motions = write_babel_raw(tmp_path, np.random.default_rng(3))
    stored = {}
    for sequence in (SEQ_FRAME_ANN, SEQ_SEQ_ANN):
        poses, trans, rate = motions[sequence["feat_p"]]
        body = np.concatenate([poses[:, :66], np.zeros((len(poses), 6))], axis=1)
        body, trans = ndimage.zoom(body, [30 / rate, 1]), ndimage.zoom(trans, [30 / rate, 1])
        features = smpl_channels(body.reshape(-1, 24, 3), trans).astype(np.float64)  # (6, 25, T)
        segments = [("seg-jump_l00_A014", 0, 6), ("seg-walk_l01_A004", 3, 12), ("seg-walk_l01_A001", 3, 12),
                    ("seg-slide_l04_A120", 11, 12)]  # ActFormer's order: labels in turn, categories sorted
        if sequence is SEQ_SEQ_ANN:
            segments = [("whole_l00_A004", 0, features.shape[-1])]
        for key, start, end in segments:  # ActFormer de-means a view of the sequence, in place
            view = features[..., start:end]
            view[:, 24] -= view[:, 24].mean(axis=1, keepdims=True)
            stored[key] = view.astype(np.float32)
    (tmp_path / "datasets_babel").mkdir()
    write_h5(h5py, tmp_path / "datasets_babel" / "train120.h5", stored)
    prepared = load_babel120(tmp_path / "datasets_babel", "train")
    raw = load_babel120_amass(tmp_path, "train")
    assert prepared.names == raw.names and list(prepared.actions) == list(raw.actions)
    assert_same_rotations(raw.rotations, prepared.rotations)
    np.testing.assert_allclose(raw.translation, prepared.translation, atol=1e-5)
    np.testing.assert_allclose(raw.joints, prepared.joints, atol=1e-4)


def test_babel_amass_malformed_inputs_name_file_and_field(tmp_path):
    write_babel_raw(tmp_path, np.random.default_rng(4))
    npz = tmp_path / "amass" / "rawdata" / "CMU" / "01" / "01_01_poses.npz"
    with np.load(npz) as data:
        arrays = dict(data)
    np.savez(npz, **{k: v for k, v in arrays.items() if k != "trans"})
    with pytest.raises(ValueError, match=r"01_01_poses\.npz: missing key 'trans'"):
        load_babel120_amass(tmp_path, "train")
    np.savez(npz, **dict(arrays, poses=arrays["poses"][:, :60]))
    with pytest.raises(ValueError, match=r"01_01_poses\.npz: 'poses': expected at least 66 values"):
        load_babel120_amass(tmp_path, "train")
    npz.write_bytes(npz.read_bytes()[:200])
    with pytest.raises(ValueError, match=r"01_01_poses\.npz: cannot read AMASS motion file"):
        load_babel120_amass(tmp_path, "train")
    npz.unlink()
    with pytest.raises(FileNotFoundError, match=r"01_01_poses\.npz: AMASS motion file"):
        load_babel120_amass(tmp_path, "train")
    json_path = tmp_path / "babel_v1.0_release" / "val.json"
    broken = json.loads(json.dumps(SEQ_FRAME_ANN))
    del broken["frame_ann"]["labels"][1]["end_t"]
    json_path.write_text(json.dumps({"7": broken}))
    np.savez(npz, **arrays)
    with pytest.raises(ValueError, match=r"val\.json: \['7'\]\['frame_ann'\]\['labels'\]\[1\]: missing key 'end_t'"):
        load_babel120_amass(tmp_path, "val")
    json_path.write_text(json.dumps({"7": {"frame_ann": None}}))
    with pytest.raises(ValueError, match=r"val\.json: \['7'\]: missing key 'feat_p'"):
        load_babel120_amass(tmp_path, "val")
    json_path.write_text("{")
    with pytest.raises(ValueError, match=r"val\.json: cannot read BABEL annotations as JSON"):
        load_babel120_amass(tmp_path, "val")
    with pytest.raises(FileNotFoundError, match=r"elsewhere\.json: BABEL category index"):
        load_babel120_amass(tmp_path, "train", label_map=tmp_path / "elsewhere.json")
