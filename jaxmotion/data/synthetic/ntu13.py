"""The 13 NTU-13 action classes (FACTS 1.1 order: NTU actions 6, 7, 8, 9, 22, 23, 24, 38, 80, 93, 99, 100, 102).

Mode names are the ground-truth style labels; one-sided modes are named by the acting side. Throwing and
sitting down are the HumanAct12 compositions (same skills, same modes). Figures: MOTION_FACTS 3 and 4.
"""

from __future__ import annotations

import numpy as np

from jaxmotion.data.synthetic import humanact12, skills, timing
from jaxmotion.data.synthetic.engine import ActionClass
from jaxmotion.data.synthetic.take import SIDES, Take, other


def _side(take: Take) -> str:
    """The acting side named by the mode, else the right (most people use their right hand or leg)."""
    return "left" if "left" in take.mode else "right"


def _down_hold_up(take: Take, down: float, hold: float, up: float | None) -> np.ndarray:
    """``[T]`` envelope 0 -> 1 over ``down`` s, held ``hold`` s, back to 0 over ``up`` s (None: stays down)."""
    busy = down + hold + (up or 0.0)
    t0 = take.onset(busy)
    if up is None:
        return timing.keyframes(take.t, [t0, t0 + down], [0.0, 1.0])
    return timing.keyframes(take.t, [t0, t0 + down, t0 + down + hold, t0 + busy], [0.0, 1.0, 1.0, 0.0])


# Pick-up folds: (knee flexion, trunk lean, heel raise), degrees. A stoop bends the trunk past horizontal on
# nearly straight knees; a squat folds the knees with a moderate lean (MOTION_FACTS 4: hip flexion >= 90).
PICKUP_FOLDS = {"squat": (120.0, 60.0, 10.0), "stoop": (40.0, 120.0, 0.0)}


def pickup(take: Take) -> None:
    skills.stand(take)
    knee, lean, heel = PICKUP_FOLDS[take.mode]
    fold = _down_hold_up(take, take.vary(1.1, 0.15) / take.tempo, take.vary(0.4, 0.3), take.vary(1.1, 0.15) / take.tempo)
    lean = take.vary(lean, 0.08) * fold
    skills.crouch(take, take.vary(knee, 0.08) * fold, lean, heel=heel * fold)
    hand = take.choice(SIDES) if take.rng.uniform() < 0.3 else "right"
    grasped = (take.t >= take.t[np.argmax(fold)]).astype(float)  # holding the object from the lowest point on
    # The reaching arm points at the floor in front of the feet (flexion = trunk lean, plus a little
    # forward); once it has the object, the elbow bends to carry it at the waist on the way up.
    skills.set_arm(take, hand, lean + 10.0 * fold, 6.0, elbow=take.subject.arm_carry * (1.0 - fold)
                   + 35.0 * grasped * (1.0 - fold))
    skills.set_arm(take, other(hand), lean * (0.7 + 0.3 * take.uniform(0.0, 1.0)), 10.0,
                   elbow=take.subject.arm_carry + 20.0 * fold)
    take["neck.flex"] += 10.0 * fold  # eyes on the object


def standing_up(take: Take) -> None:
    skills.stand(take)
    duration = take.vary(2.0, 0.15) / take.tempo
    skills.sit_transition(take, take.onset(duration + 0.5), duration, down=False,
                          hand_push=take.mode == "with hand push")


def _bounce(take: Take, rate: float, depth: float, *, heel: float = 0.0) -> np.ndarray:
    """Rhythmic knee bounce at ``rate`` /s (a shallow balanced crouch, heels lifting); returns its ``[T]`` 0..1."""
    b = 0.5 - 0.5 * np.cos(2 * np.pi * timing.warped_phase(take.t, rate * take.tempo, take.rng))
    skills.crouch(take, depth * b + 4.0, 3.0 * b, heel=heel * b)
    return b


def cheer_up(take: Take) -> None:
    skills.stand(take)
    s = take.amp
    if take.mode == "fist pumps":  # fists thrust from the shoulders to overhead, a dip with each thrust
        pumps = skills.bumps(take, skills.beats(take, take.vary(0.65, 0.15), jitter=0.12), take.vary(0.5, 0.1))
        skills.crouch(take, 12.0 * pumps + 4.0, 2.0 * pumps)
        for side in SIDES:
            skills.set_arm(take, side, 30.0 + 120.0 * s * pumps, 60.0 - 35.0 * pumps, rot=-40.0 * (1 - pumps),
                           elbow=120.0 - 110.0 * pumps)
            take[f"{side}_wrist.flex"] = -15.0  # clenched fist
    elif take.mode == "open hands with bounce":  # arms up in a V, hands swaying, bouncing on the toes
        _bounce(take, take.vary(2.0, 0.1), 14.0, heel=15.0)
        sway = 12.0 * np.sin(2 * np.pi * take.vary(1.0, 0.2) * take.t)
        for side in SIDES:
            skills.set_arm(take, side, 25.0 + take.wander(5.0), take.vary(145.0, 0.06) * s + sway, elbow=15.0)
            take[f"{side}_wrist.dev"] = 0.8 * sway
        take["neck.flex"] -= 10.0
    else:  # jumping: small jumps, fists thrust up at every take-off
        t = take.uniform(0.1, 0.4)
        lift = np.zeros(take.num_frames)
        while t + 1.3 < take.duration:
            end = skills.jump(take, t, height=take.vary(0.12, 0.25), dip=0.6, arm_swing=0.0)
            lift = np.maximum(lift, skills.bumps(take, [t + 0.3], end - t - 0.2))
            t = end + take.uniform(0.0, 0.3)
        for side in SIDES:
            skills.set_arm(take, side, 40.0 + 110.0 * s * lift, 40.0 - 15.0 * lift, elbow=100.0 - 90.0 * lift)


# Hand-waving postures: wrist position relative to the shoulder (side-normalised thorax frame, metres at
# template size), sideways wave amplitude (m) and rate (waves/s); MOTION_FACTS 4: shoulder 90-150,
# elbow ~90, forearm +-30 degrees, 2-3 waves/s; a high wave swings the whole raised arm, more slowly.
WAVES = {"normal": ((0.18, 0.36, 0.14), 0.11, 2.4), "high": ((0.12, 0.60, 0.06), 0.22, 1.4),
         "low": ((0.02, 0.02, 0.38), 0.07, 2.8)}


def hand_waving(take: Take) -> None:
    skills.stand(take)
    side = _side(take)
    offset, amplitude, rate = WAVES.get(take.mode, WAVES["normal"])
    busy = take.vary(0.8, 0.2) * take.duration
    up = _down_hold_up(take, take.vary(0.45, 0.15), busy, take.vary(0.5, 0.15))
    phase = timing.warped_phase(take.t, take.vary(rate, 0.12) * take.tempo, take.rng)
    wave = amplitude * take.amp * take.scale() * np.sin(2 * np.pi * phase) * up
    target = take.shoulder_point() + take.scale() * np.asarray(offset) + np.stack(
        [wave, -0.15 * np.abs(wave), np.zeros_like(wave)], axis=-1)
    skills.toward(take, side, up, target, elbow_hint=(1.0, -0.4, -0.2))
    take[f"{side}_elbow.pron"] = -10.0 * up
    take[f"{side}_wrist.dev"] = 60.0 * wave / take.scale()  # the hand flaps with the forearm
    take["neck.twist"] += (8.0 if side == "left" else -8.0) * up  # looking toward whom one waves at


def kicking_something(take: Take) -> None:
    skills.stand(take, heading=take.rng.normal(0.0, 15.0))
    side = _side(take)
    start = take.onset(1.6)
    if take.rng.uniform() < 0.5:  # a short approach step with the standing foot
        skills.step_out(take, other(side), start, 0.5, length=take.vary(0.3, 0.2) * take.scale())
        start += 0.45
    end = skills.kick(take, side, start, height=take.vary(0.9, 0.15), duration=take.vary(0.95, 0.1) / take.tempo)
    swing = timing.keyframes(take.t, [start, start + 0.35, end], [0.0, 1.0, 0.0])
    skills.set_arm(take, other(side), 10.0 + 40.0 * swing, 25.0 * swing, elbow=take.subject.arm_carry + 30 * swing)
    skills.set_arm(take, side, 5.0 - 30.0 * swing, 20.0 * swing, elbow=take.subject.arm_carry + 15 * swing)
    take["neck.flex"] += 12.0 * swing  # eyes on the object


def salute(take: Take) -> None:
    skills.stand(take)
    crisp = take.mode == "crisp"
    if crisp:  # at attention: straight, heels together, the other arm straight down
        take["spine1.flex"] -= 2.0
        skills.set_arm(take, "left", 0.0, 4.0, elbow=3.0)
        for leg in SIDES:
            take[f"{leg}_hip.abd"] -= 2.0
    raise_t = take.vary(0.3 if crisp else 0.6, 0.15)
    up = _down_hold_up(take, raise_t, take.vary(1.4 if crisp else 1.0, 0.25),
                       take.vary(0.3 if crisp else 0.6, 0.15))
    hint = (1.0, -0.1, 0.1) if crisp else (0.7, -0.6, 0.4)  # crisp: elbow out level with the shoulder
    skills.toward(take, "right", up, skills.landmark(take, "brow"), elbow_hint=hint, bulge=0.05)
    take["right_elbow.pron"] = 70.0 * up
    take["right_wrist.dev"] = (-10.0 if crisp else 5.0) * up
    if not crisp:
        take["neck.bend"] -= 5.0 * up


# Squat-down holds: (knee flexion, trunk lean, heel raise), degrees (MOTION_FACTS 3.4; a deep squat goes onto
# the balls of the feet).
SQUATS = {"arms forward": (105.0, 25.0, 5.0), "hands on knees": (95.0, 40.0, 0.0), "deep": (140.0, 30.0, 28.0)}


def squat_down(take: Take) -> None:
    skills.stand(take)
    knee, lean, heel = SQUATS[take.mode]
    rises = take.rng.uniform() < 0.5  # some clips end crouched, some stand back up
    fold = _down_hold_up(take, take.vary(1.6, 0.15) / take.tempo, take.vary(1.5, 0.3),
                         take.vary(1.2, 0.15) / take.tempo if rises else None)
    lean = take.vary(lean, 0.1) * fold
    skills.crouch(take, take.vary(knee, 0.06) * fold, lean, heel=heel * fold)
    for side in SIDES:
        if take.mode == "arms forward":  # arms reach forward as a counterweight
            skills.set_arm(take, side, 5.0 + 85.0 * fold, 8.0, elbow=take.subject.arm_carry * (1 - fold) + 5.0)
        elif take.mode == "hands on knees":
            skills.set_arm(take, side, 5.0 + (lean + 45.0) * fold, 8.0 + 6.0 * fold,
                           elbow=take.subject.arm_carry + 10.0 * fold)
        else:  # forearms resting forward over the knees
            skills.set_arm(take, side, 5.0 + 55.0 * fold, 15.0 * fold, elbow=take.subject.arm_carry + 50.0 * fold)


# Fist postures: wrist relative to the shoulder (side-normalised thorax frame, m at template size).
FISTS = {"raised": (0.10, 0.30, 0.14), "forward": (0.0, 0.05, 0.30)}


def shake_fist(take: Take) -> None:
    skills.stand(take)
    side = _side(take)
    offset = FISTS["forward" if take.mode.endswith("forward") else "raised"]
    up = _down_hold_up(take, take.vary(0.45, 0.15), take.vary(0.7, 0.2) * take.duration, take.vary(0.5, 0.15))
    # Bursts of a small 3-5 Hz shake (MOTION_FACTS 4), the fist moving along the forearm.
    burst = np.clip(0.7 + take.wander(0.6, 0.5), 0.0, 1.0) * up
    shake = take.vary(0.035, 0.2) * take.scale() * burst * np.sin(2 * np.pi * take.uniform(3.0, 5.0) * take.t)
    target = take.shoulder_point() + take.scale() * np.asarray(offset) + shake[:, None] * np.array([0.0, 0.6, 0.8])
    skills.toward(take, side, up, target, elbow_hint=(0.8, -0.6, -0.2))
    take[f"{side}_wrist.flex"] = -20.0 * up
    take["spine1.flex"] += 5.0 * up  # leaning in, head forward
    take["neck.flex"] -= 4.0 * up


SPOT_RUNS = {"normal": (2.8, 1.0), "high knees": (3.2, 1.8)}  # cadence (steps/s), size


def running_on_the_spot(take: Take) -> None:
    skills.stand(take)
    cadence, size = SPOT_RUNS[take.mode]
    skills.gait(take, skills.SPOT_RUN, cadence=take.vary(cadence, 0.06), size=take.vary(size, 0.06))
    skills.in_place(take)


def butt_kicks(take: Take) -> None:
    skills.stand(take)
    skills.gait(take, skills.BUTT_KICKS, cadence=take.vary(3.0, 0.06), size=take.vary(1.0, 0.05))
    skills.in_place(take)
    if take.mode == "hands behind":  # palms on the buttocks, elbows back
        behind = take.scale() * np.array([0.13, -0.4, -0.15])
        for side in SIDES:
            skills.reach(take, side, behind, elbow_hint=(0.3, -0.2, -1.0))
            take[f"{side}_elbow.pron"] = 0.0


def side_kick(take: Take) -> None:
    side = _side(take)
    # The body half-turns so that the kicking hip faces the target.
    turn = (1.0 if side == "right" else -1.0) * take.uniform(10.0, 40.0)
    skills.stand(take, heading=take.rng.normal(0.0, 15.0) + turn)
    kicks = 1 if take.duration < 3.0 or take.rng.uniform() < 0.5 else 2
    start = take.onset(1.2 * kicks)
    for _ in range(kicks):
        start = skills.kick(take, side, start, height=take.vary(0.9, 0.15), lateral=1.0,
                            duration=take.vary(1.0, 0.1) / take.tempo) + take.uniform(0.0, 0.2)
    guard = skills.landmark(take, "chin") + np.array([0.0, -0.05, 0.02])
    for arm in SIDES:
        skills.reach(take, arm, guard, elbow_hint=(0.4, -1.0, 0.0))


CLASSES = (
    ActionClass("pickup", tuple(PICKUP_FOLDS), pickup),
    ActionClass("throw", ("overarm", "underarm"), humanact12.throw),
    ActionClass("sitting down", ("with hand push", "without hand push"), humanact12.sit),
    ActionClass("standing up", ("with hand push", "without hand push"), standing_up),
    ActionClass("cheer up", ("fist pumps", "open hands with bounce", "jumping"), cheer_up),
    ActionClass("hand waving", ("right", "left", "high", "low"), hand_waving),
    ActionClass("kicking something", ("right", "left"), kicking_something),
    ActionClass("salute", ("crisp", "relaxed"), salute),
    ActionClass("squat down", tuple(SQUATS), squat_down),
    ActionClass("shake fist", ("right raised", "left raised", "right forward"), shake_fist),
    ActionClass("running on the spot", tuple(SPOT_RUNS), running_on_the_spot),
    ActionClass("butt kicks", ("arms swinging", "hands behind"), butt_kicks),
    ActionClass("side kick", ("right", "left"), side_kick),
)
