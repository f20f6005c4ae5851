"""Root translation from the posed body: feet pinned while they bear weight, on the floor, ballistic in flight.

Input is the body posed about a root at the origin (FK with zero translation). Each foot touches the
floor at two sole points: the ball (the SMPL toe joint) and a virtual heel behind the ankle at the same
rest height. Then, frame by frame:

* horizontal: while a foot bears weight its contact point (the heel at heel strike, then the ball) does
  not move, so the root moves by minus that point's displacement (the weight-shared average during double support). Single support slides
  by float rounding only; in double support the feet's disagreement is split by their weights.
* vertical: the weight-bearing feet's lowest sole points sit on their support (y = 0 on the floor, or the
  height of the step or rung under that foot);
* airborne frames (no weight on either foot): the root follows a parabola under gravity from take-off to
  landing, keeping (a ``carry`` fraction of) the horizontal velocity of the preceding support phase plus the
  action's ``flight_speed`` along the heading; the rest of the flight (``1 - carry``) brings each landing foot
  back down where it last stood (hopping and jumping in place stay in place however the legs swing);
* nothing ever goes through the support: the root is raised if any sole point would be below the support
  under its foot.
"""

from __future__ import annotations

import numpy as np

GRAVITY = 9.81
HEEL_BEHIND_ANKLE = 0.045  # metres, at template size: the heel's back lies ~4-5 cm behind the ankle joint
BALL_CONTACT = 0.012  # metres: the ball counts as down when at most this much above the heel
_MOMENTUM_WINDOW = 0.25  # seconds of support before take-off whose mean velocity carries into flight
_RETURN_TIME = 0.2  # seconds of flight it takes to land the feet fully back where they stood


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


def _back_where_stood(path: np.ndarray, pinned: np.ndarray, contact: np.ndarray, landing: np.ndarray, a: int,
                      b: int) -> np.ndarray:
    """``[2]`` horizontal root displacement over a flight ``[a, b)`` that lands each foot (``landing [2]``
    weights at frame ``b``) where it last bore weight.

    ``path``: ``[T, 2]`` horizontal root path (valid before ``a``); ``pinned``: ``[T, 2, 2]`` each foot's contact
    point about the root; ``contact``: ``[T, 2]`` weight shares. A landing foot that never stood lands as it comes.
    """
    shift, total = np.zeros(2), 0.0
    for f in np.flatnonzero(landing > 0):
        stood = np.flatnonzero(contact[:a, f] > 0)
        if len(stood):
            last = stood[-1]
            shift += landing[f] * (path[last] + pinned[last, f] - pinned[b, f] - path[a - 1])
            total += landing[f]
    return shift / total if total else shift


def root_translation(soles: np.ndarray, contact: np.ndarray, ground: np.ndarray, heading: np.ndarray, fps: float,
                     flight_speed: float | np.ndarray = 0.0, carry: float | np.ndarray = 1.0) -> np.ndarray:
    """Root path ``[T, 3]`` for a posed body.

    Args:
      soles: ``[T, 2, 2, 3]`` (left, right) x (heel, ball) sole points of the body posed at the origin.
      contact: ``[T, 2]`` weight share of the (left, right) foot; both zero = airborne.
      ground: ``[T, 2]`` support height (m) under the (left, right) foot.
      heading: ``[T]`` facing angle about +Y, radians (0 = facing +Z).
      fps: frame rate.
      flight_speed: extra forward speed (m/s) during flight, along the heading.
      carry: fraction of the support phase's horizontal velocity kept in flight (1 for running; 0 for a
        jump, whose push-off moves the hips over the feet without launching the body forward, or running on
        the spot: the feet then land where they stood, plus ``flight_speed``).
      Both are one value for the clip or ``[T]`` per frame (a take of several actions); a flight takes the values
      of its first frame.
    """
    num_frames = len(contact)
    flight_speed = np.broadcast_to(np.asarray(flight_speed, float), (num_frames,))
    carry = np.broadcast_to(np.asarray(carry, float), (num_frames,))
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

    clearance = ground - height.min(axis=2)  # [T, 2] root height that puts each foot on its support
    vertical = np.einsum("tf,tf->t", weights, clearance)
    window = max(round(_MOMENTUM_WINDOW * fps), 1)
    for a, b in _segments(airborne):
        support = step[max(a - window, 1):a]
        velocity = carry[a] * support.mean(axis=0) * fps if len(support) else np.zeros(2)
        facing = heading[a:b].mean()
        velocity = velocity + flight_speed[a] * np.array([np.sin(facing), np.cos(facing)])
        if carry[a] < 1.0 and 0 < a and b < num_frames:
            # A short flight (running on the spot) makes up only part of the way back, so that a foot still
            # near the floor does not visibly slide; the next landings make up the rest.
            share = (1.0 - carry[a]) * min(1.0, (b - a + 1) / (fps * _RETURN_TIME))
            velocity = velocity + share * fps / (b - a + 1) * _back_where_stood(
                np.cumsum(step, axis=0), pinned_now, contact, weights[b], a, b)
        step[a:b + 1] = velocity / fps  # through the landing frame
        # Parabola under gravity from the last supported frame (a - 1) to the first one (b).
        before = vertical[a - 1] if a > 0 else vertical[b]
        after = vertical[b] if b < num_frames else before
        tau = (b - a + 1) / fps
        s = (np.arange(a, b) - (a - 1)) / fps
        vertical[a:b] = before + (after - before) * s / tau + 0.5 * GRAVITY * s * (tau - s)
    horizontal = np.cumsum(step, axis=0)
    vertical = np.maximum(vertical, clearance.max(axis=1))
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
