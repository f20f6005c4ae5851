"""Bodies as capsules around their bones, for contact and separation tests of multi-person scenes."""

import numpy as np

from jaxmotion.geometry.skeletons import SMPL24

# Capsule radius around each joint's incoming bone (metres, adult, est.): torso, neck and head, arms, legs.
_RADIUS = {"pelvis": 0.11, "spine": 0.11, "neck": 0.05, "head": 0.09, "collar": 0.05, "shoulder": 0.05,
           "elbow": 0.045, "wrist": 0.035, "hand": 0.035, "hip": 0.08, "knee": 0.055, "ankle": 0.045, "foot": 0.04}
RADII = np.array([next(r for k, r in _RADIUS.items() if k in n) for n in SMPL24.joint_names])
_SAMPLES = np.linspace(0.0, 1.0, 5)


def _bone_points(joints, bones):
    """``joints [T, 24, 3]``, (parent, child) pairs -> points along them ``[T, N, 3]`` and their radii ``[N]``."""
    if not bones:
        return np.zeros(joints.shape[:1] + (0, 3)), np.zeros(0)
    parent, child = (np.array(x) for x in zip(*bones))
    s = _SAMPLES[None, :, None]
    pts = joints[:, parent, None] + s[None] * (joints[:, child, None] - joints[:, parent, None])  # [T, B, S, 3]
    radii = np.minimum(RADII[parent], RADII[child])[:, None].repeat(len(_SAMPLES), 1)
    return pts.reshape(len(joints), -1, 3), radii.reshape(-1)


def part_points(joints, names):
    """A body part: the bones between its listed joints (and the joints themselves)."""
    idx = {SMPL24.index(n) for n in names}
    bones = [(p, c) for c, p in enumerate(SMPL24.parents) if p >= 0 and p in idx and c in idx]
    bones += [(j, j) for j in idx]
    return _bone_points(joints, bones)


def limbs(names):
    """The joints of ``names`` and of the limbs that carry them: a hand's arm up to the collar, a foot's leg up
    to the hip (a touching hand brings its arm along)."""
    out = set(names)
    for n in names:
        for side in ("left", "right"):
            if n.startswith(side) and any(k in n for k in ("wrist", "hand", "elbow")):
                out |= {f"{side}_{j}" for j in ("collar", "shoulder", "elbow", "wrist", "hand")}
            if n.startswith(side) and any(k in n for k in ("ankle", "foot", "knee")):
                out |= {f"{side}_{j}" for j in ("hip", "knee", "ankle", "foot")}
    return out


def all_points(joints, excluded=frozenset()):
    """The whole body but the bones into (or out of) the ``excluded`` joints."""
    idx = {SMPL24.index(n) for n in excluded}
    bones = [(p, c) for c, p in enumerate(SMPL24.parents) if p >= 0 and c not in idx and p not in idx]
    return _bone_points(joints, bones)


def surface_gap(a, b):
    """``[T]`` the smallest distance between two bodies' capsule surfaces per frame (negative: overlap)."""
    (pa, ra), (pb, rb) = a, b
    d = np.linalg.norm(pa[:, :, None] - pb[:, None], axis=-1) - ra[None, :, None] - rb[None, None, :]
    return d.min(axis=(1, 2))
