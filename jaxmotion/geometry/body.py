"""SMPL-format linear-blend-skinning body layer.

No body model ships with jaxmotion (the SMPL files are licence-restricted); the user supplies one.
A model file holds the fields of the official SMPL release (axis names: V vertices, J joints,
S shape coefficients, F faces):

    v_template    [V, 3]            rest-pose mean-shape vertices
    shapedirs     [V, 3, S]         shape blend shapes, driven by betas [S]
    posedirs      [V, 3, 9*(J-1)]   pose blend shapes, driven by (R_j - I) of the non-root joints in
                                    joint order, each 3x3 flattened row-major
    J_regressor   [J, V]            rest joints = J_regressor @ shaped vertices (dense, or a scipy
                                    sparse matrix as in the official pickles)
    weights       [V, J]            skinning weights
    kintree_table [2, J]            row 0: parent of each joint; the root's parent is -1 or a value
                                    outside [0, J) (4294967295 in the official files)
    f             [F, 3]            triangle faces (optional; kept for meshing, unused here)

Other keys (e.g. ``bs_style``, ``J``) are ignored. Supported containers: ``.npz`` (numpy) and the
official ``.pkl`` (a Python-2 pickle of a dict). The official pickles store some arrays as chumpy
objects; they load only where chumpy is importable, otherwise convert them once, in an environment
with chumpy, with ``save_body_model("model.npz", pickle_dict)``. Unpickling runs code from the file:
load only ``.pkl`` files you trust.

The forward pass is SMPL's: shape, pose-corrective blend shapes, forward kinematics (delegated to
``kinematics.forward_kinematics_transforms``) and linear blend skinning. Output vertices are in world
coordinates, NOT root-centred: the root joint sits at its rest position plus ``translation``.
"""

from __future__ import annotations

import functools
import pickle
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import jax
import jax.numpy as jnp
import numpy as np
from flax import struct

from jaxmotion.geometry.kinematics import forward_kinematics_transforms
from jaxmotion.geometry.rotations import axis_angle_to_matrix, check_rotations
from jaxmotion.geometry.skeletons import topological_order

__all__ = ["BodyModel", "body_forward", "body_forward_rotmats", "load_body_model", "rest_joints", "root_translation",
           "save_body_model", "skinning_transforms"]

# Default matmul precision on GPU/TPU (TF32/bf16) would put millimetre errors on the vertices.
_einsum = functools.partial(jnp.einsum, precision=jax.lax.Precision.HIGHEST)


@struct.dataclass
class BodyModel:
    """Parameters of an SMPL-format body model; a JAX pytree whose ``parents`` are static.

    Attributes:
      v_template: [V, 3] float32 rest-pose template vertices.
      shapedirs: [V, 3, S] float32 shape blend shapes.
      posedirs: [V, 3, 9*(J-1)] float32 pose blend shapes.
      joint_regressor: [J, V] float32 (file field ``J_regressor``).
      weights: [V, J] float32 skinning weights.
      parents: static tuple of J parent indices, -1 for the root (joint 0).
      faces: [F, 3] int32 triangles (file field ``f``), or None when the file has none.
    """

    v_template: jax.Array
    shapedirs: jax.Array
    posedirs: jax.Array
    joint_regressor: jax.Array
    weights: jax.Array
    parents: tuple[int, ...] = struct.field(pytree_node=False)
    faces: jax.Array | None = None

    @property
    def num_vertices(self) -> int:
        return self.v_template.shape[0]

    @property
    def num_joints(self) -> int:
        return len(self.parents)

    @property
    def num_betas(self) -> int:
        return self.shapedirs.shape[-1]


def _densify(value: Any) -> Any:
    """Turns a scipy sparse matrix (the official J_regressor) into a dense array."""
    try:
        import scipy.sparse
    except ImportError:
        return value  # without scipy no sparse matrix can have been unpickled
    return value.toarray() if scipy.sparse.issparse(value) else value


# Axis names of each file field, for the rank check and the error messages.
_AXES = {
    "v_template": ("V", "3"),
    "shapedirs": ("V", "3", "S"),
    "posedirs": ("V", "3", "9*(J-1)"),
    "J_regressor": ("J", "V"),
    "weights": ("V", "J"),
    "kintree_table": ("2", "J"),
    "f": ("F", "3"),
}


def _axes(name: str) -> str:
    return f"[{', '.join(_AXES[name])}]"


def _field(raw: Mapping[str, Any], name: str, kinds: str, source: str) -> np.ndarray:
    if name not in raw:
        raise ValueError(f"{source}: missing field {name!r} {_axes(name)} (present: {sorted(raw)})")
    try:
        arr = np.asarray(_densify(raw[name]))
    except Exception as e:  # e.g. an object that numpy cannot convert
        raise ValueError(f"{source}: field {name!r} cannot be converted to an array: {e}") from e
    if arr.dtype.kind not in kinds:
        wanted = "an integer" if kinds == "iu" else "a numeric"
        raise ValueError(f"{source}: field {name!r} has dtype {arr.dtype}; expected {wanted} array {_axes(name)}")
    if arr.ndim != len(_AXES[name]):
        rank = len(_AXES[name])
        raise ValueError(f"{source}: field {name!r} has shape {arr.shape}; expected rank {rank}, {_axes(name)}")
    return arr


def _check_shape(source: str, name: str, arr: np.ndarray, expected: tuple[int, ...]) -> None:
    if arr.shape != expected:
        raise ValueError(f"{source}: field {name!r} has shape {arr.shape}; expected {_axes(name)} = {expected}")


def _parents_from_kintree(kintree: np.ndarray, source: str) -> tuple[int, ...]:
    raw_parents = kintree[0].astype(np.int64).tolist()
    # The root's parent is a sentinel outside [0, J): -1, or 4294967295 (uint32 -1) in the official files.
    if not raw_parents or 0 <= raw_parents[0] < len(raw_parents):
        raise ValueError(
            f"{source}: field 'kintree_table' must give joint 0 as the root (parent -1 or 4294967295); "
            f"got parents {raw_parents}"
        )
    parents = (-1, *raw_parents[1:])
    try:
        topological_order(parents)
    except ValueError as e:
        raise ValueError(f"{source}: field 'kintree_table' is not a tree rooted at joint 0: {e}") from e
    return parents


def _validate(raw: Mapping[str, Any], source: str) -> dict[str, np.ndarray]:
    """Checks the SMPL-format fields of ``raw``; returns them as numpy arrays (file field names)."""
    real, integer = "iuf", "iu"
    kintree = _field(raw, "kintree_table", integer, source)
    _check_shape(source, "kintree_table", kintree, (2, kintree.shape[1]))
    num_joints = len(_parents_from_kintree(kintree, source))
    v_template = _field(raw, "v_template", real, source)
    num_vertices = v_template.shape[0]
    _check_shape(source, "v_template", v_template, (num_vertices, 3))
    shapedirs = _field(raw, "shapedirs", real, source)
    _check_shape(source, "shapedirs", shapedirs, (num_vertices, 3, shapedirs.shape[2]))
    posedirs = _field(raw, "posedirs", real, source)
    _check_shape(source, "posedirs", posedirs, (num_vertices, 3, 9 * (num_joints - 1)))
    regressor = _field(raw, "J_regressor", real, source)
    _check_shape(source, "J_regressor", regressor, (num_joints, num_vertices))
    weights = _field(raw, "weights", real, source)
    _check_shape(source, "weights", weights, (num_vertices, num_joints))
    fields = {
        "v_template": v_template,
        "shapedirs": shapedirs,
        "posedirs": posedirs,
        "J_regressor": regressor,
        "weights": weights,
        "kintree_table": kintree,
    }
    if "f" in raw:
        faces = _field(raw, "f", integer, source)
        _check_shape(source, "f", faces, (faces.shape[0], 3))
        fields["f"] = faces
    return fields


def _read_pickle(path: Path) -> Any:
    try:
        with path.open("rb") as fh:
            # latin1 decodes the Python-2 numpy buffers of the official files byte for byte.
            return pickle.load(fh, encoding="latin1")
    except ImportError as e:
        if (e.name or "").split(".")[0] == "chumpy":
            raise ImportError(
                f"{path}: this pickle stores chumpy objects and chumpy is not importable; install chumpy, or "
                "where it is importable convert the file once with "
                "save_body_model('model.npz', pickle.load(f, encoding='latin1'))"
            ) from e
        raise ImportError(f"{path}: unpickling failed to import {e.name!r} ({e}); convert the file to .npz") from e
    except Exception as e:
        raise ValueError(f"{path}: cannot unpickle as an SMPL-format model ({type(e).__name__}: {e})") from e


def load_body_model(path: str | Path) -> BodyModel:
    """Loads an SMPL-format model from ``.npz`` or the official ``.pkl``.

    Raises:
      FileNotFoundError: ``path`` does not exist.
      ValueError: unknown suffix, or a missing / malformed field (the message names the file, the
        field and the expected shape).
      ImportError: a ``.pkl`` needs a module that is not importable (chumpy, scipy).
    """
    path = Path(path)
    if not path.is_file():
        raise FileNotFoundError(f"SMPL-format body model not found: {path}")
    suffix = path.suffix.lower()
    if suffix == ".npz":
        try:
            with np.load(path, allow_pickle=False) as npz:
                raw = {key: npz[key] for key in npz.files}
        except Exception as e:  # a corrupt archive, or object arrays (refused: they would unpickle code)
            raise ValueError(f"{path}: cannot read as a plain-array .npz ({type(e).__name__}: {e})") from e
    elif suffix == ".pkl":
        raw = _read_pickle(path)
        if not isinstance(raw, Mapping):
            raise ValueError(f"{path}: expected a pickled dict of SMPL fields, got {type(raw).__name__}")
    else:
        raise ValueError(f"{path}: unsupported body-model format {suffix!r}; expected .npz or .pkl")
    fields = _validate(raw, str(path))
    return BodyModel(
        v_template=jnp.asarray(fields["v_template"], jnp.float32),
        shapedirs=jnp.asarray(fields["shapedirs"], jnp.float32),
        posedirs=jnp.asarray(fields["posedirs"], jnp.float32),
        joint_regressor=jnp.asarray(fields["J_regressor"], jnp.float32),
        weights=jnp.asarray(fields["weights"], jnp.float32),
        parents=_parents_from_kintree(fields["kintree_table"], str(path)),
        faces=jnp.asarray(fields["f"], jnp.int32) if "f" in fields else None,
    )


def save_body_model(path: str | Path, model: BodyModel | Mapping[str, Any]) -> None:
    """Writes a model as ``.npz`` in the SMPL field layout that ``load_body_model`` reads.

    ``model`` is a ``BodyModel`` or a mapping with the SMPL field names (e.g. an official pickle's
    dict: chumpy arrays and sparse J_regressor are converted, extra keys dropped). Mappings are
    validated first so no unloadable file is written.
    """
    if isinstance(model, BodyModel):
        model = {
            "v_template": model.v_template,
            "shapedirs": model.shapedirs,
            "posedirs": model.posedirs,
            "J_regressor": model.joint_regressor,
            "weights": model.weights,
            "kintree_table": np.stack([np.asarray(model.parents), np.arange(model.num_joints)]),
            **({} if model.faces is None else {"f": model.faces}),
        }
    np.savez(path, **_validate(model, str(path)))


def _betas(model: BodyModel, betas: jax.Array | None, dtype) -> jax.Array:
    betas = jnp.zeros((0,), dtype) if betas is None else jnp.asarray(betas)
    if betas.ndim < 1 or betas.shape[-1] > model.num_betas:
        raise ValueError(f"betas must have shape [..., S'] with S' <= {model.num_betas}; got {betas.shape}")
    return betas


def _shaped(model: BodyModel, betas: jax.Array) -> jax.Array:
    """``[..., V, 3]`` the rest-pose vertices for ``betas [..., S']``: zero-padding betas to S equals using only the
    first S' blend shapes."""
    return model.v_template + _einsum("vcs,...s->...vc", model.shapedirs[..., : betas.shape[-1]], betas)


def rest_joints(model: BodyModel, betas: jax.Array | None = None) -> jax.Array:
    """``[..., J, 3]`` the body's joints in the rest pose for shape ``betas [..., S']`` (S' <= S; None: the mean
    shape), in the model's frame without translation: where :func:`body_forward_rotmats` puts them for identity
    rotations and zero translation. Joint 0's row is SMPL's ``J_0(betas)``: a posed body's root sits at
    ``J_0(betas) + translation``, which is how AMASS's ``trans`` is meant (:mod:`jaxmotion.data.export`)."""
    betas = _betas(model, betas, model.v_template.dtype)
    return _einsum("jv,...vc->...jc", model.joint_regressor, _shaped(model, betas))


def root_translation(model: BodyModel, root: jax.Array, betas: jax.Array | None = None) -> jax.Array:
    """``[..., 3]`` the body's ``translation`` that puts its root joint at ``root [..., 3]`` (the library's
    ``translation``, a root position): SMPL places the root at ``J_0(betas) + translation``
    (:func:`rest_joints`)."""
    return jnp.asarray(root) - rest_joints(model, betas)[..., 0, :]


def _posed(model: BodyModel, rotmats: jax.Array, betas: jax.Array | None, translation: jax.Array | None,
           check: bool) -> tuple[jax.Array, jax.Array, jax.Array, jax.Array]:
    """The inputs checked, then ``(v_posed [..., V, 3], rotations [..., J, 3, 3], shifts [..., J, 3], joints [..., J,
    3])``: the shaped rest vertices with the pose correctives, and per joint the rigid map ``x -> R x + s`` that
    carries a rest-pose point attached to it to where the posed body puts it."""
    num_joints = model.num_joints
    rotmats = jnp.asarray(rotmats)
    if rotmats.shape[-3:] != (num_joints, 3, 3):
        raise ValueError(f"rotmats must have shape [..., {num_joints}, 3, 3]; got {rotmats.shape}")
    if check:
        check_rotations(rotmats, where="body_forward_rotmats: rotmats", allow_nonfinite=True)
    betas = _betas(model, betas, rotmats.dtype)
    translation = jnp.zeros((3,), rotmats.dtype) if translation is None else jnp.asarray(translation)
    if translation.ndim < 1 or translation.shape[-1] != 3:
        raise ValueError(f"translation must have shape [..., 3]; got {translation.shape}")
    batch = jnp.broadcast_shapes(rotmats.shape[:-3], betas.shape[:-1], translation.shape[:-1])

    v_shaped = _shaped(model, betas)  # [..., V, 3]
    rest_joints = _einsum("jv,...vc->...jc", model.joint_regressor, v_shaped)  # [..., J, 3]

    # Pose correctives vanish at the rest pose because they are driven by R - I, not R.
    pose_feature = (rotmats[..., 1:, :, :] - jnp.eye(3, dtype=rotmats.dtype)).reshape(
        *rotmats.shape[:-3], 9 * (num_joints - 1)
    )
    v_posed = v_shaped + _einsum("vcp,...p->...vc", model.posedirs, pose_feature)  # [..., V, 3]

    parent_index = np.array([max(p, 0) for p in model.parents])  # root offset is unused by FK
    offsets = rest_joints - rest_joints[..., parent_index, :]
    # Translation enters as the root position, so the skinning transforms carry it to the vertices.
    root = rest_joints[..., 0, :] + translation
    global_rotmats, joints = forward_kinematics_transforms(
        jnp.broadcast_to(rotmats, (*batch, num_joints, 3, 3)),
        jnp.broadcast_to(root, (*batch, 3)),
        jnp.broadcast_to(offsets, (*batch, num_joints, 3)),
        model.parents,
        check=False,
    )
    # A_j maps a rest-pose point to its posed position if rigidly attached to joint j.
    rest_to_posed = joints - _einsum("...jab,...jb->...ja", global_rotmats, rest_joints)  # [..., J, 3]
    return v_posed, global_rotmats, rest_to_posed, joints


def body_forward_rotmats(
    model: BodyModel,
    rotmats: jax.Array,
    betas: jax.Array | None = None,
    translation: jax.Array | None = None,
    *,
    check: bool = True,
) -> tuple[jax.Array, jax.Array]:
    """Poses and skins the body from local joint rotation matrices.

    Leading axes ``...`` of the three inputs broadcast against each other (e.g. one ``betas [S']``
    for a whole ``[T, J, 3, 3]`` sequence).

    Args:
      model: the body model.
      rotmats: [..., J, 3, 3] local (parent-relative) joint rotations, joint 0 global.
      betas: [..., S'] shape coefficients with S' <= S; missing trailing ones count as zero. None = zeros.
      translation: [..., 3] world translation of the whole body. None = zeros.
      check: refuse concrete ``rotmats`` that are not rotations (skipped under ``jit``; ``False`` skins
        any 3x3, see :func:`jaxmotion.geometry.kinematics.forward_kinematics_transforms`).

    Returns:
      vertices [..., V, 3] and joints [..., J, 3], both in world coordinates (not root-centred).
    """
    v_posed, rotations, shifts, joints = _posed(model, rotmats, betas, translation, check)
    blend_rot = _einsum("vj,...jab->...vab", model.weights, rotations)  # [..., V, 3, 3]
    blend_trans = _einsum("vj,...ja->...va", model.weights, shifts)  # [..., V, 3]
    vertices = _einsum("...vab,...vb->...va", blend_rot, v_posed) + blend_trans
    return vertices, joints


def skinning_transforms(model: BodyModel, rotmats: jax.Array, betas: jax.Array | None = None,
                        translation: jax.Array | None = None, *, check: bool = True) -> tuple[jax.Array, jax.Array]:
    """What a renderer skins with, per joint, for the inputs of :func:`body_forward_rotmats`: ``(rotations [..., J, 3,
    3], shifts [..., J, 3])`` such that ``sum_j weights[v, j] (rotations_j x + shifts_j)`` is where the posed body
    puts a shaped rest vertex ``x`` (:func:`body_forward_rotmats` without the pose correctives: a preview's
    skinning, in ``J · 12`` numbers a frame instead of ``V · 3``)."""
    _, rotations, shifts, _ = _posed(model, rotmats, betas, translation, check)
    return rotations, shifts


def body_forward(
    model: BodyModel,
    pose: jax.Array,
    betas: jax.Array | None = None,
    translation: jax.Array | None = None,
) -> tuple[jax.Array, jax.Array]:
    """``body_forward_rotmats`` with the pose given as axis-angle ``[..., J, 3]`` (radians)."""
    return body_forward_rotmats(model, axis_angle_to_matrix(jnp.asarray(pose)), betas, translation)
