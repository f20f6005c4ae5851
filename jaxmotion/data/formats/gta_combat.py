"""GTA Combat, ActFormer's synthetic multi-person combat set (2 to 5 persons), as ActFormer distributes it.

Layout of the dataset folder (ActFormer's ``datasets/gta``; the files of its README's download link, and
``gta_adjacency.h5`` from its repository)::

    <data_root>/gta_combat_{2,3,4,5}p.h5    one file per person count P
    <data_root>/gta_adjacency.h5            ``avglength`` (and ``parent``, ``adjacency``): required

Each key of ``gta_combat_<P>p.h5`` is one clip, float32 ``(3P, 22, T)``: channel ``3p + c`` of person p, joint 0
the root position (relative to the clip's mean root), joint j > 0 the unit vector from its parent, as for
ActFormer's NTU data (its ``config/generator/gta/actformer_<P>p.yaml`` reads them with ``C = 3P``, ``V = 22``).
There is one class, ``"combat"``: every clip has label 0 (ActFormer's feeder, ``dataset: gta``). Joints are
rebuilt with :func:`~jaxmotion.geometry.representations.joints_from_limb_vectors` and ``avglength`` of
``gta_adjacency.h5``, which is required: ActFormer publishes no other value of the GTA bone lengths. When the
file has ``parent``, its tree must be :data:`GTA22`'s.

Splits: ActFormer's configs train on the whole ``gta_combat_<P>p.h5`` (``config/generator/gta/``) and have no
held-out file; its evaluation configs (``config/eval_motion_multip/gta_<P>p.yaml``) compare against
``datasets/joint_ntu_gta/gta_personwise_rescaled/gta_combat_<P>p.h5``, the same clips remapped to 15 joints,
which is not released. So ``"train"``, ``"test"`` and ``"all"`` are the same clips here, as for NTU-13.

Frame: GTA's world frame is z-up (ActFormer's ``visualize/visualize_skt_gta.py`` plots x, y, z as they are,
z vertical, where it swaps y and z for NTU; it scales the root's x and y by 5 for display only).
:data:`GTA_TO_LIBRARY`, the rotation by -90 degrees about X, ``(x, y, z) -> (x, z, -y)`` (determinant +1, so
left stays left), makes +Z up into +Y up; the facing direction is wherever the game put the fighters.
Lengths are metres (``avglength``: femur 0.41). Frame rate: ActFormer states none; 30 fps is assumed (JTA,
the GTA-V capture tool ActFormer extends, records at 30 fps). Subjects are unknown (-1); names are the keys.

Reading ``.h5`` files needs h5py: ``pip install -e ".[h5]"``.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from jaxmotion.data.formats._common import check_split
from jaxmotion.data.formats.ntu120_files import (
    limb_clips_to_joints,
    read_avglength,
    read_h5_clips,
    require_h5py,
)
from jaxmotion.data.motion import Motion, MotionDataset, pack
from jaxmotion.geometry.skeletons import GTA22

#: GTA's z-up world frame -> library frame (y up): R_x(-90 degrees), on column vectors.
GTA_TO_LIBRARY = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, -1.0, 0.0]])
CLASS_NAMES = ("combat",)
#: Assumed: ActFormer gives no frame rate; JTA records GTA-V at 30 fps.
FPS = 30.0
PERSON_COUNTS = (2, 3, 4, 5)
ADJACENCY_FILE = "gta_adjacency.h5"
NUM_JOINTS = 22


def load_gta_combat(root: str | Path, split: str = "train", *, persons: int = 2) -> MotionDataset:
    """GTA Combat with ``persons`` (2..5) fighters per clip: ``gta_combat_<persons>p.h5`` under ``root``
    (ActFormer's ``datasets/gta``), joints rebuilt with ``gta_adjacency.h5``. ``split``: ``"train"``,
    ``"test"`` or ``"all"``, the same clips (module docstring)."""
    if persons not in PERSON_COUNTS:
        raise ValueError(f"persons: expected one of {PERSON_COUNTS}, got {persons!r}")
    name = f"combat-{persons}p"
    require_h5py()  # first: without it, say so before anything else
    check_split(split, ("train", "test", "all"), name)
    root = Path(root)
    adjacency = root / ADJACENCY_FILE
    if not adjacency.is_file():
        raise FileNotFoundError(
            f"{adjacency}: GTA skeleton file not found: it holds 'avglength', the average bone lengths that "
            f"rebuild joints from the limb vectors, and no published constant replaces it; copy "
            f"datasets/gta/{ADJACENCY_FILE} of ActFormer's repository (Szy-Young/ActFormer) into {root}")
    lengths = read_avglength(adjacency, GTA22, "ActFormer's GTA skeleton file (gta_adjacency.h5)")
    path = root / f"gta_combat_{persons}p.h5"
    clips = read_h5_clips(path, f"GTA Combat {persons}P clips", (3 * persons, NUM_JOINTS))
    # (3P, V, T) -> (P, T, V, 3)
    vectors = [(key, a.reshape(persons, 3, NUM_JOINTS, -1).transpose(0, 3, 2, 1)) for key, a in clips]
    joints = limb_clips_to_joints(vectors, GTA22, lengths, GTA_TO_LIBRARY, file=path)
    motions = [Motion(joints=j, translation=j[..., 0, :], rotations=None, action=0, name=key)
               for (key, _), j in zip(clips, joints)]
    return pack(motions, name=name, split=split, class_names=CLASS_NAMES, skeleton=GTA22, fps=FPS,
                persons=persons)


def load_combat_2p(root: str | Path, split: str = "train") -> MotionDataset:
    """``combat-2p``: GTA Combat, 2 persons (:func:`load_gta_combat`)."""
    return load_gta_combat(root, split, persons=2)


def load_combat_3p(root: str | Path, split: str = "train") -> MotionDataset:
    """``combat-3p``: GTA Combat, 3 persons (:func:`load_gta_combat`)."""
    return load_gta_combat(root, split, persons=3)


def load_combat_4p(root: str | Path, split: str = "train") -> MotionDataset:
    """``combat-4p``: GTA Combat, 4 persons (:func:`load_gta_combat`)."""
    return load_gta_combat(root, split, persons=4)


def load_combat_5p(root: str | Path, split: str = "train") -> MotionDataset:
    """``combat-5p``: GTA Combat, 5 persons (:func:`load_gta_combat`)."""
    return load_gta_combat(root, split, persons=5)
