"""Motion export: SMPL parameters in AMASS's ``.npz`` layout, joint positions as ``.npy``, and BVH.

Any motion the library makes or loads (a ``MotionDataset``, or a padded batch as the samplers return it)
goes to files with :func:`export_motions`; the single-clip writers and readers are public too.

Axes: N motions, T frames, J joints. Inputs are in the library frame (metres, +Y up, facing +Z at rest,
+X the subject's left); rotations are local axis-angle ``[T, J, 3]`` with joint 0's global, and
``translation [T, 3]`` is the position of joint 0 (the root).

Formats:

* ``.npy``: the joint positions ``[T, J, 3]`` float32, library frame. Any skeleton, rotations not needed.
* ``.npz``, AMASS's layout (:class:`AmassOptions`), only for the 24-joint SMPL tree. By default SMPL+H, as
  AMASS's own files and the tools that read them (AMASS's loaders, aitviewer, HumanML3D's preprocessing):
  ``poses [T, 156]`` float64 axis-angle (SMPL+H's 52 joints x 3: joint 0 = global orientation, the 21 other
  body joints in SMPL's order, then 15 left-hand and 15 right-hand finger joints, written at rest: zeros; SMPL's
  two hand joints 22 and 23, leaves that move no joint, have no place in SMPL+H), ``trans [T, 3]`` float64,
  ``betas [16]`` float64 (zeros unless given), ``dmpls [T, 8]`` (zeros: no soft tissue), ``mocap_framerate``
  (0-d float64) and ``gender`` (0-d string, ``"neutral"`` by default). ``layout="smpl"``: ``poses [T, 72]`` (24
  joints) and ``betas [10]``, no ``dmpls``. AMASS's world is z up, the library's y up: with ``up="z"`` (the
  default) the writer turns the world by ``R_x(+90 deg)`` (library +Y -> +Z, library +Z -> -Y), through the
  global orientation and the translation, and :func:`load_amass_npz` turns it back; ``up="y"`` writes the
  library frame as it is. **trans**: SMPL and SMPL+H put the pelvis at ``J_0(betas) + trans``, where ``J_0`` is
  the body model's rest pelvis for the file's betas (its frame, not turned); with a body model
  (:meth:`AmassOptions.for_body`) the writer subtracts it, so that a reader posing the file with that model puts
  the pelvis on the motion's root. Without one ``J_0`` counts as zero and ``trans`` is the root position. The
  file holds no bone lengths: the body's shape comes from ``betas`` and the model, so its joints are the
  motion's only where the model's rest skeleton for those betas has the motion's bone lengths; joints read back
  by :func:`load_amass_npz` are forward kinematics on the offsets the caller gives (the SMPL-24 template by
  default).
* ``.bvh``: the skeleton's tree with the motion's own rest offsets (:func:`rest_offsets`, from frame 0),
  joints written depth-first (children in joint order), one ``End Site`` per leaf. The root has six
  channels (``Xposition Yposition Zposition`` then three rotations), every other joint three rotations,
  in one stated Euler order (``"ZXY"`` by default; see :func:`jaxmotion.geometry.rotations.euler_to_matrix`
  for the convention, which is BVH's: angles listed in channel order, ``R = R_first R_second R_third``).
  Angles in degrees, lengths in metres (importers with a scale option, such as Blender's, may want 100 for
  centimetre rigs), ``Frame Time`` = 1 / fps. The root's ``OFFSET`` is the root row of the offsets and
  its position channels are ``translation - offset_0``, so that ``OFFSET + channels`` (what BVH readers
  place the root at) is the root position. An End Site has no joint behind it; it repeats its leaf's own
  offset so that viewers draw the leaf bone (head, hands, feet) with a length, and :func:`load_bvh`
  ignores it.

BVH is written and read here rather than with a package: the format is a small text grammar, the library's
runtime dependencies are kept to jax, flax, optax, numpy, orbax-checkpoint, chex and matplotlib, and the
Python BVH packages we know of either only parse (``bvh``) or bring pandas and scikit-learn (``pymo``);
none converts to and from this library's axis-angle conventions, which is most of the work anyway.

Round trips reproduce the joints within a few micrometres (the text keeps 1e-6 m and 1e-6 degrees; the
arithmetic is float32) when ``joints`` are forward kinematics of ``rotations`` with fixed offsets, as for
every generated and embedded motion. Where joints come from
elsewhere (real data whose joints a body model or a camera made) BVH and SMPL parameters still carry the
rotations, posed on the bone vectors of frame 0.
"""

from __future__ import annotations

import argparse
import dataclasses
import functools
import itertools
import math
import re
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import NamedTuple

import jax
import jax.numpy as jnp
import numpy as np

from jaxmotion.data.arrays import bucket, check_finite, checked, padded
from jaxmotion.data.motion import Motion, MotionDataset
from jaxmotion.data.retarget import clean_feet, mixamo_names
from jaxmotion.geometry.body import BodyModel, load_body_model, rest_joints
from jaxmotion.geometry.kinematics import forward_kinematics
from jaxmotion.geometry.rotations import (
    EULER_ORDERS,
    axis_angle_to_matrix,
    euler_to_matrix,
    matrix_to_axis_angle,
    matrix_to_euler,
)
from jaxmotion.geometry.skeletons import SMPL24, Skeleton, topological_order
from jaxmotion.progress import phase

__all__ = [
    "FORMATS", "RIGS", "AmassOptions", "BvhMotion", "ExportOptions", "export_arguments", "export_motions",
    "export_options", "load_amass_npz", "load_bvh", "rest_offsets", "save_amass_npz", "save_bvh", "save_joints_npy",
    "with_clean_feet",
]

#: File formats of :func:`export_motions`, by file extension.
FORMATS = ("bvh", "npz", "npy")

_GENDERS = ("neutral", "male", "female")
# AMASS z up from the library's y up: R_x(+90 deg), acting on column vectors.
_Y_UP_TO_Z_UP = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]])
_UP_TURNS = {"z": _Y_UP_TO_Z_UP, "y": np.eye(3)}
# Widths of AMASS ``poses``: SMPL (24 joints) and SMPL+H (22 body joints, then 30 finger joints that replace
# SMPL's two hand joints).
_SMPL_POSE, _SMPLH_POSE, _BODY_JOINTS = 72, 156, 22
#: Per layout: the width of ``poses`` and of ``betas`` (SMPL's 10; AMASS's SMPL+H files carry 16).
_LAYOUTS = {"smplh": (_SMPLH_POSE, 16), "smpl": (_SMPL_POSE, 10)}
_DMPLS = 8  # AMASS's soft-tissue coefficients per frame (DMPL); written as zeros: no soft tissue
_VALUE_FORMAT = "%.6f"  # metres and degrees: 1e-6 m, and 2e-8 rad, far inside the 1e-4 m round trip
_AXES = "XYZ"


# --- conversions, shared by every clip length ------------------------------------------------------------
#
# Called eagerly, not jitted: under jit the static Euler order would make each order its own compilation,
# while eager operations are compiled once per shape and shared by all orders. Inputs are padded to a few
# sizes (``_rows``, ``_per_frame``) so that shapes repeat across clip lengths and skeletons as well.


def _axis_angle_to_euler(rotations, order: str) -> jax.Array:
    """``[N, 3]`` axis-angle -> ``[N, 3]`` Euler radians in ``order``."""
    return matrix_to_euler(axis_angle_to_matrix(rotations), order)


def _euler_to_axis_angle(angles, order: str) -> jax.Array:
    """``[N, 3]`` Euler radians in ``order`` -> ``[N, 3]`` axis-angle."""
    return matrix_to_axis_angle(euler_to_matrix(angles, order))


def _turn(rotations, turn: np.ndarray) -> jax.Array:
    """``[N, 3]`` axis-angle R, ``[3, 3]`` M -> ``[N, 3]`` axis-angle of ``M R``."""
    turned = jnp.matmul(jnp.asarray(turn, jnp.float32), axis_angle_to_matrix(rotations),
                        precision=jax.lax.Precision.HIGHEST)
    return matrix_to_axis_angle(turned)


def _joints(rotations, translation, offsets: np.ndarray, parents: tuple[int, ...]) -> np.ndarray:
    """``[T, J, 3]`` axis-angle, ``[T, 3]``, ``[J, 3]`` -> ``[T, J, 3]`` joint positions."""
    offsets = jnp.asarray(offsets, jnp.float32)
    return _per_frame(lambda rotmats, root: forward_kinematics(rotmats, root, offsets, parents),
                      [_rows(axis_angle_to_matrix, rotations), translation])


def _rows(kernel, values, *shared) -> np.ndarray:
    """A row-wise ``kernel`` on ``values [..., 3]``, run on the rows padded to a power of two >= 512."""
    values = np.asarray(values)
    rows = values.reshape(-1, 3)
    out = np.asarray(kernel(padded(np.asarray(rows, np.float32), bucket(len(rows), 512)), *shared))[: len(rows)]
    return out.reshape(values.shape[:-1] + out.shape[1:])


def _per_frame(kernel, frames: Sequence[np.ndarray]) -> np.ndarray:
    """``kernel(*frames)`` on the per-frame arrays padded to a power of two >= 16 frames."""
    count = len(frames[0])
    size = bucket(count, 16)
    return np.asarray(kernel(*(padded(np.asarray(a, np.float32), size) for a in frames)))[:count]


# --- checks ----------------------------------------------------------------------------------------------


def _check_order(order: str) -> None:
    if order not in EULER_ORDERS:
        raise ValueError(f"order: expected one of {list(EULER_ORDERS)}, got {order!r}")


def _check_fps(fps) -> float:
    if fps is None or not math.isfinite(float(fps)) or float(fps) <= 0:
        raise ValueError(f"fps: expected a positive frame rate, got {fps!r}")
    return float(fps)


def _check_up(up: str) -> np.ndarray:
    if up not in _UP_TURNS:
        raise ValueError(f"up: expected 'z' (AMASS's world) or 'y' (the library frame), got {up!r}")
    return _UP_TURNS[up]


def _root_rest(root_rest) -> np.ndarray:
    return np.zeros(3) if root_rest is None else checked(root_rest, "root_rest", (3,), "[3]").astype(np.float64)


# --- offsets and joints ------------------------------------------------------------------------------------


def rest_offsets(rotations, joints, parents: tuple[int, ...]) -> np.ndarray:
    """The rest offsets a motion was posed with, from its first frame: ``[J, 3]`` float32.

    ``offset_j = G_parent(j)(0)^T (p_j(0) - p_parent(j)(0))``, with ``G`` the global rotations composed from
    the local ones; the root row is zero (forward kinematics ignores it). When ``joints`` are forward
    kinematics of ``rotations`` with some offsets (per-subject bone lengths included, as in the embedded data),
    these are those offsets; otherwise they are frame 0's bone vectors, unposed.

    Args:
      rotations: ``[T, J, 3]`` or ``[J, 3]`` local axis-angle (joint 0 global); only frame 0 is read.
      joints: ``[T, J, 3]`` or ``[J, 3]`` positions; only frame 0 is read.
      parents: the static parent tuple (``-1`` for joint 0).
    """
    num_joints = len(parents)
    rotations, joints = np.asarray(rotations), np.asarray(joints)
    if rotations.ndim == 3:
        rotations = checked(rotations, "rotations", (None, num_joints, 3), f"[T, {num_joints}, 3]")[0]
    rotations = checked(rotations, "rotations", (num_joints, 3), f"[J, 3] or [T, J, 3] with J = {num_joints}")
    if joints.ndim == 3:
        joints = checked(joints, "joints", (None, num_joints, 3), f"[T, {num_joints}, 3]")[0]
    joints = checked(joints, "joints", (num_joints, 3), f"[J, 3] or [T, J, 3] with J = {num_joints}")
    local = _rows(axis_angle_to_matrix, rotations).astype(np.float64)
    points = joints.astype(np.float64)
    # Composed in numpy: one frame does not pay for compiling forward kinematics.
    global_rotations, offsets = np.empty_like(local), np.zeros((num_joints, 3))
    for joint in topological_order(parents):
        parent = parents[joint]
        if parent < 0:
            global_rotations[joint] = local[joint]
        else:
            global_rotations[joint] = global_rotations[parent] @ local[joint]
            offsets[joint] = global_rotations[parent].T @ (points[joint] - points[parent])
    return offsets.astype(np.float32)


# --- npy ---------------------------------------------------------------------------------------------------


def save_joints_npy(path: str | Path, joints) -> Path:
    """Write joint positions ``[T, J, 3]`` (library frame, metres) as float32 ``.npy`` at ``path``."""
    joints = checked(joints, "joints", (None, None, 3), "[T, J, 3]").astype(np.float32)
    path = Path(path)
    with path.open("wb") as file:  # a file object: np.save would append ".npy" to a path lacking it
        np.save(file, joints)
    return path


# --- AMASS npz ---------------------------------------------------------------------------------------------


@dataclasses.dataclass(frozen=True)
class AmassOptions:
    """What an AMASS ``.npz`` says beyond the motion's rotations and root path (see the module docstring).

    Attributes:
      layout: ``"smplh"`` (AMASS's own files: ``poses [T, 156]``, hands at rest, ``dmpls``) or ``"smpl"``
        (``poses [T, 72]``).
      betas: shape coefficients; written padded with zeros to the layout's width (16 for SMPL+H as in AMASS, 10 for
        SMPL), never cut.
      gender: ``"neutral"``, ``"male"`` or ``"female"`` (which body model a reader loads).
      up: ``"z"``: AMASS's z-up world (``R_x(+90 deg)`` applied); ``"y"``: the library frame.
      root_rest: the body model's rest pelvis ``J_0(betas)`` (its frame, metres): ``trans`` is the root position
        minus it, SMPL's convention. ``None``: zeros, ``trans`` is the root position; :meth:`for_body` fills it from a
        body model.
    """

    layout: str = "smplh"
    betas: tuple[float, ...] = ()
    gender: str = "neutral"
    up: str = "z"
    root_rest: tuple[float, float, float] | None = None

    def __post_init__(self):
        if self.layout not in _LAYOUTS:
            raise ValueError(f"layout: expected one of {list(_LAYOUTS)}, got {self.layout!r}")
        if len(self.betas):
            object.__setattr__(self, "betas", tuple(float(b) for b in checked(self.betas, "betas", (None,), "[S]")))
        if self.gender not in _GENDERS:
            raise ValueError(f"gender: expected one of {list(_GENDERS)}, got {self.gender!r}")
        _check_up(self.up)
        if self.root_rest is not None:
            object.__setattr__(self, "root_rest", tuple(float(v) for v in _root_rest(self.root_rest)))

    @classmethod
    def for_body(cls, body: BodyModel, betas=(), **options) -> AmassOptions:
        """Options whose ``trans`` follows ``body``'s convention for ``betas``: ``root_rest`` is its rest pelvis
        ``J_0(betas)`` (:func:`~jaxmotion.geometry.body.rest_joints`), so that a reader posing the file with that
        model for these betas puts the pelvis on the motion's root."""
        betas = tuple(float(b) for b in np.ravel(betas))
        if len(betas) > body.num_betas:
            raise ValueError(f"betas: the body model has {body.num_betas} shape coefficients, got {len(betas)}")
        pelvis = np.asarray(rest_joints(body, np.asarray(betas, np.float32))[0], np.float64)
        return cls(betas=betas, root_rest=tuple(pelvis), **options)


#: The BVH joint names of :class:`ExportOptions`'s ``rig``: the skeleton's own, or Mixamo's bone names (SMPL-24).
RIGS = ("smpl", "mixamo")


@dataclasses.dataclass(frozen=True)
class ExportOptions:
    """How :func:`export_motions` writes, beyond the formats.

    Attributes:
      amass: what npz files say about the body (:class:`AmassOptions`).
      rig: the BVH's joint names: ``"smpl"``, the skeleton's own; ``"mixamo"``, Mixamo's bone names with the
        ``mixamorig:`` prefix (:func:`~jaxmotion.data.retarget.mixamo_names`; SMPL-24 only), for retargeting.
      clean_feet: hold each foot still while it bears weight (:func:`~jaxmotion.data.retarget.clean_feet`) before
        anything is written, so every format (the npy's joints too) carries the cleaned motion.
      order: the BVH Euler order (:func:`save_bvh`).
    """

    amass: AmassOptions = AmassOptions()
    rig: str = "smpl"
    clean_feet: bool = False
    order: str = "ZXY"

    def __post_init__(self):
        if self.rig not in RIGS:
            raise ValueError(f"rig: expected one of {list(RIGS)}, got {self.rig!r}")
        _check_order(self.order)


def export_arguments(parser: argparse.ArgumentParser) -> None:
    """Add the flags of :class:`ExportOptions` to a command line (the compose command, every experiment's
    ``--export``); :func:`export_options` reads them back."""
    group = parser.add_argument_group("exported files")
    group.add_argument("--npz-layout", choices=list(_LAYOUTS), default="smplh",
                       help="npz: smplh, poses [T, 156] as AMASS's own files (default); smpl, poses [T, 72]")
    group.add_argument("--betas", default="", metavar="B1,B2,...",
                       help="npz: the body's shape coefficients (default zeros)")
    group.add_argument("--gender", choices=_GENDERS, default="neutral", help="npz: the body model a reader loads")
    group.add_argument("--body-model", metavar="FILE",
                       help="npz: an SMPL(+H)-format body model (.npz or .pkl): trans follows its rest pelvis for the "
                            "betas, so that the model posed by the file stands on the motion's root (without one, "
                            "trans is the root position)")
    group.add_argument("--rig", choices=RIGS, default="smpl",
                       help="bvh: joint names, SMPL's (default) or Mixamo's (mixamorig:Hips, ...) for retargeting")
    group.add_argument("--clean-feet", action="store_true",
                       help="hold each foot still while it bears weight (two-bone IK on the legs) before writing")


def export_options(args: argparse.Namespace, formats: Sequence[str]) -> ExportOptions:
    """The :class:`ExportOptions` the flags of :func:`export_arguments` ask for (the body model loaded), checked
    against the ``formats`` written: a flag for a format not written is refused."""
    try:
        betas = tuple(float(b) for b in args.betas.split(",") if b.strip())
    except ValueError:
        raise ValueError(f"--betas: expected comma-separated numbers, got {args.betas!r}") from None
    npz = {"layout": args.npz_layout, "gender": args.gender}
    amass = (AmassOptions.for_body(load_body_model(args.body_model), betas, **npz) if args.body_model
             else AmassOptions(betas=betas, **npz))
    if amass != AmassOptions() and "npz" not in formats:
        raise ValueError(f"--npz-layout, --betas, --gender, --body-model: they say what npz files hold; the formats "
                         f"written are {', '.join(formats) or 'none'}")
    if args.rig != "smpl" and "bvh" not in formats:
        raise ValueError(f"--rig: it names a BVH's joints; the formats written are {', '.join(formats) or 'none'}")
    if args.clean_feet and not formats:
        raise ValueError("--clean-feet: no motion files are written")
    return ExportOptions(amass=amass, rig=args.rig, clean_feet=args.clean_feet)


def save_amass_npz(path: str | Path, rotations, translation, fps: float,
                   options: AmassOptions = AmassOptions()) -> Path:
    """Write SMPL+H (default) or SMPL parameters in AMASS's ``.npz`` layout (see the module docstring).

    Args:
      rotations: ``[T, 24, 3]`` local axis-angle on the SMPL-24 tree, joint 0 global (library frame).
      translation: ``[T, 3]`` root (joint 0) positions, library frame.
      fps: frames per second (``mocap_framerate``).
      options: layout, betas, gender, up axis and the body model's rest pelvis (:class:`AmassOptions`).
    """
    rotations = checked(rotations, "rotations", (None, 24, 3), "[T, 24, 3]")
    frames = rotations.shape[0]
    translation = checked(translation, "translation", (frames, 3), f"[T, 3] = ({frames}, 3)")
    fps, turn = _check_fps(fps), _check_up(options.up)
    width, betas_width = _LAYOUTS[options.layout]
    body = 24 if options.layout == "smpl" else _BODY_JOINTS
    poses = np.zeros((frames, width // 3, 3))
    poses[:, :body] = rotations[:, :body]
    poses[:, 0] = _rows(_turn, rotations[:, 0], turn)
    trans = translation.astype(np.float64) @ turn.T - _root_rest(options.root_rest)
    betas = np.zeros(max(betas_width, len(options.betas)))
    betas[: len(options.betas)] = options.betas
    extra = {"dmpls": np.zeros((frames, _DMPLS))} if options.layout == "smplh" else {}
    path = Path(path)
    with path.open("wb") as file:  # a file object: np.savez would append ".npz" to a path lacking it
        np.savez(file, poses=poses.reshape(frames, width), trans=trans, betas=betas,
                 mocap_framerate=np.float64(fps), gender=np.array(options.gender), **extra)
    return path


def load_amass_npz(path: str | Path, *, up: str = "z", offsets=None, root_rest=None,
                   body: BodyModel | None = None) -> tuple[Motion, float]:
    """Read an AMASS-layout ``.npz`` (this module's, or AMASS's own SMPL+H files) into the library frame.

    ``poses`` may be ``[T, 72]`` (SMPL) or ``[T, 156]`` (SMPL+H: the 22 body joints are kept and SMPL's two
    hand joints get no rotation). ``up`` and ``root_rest`` mean what they mean for :class:`AmassOptions` and undo
    it; or ``body``: the body model whose rest pelvis for the file's ``betas`` is ``root_rest``. Joints are forward
    kinematics on ``offsets`` (``[24, 3]``, default the SMPL-24 template), not a body model's joints for the
    file's betas.

    Returns:
      ``(motion, fps)``: a ``Motion`` with rotations ``[T, 24, 3]``, translation and joints (action -1: the
      file has no label; name: the file's stem), and the file's ``mocap_framerate``.
    """
    path = Path(path)
    turn = _check_up(up)
    if body is not None and root_rest is not None:
        raise ValueError("root_rest, body: give one of them (body: its rest pelvis for the file's betas)")
    offsets = SMPL24.offsets if offsets is None else checked(offsets, "offsets", (24, 3), "[24, 3]")
    with np.load(path, allow_pickle=False) as data:
        missing = [key for key in ("poses", "trans", "mocap_framerate") if key not in data.files]
        if missing:
            raise ValueError(f"{path}: missing {missing}; an AMASS file has poses, trans, betas, mocap_framerate, "
                             f"gender (found {sorted(data.files)})")
        poses, trans, fps = data["poses"], data["trans"], float(data["mocap_framerate"])
        betas = np.ravel(data["betas"]) if "betas" in data.files else np.zeros(0)
    if body is not None:
        if np.any(betas[body.num_betas:] != 0):
            raise ValueError(f"{path}: betas: {len(betas)} shape coefficients, non-zero past the body model's "
                             f"{body.num_betas}")
        root_rest = rest_joints(body, np.asarray(betas[: body.num_betas], np.float32))[0]
    width = poses.shape[-1] if poses.ndim == 2 else None
    if width not in (_SMPL_POSE, _SMPLH_POSE) or len(poses) < 1:
        raise ValueError(f"{path}: poses: expected [T, {_SMPL_POSE}] (SMPL) or [T, {_SMPLH_POSE}] (SMPL+H), "
                         f"got {poses.shape}")
    check_finite(poses, f"{path}: poses")
    frames = len(poses)
    trans = checked(trans, f"{path}: trans", (frames, 3), f"[T, 3] = ({frames}, 3)")
    rotations = np.zeros((frames, 24, 3), np.float32)
    body = 24 if width == _SMPL_POSE else _BODY_JOINTS
    rotations[:, :body] = poses[:, : body * 3].reshape(frames, body, 3)
    rotations[:, 0] = _rows(_turn, rotations[:, 0], turn.T)
    # p = turn^T (trans + J_0), written for row vectors
    translation = ((trans.astype(np.float64) + _root_rest(root_rest)) @ turn).astype(np.float32)
    joints = _joints(rotations, translation, offsets, SMPL24.parents)
    motion = Motion(joints=joints, translation=translation, rotations=rotations, action=-1, name=path.stem)
    return motion, fps


# --- BVH ---------------------------------------------------------------------------------------------------


class BvhMotion(NamedTuple):
    """A BVH file read by :func:`load_bvh`; joints in the file's (depth-first) order, End Sites dropped.

    Attributes:
      names: ``J`` joint names.
      parents: ``J`` parent indices, ``-1`` for the root (joint 0).
      offsets: ``[J, 3]`` float32 ``OFFSET`` of each joint (the root's row is the root's ``OFFSET``).
      rotations: ``[T, J, 3]`` float32 local axis-angle, joint 0 global; zero for joints without rotation
        channels.
      translation: ``[T, 3]`` float32 root position, its ``OFFSET`` plus its position channels.
      fps: ``1 / Frame Time``.
      orders: per joint, the Euler order of its rotation channels (e.g. ``"ZXY"``), ``""`` where it has none.
    """

    names: tuple[str, ...]
    parents: tuple[int, ...]
    offsets: np.ndarray
    rotations: np.ndarray
    translation: np.ndarray
    fps: float
    orders: tuple[str, ...]


def _depth_first(parents: tuple[int, ...]) -> list[int]:
    """Joint indices in BVH's nesting order: each joint followed by its subtrees, children in joint order."""
    children = [[c for c, p in enumerate(parents) if p == joint] for joint in range(len(parents))]
    order, stack = [], [0]
    while stack:
        joint = stack.pop()
        order.append(joint)
        stack.extend(reversed(children[joint]))
    return order


def _check_names(names: Sequence[str], num_joints: int) -> tuple[str, ...]:
    names = tuple(names)
    if len(names) != num_joints:
        raise ValueError(f"names: expected {num_joints} joint names, got {len(names)}")
    for name in names:
        if not isinstance(name, str) or not name or re.search(r"[\s{}]", name):
            raise ValueError(f"names: BVH joint names must be non-empty, without spaces or braces; got {name!r}")
    if len(set(names)) != num_joints:
        raise ValueError(f"names: expected unique names, got {names}")
    return names


def _numbers(values) -> str:
    return " ".join(_VALUE_FORMAT % v for v in values)


def save_bvh(path: str | Path, rotations, translation, offsets, parents: tuple[int, ...], names: Sequence[str],
             fps: float, order: str = "ZXY") -> Path:
    """Write one motion as BVH (see the module docstring for the layout).

    Args:
      rotations: ``[T, J, 3]`` local axis-angle, joint 0 global.
      translation: ``[T, 3]`` root (joint 0) positions.
      offsets: ``[J, 3]`` rest offsets (e.g. :func:`rest_offsets` of the motion); the root row becomes the
        root's ``OFFSET``.
      parents: ``J`` parent indices, ``-1`` for joint 0.
      names: ``J`` joint names (no spaces).
      fps: frames per second; ``Frame Time`` is its inverse.
      order: Euler order of every joint's rotation channels, one of ``EULER_ORDERS``.
    """
    parents = tuple(int(p) for p in parents)
    topological_order(parents)
    num_joints = len(parents)
    rotations = checked(rotations, "rotations", (None, num_joints, 3), f"[T, {num_joints}, 3]")
    frames = rotations.shape[0]
    translation = checked(translation, "translation", (frames, 3), f"[T, 3] = ({frames}, 3)")
    offsets = checked(offsets, "offsets", (num_joints, 3), f"[{num_joints}, 3]").astype(np.float64)
    names, fps = _check_names(names, num_joints), _check_fps(fps)
    _check_order(order)

    rotation_channels = " ".join(f"{axis}rotation" for axis in order)
    children = [[c for c, p in enumerate(parents) if p == joint] for joint in range(num_joints)]
    lines = ["HIERARCHY"]

    def write(joint: int, depth: int) -> None:
        pad = "\t" * depth
        if joint == 0:
            lines.append(f"ROOT {names[0]}")
            channels = f"CHANNELS 6 Xposition Yposition Zposition {rotation_channels}"
        else:
            lines.append(f"{pad}JOINT {names[joint]}")
            channels = f"CHANNELS 3 {rotation_channels}"
        lines.extend([f"{pad}{{", f"{pad}\tOFFSET {_numbers(offsets[joint])}", f"{pad}\t{channels}"])
        for child in children[joint]:
            write(child, depth + 1)
        if not children[joint]:
            lines.extend([f"{pad}\tEnd Site", f"{pad}\t{{", f"{pad}\t\tOFFSET {_numbers(offsets[joint])}",
                          f"{pad}\t}}"])
        lines.append(f"{pad}}}")

    write(0, 0)
    lines += ["MOTION", f"Frames: {frames}", f"Frame Time: {1.0 / fps!r}"]
    degrees = np.degrees(_rows(functools.partial(_axis_angle_to_euler, order=order), rotations))
    values = np.concatenate(
        [translation - offsets[0], degrees[:, _depth_first(parents)].reshape(frames, 3 * num_joints)], axis=1)
    path = Path(path)
    with path.open("w", encoding="utf-8") as file:
        file.write("\n".join(lines) + "\n")
        np.savetxt(file, values, fmt=_VALUE_FORMAT)
    return path


class _Tokens:
    """Whitespace-separated tokens of a BVH text with their line numbers, read front to back."""

    def __init__(self, text: str, path: Path):
        self.path = path
        self.items = [(token, number) for number, line in enumerate(text.splitlines(), start=1)
                      for token in line.split()]
        self.index = 0

    def error(self, message: str, line: int | None = None) -> ValueError:
        if line is None:
            line = self.items[min(self.index, len(self.items) - 1)][1] if self.items else 1
        return ValueError(f"{self.path}, line {line}: {message}")

    def next(self, what: str) -> tuple[str, int]:
        if self.index >= len(self.items):
            raise ValueError(f"{self.path}: unexpected end of file, expected {what}")
        self.index += 1
        return self.items[self.index - 1]

    def expect(self, keyword: str) -> int:
        token, line = self.next(repr(keyword))
        if token != keyword:
            raise self.error(f"expected {keyword!r}, got {token!r}", line)
        return line

    def number(self, what: str, kind=float):
        token, line = self.next(what)
        try:
            return kind(token)
        except ValueError:
            raise self.error(f"expected {what}, got {token!r}", line) from None


_CHANNELS = {f"{axis}{kind}" for axis in _AXES for kind in ("position", "rotation")}


def _read_joint(tokens: _Tokens, parent: int, joints: list[dict]) -> None:
    """Parse ``<name> { OFFSET ... CHANNELS ... (JOINT ... | End Site {...})* }`` into ``joints``."""
    name, _ = tokens.next("a joint name")
    index = len(joints)
    joint = {"name": name, "parent": parent, "offset": None, "channels": [], "line": tokens.expect("{")}
    joints.append(joint)
    while True:
        token, line = tokens.next("'}' closing joint " + name)
        if token == "OFFSET":
            joint["offset"] = [tokens.number("an OFFSET value") for _ in range(3)]
        elif token == "CHANNELS":
            count = tokens.number("the channel count", int)
            joint["channels"] = [tokens.next("a channel name")[0] for _ in range(count)]
            bad = [c for c in joint["channels"] if c not in _CHANNELS]
            if bad:
                raise tokens.error(f"unknown channel {bad[0]!r} of joint {name}; expected one of "
                                   f"{sorted(_CHANNELS)}", line)
            positions = [c for c in joint["channels"] if c.endswith("position")]
            rotations = [c for c in joint["channels"] if c.endswith("rotation")]
            if len(rotations) not in (0, 3) or len(set(rotations)) != len(rotations):
                raise tokens.error(f"joint {name}: expected no rotation channels or one per axis, got {rotations}",
                                   line)
            if positions and (parent >= 0 or len(positions) != 3 or len(set(positions)) != 3):
                raise tokens.error(f"joint {name}: position channels are read on the root only, one per axis; "
                                   f"got {positions}", line)
        elif token == "JOINT":
            _read_joint(tokens, index, joints)
        elif token == "End":
            tokens.expect("Site")
            tokens.expect("{")
            tokens.expect("OFFSET")
            for _ in range(3):
                tokens.number("an End Site OFFSET value")
            tokens.expect("}")
        elif token == "}":
            break
        else:
            raise tokens.error(f"expected OFFSET, CHANNELS, JOINT, End Site or '}}' in joint {name}, got {token!r}",
                               line)
    if joint["offset"] is None:
        raise tokens.error(f"joint {name} has no OFFSET", joint["line"])


def _motion_rows(tokens: _Tokens, frames: int, width: int) -> np.ndarray:
    """The ``frames`` data lines after the MOTION header, ``width`` numbers each -> ``[frames, width]``."""
    rows = []
    for line, group in itertools.groupby(tokens.items[tokens.index:], key=lambda item: item[1]):
        values = [token for token, _ in group]
        if len(values) != width:
            raise tokens.error(f"expected {width} channel values per frame, got {len(values)}", line)
        try:
            numbers = [float(v) for v in values]
        except ValueError:
            raise tokens.error(f"expected numbers, got {values}", line) from None
        if not all(math.isfinite(v) for v in numbers):
            raise tokens.error(f"expected finite numbers, got {[v for v in values if not math.isfinite(float(v))]}",
                               line)
        rows.append(numbers)
    if len(rows) != frames:
        raise ValueError(f"{tokens.path}: 'Frames: {frames}' but {len(rows)} frame lines follow")
    return np.asarray(rows, np.float64).reshape(frames, width)


def load_bvh(path: str | Path) -> BvhMotion:
    """Read a single-root BVH file (any Euler order per joint; position channels on the root only).

    Malformed input raises ``ValueError`` naming the file and the line. Rotations are converted from each
    joint's own channel order with BVH's convention (:func:`jaxmotion.geometry.rotations.euler_to_matrix`).
    """
    path = Path(path)
    tokens = _Tokens(path.read_text(encoding="utf-8"), path)
    tokens.expect("HIERARCHY")
    tokens.expect("ROOT")
    joints: list[dict] = []
    _read_joint(tokens, -1, joints)
    token, line = tokens.next("'MOTION'")
    if token == "ROOT":
        raise tokens.error("a second ROOT: only single-root files are supported", line)
    if token != "MOTION":
        raise tokens.error(f"expected 'MOTION', got {token!r}", line)
    tokens.expect("Frames:")
    frames = tokens.number("the frame count", int)
    tokens.expect("Frame")
    tokens.expect("Time:")
    frame_time = tokens.number("the frame time")
    if frames < 1 or not frame_time > 0:
        raise tokens.error(f"expected at least one frame and a positive frame time, got {frames} and {frame_time}")
    data = _motion_rows(tokens, frames, sum(len(j["channels"]) for j in joints))

    num_joints = len(joints)
    offsets = np.array([j["offset"] for j in joints], np.float64)
    translation = np.broadcast_to(offsets[0], (frames, 3)).copy()
    angles = np.zeros((frames, num_joints, 3))
    orders = []
    column = 0
    for index, joint in enumerate(joints):
        order = ""
        for channel in joint["channels"]:
            axis = _AXES.index(channel[0])
            if channel.endswith("position"):
                translation[:, axis] += data[:, column]
            else:
                angles[:, index, len(order)] = np.radians(data[:, column])
                order += channel[0]
            column += 1
        orders.append(order)
    rotations = np.zeros((frames, num_joints, 3), np.float32)
    for order in sorted(set(orders) - {""}):
        chosen = [i for i, o in enumerate(orders) if o == order]
        rotations[:, chosen] = _rows(functools.partial(_euler_to_axis_angle, order=order), angles[:, chosen])
    return BvhMotion(
        names=tuple(j["name"] for j in joints), parents=tuple(j["parent"] for j in joints),
        offsets=offsets.astype(np.float32), rotations=rotations, translation=translation.astype(np.float32),
        fps=1.0 / frame_time, orders=tuple(orders),
    )


# --- many motions ------------------------------------------------------------------------------------------


class _Clip(NamedTuple):
    joints: np.ndarray  # [T, J, 3]
    rotations: np.ndarray | None  # [T, J, 3]
    translation: np.ndarray | None  # [T, 3]


def _batch_lengths(motions: Mapping, count: int, frames: int) -> np.ndarray:
    """``[N]`` frames to keep per motion, from ``lengths`` or a prefix ``mask``; all frames if neither."""
    lengths = mask_lengths = None
    if motions.get("lengths") is not None:
        lengths = np.asarray(motions["lengths"])
        if lengths.shape != (count,) or not np.issubdtype(lengths.dtype, np.integer) or (
                lengths.min() < 1 or lengths.max() > frames):
            raise ValueError(f"lengths: expected [N] = ({count},) integers in [1, T = {frames}], got "
                             f"{lengths.dtype} {lengths.shape}" + (f" in [{lengths.min()}, {lengths.max()}]"
                                                                   if lengths.size else ""))
    if motions.get("mask") is not None:
        mask = np.asarray(motions["mask"])
        if mask.shape != (count, frames):
            raise ValueError(f"mask: expected [N, T] = ({count}, {frames}), got {mask.shape}")
        mask = mask.astype(bool)
        mask_lengths = mask.sum(axis=1)
        prefix = np.arange(frames)[None, :] < mask_lengths[:, None]
        bad = np.flatnonzero(np.any(mask != prefix, axis=1) | (mask_lengths < 1))
        if bad.size:
            raise ValueError(f"mask: expected each row to be a non-empty run of valid frames from frame 0; "
                             f"motion {bad[0]} is not")
        if lengths is not None and np.any(lengths != mask_lengths):
            raise ValueError("lengths and mask disagree: "
                             f"motion {np.flatnonzero(lengths != mask_lengths)[0]}")
    if lengths is not None:
        return lengths.astype(np.int64)
    return mask_lengths if mask_lengths is not None else np.full(count, frames, np.int64)


def _batch_clips(motions: Mapping, num_joints: int) -> list[_Clip]:
    """A padded batch (``joints [N, T, J, 3]``, optional ``rotations``, ``translation``, ``lengths`` or
    ``mask``) -> one clip per motion, cut to its length."""
    if "joints" not in motions:
        raise ValueError(f"motions: expected a batch with 'joints' [N, T, {num_joints}, 3] (and optionally "
                         f"rotations, translation, lengths or mask), got keys {sorted(motions)}")
    joints = checked(motions["joints"], "joints", (None, None, num_joints, 3), f"[N, T, {num_joints}, 3]")
    count, frames = joints.shape[:2]
    rotations = translation = None
    if motions.get("rotations") is not None:
        rotations = checked(motions["rotations"], "rotations", (count, frames, num_joints, 3),
                           f"[N, T, {num_joints}, 3] = ({count}, {frames}, {num_joints}, 3)")
    if motions.get("translation") is not None:
        translation = checked(motions["translation"], "translation", (count, frames, 3),
                             f"[N, T, 3] = ({count}, {frames}, 3)")
    lengths = _batch_lengths(motions, count, frames)
    return [_Clip(joints[n, :t], None if rotations is None else rotations[n, :t],
                  None if translation is None else translation[n, :t]) for n, t in enumerate(lengths)]


def with_clean_feet(rotations, translation, joints, parents: tuple[int, ...], fps: float
                    ) -> tuple[np.ndarray, np.ndarray]:
    """One motion (``rotations [T, J, 3]``, ``translation [T, 3]``, ``joints [T, J, 3]``) with its feet held while
    they bear weight (:func:`~jaxmotion.data.retarget.clean_feet`): ``(rotations, joints)``, the joints posed again
    from the new rotations on the motion's own offsets (:func:`rest_offsets`); the translation does not change."""
    offsets = rest_offsets(rotations, joints, parents)
    cleaned = clean_feet(rotations, translation, offsets, parents, fps=fps).rotations
    return cleaned, _joints(cleaned, translation, offsets, parents)


_UNSAFE = re.compile(r"[^A-Za-z0-9._#+-]")


def _file_names(names, defaults: Sequence[str]) -> list[str]:
    """The file stem of each motion: the caller's names as they are, or the defaults made file-safe."""
    if names is None:
        names = [_UNSAFE.sub("_", name) or f"{i:04d}" for i, name in enumerate(defaults)]
    names = list(names)
    if len(names) != len(defaults):
        raise ValueError(f"names: expected one name per motion ({len(defaults)}), got {len(names)}")
    for name in names:
        if not isinstance(name, str) or not name or name in (".", "..") or re.search(r"[/\\\0]", name):
            raise ValueError(f"names: expected plain file names (no path separators), got {name!r}")
    if len(set(names)) != len(names):
        duplicate = next(n for n in names if names.count(n) > 1)
        raise ValueError(f"names: expected unique names, {duplicate!r} appears twice")
    return names


def export_motions(folder: str | Path, motions: MotionDataset | Mapping, skeleton: Skeleton | None = None,
                   fps: float | None = None, formats: Sequence[str] = FORMATS, names: Sequence[str] | None = None,
                   *, options: ExportOptions = ExportOptions()) -> list[Path]:
    """Write every motion in every format: ``folder/<name>.<format>``, exactly each motion's own frames.

    Args:
      folder: created if missing.
      motions: a ``MotionDataset``, or a padded batch as the samplers return it: ``joints [N, T, J, 3]``,
        optional ``rotations [N, T, J, 3]`` axis-angle and ``translation [N, T, 3]``, optional
        ``lengths [N]`` or prefix ``mask [N, T]`` (without either, all T frames).
      skeleton: the joint layout; default the dataset's (required for a batch).
      fps: frames per second; default the dataset's (required for a batch written as bvh or npz).
      formats: a subset of ``FORMATS``. ``npy``: joint positions, any motion. ``bvh``: needs rotations and
        translation; offsets from :func:`rest_offsets` per motion. ``npz``: the same, on the SMPL-24 tree only.
      names: one file stem per motion; default the dataset's clip names (characters other than letters,
        digits and ``._#+-`` replaced by ``_``), or ``0000``, ``0001``, ... for a batch.
      options: the npz files' body, the BVH's joint names and Euler order, the foot clean-up
        (:class:`ExportOptions`).

    Returns:
      The paths written, motion by motion, in the order of ``formats``. Everything is checked before the
      first file is written.
    """
    formats = tuple(formats)
    if not formats or len(set(formats)) != len(formats) or not set(formats) <= set(FORMATS):
        raise ValueError(f"formats: expected a non-empty subset of {list(FORMATS)}, got {list(formats)}")
    if isinstance(motions, MotionDataset):
        skeleton = motions.skeleton if skeleton is None else skeleton
        if skeleton.num_joints != motions.skeleton.num_joints:
            raise ValueError(f"skeleton: {skeleton.name} has {skeleton.num_joints} joints, the dataset's "
                             f"{motions.skeleton.name} {motions.skeleton.num_joints}")
        fps = motions.fps if fps is None else fps
        clips = [_Clip(m.joints, m.rotations, m.translation) for m in motions]
        defaults = motions.names
    elif isinstance(motions, Mapping):
        if skeleton is None:
            raise ValueError("skeleton: required for a batch of motions (e.g. SMPL24)")
        clips = _batch_clips(motions, skeleton.num_joints)
        defaults = [f"{n:04d}" for n in range(len(clips))]
    else:
        raise TypeError(f"motions: expected a MotionDataset or a batch mapping, got {type(motions).__name__}")
    stems = _file_names(names, defaults)
    rotation_formats = [f for f in formats if f in ("bvh", "npz")] + ["clean_feet"] * options.clean_feet
    if rotation_formats:
        fps = _check_fps(fps)
        for field in ("rotations", "translation"):
            if clips and getattr(clips[0], field) is None:
                what = "" if options.clean_feet else "; only 'npy' (joint positions) can be written"
                raise ValueError(f"{rotation_formats[0]}: needs {field} ([N, T, J, 3] axis-angle rotations and "
                                 f"[N, T, 3] root translation); these motions have none{what}")
    if "npz" in formats and skeleton.parents != SMPL24.parents:
        raise ValueError(f"npz: SMPL parameters need the 24-joint SMPL tree; {skeleton.name} has "
                         f"{skeleton.num_joints} joints")
    smpl = skeleton.parents == SMPL24.parents
    if options.clean_feet and not smpl:
        raise ValueError(f"clean_feet: the legs it holds are SMPL-24's; {skeleton.name} has {skeleton.num_joints} "
                         f"joints")
    if "bvh" in formats and options.rig == "mixamo" and not smpl:
        raise ValueError(f"rig: Mixamo's names are for the SMPL-24 tree; {skeleton.name} has {skeleton.num_joints} "
                         f"joints")
    joint_names = mixamo_names() if options.rig == "mixamo" else skeleton.joint_names
    if "bvh" in formats:
        _check_names(joint_names, skeleton.num_joints)
    for stem, clip in zip(stems, clips):  # every motion before the first file: a bad one must not leave half an export
        check_finite(np.asarray(clip.joints), f"motion {stem!r}: joints")
        if rotation_formats:
            check_finite(np.asarray(clip.rotations), f"motion {stem!r}: rotations")
            check_finite(np.asarray(clip.translation), f"motion {stem!r}: translation")

    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    written = []
    with phase(f"[export] {folder.name}", len(clips), unit="motion") as bar:
        for stem, clip in zip(stems, clips):
            if options.clean_feet:
                rotations, joints = with_clean_feet(clip.rotations, clip.translation, clip.joints, skeleton.parents,
                                                    fps)
                clip = _Clip(joints, rotations, clip.translation)
            for fmt in formats:
                path = folder / f"{stem}.{fmt}"
                if fmt == "npy":
                    written.append(save_joints_npy(path, clip.joints))
                elif fmt == "npz":
                    written.append(save_amass_npz(path, clip.rotations, clip.translation, fps, options.amass))
                else:
                    offsets = rest_offsets(clip.rotations, clip.joints, skeleton.parents)
                    written.append(save_bvh(path, clip.rotations, clip.translation, offsets, skeleton.parents,
                                            joint_names, fps, options.order))
            bar.advance()
    return written
