"""Root translation from the posed body: feet pinned while they bear weight, on the floor, ballistic in flight.

Input is the body posed about a root at the origin (FK with zero translation). Each foot touches the
floor at two sole points: the ball (the SMPL toe joint) and a virtual heel behind the ankle at the same
rest height. Then, frame by frame:

* horizontal: while a foot bears weight its contact point (the heel at heel strike, then the ball) does
  not move, so the root moves by minus that point's displacement (the weight-shared average during double support). Single support slides
  by float rounding only; in double support the feet's disagreement is split by their weights.
* vertical: the weight-bearing feet's lowest sole points sit on the floor (y = 0);
* airborne frames (no weight on either foot): the root follows a parabola under gravity from take-off to
  landing, keeping (a ``carry`` fraction of) the horizontal velocity of the preceding support phase plus the
  action's ``flight_speed`` along the heading;
* nothing ever goes through the floor: the root is raised if any sole point would be below y = 0.
"""

from __future__ import annotations

import numpy as np

GRAVITY = 9.81
HEEL_BEHIND_ANKLE = 0.045  # metres, at template size: the heel's back lies ~4-5 cm behind the ankle joint
BALL_CONTACT = 0.012  # metres: the ball counts as down when at most this much above the heel
_MOMENTUM_WINDOW = 0.25  # seconds of support before take-off whose mean velocity carries into flight


def sole_points(ankle_pos: np.ndarray, ankle_rot: np.ndarray, toe_pos: np.ndarray, foot_offset: np.ndarray,
                scale: float) -> np.ndarray:
    """Heel and ball of one foot: ``[T, 3]`` ankle position, ``[T, 3, 3]`` ankle global rotation, ``[T, 3]``
    toe joint, ``[3]`` rest ankle->toe offset -> ``[T, 2, 3]`` (heel, ball)."""
    heel_local = np.array([foot_offset[0], foot_offset[1], -HEEL_BEHIND_ANKLE * scale])
    heel = ankle_pos + ankle_rot @ heel_local
    return np.stack([heel, toe_pos], axis=1)


def _segments(mask: np.ndarray) -> list[tuple[int, int]]:
    """Half-open ``[a, b)`` runs of True in a boolean ``[T]``."""
    edges = np.diff(np.concatenate([[0], mask.astype(np.int8), [0]]))
    return list(zip(np.flatnonzero(edges == 1), np.flatnonzero(edges == -1)))


def root_translation(soles: np.ndarray, contact: np.ndarray, heading: np.ndarray, fps: float,
                     flight_speed: float = 0.0, carry: float = 1.0) -> np.ndarray:
    """Root path ``[T, 3]`` for a posed body.

    Args:
      soles: ``[T, 2, 2, 3]`` (left, right) x (heel, ball) sole points of the body posed at the origin.
      contact: ``[T, 2]`` weight share of the (left, right) foot; both zero = airborne.
      heading: ``[T]`` facing angle about +Y, radians (0 = facing +Z).
      fps: frame rate.
      flight_speed: extra forward speed (m/s) during flight, along the heading.
      carry: fraction of the support phase's horizontal velocity kept in flight (1 for running; 0 for a
        jump, whose push-off moves the hips over the feet without launching the body forward).
    """
    num_frames = len(contact)
    airborne = contact.sum(axis=1) <= 1e-6
    if airborne.all():  # nothing to stand on: treat the whole clip as supported by both feet
        contact, airborne = np.full_like(contact, 0.5), np.zeros_like(airborne)
    weights = contact / np.maximum(contact.sum(axis=1, keepdims=True), 1e-6)
    height = soles[..., 1]  # [T, 2, 2]
    # The contact point of each foot: the heel while only it is down (heel strike), else the ball, which
    # then stays put through foot-flat and push-off (and is where a pivoting foot turns).
    lowest = (height[..., 1] <= height[..., 0] + BALL_CONTACT).astype(int)  # [T, 2]: 0 heel, 1 ball
    frames = np.arange(num_frames)[:, None]
    feet = np.arange(2)[None, :]
    pinned_now = soles[frames, feet, lowest][..., [0, 2]]  # [T, 2, 2] horizontal
    pinned_before = soles[np.maximum(frames - 1, 0), feet, lowest][..., [0, 2]]
    share = 0.5 * (weights + np.roll(weights, 1, axis=0))
    share = share / np.maximum(share.sum(axis=1, keepdims=True), 1e-6)
    step = -np.einsum("tf,tfc->tc", share, pinned_now - pinned_before)  # [T, 2] root displacement
    step[0] = 0.0

    vertical = -np.einsum("tf,tf->t", weights, height.min(axis=2))
    window = max(round(_MOMENTUM_WINDOW * fps), 1)
    for a, b in _segments(airborne):
        support = step[max(a - window, 1):a]
        velocity = carry * support.mean(axis=0) * fps if len(support) else np.zeros(2)
        facing = heading[a:b].mean()
        velocity = velocity + flight_speed * np.array([np.sin(facing), np.cos(facing)])
        step[a:b + 1] = velocity / fps  # through the landing frame
        # Parabola under gravity from the last supported frame (a - 1) to the first one (b).
        before = vertical[a - 1] if a > 0 else vertical[b]
        after = vertical[b] if b < num_frames else before
        tau = (b - a + 1) / fps
        s = (np.arange(a, b) - (a - 1)) / fps
        vertical[a:b] = before + (after - before) * s / tau + 0.5 * GRAVITY * s * (tau - s)
    horizontal = np.cumsum(step, axis=0)
    vertical = np.maximum(vertical, -height.min(axis=(1, 2)))
    return np.stack([horizontal[:, 0], vertical, horizontal[:, 1]], axis=-1)


def foot_skate(joints: np.ndarray, toe_joints: tuple[int, int], fps: float, *, floor_tolerance: float = 0.02
               ) -> np.ndarray:
    """Horizontal speed (m/s) of each toe joint on the frames where it is within ``floor_tolerance`` of the
    floor at both ends of the frame step: ``[T, J, 3] -> [K]`` over all such (frame, foot) pairs."""
    toes = joints[:, list(toe_joints)]  # [T, 2, 3]
    low = toes[..., 1] < floor_tolerance
    both = low[1:] & low[:-1]
    speed = np.linalg.norm(np.diff(toes[..., [0, 2]], axis=0), axis=-1) * fps
    return speed[both]
