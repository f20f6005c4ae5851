"""Shared pieces of the real-format loaders: file reading with uniform errors, the validation helpers, and the
conversions of camera-frame data and SMPL poses into the library frame.

Errors, for every loader:
  * a missing file raises ``FileNotFoundError`` naming the path and what the file is;
  * a malformed file (unreadable or truncated, a missing key, a wrong shape or dtype, a label out of range)
    raises ``ValueError`` naming the file, the key or field, what was expected and what was found.

Pickles run code when loaded: read only dataset files from a source you trust (as the authors' code does).
"""

from __future__ import annotations

import pickle
from pathlib import Path

import jax
import jax.numpy as jnp
import numpy as np

from jaxmotion.geometry.kinematics import forward_kinematics, humanact12_to_library_frame
from jaxmotion.geometry.rotations import axis_angle_to_matrix, check_rotations, matrix_to_axis_angle
from jaxmotion.geometry.skeletons import SMPL24

#: ``[3, 3]`` map from the camera frame that HumanAct12, VIBE (UESTC, NTU-13) and Action2Motion's joints use
#: (y down, the subject facing -Z) to the library frame: the 180-degree turn about X of
#: :func:`~jaxmotion.geometry.kinematics.humanact12_to_library_frame`, as a matrix acting on column vectors.
CAMERA_TO_LIBRARY = np.diag([1.0, -1.0, -1.0])

# Frames per call of the compiled kernels below: every call has this shape, so each compiles once per process
# (about 2 s for forward kinematics on a CPU), whatever the clip lengths.
_CHUNK = 4096


# --- files ---------------------------------------------------------------------------------------------


def require_file(path: Path, what: str) -> Path:
    """``path`` if it is a file, else ``FileNotFoundError`` naming it and what it should hold."""
    if not path.is_file():
        raise FileNotFoundError(f"{path}: {what} not found")
    return path


def read_lines(path: Path, what: str) -> list[str]:
    """Stripped lines of a text file, trailing blank lines dropped (a final newline is not a clip)."""
    lines = [line.strip() for line in require_file(path, what).read_text(encoding="utf-8").splitlines()]
    while lines and not lines[-1]:
        lines.pop()
    return lines


def read_pickle(path: Path, what: str) -> object:
    """Unpickle ``path``; a truncated or corrupt file is a ``ValueError`` naming it.

    A pickle that refers to joblib (a joblib dump whose arrays sit outside the pickle stream) raises
    ``ImportError`` telling the user to install joblib, which this library does not depend on.
    """
    require_file(path, what)
    try:
        with path.open("rb") as f:
            return pickle.load(f)
    except ModuleNotFoundError as err:
        if (err.name or "").split(".")[0] == "joblib":
            raise ImportError(f"{path}: {what} was written by joblib and needs it to be read: "
                              "pip install joblib") from err
        raise ValueError(f"{path}: cannot unpickle {what}: {err}") from err
    except (pickle.UnpicklingError, EOFError, AttributeError, ImportError, IndexError, KeyError, TypeError,
            ValueError, OverflowError) as err:
        raise ValueError(f"{path}: cannot unpickle {what} (truncated or corrupt?): {err!r}") from err


def read_npy(path: Path, what: str) -> np.ndarray:
    """Load a ``.npy`` array (no pickled objects); a truncated or corrupt file is a ``ValueError``."""
    require_file(path, what)
    try:
        return np.load(path, allow_pickle=False)
    except (ValueError, OSError, EOFError) as err:
        raise ValueError(f"{path}: cannot read {what} as a .npy array (truncated or corrupt?): {err}") from err


# --- validation ----------------------------------------------------------------------------------------


def field(container: object, key: object, *, file: Path, sequence: bool = False, length: int | None = None):
    """``container[key]``, or a ``ValueError`` naming the file and the missing key.

    With ``sequence`` or ``length``, the value must also pass :func:`check_sequence`.
    """
    try:
        value = container[key]  # type: ignore[index]
    except (KeyError, IndexError, TypeError):
        found = sorted(map(repr, container)) if isinstance(container, dict) else type(container).__name__
        raise ValueError(f"{file}: missing key {key!r} (found: {found})") from None
    return check_sequence(value, length, file=file, key=repr(key)) if sequence or length is not None else value


def check_sequence(value: object, length: int | None, *, file: Path, key: str):
    """``value`` if it is a list, tuple or array of ``length`` items (any number if ``None``), one per clip."""
    is_sequence = isinstance(value, (list, tuple)) or (isinstance(value, np.ndarray) and value.ndim > 0)
    if not (is_sequence and length in (None, len(value))):
        got = f"{len(value)} items" if is_sequence else type(value).__name__
        want = "items" if length is None else f"{length} items"
        raise ValueError(f"{file}: {key}: expected a sequence of {want} (one per clip), got {got}")
    return value


def check_array(value: object, shape: tuple[int | str, ...], *, file: Path | str, key: str) -> np.ndarray:
    """``value`` as a float64 array after checking it is a real numeric array of ``shape`` whose values are finite
    in float32, the precision every dataset stores (a finite 1e39 would become infinite there).

    ``shape`` entries are sizes, or names of free axes (e.g. ``("T", 72)``); a free axis must be non-empty,
    since every clip has at least one frame.
    """
    expected = "[" + ", ".join(map(str, shape)) + "]"
    array = value if isinstance(value, np.ndarray) else None
    ok = (
        array is not None
        and array.ndim == len(shape)
        and (np.issubdtype(array.dtype, np.floating) or np.issubdtype(array.dtype, np.integer))
        and all(size == want if isinstance(want, int) else size > 0 for size, want in zip(array.shape, shape))
    )
    if not ok:
        got = f"shape {array.shape} dtype {array.dtype}" if array is not None else type(value).__name__
        raise ValueError(f"{file}: {key}: expected a real numeric array of shape {expected}, got {got}")
    array = np.asarray(array, dtype=np.float64)
    with np.errstate(over="ignore"):  # the overflow is what is being looked for
        bad = ~np.isfinite(array.astype(np.float32))
    if bad.any():
        first = tuple(int(i) for i in np.argwhere(bad)[0])
        raise ValueError(f"{file}: {key}: {int(bad.sum())} values that are not finite in float32 (NaN, infinite or "
                         f"beyond ±3.4e38), the first at index {first}: {array[first]}")
    return array


def check_unique(names: list[str], places: list[int | str], *, file: Path | str, what: str) -> None:
    """Each clip listed once: a name listed twice would enter a split twice (or both splits)."""
    seen: dict[str, int | str] = {}
    for name, place in zip(names, places):
        if name in seen:
            raise ValueError(f"{file}: {what} {name!r} is listed twice (at {seen[name]} and {place}); each clip "
                             f"must be listed once")
        seen[name] = place


def check_label(value: object, num_classes: int, *, file: Path | str, key: str) -> int:
    """``value`` as a class index, or a ``ValueError`` if it is not an integer in ``[0, num_classes)``."""
    integral = isinstance(value, (int, np.integer)) and not isinstance(value, (bool, np.bool_))
    if not integral or not 0 <= value < num_classes:
        raise ValueError(f"{file}: {key}: expected an integer class index in [0, {num_classes}), got {value!r}")
    return int(value)


def check_split(split: str, allowed: tuple[str, ...], dataset: str, note: str = "") -> str:
    """``split`` if the dataset has it, else a ``ValueError`` listing the ones it has."""
    if split not in allowed:
        raise ValueError(f"{dataset}: no split {split!r}; expected one of {allowed}{'. ' + note if note else ''}")
    return split


# --- into the library frame ------------------------------------------------------------------------------


def camera_points_to_library(clips: list[np.ndarray]) -> list[np.ndarray]:
    """Per clip ``[T, J, 3]`` camera-frame points -> ``[T, J, 3]`` float32 library-frame points.

    One call of :func:`~jaxmotion.geometry.kinematics.humanact12_to_library_frame` on all frames, so a
    dataset of many clip lengths costs one compiled shape, not one per length.
    """
    if not clips:
        return []
    points = np.asarray(humanact12_to_library_frame(np.concatenate(clips).astype(np.float32)))
    return np.split(points, np.cumsum([len(c) for c in clips])[:-1])


@jax.jit
def _turn_roots(rotations: jax.Array, matrices: jax.Array) -> jax.Array:
    """``[N, J, 3]`` axis-angle, ``[N, 3, 3]`` M -> ``[N, J, 3]`` with joint 0's rotation R replaced by M R."""
    turned = jnp.matmul(matrices, axis_angle_to_matrix(rotations[:, 0]), precision=jax.lax.Precision.HIGHEST)
    return rotations.at[:, 0].set(matrix_to_axis_angle(turned))


@jax.jit
def _template_fk(rotations: jax.Array, translation: jax.Array) -> jax.Array:
    """``[N, 24, 3]`` axis-angle, ``[N, 3]`` root positions -> ``[N, 24, 3]`` joints of the SMPL template."""
    return forward_kinematics(axis_angle_to_matrix(rotations), translation, SMPL24.offsets, SMPL24.parents)


def _by_chunks(kernel, rotations: np.ndarray, other: np.ndarray) -> np.ndarray:
    """``kernel`` over the frames in chunks of one fixed size (the last padded with copies of its final
    frame), so that it compiles once per process: ``[F, J, 3]``, ``[F, ...]`` -> ``[F, J, 3]`` float32."""
    chunks = []
    for start in range(0, len(rotations), _CHUNK):
        parts = [a[start:start + _CHUNK].astype(np.float32) for a in (rotations, other)]
        pad = _CHUNK - len(parts[0])
        parts = [np.pad(a, [(0, pad)] + [(0, 0)] * (a.ndim - 1), mode="edge") for a in parts]
        chunks.append(np.asarray(kernel(*parts))[: _CHUNK - pad])
    return np.concatenate(chunks) if chunks else np.zeros(rotations.shape, np.float32)


def rotate_roots(rotations: np.ndarray, matrices: np.ndarray) -> np.ndarray:
    """Turn each frame's global orientation: ``[F, J, 3]`` axis-angle, ``[F, 3, 3]`` M -> ``[F, J, 3]``.

    Joint 0's rotation R becomes ``M @ R``; the local rotations of the other joints are frame-independent.
    ``matrices`` must be rotations (a reflection would give some other, wrong, orientation).
    """
    check_rotations(matrices, where="rotate_roots: matrices (the turns into the library frame)")
    return _by_chunks(_turn_roots, rotations, matrices)


def template_joints(rotations: np.ndarray, translation: np.ndarray) -> np.ndarray:
    """FK with the project SMPL template (``SMPL24.offsets``): ``[F, 24, 3]``, ``[F, 3]`` -> ``[F, 24, 3]``.

    No SMPL body model ships with the library, so joint positions of rotation-based data come from the
    template's fixed bone lengths rather than from each subject's shape.
    """
    return _by_chunks(_template_fk, rotations, translation)


def smpl_clips_to_library(
    poses: list[np.ndarray], to_library: list[np.ndarray], translations: list[np.ndarray]
) -> tuple[list[np.ndarray], list[np.ndarray]]:
    """Rotations and template joints of SMPL clips, all frames at once.

    Args:
      poses: per clip ``[T, 24, 3]`` SMPL axis-angle in the source frame.
      to_library: per clip ``[3, 3]`` map from the source frame to the library frame.
      translations: per clip ``[T, 3]`` root positions, already in the library frame.

    Returns:
      ``(rotations, joints)``: per clip ``[T, 24, 3]`` library-frame axis-angle and ``[T, 24, 3]``
      ``template_joints`` positions.
    """
    if not poses:
        return [], []
    lengths = [len(p) for p in poses]
    matrices = np.concatenate([np.broadcast_to(m, (n, 3, 3)) for m, n in zip(to_library, lengths)])
    rotations = rotate_roots(np.concatenate(poses), matrices)
    joints = template_joints(rotations, np.concatenate(translations))
    cuts = np.cumsum(lengths)[:-1]
    return np.split(rotations, cuts), np.split(joints, cuts)
