"""Timing primitives: keyframed transitions, periodic cycles, phase warping and smooth noise.

All functions are pure numpy over a time axis ``t [T]`` (seconds) or a phase axis (cycles); values may
carry trailing channels ``[K, C]`` (K keyframes), giving ``[T, C]``.
"""

from __future__ import annotations

import numpy as np


def minimum_jerk(s: np.ndarray) -> np.ndarray:
    """The minimum-jerk profile 10s^3 - 15s^4 + 6s^5 on [0, 1] (clamped outside): zero velocity and
    acceleration at both ends, as in point-to-point human reaching."""
    s = np.clip(s, 0.0, 1.0)
    return s * s * s * (10.0 + s * (-15.0 + 6.0 * s))


def keyframes(t: np.ndarray, times, values) -> np.ndarray:
    """Minimum-jerk transitions between keyframes, holding the first/last value outside them.

    Args:
      t: ``[T]`` query times.
      times: ``[K]`` increasing keyframe times (equal neighbours give an instant switch).
      values: ``[K]`` or ``[K, C]`` values at the keyframes.

    Returns:
      ``[T]`` or ``[T, C]``: the pose comes to rest at every keyframe (a hold is two equal keys).
    """
    times = np.asarray(times, float)
    values = np.asarray(values, float)
    seg = np.clip(np.searchsorted(times, t, side="right") - 1, 0, len(times) - 2)
    span = times[seg + 1] - times[seg]
    s = minimum_jerk(np.where(span > 0, (t - times[seg]) / np.where(span > 0, span, 1.0), 1.0))
    if values.ndim == 2:
        s = s[:, None]
    return values[seg] + s * (values[seg + 1] - values[seg])


def periodic(phase: np.ndarray, knots, values) -> np.ndarray:
    """A smooth periodic curve through ``(knots, values)``: cyclic Catmull-Rom (C1) interpolation.

    Args:
      phase: ``[T]`` phase in cycles (any real; only the fractional part matters).
      knots: ``[K]`` increasing phases in [0, 1).
      values: ``[K]`` or ``[K, C]`` curve values at the knots (e.g. a joint angle over a gait cycle).
    """
    knots = np.asarray(knots, float)
    values = np.asarray(values, float)
    k = len(knots)
    # Pad one knot on each side (wrapped by one period) so every segment has both neighbours.
    kx = np.concatenate([knots[-1:] - 1.0, knots, knots[:2] + 1.0])
    kv = np.concatenate([values[-1:], values, values[:2]])
    p = np.mod(phase, 1.0)
    p = np.where(p < knots[0], p + 1.0, p)
    seg = np.clip(np.searchsorted(kx, p, side="right") - 1, 1, k)
    x0, x1, x2, x3 = kx[seg - 1], kx[seg], kx[seg + 1], kx[seg + 2]
    v0, v1, v2, v3 = kv[seg - 1], kv[seg], kv[seg + 1], kv[seg + 2]
    h = x2 - x1
    s = (p - x1) / h
    if values.ndim == 2:
        s, h, x0, x1, x2, x3 = (a[:, None] for a in (s, h, x0, x1, x2, x3))
    m1 = (v2 - v0) / (x2 - x0) * h  # tangents from the neighbours (non-uniform Catmull-Rom)
    m2 = (v3 - v1) / (x3 - x1) * h
    s2, s3 = s * s, s * s * s
    return (2 * s3 - 3 * s2 + 1) * v1 + (s3 - 2 * s2 + s) * m1 + (-2 * s3 + 3 * s2) * v2 + (s3 - s2) * m2


def warped_phase(t: np.ndarray, rate: float, rng: np.random.Generator, *, wobble: float = 0.06,
                 start: float | None = None) -> np.ndarray:
    """Phase (cycles) ``[T]`` of a rhythm at ``rate`` cycles/s whose tempo drifts slowly, as people's does.

    The instantaneous rate is ``rate * (1 + wobble * sin(...))`` with a random slow period and phase, so
    the phase is monotonic for ``wobble < 1``; ``start`` is the phase at t = 0 (random if None).
    """
    period = rng.uniform(2.0, 5.0)
    psi = rng.uniform(0.0, 2.0 * np.pi)
    start = rng.uniform() if start is None else start
    omega = 2.0 * np.pi / period
    drift = wobble * (np.cos(psi) - np.cos(omega * t + psi)) / omega  # integral of wobble * sin
    return start + rate * (t + drift)


def smooth_noise(t: np.ndarray, rng: np.random.Generator, amplitude: float, *, max_hz: float = 1.0,
                 channels: int | None = None, terms: int = 3) -> np.ndarray:
    """Slow random wander ``[T]`` (or ``[T, channels]``): a few random sinusoids below ``max_hz``.

    Its standard deviation is about ``amplitude``; used for postural sway and to keep repeated cycles from
    being identical copies.
    """
    shape = (terms,) if channels is None else (terms, channels)
    freq = rng.uniform(0.15, max_hz, size=shape)
    phase = rng.uniform(0.0, 2.0 * np.pi, size=shape)
    amp = amplitude * np.sqrt(2.0 / terms)
    waves = np.sin(2.0 * np.pi * freq * t.reshape((-1,) + (1,) * len(shape)) + phase)
    return amp * waves.sum(axis=1)


def pulses(phase: np.ndarray, duty: float, ramp: float) -> np.ndarray:
    """``[T]`` in [0, 1]: on during the first ``duty`` of every cycle, rising over its first ``ramp`` and
    falling over its last ``ramp`` (minimum jerk), e.g. a foot's share of the body weight over a gait
    cycle; two such curves half a cycle apart sum to 1 through a double support of ``ramp``."""
    p = np.mod(phase, 1.0)
    return minimum_jerk(p / ramp) * (1.0 - minimum_jerk((p - duty + ramp) / ramp))
