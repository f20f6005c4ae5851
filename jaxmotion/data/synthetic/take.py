"""A take: one sequence being performed, and the pose track its action builds.

An action class is a function ``perform(take) -> None`` that writes anatomical angles (degrees, see
:mod:`anatomy`) into ``take`` by channel name (``take["left_knee.flex"] += ...``), declares which feet
bear weight (``take.contact``), and reads its timing, randomness and performer from the take.
"""

from __future__ import annotations

import numpy as np

from jaxmotion.data.synthetic import anatomy, timing
from jaxmotion.data.synthetic.body import Subject
from jaxmotion.geometry.skeletons import SMPL24

SIDES = ("left", "right")


def other(side: str) -> str:
    return "right" if side == "left" else "left"


class Take:
    """One sequence in progress.

    Attributes:
      t: ``[T]`` time of each frame, seconds.
      fps: frames per second.
      rng: this sequence's own generator (every random choice of the take comes from it).
      subject: the performer (body, tempo, amplitude and posture habits).
      mode: the style mode's name within the class.
      tempo: subject tempo times a per-take factor: multiply rates by it.
      amp: subject amplitude times a per-take factor: multiply movement sizes by it.
      angles: ``[T, J, 3]`` the pose being built, degrees (indexable by ``"joint.channel"``).
      contact: ``[T, 2]`` share of the body weight on the (left, right) foot; a frame where both are 0 is
        airborne (the root then follows a ballistic path).
      ground: ``[T, 2]`` height (m) of the support under the (left, right) foot: 0 is the floor, more is a
        step, stair or rung the foot stands on (see :func:`grounding.root_translation`).
      flight_speed: forward speed (m/s, along the heading) added during flight, e.g. a jump forward.
      flight_carry: fraction of the support phase's horizontal velocity kept in flight (see
        :func:`grounding.root_translation`).
    """

    def __init__(self, num_frames: int, fps: float, rng: np.random.Generator, subject: Subject, mode: str):
        self.t = np.arange(num_frames) / fps
        self.fps = fps
        self.rng = rng
        self.subject = subject
        self.mode = mode
        self.tempo = subject.tempo * float(np.exp(rng.normal(0.0, 0.05)))
        self.amp = subject.amplitude * float(np.clip(rng.normal(1.0, 0.06), 0.85, 1.15))
        self.angles = np.zeros((num_frames, anatomy.NUM_JOINTS, 3))
        self.contact = np.full((num_frames, 2), 0.5)
        self.ground = np.zeros((num_frames, 2))
        self.flight_speed = 0.0
        self.flight_carry = 1.0

    @property
    def num_frames(self) -> int:
        return len(self.t)

    @property
    def duration(self) -> float:
        return self.num_frames / self.fps

    def __getitem__(self, name: str) -> np.ndarray:
        j, c = anatomy.channel(name)
        return self.angles[:, j, c]

    def __setitem__(self, name: str, value) -> None:
        j, c = anatomy.channel(name)
        self.angles[:, j, c] = value

    # --- randomness helpers: every draw comes from the take's generator --------------------------------

    def uniform(self, low: float, high: float) -> float:
        return float(self.rng.uniform(low, high))

    def vary(self, value: float, spread: float = 0.1) -> float:
        """``value`` times a random factor N(1, spread) (clipped to +-2 spread)."""
        return value * float(1.0 + np.clip(self.rng.normal(0.0, spread), -2 * spread, 2 * spread))

    def choice(self, options):
        return options[int(self.rng.integers(len(options)))]

    def onset(self, busy: float, margin: float = 0.15) -> float:
        """A random start time (s) for a one-off movement lasting ``busy`` seconds, so it fits in the clip."""
        slack = max(self.duration - busy, 0.0)
        return slack * self.uniform(margin, 1.0 - margin) if slack > 0 else 0.0

    def wander(self, amplitude: float, max_hz: float = 0.8) -> np.ndarray:
        """``[T]`` slow random wander of about ``amplitude`` (degrees), for sway and irregularity."""
        return timing.smooth_noise(self.t, self.rng, amplitude, max_hz=max_hz)

    # --- body landmarks in the thorax (spine3) frame, side-normalised: x lateral, y up, z forward -------

    def shoulder_point(self) -> np.ndarray:
        """``[3]`` the shoulder joint relative to spine3 (left-side coordinates; the right is the mirror)."""
        o = self.subject.offsets
        return o[SMPL24.index("left_collar")] + o[SMPL24.index("left_shoulder")]

    def head_point(self) -> np.ndarray:
        """``[3]`` the head joint relative to spine3 with the neck and head upright."""
        o = self.subject.offsets
        return o[SMPL24.index("neck")] + o[SMPL24.index("head")]

    def arm_lengths(self) -> tuple[float, float]:
        o = self.subject.offsets
        return (float(np.linalg.norm(o[SMPL24.index("left_elbow")])),
                float(np.linalg.norm(o[SMPL24.index("left_wrist")])))

    def scale(self) -> float:
        """Body size relative to the 1.70 m template, for distances in skills."""
        return self.subject.height / 1.70


def finish(take: Take) -> np.ndarray:
    """Secondary motion every take gets, then joint limits: returns the final angles ``[T, J, 3]``.

    * breathing: ~0.25 Hz chest rise (thoracic extension, collar elevation);
    * scapulohumeral rhythm: the collar takes about a quarter of arm elevation above 30 degrees;
    * head stabilisation: neck and head undo part of the trunk's pitch and roll, keeping the gaze level.
    """
    breath = np.sin(2.0 * np.pi * take.uniform(0.2, 0.33) * take.t + take.uniform(0.0, 2.0 * np.pi))
    take["spine3.flex"] -= 0.8 * breath
    for side in SIDES:
        take[f"{side}_collar.elev"] += 0.6 * breath + 0.25 * np.maximum(take[f"{side}_shoulder.elev"] - 30.0, 0.0)
    trunk_pitch = take["pelvis.tilt"] + take["spine1.flex"] + take["spine2.flex"] + take["spine3.flex"]
    trunk_roll = take["spine1.bend"] + take["spine2.bend"] + take["spine3.bend"] - take["pelvis.obliquity"]
    for joint, share in (("neck", 0.2), ("head", 0.15)):
        take[f"{joint}.flex"] -= share * trunk_pitch
        take[f"{joint}.bend"] -= share * trunk_roll
    return anatomy.clip_to_limits(take.angles)
