"""Reusable, parametrised movement skills that action classes compose.

Every skill writes into a :class:`~jaxmotion.data.synthetic.take.Take` (adding to the channels it
drives, so skills layer) and is written once for the LEFT side with a ``side`` argument: the anatomy
mirrors the right side. Angles are degrees, times seconds, distances metres at template size (multiply
by ``take.scale()``). Figures are from MOTION_FACTS (section numbers in the docstrings).
"""

from __future__ import annotations

import dataclasses

import numpy as np

from jaxmotion.data.synthetic import anatomy, timing
from jaxmotion.data.synthetic.take import SIDES, Take, other
from jaxmotion.geometry.skeletons import SMPL24

# --- arms ----------------------------------------------------------------------------------------------


def arm_direction(flex: np.ndarray, abd: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Humerus flexion (forward) and abduction (sideways) angles -> (plane, elevation), degrees.

    The arm hanging down, turned forward by ``flex`` after sideways by ``abd``; ``plane`` is meaningless
    at zero elevation, where its jump between +-90 does not move the arm.
    """
    f, a = np.radians(flex), np.radians(abd)
    d = np.stack(np.broadcast_arrays(np.sin(a), -np.cos(a) * np.cos(f), np.cos(a) * np.sin(f)))
    return np.degrees(np.arctan2(d[2], d[0])), np.degrees(np.arccos(np.clip(-d[1], -1.0, 1.0)))


def set_arm(take: Take, side: str, flex, abd, *, rot=0.0, elbow=None) -> None:
    """Point ``side``'s upper arm by flexion/abduction (degrees), overwriting the shoulder channels."""
    plane, elev = arm_direction(np.asarray(flex, float), np.asarray(abd, float))
    take[f"{side}_shoulder.plane"] = plane
    take[f"{side}_shoulder.elev"] = elev
    take[f"{side}_shoulder.rot"] = rot
    if elbow is not None:
        take[f"{side}_elbow.flex"] = elbow


def reach(take: Take, side: str, target: np.ndarray, *, elbow_hint=(0.4, -1.0, -0.3)) -> None:
    """Two-bone inverse kinematics: place ``side``'s wrist at ``target``.

    Args:
      target: ``[T, 3]`` (or ``[3]``) wrist position in the thorax (spine3) frame, side-normalised: x away
        from the midline, y up, z forward. Targets out of reach are pulled onto the reachable shell.
      elbow_hint: side-normalised direction the elbow points to (down-out-back by default).
    """
    upper, fore = take.arm_lengths()
    shoulder = take.shoulder_point()
    target = np.broadcast_to(np.asarray(target, float), (take.num_frames, 3))
    to_wrist = target - shoulder
    dist = np.clip(np.linalg.norm(to_wrist, axis=-1), abs(upper - fore) + 0.02, upper + fore - 1e-3)
    u = to_wrist / np.linalg.norm(to_wrist, axis=-1, keepdims=True)
    hint = np.asarray(elbow_hint, float)
    v = hint - (u @ hint)[:, None] * u
    v = v / np.maximum(np.linalg.norm(v, axis=-1, keepdims=True), 1e-9)
    cos_a = np.clip((upper**2 + dist**2 - fore**2) / (2 * upper * dist), -1.0, 1.0)
    arm = cos_a[:, None] * u + np.sqrt(1.0 - cos_a**2)[:, None] * v  # upper-arm direction
    wrist = dist[:, None] * u
    forearm = wrist - upper * arm
    forearm = forearm / np.linalg.norm(forearm, axis=-1, keepdims=True)
    cos_e = np.clip(np.sum(arm * forearm, axis=-1), -1.0, 1.0)
    elev = np.degrees(np.arccos(np.clip(-arm[:, 1], -1.0, 1.0)))
    plane = np.degrees(np.arctan2(arm[:, 2], arm[:, 0]))
    # Humeral rotation: turn the elbow's flexion axis (where the swing alone leaves it) onto arm x forearm.
    swing_axis = _swing(plane, elev) @ np.array([-1.0, 0.0, 0.0])
    wanted = np.cross(arm, forearm)
    wanted = wanted / np.maximum(np.linalg.norm(wanted, axis=-1, keepdims=True), 1e-9)
    rot = np.degrees(np.arctan2(np.sum(np.cross(swing_axis, wanted) * arm, axis=-1),
                                np.sum(swing_axis * wanted, axis=-1)))
    take[f"{side}_shoulder.plane"] = plane
    take[f"{side}_shoulder.elev"] = elev
    take[f"{side}_shoulder.rot"] = rot
    take[f"{side}_elbow.flex"] = np.degrees(np.arccos(cos_e))


def _swing(plane: np.ndarray, elev: np.ndarray) -> np.ndarray:
    """``[T, 3, 3]`` Ry(-plane) Rz(elev) Ry(plane): the arm's minimal rotation up from hanging."""
    p, e = np.radians(plane), np.radians(elev)
    cp, sp, ce, se = np.cos(p), np.sin(p), np.cos(e), np.sin(e)

    def ry(c, s):
        z, o = np.zeros_like(c), np.ones_like(c)
        return np.stack([np.stack([c, z, s], -1), np.stack([z, o, z], -1), np.stack([-s, z, c], -1)], -2)

    z, o = np.zeros_like(ce), np.ones_like(ce)
    rz = np.stack([np.stack([ce, -se, z], -1), np.stack([se, ce, z], -1), np.stack([z, z, o], -1)], -2)
    return ry(cp, -sp) @ rz @ ry(cp, sp)


def relaxed_wrist(take: Take) -> np.ndarray:
    """``[3]`` side-normalised thorax-frame wrist position of a relaxed hanging arm."""
    upper, fore = take.arm_lengths()
    carry = np.radians(take.subject.arm_carry)
    return take.shoulder_point() + np.array([0.04, -upper - fore * np.cos(carry), fore * np.sin(carry)])


def toward(take: Take, side: str, envelope: np.ndarray, target, *, elbow_hint=(0.4, -1.0, -0.3),
           start=None, bulge: float = 0.12) -> None:
    """Move ``side``'s wrist from ``start`` (relaxed by default) to ``target`` as ``envelope [T]`` goes 0 -> 1,
    on a path bowed ``bulge`` metres forward (hands travel in front of the body, not through it)."""
    start = relaxed_wrist(take) if start is None else np.asarray(start, float)
    path = start + envelope[:, None] * (np.asarray(target, float) - start)
    path[:, 2] += bulge * take.scale() * np.sin(np.pi * np.clip(envelope, 0.0, 1.0))
    reach(take, side, path, elbow_hint=elbow_hint)


def landmark(take: Take, name: str) -> np.ndarray:
    """``[3]`` side-normalised thorax-frame point for a wrist target near the head or chest."""
    s = take.scale()
    head = take.head_point()
    points = {
        "mouth": head + s * np.array([0.03, -0.10, 0.05]),  # wrist such that the hand is at the mouth
        "ear": head + s * np.array([0.11, -0.09, -0.01]),
        "brow": head + s * np.array([0.09, 0.01, 0.08]),
        "chin": head + s * np.array([0.09, -0.16, 0.15]),
        "chest": s * np.array([0.07, -0.12, 0.28]),
        "bowl": s * np.array([0.10, -0.27, 0.27]),
    }
    return points[name]


def straight_ahead(take: Take, extension: float) -> np.ndarray:
    """``[3]`` wrist target straight in front of the shoulder at shoulder height, ``extension`` of full reach."""
    upper, fore = take.arm_lengths()
    return take.shoulder_point() + np.array([-0.06, -0.02, extension * (upper + fore)])


# --- posture -------------------------------------------------------------------------------------------


def stand(take: Take, *, heading: float | None = None) -> None:
    """Relaxed standing: habitual trunk posture, arms hanging with their carry angle, soft knees, and
    postural sway (ankle strategy forward/back, weight shifts side to side, ~0.1-0.8 Hz)."""
    take["pelvis.heading"] += take.rng.normal(0.0, 20.0) if heading is None else heading
    take["spine1.flex"] += 0.4 * take.subject.posture
    take["spine2.flex"] += 0.6 * take.subject.posture
    sway_ap, sway_ml = take.wander(0.8, 0.6), take.wander(1.0, 0.4)
    for side in SIDES:
        set_arm(take, side, 3.0 + take.wander(2.0), 6.0 + take.wander(1.5), elbow=take.subject.arm_carry)
        take[f"{side}_elbow.pron"] = 10.0
        take[f"{side}_knee.flex"] += 3.0
        take[f"{side}_hip.flex"] += 2.0
        take[f"{side}_ankle.dorsi"] += sway_ap + 1.0
    take["left_hip.abd"] += sway_ml
    take["right_hip.abd"] -= sway_ml
    take["pelvis.obliquity"] += 0.5 * sway_ml
    take["neck.twist"] += take.wander(3.0, 0.3)


def seated(take: Take, weight: np.ndarray | float = 1.0) -> None:
    """Sitting on a ~knee-height seat (thighs horizontal, shanks vertical, a little back lean), blended in
    by ``weight [T]`` (1 = seated)."""
    w = np.asarray(weight, float)
    for side in SIDES:
        take[f"{side}_hip.flex"] += w * take.vary(88.0, 0.05)
        take[f"{side}_knee.flex"] += w * take.vary(88.0, 0.05)
        take[f"{side}_ankle.dorsi"] += w * 2.0
        take[f"{side}_hip.abd"] += w * 6.0
    take["spine1.flex"] -= w * 6.0


def sit_transition(take: Take, start: float, duration: float, *, down: bool, hand_push: bool) -> None:
    """Stand-to-sit (``down``) or sit-to-stand over ``duration`` s (MOTION_FACTS 3.4): the trunk flexes
    forward to bring the weight over the feet, the hips and knees fold (or extend), the trunk comes
    upright; optionally the hands push on the thighs."""
    phases = np.array([0.0, 0.35, 0.75, 1.0]) * duration + start
    lean = timing.keyframes(take.t, phases, [0.0, 1.0, 0.6, 0.0])
    sit = timing.keyframes(take.t, [phases[0] + 0.15 * duration, phases[2] + 0.1 * duration], [0.0, 1.0])
    if not down:
        sit = 1.0 - timing.keyframes(take.t, [phases[0] + 0.2 * duration, phases[2]], [0.0, 1.0])
    seated(take, sit)
    lean_deg = take.vary(30.0, 0.15)
    take["pelvis.tilt"] += 0.4 * lean_deg * lean
    take["spine1.flex"] += 0.4 * lean_deg * lean
    take["spine2.flex"] += 0.2 * lean_deg * lean
    take["neck.flex"] -= 0.2 * lean_deg * lean
    for side in SIDES:
        take[f"{side}_hip.flex"] += 0.4 * lean_deg * lean
        take[f"{side}_ankle.dorsi"] += 8.0 * lean * (1.0 - sit) + 4.0 * sit * lean
        if hand_push:
            push = np.maximum(lean, sit)
            set_arm(take, side, 5.0 + 35.0 * push, 8.0 + 4 * push, elbow=take.subject.arm_carry + 25.0 * push)
        else:
            arm = take[f"{side}_shoulder.elev"] + 25.0 * lean
            set_arm(take, side, arm, 8.0, elbow=take.subject.arm_carry + 15.0 * lean)


# --- locomotion ----------------------------------------------------------------------------------------


@dataclasses.dataclass(frozen=True)
class GaitCurves:
    """Sagittal joint angles over one stride (phase 0 = left foot strike) and the support pattern.

    ``hip``, ``knee``, ``ankle``: ``(knots, values)`` for :func:`timing.periodic`. ``duty``: stance
    fraction per foot; ``ramp``: weight-transfer (double-support) fraction; below 0.5 duty, flight.
    """

    hip: tuple
    knee: tuple
    ankle: tuple
    duty: float
    ramp: float
    elbow: float  # mean elbow flexion
    arm_swing: float  # shoulder flexion amplitude
    lean: float  # forward trunk lean


# MOTION_FACTS 3.1 (walking sagittal curves, stance 62%, double support 2 x 12%).
WALK = GaitCurves(
    hip=((0.0, 0.12, 0.3, 0.5, 0.62, 0.75, 0.87), (25.0, 22.0, 6.0, -12.0, -2.0, 20.0, 30.0)),
    knee=((0.0, 0.12, 0.35, 0.5, 0.62, 0.72, 0.88), (3.0, 17.0, 5.0, 10.0, 42.0, 70.0, 20.0)),
    ankle=((0.0, 0.08, 0.3, 0.45, 0.6, 0.7, 0.8), (0.0, -5.0, 6.0, 10.0, -18.0, 0.0, 5.0)),
    duty=0.62, ramp=0.12, elbow=15.0, arm_swing=14.0, lean=2.0,
)
# MOTION_FACTS 3.2 (jogging: contact ~37% of the stride per foot, two flights per stride); the hip
# retracts before touchdown so the foot lands nearly at rest on the ground.
RUN = GaitCurves(
    hip=((0.0, 0.15, 0.37, 0.5, 0.7, 0.82), (36.0, 20.0, -12.0, -2.0, 45.0, 52.0)),
    knee=((0.0, 0.12, 0.37, 0.6, 0.78, 0.92), (28.0, 42.0, 22.0, 95.0, 72.0, 35.0)),
    ankle=((0.0, 0.12, 0.3, 0.42, 0.6, 0.85), (8.0, 18.0, 10.0, -25.0, -10.0, 16.0)),
    duty=0.37, ramp=0.03, elbow=85.0, arm_swing=28.0, lean=8.0,
)


def gait(take: Take, curves: GaitCurves, *, cadence: float, size: float = 1.0, turn: float = 0.0,
         hip_bias: float = 0.0, knee_boost: tuple = (0.0, 0.0), phase: np.ndarray | None = None) -> np.ndarray:
    """Locomotion from a stride pattern, with coordinated pelvis, trunk, arms and support.

    Args:
      cadence: steps per second (two per stride).
      size: scales the joint excursions (longer strides, higher knees).
      turn: heading change, degrees per second (+ = to the subject's left).
      hip_bias: added hip flexion (negative shortens the forward reach: in-place gaits).
      knee_boost: ``(degrees, centre phase)`` extra swing knee flexion (butt kicks) peaking at that phase.
      phase: stride phase ``[T]`` to use instead of a fresh, slowly drifting one.

    Returns:
      the stride phase ``[T]`` (cycles) of the left leg.
    """
    if phase is None:
        phase = timing.warped_phase(take.t, cadence / 2.0 * take.tempo, take.rng, wobble=0.04)
    size = size * take.amp
    for side, offset in (("left", 0.0), ("right", 0.5)):
        p = phase - offset
        hip = timing.periodic(p, *curves.hip)
        take[f"{side}_hip.flex"] += size * hip + hip_bias
        knee = (0.5 + 0.5 * size) * timing.periodic(p, *curves.knee)  # keeps toe clearance when slow
        if knee_boost[0]:
            knee += knee_boost[0] * np.exp(np.cos(2 * np.pi * (p - knee_boost[1])) * 3.0 - 3.0)
        take[f"{side}_knee.flex"] += knee
        take[f"{side}_ankle.dorsi"] += (0.5 + 0.5 * size) * timing.periodic(p, *curves.ankle)
        take[f"{side}_ankle.out"] += 5.0
        take.contact[:, SIDES.index(side)] = timing.pulses(p, curves.duty, curves.ramp)
        # Arms swing opposite the same-side leg (MOTION_FACTS 3.1): forward when that leg is behind.
        swing = size * curves.arm_swing * np.cos(2 * np.pi * (p - 0.55))
        set_arm(take, side, 4.0 + swing, 8.0, elbow=curves.elbow + 0.25 * swing)
        take[f"{side}_elbow.pron"] = 15.0
    cycle = 2 * np.pi * phase
    take["pelvis.heading"] += turn * take.t - 4.0 * size * np.cos(cycle)  # swing side forward
    take["spine2.twist"] += 4.5 * size * np.cos(cycle)  # thorax counter-rotates
    take["spine3.twist"] += 4.5 * size * np.cos(cycle)
    obliquity = 4.0 * size * np.sin(cycle)  # stance side up
    take["pelvis.obliquity"] += obliquity
    take["left_hip.abd"] -= obliquity
    take["right_hip.abd"] += obliquity
    take["pelvis.tilt"] += curves.lean + 1.5 * size * np.cos(2 * cycle)
    take["spine1.flex"] += 0.5 * curves.lean
    take["pelvis.obliquity"] -= turn / 15.0  # lean into the turn
    return phase


def leg_bend(take: Take, rise: float, reach: float) -> tuple[float, float]:
    """Hip and knee flexion (degrees, two-bone sagittal IK) that put the ankle ``rise`` metres above a
    straight leg's and ``reach`` metres ahead of the hip (both at template size)."""
    s = take.scale()
    thigh, shank = 0.39 * s, 0.41 * s
    x, y = reach * s, thigh + shank - rise * s  # ankle ahead of and below the hip
    d = np.clip(np.hypot(x, y), abs(thigh - shank) + 1e-3, thigh + shank - 1e-3)
    knee = np.pi - np.arccos((thigh**2 + shank**2 - d**2) / (2 * thigh * shank))
    hip = np.arctan2(x, y) + np.arccos((thigh**2 + d**2 - shank**2) / (2 * thigh * d))
    return float(np.degrees(hip)), float(np.degrees(knee))


def stairs(take: Take, phase: np.ndarray, *, rise: float, tread: float) -> None:
    """Going up stairs or rungs foot over foot (MOTION_FACTS 4: lead hip/knee flex 60-90 degrees onto the
    step, the root rises), one move per half cycle of ``phase [T]`` (left leads from each whole cycle, right
    from each half; standing while ``phase < 0``).

    A move: the lead foot lifts, lands ``rise`` m (template size) above the other foot and ``tread`` m ahead,
    on the leg bend that puts it there (:func:`leg_bend`), the weight moves onto it (the pose held, so both
    feet stay on their supports), then the leg straightens and lifts the body by ``rise``. Sets
    ``take.ground``: each landing is one step above the other foot's support.
    """
    hip, knee = leg_bend(take, rise, tread)
    going = phase >= 0.0
    move = np.floor(2.0 * phase).astype(int)  # moves begun (left leads even ones)
    u = 2.0 * phase - move  # progress through the current move
    keys = [0.0, 0.3, 0.45, 0.6, 1.0]  # lift, peak, touch down, weight on, straight
    weight = timing.keyframes(u, keys[2:4], [0.0, 1.0])  # the lead foot's share
    landed = np.floor(2.0 * phase - keys[2]).astype(int)  # index of the latest move that has touched down
    for k, side in enumerate(SIDES):
        leads = going & (move % 2 == k)
        take[f"{side}_hip.flex"] += np.where(leads, timing.keyframes(u, keys, [0, hip + 20, hip, hip, 0]), 0.0)
        take[f"{side}_knee.flex"] += np.where(leads, timing.keyframes(u, keys, [0, knee + 40, knee, knee, 0]), 0.0)
        flat = min(knee - hip, 20.0)  # the foot lands flat on the step (the ball, on a rung)
        take[f"{side}_ankle.dorsi"] += np.where(leads, timing.keyframes(u, keys, [0, 15, flat, flat, 0]), 0.0)
        take.contact[:, k] = np.where(going, np.where(leads, weight, 1.0 - weight), 0.5)
        mine = landed - (landed - k) % 2  # this foot's latest landing: move j puts a foot on step j + 1
        take.ground[:, k] = take.scale() * rise * np.maximum(mine + 1, 0)


# --- one-off whole-body skills ---------------------------------------------------------------------------


def jump(take: Take, start: float, *, height: float, forward: float = 0.0, dip: float = 1.0,
         arm_swing: float = 1.0) -> float:
    """Countermovement jump (MOTION_FACTS 3.3) beginning at ``start``: unweight and dip, propel, fly
    ``sqrt(8 h / g)`` s, land toes first and absorb. Returns the time it ends."""
    flight = np.sqrt(8.0 * height / 9.81)
    dip_t, push_t = take.vary(0.4, 0.1), take.vary(0.22, 0.1)
    t_bottom = start + dip_t
    t_off = t_bottom + push_t
    t_land = t_off + flight
    t_absorb = t_land + 0.2
    t_end = t_absorb + take.vary(0.5, 0.1)
    keys = [start, t_bottom, t_off, t_off + 0.4 * flight, t_land, t_absorb, t_end]

    def curve(*values):
        return timing.keyframes(take.t, keys, values)

    d = dip * take.amp
    for side in SIDES:
        take[f"{side}_hip.flex"] += curve(0, 75 * d, -5, 25, 18, 45 * d, 0)
        take[f"{side}_knee.flex"] += curve(0, 85 * d, 0, 35, 12, 55 * d, 0)
        take[f"{side}_ankle.dorsi"] += curve(0, 22 * d, -35, -25, -20, 18 * d, 0)
        set_arm(take, side, 3.0 + arm_swing * curve(0, -45, 150, 120, 70, 25, 0), 10.0,
                elbow=curve(15, 10, 15, 25, 30, 20, 15))
    take["spine1.flex"] += curve(0, 25 * d, -5, 8, 6, 15 * d, 0)
    take["spine2.flex"] += curve(0, 10 * d, -5, 4, 3, 8 * d, 0)
    take["neck.flex"] += curve(0, -10 * d, -5, 0, 0, -5, 0)
    airborne = (take.t > t_off) & (take.t < t_land)
    take.contact[airborne] = 0.0
    take.flight_speed = forward / flight
    take.flight_carry = 0.0
    return t_end


def step_out(take: Take, side: str, start: float, duration: float, *, length: float) -> None:
    """Step ``side``'s foot ``length`` metres forward and stay in the staggered stance: lift (hip and knee
    flex), reach, plant, weight moves onto it."""
    leg = 0.85 * take.scale()
    reach_deg = np.degrees(np.arcsin(np.clip(length / leg, 0.0, 0.8)))
    keys = start + duration * np.array([0.0, 0.45, 1.0])
    take[f"{side}_hip.flex"] += timing.keyframes(take.t, keys, [0, 0.5 * reach_deg + 18, 0.5 * reach_deg])
    take[f"{side}_knee.flex"] += timing.keyframes(take.t, keys, [0, 35, 5])
    take[f"{other(side)}_hip.flex"] -= timing.keyframes(take.t, keys, [0, 0.2, 0.5]) * reach_deg
    take[f"{other(side)}_ankle.dorsi"] += timing.keyframes(take.t, keys, [0, 3, 6])
    lifted = (take.t > keys[0] + 0.1 * duration) & (take.t < keys[2] - 0.1 * duration)
    take.contact[lifted, SIDES.index(side)] = 0.0
    take.contact[lifted, SIDES.index(other(side))] = 1.0


def bumps(take: Take, times, width: float) -> np.ndarray:
    """``[T]`` sum of smooth 0 -> 1 -> 0 bumps of ``width`` s starting at ``times`` (a move and its return)."""
    out = np.zeros(take.num_frames)
    for t0 in times:
        out += timing.keyframes(take.t, [t0, t0 + 0.5 * width, t0 + width], [0.0, 1.0, 0.0])
    return np.minimum(out, 1.0)


def beats(take: Take, period: float, *, jitter: float = 0.15, first: float | None = None) -> np.ndarray:
    """Event times at about every ``period`` s (tempo-scaled, with timing jitter) across the clip."""
    period = period / take.tempo
    t = take.uniform(0.1, 0.6) * period if first is None else first
    times = []
    while t < take.duration:
        times.append(t)
        t += period * (1.0 + take.rng.normal(0.0, jitter))
    return np.array(times)


# --- in-place stepping, folding, kicking, steering (NTU-13 and CMU classes) ------------------------------

# Running on the spot: during stance the hip flexes by about half the knee flexion, which keeps the foot
# under the hip (no travel); the thigh swings forward to ~50 degrees (MOTION_FACTS 4; high knees: size ~1.8).
SPOT_RUN = GaitCurves(
    hip=((0.0, 0.15, 0.37, 0.55, 0.7, 0.9), (12.0, 20.0, 10.0, 30.0, 50.0, 22.0)),
    knee=((0.0, 0.15, 0.37, 0.55, 0.7, 0.9), (25.0, 40.0, 20.0, 80.0, 90.0, 45.0)),
    ankle=((0.0, 0.15, 0.37, 0.55, 0.8), (-10.0, 8.0, -25.0, -20.0, -12.0)),
    duty=0.4, ramp=0.04, elbow=85.0, arm_swing=24.0, lean=4.0,
)
# Butt kicks: the thigh stays near vertical while the heel flies up to the buttock (knee >= 130 degrees).
BUTT_KICKS = GaitCurves(
    hip=((0.0, 0.15, 0.37, 0.6, 0.85), (12.0, 20.0, 10.0, 14.0, 14.0)),
    knee=((0.0, 0.15, 0.37, 0.5, 0.65, 0.85), (25.0, 40.0, 20.0, 100.0, 140.0, 60.0)),
    ankle=((0.0, 0.15, 0.37, 0.6, 0.85), (-10.0, 8.0, -25.0, -30.0, -10.0)),
    duty=0.4, ramp=0.04, elbow=80.0, arm_swing=18.0, lean=3.0,
)

# Segment masses (fractions of body mass) and centre-of-mass positions, Winter's tables (est. rounding):
# head-arms-trunk 0.68 with its centre ~0.32 m above the hips, thighs 0.2 at 0.43 of their length from the
# hip, shanks 0.09 at 0.43 from the knee.
_HAT, _THIGHS, _SHANKS, _HAT_RISE = 0.68, 0.2, 0.09, 0.32


def _shank_lean(knee, lean, heel, scale):
    """Forward lean of the shanks (degrees) that puts the body's centre of mass over the mid-foot (over
    the balls when the heels are up), given knee flexion and trunk lean ``[T]`` (degrees): bisection on the
    sagittal stick model, whose centre of mass moves forward monotonically with the shank lean."""
    thigh_len, shank_len = 0.39 * scale, 0.41 * scale
    k, lam = np.radians(knee), np.radians(lean)
    target = scale * (0.05 + 0.002 * np.asarray(heel, float))

    def com(s):
        knee_x = shank_len * np.sin(s)
        hip_x = knee_x - thigh_len * np.sin(k - s)
        return (_HAT * (hip_x + _HAT_RISE * scale * np.sin(lam)) + _THIGHS * (hip_x + 0.57 * (knee_x - hip_x))
                + _SHANKS * 0.57 * knee_x) / (_HAT + _THIGHS + _SHANKS)

    lo, hi = np.full_like(k, np.radians(-20.0)), np.full_like(k, np.radians(60.0))
    for _ in range(24):
        mid = 0.5 * (lo + hi)
        ahead = com(mid) > target
        lo, hi = np.where(ahead, lo, mid), np.where(ahead, mid, hi)
    return np.degrees(0.5 * (lo + hi))


def crouch(take: Take, knee, lean, *, heel=0.0) -> None:
    """Fold the legs and the trunk with the body balanced over the feet (MOTION_FACTS 3.4: the trunk leans
    as the hips go back): squats, stoops, knee bounces, a crouched gait.

    Args:
      knee: ``[T]`` knee flexion of both legs, degrees.
      lean: ``[T]`` forward lean of the trunk from vertical, degrees: the pelvis takes up to half of it (less
        when the hips run out of flexion, as in deep squats), the lumbar and thoracic spine the rest.
      heel: ``[T]`` heel raise, degrees (deep squats on the balls of the feet).

    The shanks lean forward by whatever keeps the centre of mass over the feet; the hips flex to match
    (thigh inclination = knee flexion - shank lean), the ankles dorsiflex by the shank lean less the heel
    raise; deep knee flexion turns the knees a little out.
    """
    knee, lean = np.broadcast_to(knee, take.t.shape), np.broadcast_to(lean, take.t.shape)
    heel = np.broadcast_to(heel, take.t.shape)
    shank = _shank_lean(knee, lean, heel, take.scale())
    thigh = knee - shank
    tilt = np.minimum(0.5 * lean, 118.0 - thigh)
    rest = lean - tilt
    take["pelvis.tilt"] += tilt
    take["spine1.flex"] += 0.5 * rest
    take["spine2.flex"] += 0.3 * rest
    take["spine3.flex"] += 0.2 * rest
    for side in SIDES:
        take[f"{side}_hip.flex"] += thigh + tilt
        take[f"{side}_knee.flex"] += knee
        take[f"{side}_ankle.dorsi"] += shank - heel
        take[f"{side}_hip.abd"] += 0.1 * knee
        take[f"{side}_hip.rot"] -= 0.08 * knee


def kick(take: Take, side: str, start: float, *, height: float = 1.0, lateral: float = 0.0,
         duration: float = 1.0) -> float:
    """A kick with ``side``'s leg from standing (MOTION_FACTS 3.5 and 4), over ``duration`` s from ``start``;
    returns the time the foot is back down.

    ``lateral`` 0 is a front kick: the weight moves onto the other foot, the leg swings back with the
    knee folded, the thigh drives forward and stops as the shank whips straight, recoil, foot down.
    ``lateral`` 1 is a side kick: the knee chambers, the hip abducts and turns in, the knee extends
    sideways while the pelvis tips up on the kicking side and the trunk leans away. ``height`` scales the
    leg's elevation (1: hip flexion ~80 degrees, or ~70 degrees sideways).
    """
    keys = start + duration * np.array([0.0, 0.15, 0.4, 0.55, 0.72, 1.0])

    def curve(*values):
        return timing.keyframes(take.t, keys, values)

    f, s, h = 1.0 - lateral, lateral, height * take.amp
    support = other(side)
    sign = 1.0 if side == "left" else -1.0  # pelvis obliquity and trunk bend are signed toward the left
    take[f"{side}_hip.flex"] += f * curve(0, -12, 35, 80 * h, 55, 0) + s * curve(0, 10, 75, 35, 65, 0)
    take[f"{side}_knee.flex"] += f * curve(0, 60, 100, 8, 70, 0) + s * curve(0, 30, 125, 8, 110, 0)
    take[f"{side}_ankle.dorsi"] += f * curve(0, -15, -20, -35, -15, 0) + s * curve(0, 0, 10, 10, 5, 0)
    take[f"{side}_hip.abd"] += s * curve(0, 5, 25, 45 * h, 25, 0)
    take[f"{side}_hip.rot"] += s * curve(0, 5, 30, 40, 30, 0)
    tip = s * curve(0, 3, 10, 25 * h, 12, 0)  # kicking side's hip rises
    take["pelvis.obliquity"] += sign * tip
    take[f"{support}_hip.abd"] += tip  # keeps the standing leg vertical under the tipped pelvis
    take["spine1.bend"] -= sign * 0.4 * tip
    take["spine2.bend"] -= sign * 0.3 * tip
    take["spine1.flex"] -= f * curve(0, 0, 5, 12 * h, 8, 0)  # leaning back counters the leg
    take[f"{support}_knee.flex"] += curve(0, 10, 12, 15, 12, 0)
    take[f"{support}_hip.flex"] += curve(0, 6, 8, 10, 8, 0)
    take[f"{support}_ankle.dorsi"] += curve(0, 5, 6, 8, 6, 0)
    lifted = timing.keyframes(take.t, [keys[0], keys[1], keys[4], keys[5]], [0.0, 1.0, 1.0, 0.0])
    take.contact[:, SIDES.index(side)] *= 1.0 - lifted
    return float(keys[-1])


def steer(take: Take, rate: np.ndarray) -> None:
    """Turn the body by ``rate [T]`` degrees per second (+ = to the subject's left), leaning into the turn."""
    take["pelvis.heading"] += np.concatenate([[0.0], np.cumsum(rate[:-1])]) / take.fps
    take["pelvis.obliquity"] -= rate / 15.0


def side_steps(take: Take, phase: np.ndarray, *, width: float, travel: int = 0) -> None:
    """Stepping sideways to ``phase [T]`` (one unit = one step): shift the weight, the leading foot steps out
    ``width`` degrees of hip abduction, the weight moves over, the other foot closes beside it. ``travel``
    +1 keeps going to the subject's left, -1 to the right, 0 alternates (step-touch, as in dancing)."""
    step = np.floor(phase).astype(int)
    to_left = (step % 2 == 0) if travel == 0 else np.full(step.shape, travel > 0)
    p = phase - step
    keys = [0.0, 0.1, 0.4, 0.55, 0.85, 1.0]
    w = width * take.amp
    lead = {"abd": timing.keyframes(p, keys, [0, 0, w, 0.5 * w, 0, 0]),
            "lift": timing.keyframes(p, [0.1, 0.25, 0.4], [0, 1, 0]),
            "weight": timing.keyframes(p, keys, [0.5, 0, 0, 1, 1, 0.5])}
    trail = {"abd": timing.keyframes(p, keys, [0, 0, 0, 0.5 * w, 0, 0]),
             "lift": timing.keyframes(p, [0.55, 0.7, 0.85], [0, 1, 0]),
             "weight": 1.0 - lead["weight"]}
    for k, side in enumerate(SIDES):
        mine = {key: np.where(to_left == (side == "left"), lead[key], trail[key]) for key in lead}
        take[f"{side}_hip.abd"] += mine["abd"]
        take[f"{side}_hip.flex"] += 15.0 * mine["lift"]
        take[f"{side}_knee.flex"] += 30.0 * mine["lift"]
        take.contact[:, k] = mine["weight"]
    lean = 3.0 * (take.contact[:, 0] - take.contact[:, 1])  # the pelvis drops away from the stance hip
    take["pelvis.obliquity"] += lean
    take["left_hip.abd"] -= lean
    take["right_hip.abd"] += lean


def in_place(take: Take) -> None:
    """Re-aim each weight-bearing leg's hip flexion so that the ball of its foot stays under the hip at
    its standing distance (sagittal stick model; the weight share blends it in), turning a stepping or
    running pattern into one without travel: running on the spot, butt kicks, marching. Call it after the
    leg and pelvis angles are set."""
    s = take.scale()
    thigh, shank, toe = 0.39 * s, 0.41 * s, s * np.array([0.121, -0.052])  # ankle -> ball at rest
    tilt = take["pelvis.tilt"]
    # It also fades in over the ~0.2 s before each stance, so that a landing foot comes straight down under
    # the hip (but not after toe-off, where the swing is left free).
    ahead = max(round(0.2 * take.fps), 1)
    for k, side in enumerate(SIDES):
        total = np.concatenate([[0.0], np.cumsum(np.concatenate([take.contact[:, k], np.zeros(ahead)]))])
        coming = (total[1 + ahead:] - total[1:-ahead]) / ahead  # mean share over the next `ahead` frames
        weight = np.minimum(1.0, np.maximum(take.contact[:, k], 3.0 * coming))
        knee = np.radians(take[f"{side}_knee.flex"])
        dorsi = np.radians(take[f"{side}_ankle.dorsi"])
        # thigh sin(a) + shank sin(a - knee) = R sin(a - g); the foot adds its own reach, rotated by the
        # shank's inclination a - knee plus the dorsiflexion: a few fixed-point passes.
        r = np.hypot(thigh + shank * np.cos(knee), shank * np.sin(knee))
        g = np.arctan2(shank * np.sin(knee), thigh + shank * np.cos(knee))
        a = g
        for _ in range(3):
            foot = a - knee + dorsi
            ball = toe[0] * np.cos(foot) - toe[1] * np.sin(foot)
            a = g + np.arcsin(np.clip((toe[0] - ball) / r, -1.0, 1.0))
        under = np.degrees(a) + tilt
        take[f"{side}_hip.flex"] += weight * (under - take[f"{side}_hip.flex"])
    take.flight_carry = 0.0  # flights go straight up


# --- repeated exercises: cycles, knee lifts, punches, arm circles, trunk turns and bends (UESTC) ---------


def cycles(take: Take, low: float, high: float, *, reps: tuple[float, float] = (2.0, 3.0)) -> np.ndarray:
    """Phase ``[T]`` (cycles) of an exercise repeated ``reps`` times over the clip, as UESTC subjects did
    (MOTION_FACTS 4: 3 repetitions per ~6 s recording), its period held within the natural ``[low, high]``
    seconds (over the subject's tempo) and drifting a little. The clip opens in the rest at the end of a
    cycle, so a repetition starts from the neutral posture."""
    period = np.clip(take.duration / take.uniform(*reps), low / take.tempo, high / take.tempo)
    return timing.warped_phase(take.t, 1.0 / period, take.rng, wobble=0.05, start=-take.uniform(0.0, 0.2))


def pulse(phase: np.ndarray, rise: float, hold: float, fall: float) -> np.ndarray:
    """``[T]`` one 0 -> 1 -> 0 movement per cycle of ``phase``: up over the first ``rise`` of the cycle, held
    for ``hold``, down over ``fall``, then at rest for what is left (all fractions of a cycle)."""
    return timing.keyframes(np.mod(phase, 1.0), np.cumsum([0.0, rise, hold, fall]), [0.0, 1.0, 1.0, 0.0])


def alternating(phase: np.ndarray, side: str | None) -> dict[str, np.ndarray]:
    """``{side: [T]}`` 1 on the cycles of ``phase`` that side performs: every cycle for ``side``, or (None)
    left on even cycles and right on odd ones."""
    left = np.floor(phase) % 2 == 0 if side is None else np.full(phase.shape, side == "left")
    return {"left": left.astype(float), "right": 1.0 - left}


def trunk_pitch(take: Take) -> np.ndarray:
    """``[T]`` forward inclination of the thorax from vertical so far, degrees."""
    return take["pelvis.tilt"] + take["spine1.flex"] + take["spine2.flex"] + take["spine3.flex"]


def hang_arm(take: Take, side: str, forward=0.0) -> None:
    """``side``'s arm hanging plumb whatever the trunk's lean (plus ``forward`` degrees of flexion)."""
    set_arm(take, side, trunk_pitch(take) + forward, 6.0, elbow=take.subject.arm_carry)


def turn_head(take: Take, flex=0.0, twist=0.0, bend=0.0) -> None:
    """Turn the head (degrees, ``[T]`` or scalars): ``flex`` + looks down, ``twist`` + to the subject's left,
    ``bend`` + toward the left shoulder; the neck takes 0.6 and the head joint 0.4 (MOTION_FACTS 2: cervical
    flexion 50-64, rotation 80, about half of it at C1-C2)."""
    for joint, share in (("neck", 0.6), ("head", 0.4)):
        take[f"{joint}.flex"] += share * np.asarray(flex, float)
        take[f"{joint}.twist"] += share * np.asarray(twist, float)
        take[f"{joint}.bend"] += share * np.asarray(bend, float)


def posed(take: Take) -> tuple[np.ndarray, np.ndarray]:
    """Forward kinematics of the pose built so far (within the joint limits), root at the origin: ``(global
    rotations [T, J, 3, 3], positions [T, J, 3])``, for hand targets on the body itself or on the floor."""
    local = anatomy.angles_to_rotmats(anatomy.clip_to_limits(take.angles))
    offsets = take.subject.offsets.astype(float)
    rot = np.zeros_like(local)
    pos = np.zeros(local.shape[:-1])
    rot[:, 0] = local[:, 0]
    for j in range(1, len(SMPL24.parents)):  # SMPL-24 parents precede their children
        p = SMPL24.parents[j]
        rot[:, j] = rot[:, p] @ local[:, j]
        pos[:, j] = pos[:, p] + rot[:, p] @ offsets[j]
    return rot, pos


def turn_trunk(take: Take, angle) -> None:
    """Rotate the trunk ``angle [T]`` degrees (+ = to the subject's left) above still feet: mostly the
    thoracic spine (MOTION_FACTS 2: thoracic ~30 per side, lumbar less), a fifth the pelvis, which the
    hips undo so the legs keep facing forward; the head goes along."""
    for joint, share in (("spine1", 0.15), ("spine2", 0.35), ("spine3", 0.3)):
        take[f"{joint}.twist"] += share * angle
    take["pelvis.heading"] += 0.2 * angle
    take["left_hip.rot"] += 0.2 * angle  # turning the pelvis left rotates the left thigh inwards
    take["right_hip.rot"] -= 0.2 * angle


def bend_trunk(take: Take, angle) -> None:
    """Bend the trunk sideways ``angle [T]`` degrees (+ = toward the left) over the lumbar and thoracic
    spine (MOTION_FACTS 2: lumbar lateral bend 15-20, thoracic less); the hips shift the other way."""
    for joint, share in (("spine1", 0.45), ("spine2", 0.33), ("spine3", 0.22)):
        take[f"{joint}.bend"] += share * angle
    take["pelvis.obliquity"] -= 0.1 * angle
    take["left_hip.abd"] += 0.1 * angle
    take["right_hip.abd"] -= 0.1 * angle


def lift_knee(take: Take, side: str, env: np.ndarray, *, hip: float = 90.0, knee: float = 90.0) -> None:
    """Raise ``side``'s knee as ``env [T]`` goes 0 -> 1 to ``hip`` and ``knee`` flexion (degrees), balanced on
    the other leg, whose knee softens; the foot leaves the floor once the lift is under way."""
    take[f"{side}_hip.flex"] += hip * env
    take[f"{side}_knee.flex"] += knee * env
    take[f"{side}_ankle.dorsi"] -= 15.0 * env  # the foot hangs
    take[f"{other(side)}_knee.flex"] += 6.0 * env
    take[f"{other(side)}_hip.flex"] += 4.0 * env
    take.contact[:, SIDES.index(side)] *= 1.0 - timing.minimum_jerk(env / 0.15)


def punch(take: Take, side: str, env: np.ndarray, *, extension: float = 0.95) -> None:
    """``side``'s fist from the guard at the chin straight ahead at shoulder height as ``env [T]`` goes
    0 -> 1; the forearm pronates and the trunk turns into the punch (MOTION_FACTS 3.5)."""
    guard = landmark(take, "chin") + take.scale() * np.array([0.0, -0.04, 0.03])
    reach(take, side, guard + env[:, None] * (straight_ahead(take, extension) - guard),
          elbow_hint=(0.5, -1.0, -0.2))
    take[f"{side}_elbow.pron"] = 60.0 * env
    turn_trunk(take, (-15.0 if side == "left" else 15.0) * env)  # a right punch turns the trunk left


def circle_arm(take: Take, side: str, phase: np.ndarray, *, flex: float, abd: float, radius: float,
               elbow=5.0) -> None:
    """``side``'s upper arm circling ``radius`` degrees around the direction (``flex``, ``abd``) once per
    cycle of ``phase``; both arms on one phase circle mirror-symmetrically."""
    cycle = 2.0 * np.pi * phase
    set_arm(take, side, flex + radius * np.sin(cycle), abd + radius * np.cos(cycle), elbow=elbow)


# --- stepping between stances, recoiling (interactions and fights) -------------------------------------------


def stance_steps(take: Take, steps, *, lift: float = 1.0) -> None:
    """Step from stance to stance: each step ``(start, duration, side, reach)`` lifts ``side``'s foot, swings it
    and plants it ``reach`` metres ahead of the pelvis (negative: behind), while the weight stays on the other
    foot, whose hip takes the opposite angle so the pelvis ends between the feet (a staggered stance, as
    :func:`step_out` leaves it). The grounding then moves the body by what the planted feet allow: steps
    back carry the body back. Feet start under the hips; a step with ``reach`` 0 closes the stance."""
    leg = 0.85 * take.scale()
    hips = {"left": 0.0, "right": 0.0}
    for start, duration, side, reach_m in steps:
        angle = float(np.degrees(np.arcsin(np.clip(0.5 * reach_m / leg, -0.6, 0.6))))
        support = other(side)
        keys = start + duration * np.array([0.0, 0.45, 1.0])
        # channels are additive: each step adds the change from the stance before it
        take[f"{side}_hip.flex"] += timing.keyframes(
            take.t, keys, [0.0, 0.5 * (angle - hips[side]) + 12.0 * lift, angle - hips[side]])
        take[f"{side}_knee.flex"] += timing.keyframes(take.t, keys, [0.0, 30.0 * lift, 0.0])
        take[f"{support}_hip.flex"] += timing.keyframes(take.t, keys[[0, 2]], [0.0, -angle - hips[support]])
        lifted = (take.t > keys[0] + 0.1 * duration) & (take.t < keys[2] - 0.1 * duration)
        take.contact[lifted, SIDES.index(side)] = 0.0
        take.contact[lifted, SIDES.index(support)] = 1.0
        hips[side], hips[support] = angle, -angle


def recoil(take: Take, time: float, *, strength: float = 1.0, where: str = "chest") -> None:
    """The body yields to a hit at ``time`` (MOTION_FACTS 5: the trunk gives 0.1-0.3 s after contact, then
    recovers): a hit to the ``head`` snaps the neck and upper trunk back, one to the ``chest`` pushes the trunk
    back, one to the ``stomach`` folds it forward; the arms flinch toward the body."""
    delay = take.vary(0.12, 0.3)
    keys = time + np.array([0.0, delay, delay + 0.15, delay + 0.8])
    jolt = strength * timing.keyframes(take.t, keys, [0.0, 0.0, 1.0, 0.0])
    if where == "head":
        take["neck.flex"] -= 25.0 * jolt
        take["head.flex"] -= 15.0 * jolt
        take["spine3.flex"] -= 8.0 * jolt
    elif where == "stomach":
        take["spine1.flex"] += 18.0 * jolt
        take["spine2.flex"] += 12.0 * jolt
        take["neck.flex"] += 10.0 * jolt
    else:
        take["spine2.flex"] -= 10.0 * jolt
        take["spine3.flex"] -= 8.0 * jolt
    for side in SIDES:
        take[f"{side}_elbow.flex"] += 35.0 * jolt
        take[f"{side}_shoulder.elev"] += 15.0 * jolt
