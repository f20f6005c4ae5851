"""synth-ntu1p's 94 classes as a recogniser sees them, for the class tests of the NTU one-person modules: a
small clean sample (every mode at least once) seen as NTU-25 Kinect markers, and readings of those markers."""

import functools

import numpy as np

from jaxmotion.data import synthetic
from jaxmotion.data.formats.ntu120 import SINGLE_ACTIONS
from jaxmotion.data.synthetic import engine
from jaxmotion.data.synthetic.engine import Split, Variant
from jaxmotion.geometry.markers import NTU25_ON_SMPL24, markers_from_rotations
from jaxmotion.geometry.skeletons import NTU25

CLASSES = synthetic.VARIANTS["synth-ntu1p"].classes
PER_CLASS = 4  # clips per class in the sample: every mode at least once (at most 4 modes)
NTU = {name: k for k, name in enumerate(NTU25.joint_names)}


def variant(per_class: int, subjects=tuple(range(40))) -> Variant:
    """synth-ntu1p's classes, rate and clip lengths, clean (no capture noise) and SMPL-24."""
    return Variant(name="synth-ntu1p-test", classes=CLASSES, fps=30.0, lengths=(60, 150),
                   splits={"train": Split(num_sequences=len(CLASSES) * per_class, subjects=subjects)})


@functools.cache
def sample():
    """``(data, ntu)``: the generated SMPL-24 sample and its clean NTU-25 markers ``[F, 25, 3]``."""
    v = variant(PER_CLASS)
    data = engine.generate_split(v, "train", seed=0)
    offsets = np.stack([engine.subject(v, int(s), 0).offsets for s in data.subjects])
    per_frame = np.repeat(offsets, data.lengths, axis=0)
    ntu = markers_from_rotations(NTU25_ON_SMPL24, data.rotations[:, None], data.translation[:, None], per_frame)
    return data, np.asarray(ntu)[:, 0]


def clips(action_id: int):
    """``(mode name, SMPL motion, NTU joints [T, 25, 3])`` of every sampled clip of NTU action ``action_id``."""
    data, ntu = sample()
    c = SINGLE_ACTIONS.index(action_id)
    for i in np.flatnonzero(data.actions == c):
        yield CLASSES[c].modes[data.modes[i]], data[int(i)], ntu[data.starts[i]:data.starts[i + 1]]


def hands(mode: str) -> tuple[str, ...]:
    """The acting hands a mode names: ``both ...``, ``left ...``, else the right."""
    return ("left", "right") if mode.startswith("both") else ("left",) if mode.startswith("left") else ("right",)


def raised(j: np.ndarray, sides, tolerance: float = 0.02) -> np.ndarray:
    """``[T]`` frames where every named wrist is within ``tolerance`` m of its highest point: the hold."""
    keep = np.ones(len(j), bool)
    for side in sides:
        y = j[:, NTU[f"{side}_wrist"], 1]
        keep &= y >= y.max() - tolerance
    return keep


def forward(j: np.ndarray) -> np.ndarray:
    """``[T, 3]`` the horizontal direction the hips face, per frame."""
    across = j[:, NTU["left_hip"]] - j[:, NTU["right_hip"]]
    f = np.cross(across, np.array([0.0, 1.0, 0.0]))
    f[:, 1] = 0.0
    return f / np.linalg.norm(f, axis=-1, keepdims=True)
