"""An SMPL-format body model of boxes around SMPL-24's bones, written as a file (no real body model can be shipped):
every box rides on its bone's parent joint, and one vertex sits on each joint (the regressor reads it back), so the
body's rest joints are the library's template skeleton and its posed joints are the library's forward kinematics.
Its boxes' faces can be subdivided and the body padded with unused vertices, to time a body of SMPL's size."""

import numpy as np

from jaxmotion.geometry.body import save_body_model
from jaxmotion.geometry.kinematics import forward_kinematics
from jaxmotion.geometry.skeletons import SMPL24


def subdivided_cube(k: int) -> tuple[np.ndarray, np.ndarray]:
    """A cube [-1, 1]^3 whose faces are k x k grids: ``(vertices [V, 3], triangles [F, 3])``, shared corners once,
    every triangle wound counter-clockwise seen from outside; ``k = 1``: its 8 corners and 12 triangles."""
    index: dict[tuple[int, int, int], int] = {}
    triangles = []
    for axis in range(3):
        for side in (0, k):
            u_axis, v_axis = [a for a in range(3) if a != axis]

            def vertex(u, v):
                cell = [0, 0, 0]
                cell[axis], cell[u_axis], cell[v_axis] = side, u, v
                return index.setdefault(tuple(cell), len(index))

            for u in range(k):
                for v in range(k):
                    a, b, c, d = vertex(u, v), vertex(u + 1, v), vertex(u + 1, v + 1), vertex(u, v + 1)
                    # e_u x e_v is +axis except for the y faces (x cross z = -y): wound to face outward
                    outward = (side == k) != (axis == 1)
                    triangles += [(a, b, c), (a, c, d)] if outward else [(a, c, b), (a, d, c)]
    vertices = np.array(sorted(index, key=index.get), float) * 2 / k - 1
    return vertices, np.array(triangles)


def box_body(path, half_width: float = 0.04, *, subdivisions: int = 1, vertices: int | None = None):
    """Write the body to ``path`` (``.npz``) and return it: 24 joint vertices, then a box per bone whose faces are
    ``subdivisions`` x ``subdivisions`` grids, then (``vertices``: the total wanted) unused vertices at the pelvis."""
    cube, cube_faces = subdivided_cube(subdivisions)
    rest = np.asarray(forward_kinematics(np.broadcast_to(np.eye(3, dtype=np.float32), (24, 3, 3)),
                                         np.array([0.0, 0.95, 0.0], np.float32), SMPL24.offsets, SMPL24.parents))
    points, weights, faces = [rest], [np.eye(24)], []
    for child, parent in enumerate(SMPL24.parents):
        if parent < 0:
            continue
        middle, half = (rest[child] + rest[parent]) / 2, np.abs(rest[child] - rest[parent]) / 2 + half_width
        faces.append(cube_faces + sum(len(p) for p in points))
        points.append(middle + cube * half)
        weights.append(np.eye(24)[[parent] * len(cube)])
    count = sum(len(p) for p in points)
    if vertices is not None:
        if vertices < count:
            raise ValueError(f"vertices: the boxes have {count}, got {vertices}")
        points.append(np.broadcast_to(rest[0], (vertices - count, 3)))
        weights.append(np.eye(24)[[0] * (vertices - count)])
        count = vertices
    save_body_model(path, {"v_template": np.concatenate(points).astype(np.float32),
                           "shapedirs": np.zeros((count, 3, 10)), "posedirs": np.zeros((count, 3, 207)),
                           "J_regressor": np.eye(24, count), "weights": np.concatenate(weights),
                           "f": np.concatenate(faces).astype(np.int32),
                           "kintree_table": np.stack([np.asarray(SMPL24.parents), np.arange(24)])})
    return path
