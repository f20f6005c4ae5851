"""The 7 CMU-mocap classes of ODMO (FACTS 1.2: A2M's order without Wash), as 100-frame, 12 fps clips.

Each clip lasts ~8.3 s, so the locomotion classes follow long paths that curve, turn back and change
speed. Mode names are the ground-truth style labels. Figures: MOTION_FACTS 3 and 4 (estimates where
marked).

The real set stores 20 joints (A2M's CMU skeleton); this stand-in keeps the SMPL-24 rotations and joints
of every synthetic variant. ``Step`` (high steps) goes up a flight of stairs and ``Climb`` up a ladder or a
steep rocky slope: the feet land on supports above the floor (``take.ground``) and the root rises.
"""

from __future__ import annotations

import numpy as np

from jaxmotion.data.synthetic import skills, timing
from jaxmotion.data.synthetic.engine import ActionClass
from jaxmotion.data.synthetic.take import SIDES, Take


def _turn_rate(take: Take, mode: str) -> np.ndarray:
    """``[T]`` heading rate (degrees/s, + = left) of a path: nearly straight, curving (a steady bend that
    drifts), or with one 180-degree turn back (est.: ~1.5 s to turn on foot)."""
    sign = take.choice((1.0, -1.0))
    rate = take.wander(4.0, 0.2)
    if mode == "curving":
        rate += sign * take.uniform(15.0, 35.0) + take.wander(12.0, 0.25)
    elif mode == "turn around":
        width = take.vary(1.6, 0.15)
        rate += sign * skills.bumps(take, [take.onset(width, 0.3)], width) * 180.0 / (0.5 * width)
    return rate


def _phase(take: Take, cadence: np.ndarray) -> np.ndarray:
    """Stride phase ``[T]`` (cycles) of a gait whose cadence ``[T]`` (steps/s) changes over the clip."""
    return take.uniform(0.0, 1.0) + np.concatenate([[0.0], np.cumsum(cadence[:-1])]) * take.tempo / (2 * take.fps)


def _speed_profile(take: Take, mode: str) -> np.ndarray:
    """``[T]`` relative speed: constant-ish, or slow <-> fast changes every few seconds."""
    if mode == "speed changes":
        return np.clip(1.0 + timing.smooth_noise(take.t, take.rng, 0.22, max_hz=0.3), 0.65, 1.35)
    return 1.0 + take.wander(0.03, 0.3)


def _travel(take: Take, curves: skills.GaitCurves, cadence: float, size: float, path: str, speed: str) -> None:
    """Locomotion along a path: cadence and stride length follow the speed profile (both grow with
    speed, MOTION_FACTS 3.1)."""
    skills.stand(take)
    relative = _speed_profile(take, speed)
    skills.gait(take, curves, cadence=cadence, size=take.vary(size, 0.05) * np.sqrt(relative),
                phase=_phase(take, take.vary(cadence, 0.05) * np.sqrt(relative)))
    skills.steer(take, _turn_rate(take, path))


def walk(take: Take) -> None:
    _travel(take, skills.WALK, 1.8, 1.0, take.mode, take.mode)


def run(take: Take) -> None:
    _travel(take, skills.RUN, 2.8, 1.1, take.mode, "steady")
    take["spine1.flex"] += 3.0


def jump(take: Take) -> None:
    skills.stand(take)
    forward = take.vary(0.8, 0.2) if take.mode == "forward" else 0.0
    height = take.vary(0.2 if take.mode == "forward" else 0.28, 0.2)
    flight = np.sqrt(8.0 * height / 9.81)
    t = take.uniform(0.2, 0.8)
    turns = np.zeros(take.num_frames)
    while t + 1.8 < take.duration:
        end = skills.jump(take, t, height=height, forward=forward)
        if take.mode == "turning":  # a quarter turn in the air (take-off ~0.6 s into the jump)
            turns += take.choice((90.0, -90.0)) * timing.keyframes(take.t, [t + 0.6, t + 0.6 + flight], [0, 1])
        t = end + take.uniform(0.2, 1.0)
    take["pelvis.heading"] += turns


def _flap(take: Take, rate: float, size: float) -> None:
    """Arms flapping like wings: sideways elevation oscillating about shoulder height."""
    beat = np.sin(2 * np.pi * timing.warped_phase(take.t, rate * take.tempo, take.rng))
    for side in SIDES:
        skills.set_arm(take, side, 10.0, 70.0 + size * take.amp * beat, elbow=15.0 - 10.0 * beat)
        take[f"{side}_wrist.flex"] = 20.0 * beat


def animal_behavior(take: Take) -> None:
    if take.mode == "frog hops":  # deep crouch, hands down between hops, leaps forward
        skills.stand(take)
        skills.crouch(take, take.vary(95.0, 0.1), take.vary(40.0, 0.15), heel=10.0)  # the frog's rest
        t = take.uniform(0.2, 0.6)
        while t + 1.5 < take.duration:
            t = skills.jump(take, t, height=take.vary(0.15, 0.2), forward=take.vary(0.6, 0.2), dip=0.5,
                            arm_swing=0.4) + take.uniform(0.1, 0.5)
        crouched = np.clip((take["left_knee.flex"] - 40.0) / 70.0, 0.0, 1.0)
        for side in SIDES:  # the hands go to the floor as the body folds
            skills.set_arm(take, side, 30.0 + 60.0 * crouched, 15.0, elbow=10.0)
        return
    skills.stand(take)
    if take.mode == "crouch walk":  # ape-like: bent knees, trunk forward, arms dangling and swinging
        skills.gait(take, skills.WALK, cadence=take.vary(1.6, 0.08), size=take.vary(0.75, 0.08))
        lean = take.vary(45.0, 0.15)
        skills.crouch(take, take.vary(55.0, 0.15), lean)
        for side in SIDES:
            take[f"{side}_shoulder.elev"] += lean
            take[f"{side}_elbow.flex"] += 15.0
    else:  # bird: slow walk, flapping wings, head bobbing
        skills.gait(take, skills.WALK, cadence=take.vary(1.5, 0.1), size=take.vary(0.8, 0.08))
        _flap(take, take.vary(1.2, 0.15), take.vary(40.0, 0.15))
        take["spine1.flex"] += take.vary(15.0, 0.3)
        take["neck.flex"] += 10.0 * np.sin(2 * np.pi * take.vary(1.5, 0.2) * take.t)
    skills.steer(take, _turn_rate(take, take.choice(("straight", "curving"))))


def dance(take: Take) -> None:
    skills.stand(take)
    beat = take.vary(2.0, 0.12) * take.tempo  # beats per second (~120 bpm)
    if take.mode == "step-touch":  # side to side on the beat, knees bouncing, arms swinging across
        phase = timing.warped_phase(take.t, 0.5 * beat, take.rng, wobble=0.02)
        skills.side_steps(take, phase, width=take.vary(14.0, 0.2))
        swing = np.sin(np.pi * phase)
        skills.crouch(take, 8.0 + 8.0 * np.abs(np.sin(2 * np.pi * phase)), 2.0)
        for k, side in enumerate(SIDES):
            skills.set_arm(take, side, 40.0 + 30.0 * swing * (1 - 2 * k), 30.0 + 20.0 * swing, elbow=80.0)
        take["spine2.bend"] += 6.0 * swing
        take["pelvis.heading"] += take.wander(20.0, 0.15)
    else:  # spins on one foot with the arms out, weight shifts and arm gestures in between
        pivot = take.choice(SIDES)
        width = take.vary(1.2, 0.15)
        spins = skills.beats(take, take.vary(2.6, 0.15), jitter=0.2)
        spins = spins[spins + width < take.duration]
        turning = skills.bumps(take, spins, width)
        take["pelvis.heading"] += take.choice((1.0, -1.0)) * 360.0 / (0.5 * width) * np.cumsum(turning) / take.fps
        lifted = SIDES.index(pivot) ^ 1
        take.contact[:, lifted] *= 1.0 - np.minimum(2.0 * turning, 1.0)
        take[f"{SIDES[lifted]}_hip.flex"] += 20.0 * turning
        take[f"{SIDES[lifted]}_knee.flex"] += 40.0 * turning
        sway = np.sin(2 * np.pi * 0.5 * beat * take.t)
        skills.crouch(take, 6.0 + 6.0 * np.abs(sway), 0.0)
        for k, side in enumerate(SIDES):
            gesture = 0.5 + 0.5 * np.sin(np.pi * beat * take.t / 2 + k * np.pi)
            skills.set_arm(take, side, 30.0 + 90.0 * gesture * (1 - turning), 30.0 + 50.0 * turning,
                           elbow=60.0 * (1 - turning) + 10.0)
        take["pelvis.obliquity"] += 3.0 * sway


def _moves(take: Take, rate: float) -> np.ndarray:
    """Phase ``[T]`` for :func:`skills.stairs` at ``rate`` moves/s: standing still for the first ~0.2-0.8 s."""
    rate = take.vary(rate, 0.1) * take.tempo
    return timing.warped_phase(take.t, 0.5 * rate, take.rng, wobble=0.04, start=-0.5 * rate * take.uniform(0.2, 0.8))


def step(take: Take) -> None:
    skills.stand(take)
    if take.mode == "high steps":  # up a flight of stairs, foot over foot, leaning a little into them
        skills.stairs(take, _moves(take, 1.0), rise=take.uniform(0.15, 0.22), tread=take.uniform(0.25, 0.32))
        take["spine1.flex"] += take.vary(6.0, 0.3)
        skills.steer(take, _turn_rate(take, "straight"))
    else:  # side steps: leading foot out, the other closes, travelling sideways
        phase = timing.warped_phase(take.t, take.vary(1.0, 0.15) * take.tempo, take.rng)
        skills.side_steps(take, phase, width=take.vary(15.0, 0.2), travel=take.choice((1, -1)))
        take["pelvis.heading"] += take.wander(8.0, 0.2)


def climb(take: Take) -> None:
    skills.stand(take)
    ladder = take.mode == "ladder"
    phase = _moves(take, 1.2 if ladder else 1.0)
    if ladder:  # rungs ~25-30 cm apart straight above each other: the feet land under the hips
        skills.stairs(take, phase, rise=take.uniform(0.24, 0.3), tread=0.04)
    else:  # scrambling up a steep slope: bent over, high steps, hands reaching for holds
        skills.crouch(take, 0.0, take.vary(35.0, 0.2))  # the trunk only: stairs() bends the legs to fit the steps
        skills.stairs(take, phase, rise=take.uniform(0.2, 0.26), tread=take.uniform(0.2, 0.28))
        skills.steer(take, _turn_rate(take, "straight"))
    for k, side in enumerate(SIDES):
        reach_up = timing.pulses(phase - 0.5 * (1 - k), 0.45, 0.15)  # with the other leg's lift
        if ladder:  # hands hand over hand on the rails
            low, high = np.array([0.15, 0.15, 0.25]), np.array([0.1, 0.62, 0.15])
        else:
            low, high = np.array([0.15, 0.05, 0.35]), np.array([0.1, 0.45, 0.4])
        target = take.shoulder_point() + take.scale() * (low + reach_up[:, None] * (high - low))
        skills.reach(take, side, target, elbow_hint=(0.5, -1.0, -0.2))


CLASSES = (
    ActionClass("Walk", ("straight", "curving", "speed changes", "turn around"), walk, weight=2.0),
    ActionClass("Run", ("straight", "curving", "turn around"), run, weight=1.2),
    ActionClass("Jump", ("forward", "in place", "turning"), jump),
    ActionClass("Animal Behavior", ("crouch walk", "frog hops", "bird flaps"), animal_behavior, weight=0.6),
    ActionClass("Dance", ("step-touch", "spins"), dance),
    ActionClass("Step", ("high steps", "side steps"), step, weight=0.7),
    ActionClass("Climb", ("ladder", "scramble"), climb, weight=0.5),
)
