"""Checks of the conditioning every generator takes: action ids and durations.

An embedding lookup clamps an out-of-range index (action 99 of 12 classes becomes class 11) and a one-hot
of one is all zeros, so a wrong id would silently give some motion. These checks run where values are
concrete (a public call, a sampler); inside ``jit`` the values are traced and the checks pass them by,
which is why every public entry point calls them before compiling anything.
"""

from __future__ import annotations

import jax
import jax.numpy as jnp
import numpy as np


def ids_in_range(ids: jax.Array, size: int) -> jax.Array:
    """``[]`` bool, jittable: every id of ``ids`` in ``[0, size)``. The jitted metric kernels turn their value
    into NaN when it is False (they cannot raise on traced values, and dropping the id would move the metric)."""
    return jnp.all((ids >= 0) & (ids < size))


def _concrete(values) -> np.ndarray | None:
    """The values as numpy, or None when they are traced (inside jit/vmap) and cannot be read."""
    if isinstance(values, jax.core.Tracer):
        return None
    if isinstance(values, jax.Array) and not values.is_fully_addressable:
        return None  # a global array of several processes: each checks the part it made
    return np.asarray(values)


def check_actions(actions, num_classes: int, *, count: int | None = None, where: str = "actions") -> None:
    """``actions [N]`` (``[count]`` when given) must be integer class ids in ``[0, num_classes)``. Shape and
    dtype are checked even under ``jit`` (they are static); the values only where they are concrete."""
    shape = np.shape(actions)
    dtype = actions.dtype if hasattr(actions, "dtype") else np.asarray(actions).dtype
    expected = "[N]" if count is None else f"[{count}]"
    if len(shape) != 1 or (count is not None and shape[0] != count) or not np.issubdtype(dtype, np.integer):
        raise ValueError(f"{where}: expected {expected} integer class ids, got {dtype} {tuple(shape)}")
    values = _concrete(actions)
    if values is not None and values.size and (values.min() < 0 or values.max() >= num_classes):
        bad = values[(values < 0) | (values >= num_classes)]
        raise ValueError(f"{where}: expected class ids in [0, {num_classes}) (the model's classes), got "
                         f"{sorted(set(bad.tolist()))[:5]}")


def check_durations(durations, count: int, max_frames: int | None = None, *, where: str = "durations") -> None:
    """``durations [count]`` must be integers in ``[1, max_frames]`` (``max_frames`` None: no upper bound)."""
    values = _concrete(durations)
    if values is None:
        return
    upper = "" if max_frames is None else f", {max_frames}"
    if values.shape != (count,) or not np.issubdtype(values.dtype, np.integer):
        raise ValueError(f"{where}: expected [N] = ({count},) integer frame counts, got {values.dtype} {values.shape}")
    if values.size and (values.min() < 1 or (max_frames is not None and values.max() > max_frames)):
        raise ValueError(f"{where}: expected frame counts in [1{upper or ', ...'}], got values from {values.min()} "
                         f"to {values.max()}")
