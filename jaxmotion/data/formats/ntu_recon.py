"""NTURecon-1P: ActFormer's SMPL reconstruction of the one-person NTU RGB+D 120 actions, as it prepares them.

Input of ActFormer's ``datasets/ntu120_smpl/prepare_data.py`` (not read here): per clip and body,
``<SRC>/Sxxx/<clip>_body<k>.pkl`` with ``smpl_poses`` ``[T, 72]`` axis-angle, ``smpl_trans`` ``[T, 3]`` and
``smpl_scaling``, the output of the AIST++ API's SMPL fitting on the NTU videos. The script keeps the 94
one-person actions, turns the global orientation by ``R_x(-pi)``, divides the translation by the scaling,
de-means it over the clip, turns it by the same ``R_x(-pi)``, and writes per clip a float32 ``(6, 25, T)``
array: joints 0..23 the SMPL rotations as rot6d (the first two rows of each matrix), joint 24 the translation
zero-padded to 6 channels. ``datasets/ntu120_smpl/split_1p.py`` then splits it cross-subject (performers of
:data:`~jaxmotion.data.formats.ntu120.XSUB_TRAIN_SUBJECTS`) and relabels ``A061..A105`` to ``A050..A094``.

That prepared output is what this loader reads (ActFormer's ``datasets/ntu120_smpl`` folder)::

    <data_root>/data_1p/xsub.train.h5
    <data_root>/data_1p/xsub.test.h5

Each key is a clip name; the label is the 3 digits after its last ``A``, minus 1 (94 classes, in ActFormer's
order :data:`~jaxmotion.data.formats.ntu120.SINGLE_ACTIONS`); the subject is the ``P`` field. Only the
cross-subject split exists (``split_1p.py``).

Rotations come from the rot6d rows by Gram-Schmidt
(:func:`~jaxmotion.geometry.representations.split_rotation_features`), translation from joint 24 (so it is
relative to the clip's mean, as prepared), and joints from forward kinematics of the project SMPL template
(``SMPL24.offsets``) rooted at the translation (no SMPL body model ships with the library; ActFormer gets joints
from the SMPL model).

Frame: ActFormer's ``R_x(-pi)`` takes the fitting's camera frame (y down, the subject facing the camera, -Z)
to y up with the subject facing +Z, which is the library frame: the stored rotations and translation are used
as they are. 30 fps (NTU's; not resampled). Reading ``.h5`` needs h5py: ``pip install -e ".[h5]"``.
"""

from __future__ import annotations

from pathlib import Path

import jax
import jax.numpy as jnp
import numpy as np

from jaxmotion.data.formats._common import check_split, template_joints
from jaxmotion.data.formats.ntu120 import FPS, SINGLE_CLASS_NAMES
from jaxmotion.data.formats.ntu120_files import actformer_label, key_subject, read_h5_clips, require_h5py
from jaxmotion.data.motion import Motion, MotionDataset, pack
from jaxmotion.geometry.representations import split_rotation_features
from jaxmotion.geometry.rotations import axis_angle_to_matrix, matrix_to_axis_angle
from jaxmotion.geometry.skeletons import SMPL24

#: The prepared output's frame -> library frame: the identity (see the module docstring).
RECON_TO_LIBRARY = np.eye(3)
SMPL_FEATURE_SHAPE = (6, 25)  # rot6d of 24 SMPL joints + the translation row


_CHUNK = 4096  # frames per call of the compiled conversion: one shape, so it compiles once per process


@jax.jit
def _features_to_library(features: jax.Array, turn: jax.Array) -> tuple[jax.Array, jax.Array]:
    """``[N, 25, 6]`` rot6d + translation row, ``[3, 3]`` turn -> ``([N, 24, 3]`` axis-angle with the global
    orientation R turned to ``turn @ R``, ``[N, 3]`` translation turned)."""
    rotations, translation = split_rotation_features(features)
    root = jnp.matmul(turn, axis_angle_to_matrix(rotations[:, 0]), precision=jax.lax.Precision.HIGHEST)
    return (rotations.at[:, 0].set(matrix_to_axis_angle(root)),
            jnp.matmul(translation, turn.T, precision=jax.lax.Precision.HIGHEST))


def check_rot6d(clips: list[tuple[str, np.ndarray]], *, file: Path) -> None:
    """Every ``(key, [6, 25, T])`` clip's rows 0..23 must define rotations (Gram-Schmidt needs two independent
    rows); else a ``ValueError`` naming the file, the key, the frame and the joint."""
    for key, array in clips:
        rows = np.transpose(array[:, :24], (2, 1, 0))  # [T, 24, 6]
        spread = np.linalg.norm(np.cross(rows[..., :3], rows[..., 3:]), axis=-1)
        if np.any(spread < 1e-6):
            t, j = (int(i) for i in np.argwhere(spread < 1e-6)[0])
            raise ValueError(f"{file}: {key!r}: frame {t}, joint {j}: expected rot6d rows of a rotation (two "
                             f"independent rows), got {rows[t, j].tolist()}")


def smpl_motions(keys: list[str], features: list[np.ndarray], to_library: np.ndarray, labels: list[int],
                 subjects: list[int]) -> list[Motion]:
    """Per clip ``[T, 25, 6]`` ActFormer SMPL features (rot6d rows + translation row) in a source frame ->
    library-frame records: rotations by :func:`~jaxmotion.geometry.representations.split_rotation_features`,
    global orientation and translation turned by ``to_library``, joints by template forward kinematics."""
    if not keys:
        return []
    frames = np.concatenate(features).astype(np.float32)
    turn = np.asarray(to_library, np.float32)
    rotations, translation = [], []
    for start in range(0, len(frames), _CHUNK):
        part = frames[start:start + _CHUNK]
        pad = _CHUNK - len(part)
        r, t = _features_to_library(np.pad(part, [(0, pad), (0, 0), (0, 0)], mode="edge"), turn)
        rotations.append(np.asarray(r)[: _CHUNK - pad])
        translation.append(np.asarray(t)[: _CHUNK - pad])
    rotations, translation = np.concatenate(rotations), np.concatenate(translation)
    joints = template_joints(rotations, translation)
    cuts = np.cumsum([len(f) for f in features])[:-1]
    return [Motion(joints=j, translation=t, rotations=r, action=label, subject=subject, name=key)
            for key, r, t, j, label, subject in zip(keys, np.split(rotations, cuts), np.split(translation, cuts),
                                                    np.split(joints, cuts), labels, subjects)]


def load_ntu_recon(root: str | Path, split: str = "train") -> MotionDataset:
    """``ntu1p-smpl``: NTURecon-1P as ActFormer prepares it. ``root``: ActFormer's ``datasets/ntu120_smpl``
    folder (holding ``data_1p/xsub.{train,test}.h5``); ``split``: ``"train"`` or ``"test"`` (cross-subject)."""
    check_split(split, ("train", "test"), "ntu1p-smpl", "NTURecon-1P has the cross-subject split only")
    require_h5py()  # first: without it, say so before anything else
    path = Path(root) / "data_1p" / f"xsub.{split}.h5"
    stored = read_h5_clips(path, "ActFormer's prepared NTURecon-1P clips", SMPL_FEATURE_SHAPE)
    check_rot6d(stored, file=path)
    keys = [key for key, _ in stored]
    labels = [actformer_label(key, len(SINGLE_CLASS_NAMES), file=path) for key in keys]
    motions = smpl_motions(keys, [np.transpose(a, (2, 1, 0)) for _, a in stored], RECON_TO_LIBRARY, labels,
                           [key_subject(key) for key in keys])
    return pack(motions, name="ntu1p-smpl", split=split, class_names=SINGLE_CLASS_NAMES, skeleton=SMPL24, fps=FPS)
