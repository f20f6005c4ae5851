"""Loaders for the real files of the datasets ACTOR, Action2Motion, ODMO, ActFormer and Neural Marionette use.

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
| ``ntu1p`` | :func:`load_ntu1p` | ``datasets/ntu120`` (``data1p/xsub.*``) | train, test | NTU-25, no |
| ``ntu2p`` | :func:`load_ntu2p` | ``datasets/ntu120`` (``data2p/xsub.*``) | train, test | NTU-25 ×2, no |
| ``ntu1p-xview`` | :func:`load_ntu1p_xview` | ``datasets/ntu120`` (``data1p/xview.*``) | train, test | NTU-25, no |
| ``ntu2p-xview`` | :func:`load_ntu2p_xview` | ``datasets/ntu120`` (``data2p/xview.*``) | train, test | NTU-25 ×2, no |
| ``ntu1p-skeletons`` | :func:`load_ntu1p_skeletons` | ``skeletons/`` + missing list | train, test | NTU-25, no |
| ``ntu2p-skeletons`` | :func:`load_ntu2p_skeletons` | ``skeletons/`` + missing list | train, test | NTU-25 ×2, no |
| ``ntu1p-smpl`` | :func:`load_ntu_recon` | ``datasets/ntu120_smpl`` (``data_1p/``) | train, test | SMPL24, yes |
| ``combat-2p`` .. ``combat-5p`` | :func:`load_combat_2p` .. | ``datasets/gta`` | train = test = all | GTA-22 ×P, no |
| ``babel120`` | :func:`load_babel120` | ``datasets/babel`` (``{train,val}120.h5``) | train, val = test | SMPL24, yes |
| ``babel120-amass`` | :func:`load_babel120_amass` | AMASS + ``babel_v1.0_release`` | train, val = test | SMPL24, yes |
| ``mag`` | :func:`load_babel_mag` | AMASS + ``babel_v1.0_release`` | train, test (= val) | SMPL24, yes; takes with segments |

The ActFormer-data loaders (NTU-120, NTURecon, GTA Combat, BABEL) read ``.h5`` files with h5py, an optional extra
(``pip install -e ".[h5]"``); the raw ``.skeleton`` and AMASS loaders do not need it. NTU splits are cross-subject,
the ``-xview`` ones cross-view. Several persons (``×2``, ``×P``): ``joints [F, P, J, 3]``, ``persons = P``.

Errors: a missing file raises ``FileNotFoundError`` naming it; a malformed one ``ValueError`` naming the file
and the key or field, what was expected and what was found.
"""

from types import MappingProxyType

from jaxmotion.data.formats.babel import load_babel120, load_babel120_amass
from jaxmotion.data.formats.babel_mag import load_babel_mag
from jaxmotion.data.formats.cmu_mocap import load_cmu_mocap, load_cmu_mocap7
from jaxmotion.data.formats.gta_combat import (
    load_combat_2p,
    load_combat_3p,
    load_combat_4p,
    load_combat_5p,
    load_gta_combat,
)
from jaxmotion.data.formats.humanact12 import load_humanact12_joints, load_humanact12poses
from jaxmotion.data.formats.ntu13 import load_ntu13, load_ntu13_smpl
from jaxmotion.data.formats.ntu120_files import (
    load_ntu1p,
    load_ntu1p_skeletons,
    load_ntu1p_xview,
    load_ntu2p,
    load_ntu2p_skeletons,
    load_ntu2p_xview,
    load_ntu_prepared,
    load_ntu_skeletons,
)
from jaxmotion.data.formats.ntu_recon import load_ntu_recon
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
    "ntu1p": load_ntu1p,
    "ntu2p": load_ntu2p,
    "ntu1p-xview": load_ntu1p_xview,
    "ntu2p-xview": load_ntu2p_xview,
    "ntu1p-skeletons": load_ntu1p_skeletons,
    "ntu2p-skeletons": load_ntu2p_skeletons,
    "ntu1p-smpl": load_ntu_recon,
    "combat-2p": load_combat_2p,
    "combat-3p": load_combat_3p,
    "combat-4p": load_combat_4p,
    "combat-5p": load_combat_5p,
    "babel120": load_babel120,
    "babel120-amass": load_babel120_amass,
    "mag": load_babel_mag,
})

__all__ = [
    "REAL_LOADERS", "load_babel120", "load_babel120_amass", "load_babel_mag", "load_cmu_mocap", "load_cmu_mocap7",
    "load_combat_2p", "load_combat_3p", "load_combat_4p", "load_combat_5p", "load_gta_combat", "load_humanact12_joints",
    "load_humanact12poses", "load_ntu13", "load_ntu13_smpl", "load_ntu1p", "load_ntu1p_skeletons",
    "load_ntu1p_xview", "load_ntu2p", "load_ntu2p_skeletons", "load_ntu2p_xview", "load_ntu_prepared",
    "load_ntu_recon", "load_ntu_skeletons", "load_uestc",
]
