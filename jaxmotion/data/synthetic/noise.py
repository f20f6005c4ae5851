"""Capture noise: monocular video pose estimates (VIBE-like) and Kinect v2 skeleton tracking.

:class:`KinectNoise` (NTU RGB+D stand-ins) acts on the output joints; see its docstring. The rest of this
docstring is :class:`EstimateNoise`, for stand-ins of video-estimated datasets.

ACTOR's UESTC motions are VIBE estimates from single RGB videos, with the root depth taken from the 2D
box scale (FACTS 1.1: z = 500 h3d / h2d); this module reproduces their errors on a clean, grounded
motion (MOTION_FACTS section 6). :class:`EstimateNoise` is a :class:`~engine.Variant` ``noise`` hook:

* **Joint jitter** (every joint, every frame, independent): ``N(0, jitter_deg)`` on every anatomical
  channel, pelvis orientation included, then the joint limits (a channel at its limit only jitters
  inwards; channels without range stay zero). Calibrated on synth-uestc: with 0.6 degrees the
  root-relative joints jitter by 7.7 / 4.8 / 8.0 mm (x / y / z, std; more at the hands and feet, whose
  chains are long) and the acceleration error, mean over joints of ``|a_noisy - a_clean|`` with ``a``
  the second difference of root-relative joints, is 23 mm/frame^2: VIBE's on 3DPW (23.2; 15.8 on H36M,
  31.6 on AIST++; iid per-axis jitter of ~6 mm gives the same, at ~3.9 sigma). Joints stay FK of the
  stored rotations because the noise is on the rotations.
* **Root jitter**: iid ``N(0, root_jitter_m)`` per axis (x, y, z = camera depth): the box scale that
  gives depth is the least stable estimate (est.: 1 % box jitter at ~3 m is 3 cm; ACTOR's refinement
  smooths it).
* **Depth from the box height**: the camera (the subject faces it, along world +Z) puts the body at
  ``distance * ref / extent`` when the vertical extent of the joints shrinks while crouching or
  bending (``ref``: the subject's standing extent); the 3D estimate's own height absorbs most of this,
  so a per-clip fraction ``depth_gain`` of it remains: the body drifts away from the camera (-Z) as it
  folds. A deep squat (extent x 0.6) at gain 0.12 moves it ~0.25 m.
* **Drift**: a slow wander of the root (below ``drift_hz``) of ``drift_m`` (est.).

Feet are not re-grounded: like real estimates they slide and dip a few centimetres below the floor.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from jaxmotion.data.formats.ntu120 import GapFill, fill_missing, gaussian_smooth
from jaxmotion.data.synthetic import anatomy, timing
from jaxmotion.data.synthetic.body import Subject
from jaxmotion.geometry.skeletons import SMPL24, Skeleton, topological_order


def standing_extent(offsets: np.ndarray) -> float:
    """Vertical extent (m) of the joints of a body ``offsets [J, 3]`` in its rest pose."""
    heights = np.zeros(len(offsets))
    for j in topological_order(SMPL24.parents)[1:]:
        heights[j] = heights[SMPL24.parents[j]] + offsets[j, 1]
    return float(heights.max() - heights.min())


@dataclasses.dataclass(frozen=True)
class EstimateNoise:
    """Monocular-estimate noise; see the module docstring for the model and where the numbers come from.

    Attributes:
      jitter_deg: per-frame standard deviation of every anatomical channel, degrees.
      root_jitter_m: per-frame standard deviation of the root along (x, y, z), metres.
      distance_m: camera distance (Kinect range 0.5-4.5 m; est. ~3 m for whole-body framing).
      depth_gain: range of the per-clip share of the box-height depth error.
      drift_m: standard deviation of the slow root wander along (x, y, z), metres.
      drift_hz: highest frequency of that wander.
    """

    jitter_deg: float = 0.6
    root_jitter_m: tuple[float, float, float] = (0.003, 0.003, 0.01)
    distance_m: float = 3.0
    depth_gain: tuple[float, float] = (0.05, 0.2)
    drift_m: tuple[float, float, float] = (0.015, 0.01, 0.03)
    drift_hz: float = 0.25

    def __call__(self, angles: np.ndarray, translation: np.ndarray, joints: np.ndarray, subject: Subject,
                 fps: float, rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
        """Noisy ``(angles [T, J, 3], translation [T, 3])`` from the clean angles (degrees), the grounded
        root path and the clean body posed about the origin ``joints [T, J, 3]``."""
        noisy = anatomy.clip_to_limits(angles + rng.normal(0.0, self.jitter_deg, angles.shape))
        t = np.arange(len(angles)) / fps
        extent = joints[..., 1].max(axis=1) - joints[..., 1].min(axis=1)
        gain = rng.uniform(*self.depth_gain)
        depth = self.distance_m * gain * (standing_extent(subject.offsets) / extent - 1.0)
        drift = timing.smooth_noise(t, rng, 1.0, max_hz=self.drift_hz, channels=3) * np.array(self.drift_m)
        jitter = rng.normal(0.0, self.root_jitter_m, translation.shape)
        root = translation + drift + jitter
        root[:, 2] -= depth
        return noisy, root


#: Joints Kinect tracks worst (the ends of the limbs), by name part.
_EXTREMITIES = ("wrist", "hand", "thumb", "ankle", "foot")


@dataclasses.dataclass(frozen=True)
class KinectNoise:
    """Kinect v2 skeleton tracking as NTU RGB+D's files hold it, then ActFormer's preparation of them.

    A :class:`~engine.Variant` ``joint_noise`` hook on the output joints (``[T, K, 3]``, a Kinect layout):

    * **Jitter**: iid ``N(0, jitter_m)`` per joint, axis and frame; ``extremity_jitter_m`` at the wrists,
      hands, thumbs, ankles and feet (est.: Kinect v2's skeletons are noisy under occlusion and at the limb
      ends, MOTION_FACTS 6; the preparation's smoothing takes most of it away).
    * **Lost tracking**: with probability ``lost_probability`` a clip has 1-2 bursts of ``lost_frames``
      frames without a detection (the file then has no body on those frames).
    * **ActFormer's preparation** (:mod:`jaxmotion.data.formats.ntu120`): gaps filled by ``rule`` (default
      the code's, which leaves all but the first frame of a gap at the camera's origin) and a Gaussian
      smoothing over time with sigma 3 frames. The camera (its origin is what an unfilled frame holds) sits
      ``camera_m`` (x, y, z) from the clip's first root position, in front of the subject.
    """

    jitter_m: float = 0.008
    extremity_jitter_m: float = 0.02
    lost_probability: float = 0.1
    lost_frames: tuple[int, int] = (2, 6)
    rule: GapFill = "code"
    camera_m: tuple[float, float, float] = (0.0, 0.0, 3.0)

    def __call__(self, joints: np.ndarray, skeleton: Skeleton, fps: float, rng: np.random.Generator) -> np.ndarray:
        """Noisy, prepared ``[T, K, 3]`` from the clean ``joints [T, K, 3]`` of ``skeleton``."""
        sigma = np.array([self.extremity_jitter_m if any(p in n for p in _EXTREMITIES) else self.jitter_m
                          for n in skeleton.joint_names])
        noisy = joints + rng.normal(size=joints.shape) * sigma[None, :, None]
        detected = np.ones(len(joints), bool)
        if rng.uniform() < self.lost_probability:
            for _ in range(int(rng.integers(1, 3))):
                length = int(rng.integers(self.lost_frames[0], self.lost_frames[1] + 1))
                start = int(rng.integers(1, max(len(joints) - length - 1, 2)))
                detected[start:start + length] = False
        if not detected.any():
            detected[0] = True
        camera = joints[0, 0] + np.array(self.camera_m)
        filled = fill_missing(noisy - camera, detected, self.rule) + camera
        return gaussian_smooth(filled, axis=0).astype(np.float32)
