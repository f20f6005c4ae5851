"""Loaders for the real files of the datasets ACTOR, Action2Motion and ODMO use.

Each loader reads one dataset in the layout its authors' code reads (the module docstrings give the exact
files and their source) and returns a :class:`~jaxmotion.data.motion.MotionDataset` in the library frame
(metres, +Y up, facing +Z at rest, +X the subject's left). :data:`REAL_LOADERS` maps a dataset name to a
function ``(data_root, split) -> MotionDataset``, where ``data_root`` is that dataset's own folder:

| name | loader | folder (authors' name) | splits | skeleton, rotations |
| --- | --- | --- | --- | --- |
| ``humanact12`` | :func:`load_humanact12poses` | ``data/HumanAct12Poses`` or its pickle | train = all | SMPL24, yes |
| ``humanact12-joints`` | :func:`load_humanact12_joints` | the folder of ``*.npy`` clips | train = all | SMPL24, no |
| ``uestc`` | :func:`load_uestc` | ``data/uestc`` | train, test | SMPL24, yes |
| ``ntu13`` | :func:`load_ntu13` | ``data/ntu13`` | train = test = all | VIBE-18, no |
| ``ntu13-smpl`` | :func:`load_ntu13_smpl` | ``data/ntu13`` | train = test = all | SMPL24, yes |
| ``cmu`` | :func:`load_cmu_mocap` | ``dataset/mocap`` | train = all | CMU-20, no |
| ``cmu7`` | :func:`load_cmu_mocap7` | ``dataset/mocap`` | train = all | CMU-20, no |

Errors: a missing file raises ``FileNotFoundError`` naming it; a malformed one ``ValueError`` naming the file
and the key or field, what was expected and what was found.
"""

from types import MappingProxyType

from jaxmotion.data.formats.cmu_mocap import load_cmu_mocap, load_cmu_mocap7
from jaxmotion.data.formats.humanact12 import load_humanact12_joints, load_humanact12poses
from jaxmotion.data.formats.ntu13 import load_ntu13, load_ntu13_smpl
from jaxmotion.data.formats.uestc import load_uestc

#: Dataset name -> ``(data_root, split) -> MotionDataset``; read-only.
REAL_LOADERS = MappingProxyType({
    "humanact12": load_humanact12poses,
    "humanact12-joints": load_humanact12_joints,
    "uestc": load_uestc,
    "ntu13": load_ntu13,
    "ntu13-smpl": load_ntu13_smpl,
    "cmu": load_cmu_mocap,
    "cmu7": load_cmu_mocap7,
})

__all__ = [
    "REAL_LOADERS", "load_cmu_mocap", "load_cmu_mocap7", "load_humanact12_joints", "load_humanact12poses",
    "load_ntu13", "load_ntu13_smpl", "load_uestc",
]
