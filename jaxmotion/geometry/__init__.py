"""Geometry: rotation conversions, kinematic trees, forward kinematics and the SMPL-format body layer.

Library frame: metres, +Y up, the subject faces +Z at rest, +X is the subject's left (SMPL's frame).
Rotations act on column vectors; quaternions are (w, x, y, z); 6D is the first two matrix rows (ACTOR);
Euler angles follow BVH (order "ZXY": R = R_z @ R_x @ R_y).
"""

from jaxmotion.geometry.body import (
    BodyModel, body_forward, body_forward_rotmats, load_body_model, rest_joints, root_translation, save_body_model,
    skinning_transforms,
)
from jaxmotion.geometry.ik import two_bone_ik, two_bone_pose
from jaxmotion.geometry.kinematics import (
    apply_transform,
    bone_lengths,
    canonicalize,
    canonicalize_transform,
    forward_kinematics,
    forward_kinematics_transforms,
    heading_transform,
    humanact12_to_library_frame,
    inverse_transform,
    library_to_humanact12_frame,
    root_relative,
    root_trajectory,
    transform_motion,
    transform_root,
)
from jaxmotion.geometry.rotations import (
    EULER_ORDERS,
    REPRESENTATIONS,
    axis_angle_to_matrix,
    axis_angle_to_quaternion,
    euler_to_matrix,
    from_matrix,
    matrix_to_axis_angle,
    matrix_to_euler,
    matrix_to_quaternion,
    matrix_to_rot6d,
    quaternion_to_axis_angle,
    quaternion_to_matrix,
    rot6d_to_matrix,
    slerp,
    to_matrix,
)
from jaxmotion.geometry.skeletons import (
    CMU_MOCAP20,
    GTA22,
    NTU25,
    SMPL24,
    UESTC18,
    VIBE18,
    Skeleton,
    bones,
    topological_order,
)

__all__ = [
    "BodyModel", "body_forward", "body_forward_rotmats", "load_body_model", "rest_joints", "root_translation",
    "save_body_model",
    "skinning_transforms",
    "two_bone_ik", "two_bone_pose",
    "apply_transform", "bone_lengths", "canonicalize", "canonicalize_transform", "forward_kinematics",
    "forward_kinematics_transforms", "heading_transform", "humanact12_to_library_frame", "inverse_transform",
    "library_to_humanact12_frame", "root_relative", "root_trajectory", "transform_motion", "transform_root",
    "EULER_ORDERS", "REPRESENTATIONS", "axis_angle_to_matrix", "axis_angle_to_quaternion", "euler_to_matrix",
    "from_matrix", "matrix_to_axis_angle", "matrix_to_euler", "matrix_to_quaternion", "matrix_to_rot6d",
    "quaternion_to_axis_angle", "quaternion_to_matrix", "rot6d_to_matrix", "slerp", "to_matrix",
    "CMU_MOCAP20", "GTA22", "NTU25", "SMPL24", "UESTC18", "VIBE18", "Skeleton", "bones", "topological_order",
]
