"""An SMPL-format body model of boxes around SMPL-24's bones, written as a file (no real body model can be shipped):
every box rides on its bone's parent joint, and one vertex sits on each joint (the regressor reads it back), so the
body's rest joints are the library's template skeleton and its posed joints are the library's forward kinematics."""

import numpy as np

from jaxmotion.geometry.body import save_body_model
from jaxmotion.geometry.kinematics import forward_kinematics
from jaxmotion.geometry.skeletons import SMPL24

_CORNERS = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], float)  # a unit cube's
_FACES = np.array([[0, 1, 3], [0, 3, 2], [4, 6, 7], [4, 7, 5], [0, 4, 5], [0, 5, 1], [2, 3, 7], [2, 7, 6],
                   [0, 2, 6], [0, 6, 4], [1, 5, 7], [1, 7, 3]])


def box_body(path, half_width: float = 0.04):
    """Write the body to ``path`` (``.npz``) and return it: 24 joint vertices, then 8 per bone."""
    rest = np.asarray(forward_kinematics(np.broadcast_to(np.eye(3, dtype=np.float32), (24, 3, 3)),
                                         np.array([0.0, 0.95, 0.0], np.float32), SMPL24.offsets, SMPL24.parents))
    vertices, weights, faces = [rest], [np.eye(24)], []
    for child, parent in enumerate(SMPL24.parents):
        if parent < 0:
            continue
        middle, half = (rest[child] + rest[parent]) / 2, np.abs(rest[child] - rest[parent]) / 2 + half_width
        faces.append(_FACES + 24 + 8 * len(faces))
        vertices.append(middle + _CORNERS * half)
        weights.append(np.eye(24)[[parent] * 8])
    vertices, count = np.concatenate(vertices), 24 + 8 * len(faces)
    save_body_model(path, {"v_template": vertices.astype(np.float32), "shapedirs": np.zeros((count, 3, 10)),
                           "posedirs": np.zeros((count, 3, 207)), "J_regressor": np.eye(24, count),
                           "weights": np.concatenate(weights), "f": np.concatenate(faces).astype(np.int32),
                           "kintree_table": np.stack([np.asarray(SMPL24.parents), np.arange(24)])})
    return path
