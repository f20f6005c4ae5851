"""Small smooth ACTOR-shaped test data shared by the ACTOR use-case tests: sinusoidal motions on SMPL24, their
joints from a numpy forward kinematics independent of the library's, and a tiny ACTOR model for them."""

import numpy as np

from jaxmotion.data.motion import Motion, pack
from jaxmotion.geometry.skeletons import SMPL24
from jaxmotion.models.actor import ActorConfig

WINDOW = 24
MODEL = ActorConfig(num_classes=2, width=16, ff=32, layers=1, heads=2)


def fk(rotations, translation):
    """Forward kinematics on SMPL24 in numpy (Rodrigues, then the chain), independent of the library's."""
    v = np.asarray(rotations, np.float64)
    theta = np.linalg.norm(v, axis=-1, keepdims=True)[..., None]
    axis = v / np.maximum(np.linalg.norm(v, axis=-1, keepdims=True), 1e-12)
    k = np.zeros(v.shape + (3,))
    k[..., 0, 1], k[..., 0, 2], k[..., 1, 2] = -axis[..., 2], axis[..., 1], -axis[..., 0]
    k -= np.swapaxes(k, -1, -2)
    local = np.eye(3) + np.sin(theta) * k + (1 - np.cos(theta)) * (k @ k)
    glob, joints = [local[..., 0, :, :]], [np.asarray(translation, np.float64)]
    for j in range(1, 24):
        p = SMPL24.parents[j]
        joints.append(joints[p] + np.einsum("...ij,j->...i", glob[p], SMPL24.offsets[j]))
        glob.append(glob[p] @ local[..., j, :, :])
    return np.stack(joints, axis=-2)


def smooth_dataset(count=6):
    """Smooth sinusoidal motions on SMPL24 (lengths 14..WINDOW, so windows are never cropped)."""
    rng = np.random.default_rng(0)
    records = []
    for i in range(count):
        n, action = 14 + 2 * i, i % 2
        t = np.arange(n, dtype=np.float32)[:, None, None]
        rotations = (0.3 * np.sin(0.15 * (1 + action) * t + rng.uniform(0, 6, (1, 24, 3)))).astype(np.float32)
        translation = np.stack([0.01 * t[:, 0, 0], np.full(n, 0.9), 0.02 * t[:, 0, 0]], -1).astype(np.float32)
        records.append(Motion(fk(rotations, translation), translation, rotations, action=action))
    return pack(records, name="smooth", split="train", class_names=("a", "b"), skeleton=SMPL24, fps=20.0)
