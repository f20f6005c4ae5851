"""Array helpers of the file writers and motion tools (:mod:`~jaxmotion.data.export`, :mod:`~jaxmotion.data.retarget`):
inputs checked with errors that name the field and the expected shape, and arrays padded to a few bucket sizes so
that eager kernels and jitted functions compile once per bucket rather than once per clip length."""

from __future__ import annotations

import numpy as np


def checked(value, field: str, expected: tuple, named: str) -> np.ndarray:
    """``value`` as a finite numeric array of shape ``expected`` (``None`` entries: any size, at least 1); a
    ``ValueError`` naming ``field`` and ``named`` (the expected shape in words, e.g. ``"[T, 24, 3]"``) otherwise."""
    array = np.asarray(value)
    if array.ndim != len(expected) or any(
        (e is None and s < 1) or (e is not None and s != e) for s, e in zip(array.shape, expected)
    ):
        raise ValueError(f"{field}: expected {named}, got {tuple(array.shape)}")
    if not np.issubdtype(array.dtype, np.number):
        raise ValueError(f"{field}: expected numbers, got dtype {array.dtype}")
    check_finite(array, field)
    return array


def check_finite(array: np.ndarray, field: str) -> None:
    """A ``ValueError`` naming ``field``, the count and the first index of non-finite values, if any."""
    bad = ~np.isfinite(array)
    if bad.any():
        first = tuple(int(i) for i in np.argwhere(bad)[0])
        raise ValueError(f"{field}: {int(bad.sum())} non-finite values (NaN or infinite), the first at index {first}")


def bucket(count: int, smallest: int) -> int:
    """The padded size of ``count`` entries: the next power of two, at least ``smallest``."""
    return max(smallest, 1 << max(count - 1, 0).bit_length())


def padded(array: np.ndarray, size: int) -> np.ndarray:
    """``array`` with axis 0 padded to ``size`` by copies of its last entry (its dtype kept)."""
    array = np.asarray(array)
    return np.pad(array, [(0, size - len(array))] + [(0, 0)] * (array.ndim - 1), mode="edge")
