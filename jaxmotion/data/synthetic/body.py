"""Per-subject bodies and movement styles.

A subject keeps its body and style across all its sequences: both are drawn from the subject's own
generator, so they do not depend on which sequences a split contains.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from jaxmotion.geometry.skeletons import SMPL24

_TEMPLATE = SMPL24.offsets.astype(float)
_TEMPLATE_HEIGHT = 1.70  # stature the SMPL neutral template stands for (MOTION_FACTS 1.2)
MAX_BONE_SCALE = 0.10  # every bone within +-10% of the template

# Bones (named by their child joint) that share one proportion factor: a left/right pair is one
# segment (same factor, plus a few-mm leg-length-inequality-like term); the spine's three links are one.
_SEGMENTS = {
    "pelvis": ("hip",), "thigh": ("knee",), "shank": ("ankle",), "foot": ("foot",),
    "spine": ("spine1", "spine2", "spine3"), "neck": ("neck",), "head": ("head",),
    "collar": ("collar",), "shoulder": ("shoulder",), "upper_arm": ("elbow",), "forearm": ("wrist",),
    "hand": ("hand",),
}


def _bone_segments() -> np.ndarray:
    """``[J]`` segment index of every joint's incoming bone (-1 for the root)."""
    names = list(_SEGMENTS)
    out = np.full(SMPL24.num_joints, -1)
    for j, joint in enumerate(SMPL24.joint_names[1:], start=1):
        part = joint.removeprefix("left_").removeprefix("right_")
        out[j] = next(names.index(s) for s, parts in _SEGMENTS.items() if part in parts)
    return out


_SEGMENT_OF = _bone_segments()
_SIDE = np.array([1.0 if n.startswith("left_") else -1.0 if n.startswith("right_") else 0.0
                  for n in SMPL24.joint_names])


@dataclasses.dataclass(frozen=True)
class Subject:
    """One performer.

    Attributes:
      index: subject id.
      height: stature in metres.
      offsets: ``[J, 3]`` float32 rest offsets (SMPL directions, subject lengths).
      tempo: multiplies every rhythm's rate (people have their own pace).
      amplitude: multiplies movement amplitudes.
      posture: habitual forward lean of the trunk, degrees.
      arm_carry: habitual elbow flexion when relaxed, degrees.
    """

    index: int
    height: float
    offsets: np.ndarray
    tempo: float
    amplitude: float
    posture: float
    arm_carry: float


def sample_subject(index: int, rng: np.random.Generator) -> Subject:
    """Draw a subject: stature ~ N(1.70, 0.07) m (clipped at 2 SD), per-segment proportions
    (1 + eps), eps ~ N(0, 0.04), a few-mm left/right length difference, every bone clipped to
    +-``MAX_BONE_SCALE`` of the template; tempo, amplitude and posture habits."""
    height = float(np.clip(rng.normal(1.70, 0.07), 1.56, 1.84))
    eps = rng.normal(0.0, 0.04, size=len(_SEGMENTS))
    # Half the relative L/R difference: legs (~0.8 m) differ by ~5 mm, as measured leg-length inequality.
    lr = rng.normal(0.0, 0.004, size=len(_SEGMENTS))
    scale = height / _TEMPLATE_HEIGHT * (1.0 + eps[_SEGMENT_OF] + _SIDE * lr[_SEGMENT_OF])
    scale = np.clip(scale, 1.0 - MAX_BONE_SCALE, 1.0 + MAX_BONE_SCALE)
    scale[0] = 1.0
    return Subject(
        index=index,
        height=height,
        offsets=(_TEMPLATE * scale[:, None]).astype(np.float32),
        tempo=float(np.exp(rng.normal(0.0, 0.08))),
        amplitude=float(np.clip(rng.normal(1.0, 0.08), 0.8, 1.2)),
        posture=float(rng.normal(2.0, 2.0)),
        arm_carry=float(np.clip(rng.normal(12.0, 4.0), 4.0, 22.0)),
    )
