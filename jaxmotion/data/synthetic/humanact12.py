"""The 12 HumanAct12 action classes (FACTS 1.1 order), each a short composition of skills.

Mode names are the ground-truth style labels. Timings and angles: MOTION_FACTS sections 3 and 4.
"""

from __future__ import annotations

import numpy as np

from jaxmotion.data.synthetic import skills, timing
from jaxmotion.data.synthetic.engine import ActionClass
from jaxmotion.data.synthetic.take import SIDES, Take, other


def _side(take: Take) -> str:
    """The acting side named by the mode (``left ...`` / ``right ...``), else the right hand."""
    return "left" if take.mode.startswith("left") else "right"


def warm_up(take: Take) -> None:
    skills.stand(take)
    if take.mode == "arm circles":
        rate = take.vary(1.2, 0.15) * take.tempo
        direction = take.choice((1.0, -1.0))
        radius = take.amp * take.vary(25.0, 0.2)
        phase = timing.warped_phase(take.t, rate, take.rng)
        for side in SIDES:
            cycle = 2 * np.pi * phase
            skills.set_arm(take, side, radius * np.sin(cycle) * direction, 80.0 + radius * np.cos(cycle),
                           elbow=5.0)
    elif take.mode == "trunk twists":
        phase = timing.warped_phase(take.t, take.vary(0.6, 0.15) * take.tempo, take.rng)
        twist = take.amp * take.vary(30.0, 0.15) * np.sin(2 * np.pi * phase)
        for joint, share in (("spine1", 0.15), ("spine2", 0.45), ("spine3", 0.4)):
            take[f"{joint}.twist"] += share * twist
        take["pelvis.heading"] += 0.25 * twist
        take["neck.twist"] += 0.3 * twist
        for side in SIDES:  # elbows out at chest height, forearms horizontal
            skills.set_arm(take, side, 15.0, 80.0, rot=-80.0, elbow=110.0)
    else:  # leg swings: one leg swings like a pendulum, arms out for balance
        side = take.choice(SIDES)
        phase = timing.warped_phase(take.t, take.vary(0.9, 0.1) * take.tempo, take.rng)
        swing = take.amp * take.vary(35.0, 0.15)
        take[f"{side}_hip.flex"] += 10.0 + swing * np.sin(2 * np.pi * phase)
        take[f"{side}_knee.flex"] += 25.0 - 12.0 * np.sin(2 * np.pi * phase)  # bent most when behind
        take[f"{side}_ankle.dorsi"] += 5.0  # toes up, clearing the floor
        take[f"{other(side)}_hip.abd"] -= 4.0  # weight over the standing leg
        take["pelvis.obliquity"] += 3.0 if side == "right" else -3.0
        take.contact[:, SIDES.index(side)] = 0.0
        take.contact[:, SIDES.index(other(side))] = 1.0
        for arm in SIDES:
            skills.set_arm(take, arm, 5.0, take.vary(45.0, 0.15), elbow=15.0)


WALK_MODES = {"slow": (1.7, 0.92, 0.0), "fast": (2.05, 1.15, 0.0), "turning": (1.8, 1.0, 40.0)}
RUN_MODES = {"jog": (2.7, 1.1), "fast": (3.0, 1.2)}


def walk(take: Take) -> None:
    skills.stand(take)
    cadence, size, turn = WALK_MODES[take.mode]
    turn = turn * take.choice((1.0, -1.0)) * take.vary(1.0, 0.2)
    skills.gait(take, skills.WALK, cadence=take.vary(cadence, 0.05), size=take.vary(size, 0.05), turn=turn)


def run(take: Take) -> None:
    skills.stand(take)
    cadence, size = RUN_MODES[take.mode]
    skills.gait(take, skills.RUN, cadence=take.vary(cadence, 0.05), size=take.vary(size, 0.05))
    take["spine1.flex"] += 3.0 * size


def jump(take: Take) -> None:
    skills.stand(take)
    forward = take.mode == "forward"
    height = take.vary(0.22 if forward else 0.3, 0.2)
    t = take.uniform(0.1, 0.5)
    while True:
        t_end = skills.jump(take, t, height=height, forward=take.vary(0.9, 0.2) if forward else 0.0)
        t = t_end + take.uniform(0.1, 0.5)
        if t + 1.6 > take.duration:
            break


def _sips(take: Take, period: float, hold: float) -> np.ndarray:
    """``[T]`` envelope 0 -> 1 -> 0 of repeated hand-to-mouth movements."""
    env = np.zeros(take.num_frames)
    for t0 in skills.beats(take, period, jitter=0.2):
        move = take.vary(0.6, 0.15)
        keys = [t0, t0 + move, t0 + move + take.vary(hold, 0.3), t0 + 2 * move + hold]
        env = np.maximum(env, timing.keyframes(take.t, keys, [0.0, 1.0, 1.0, 0.0]))
    return env


def drink(take: Take) -> None:
    skills.stand(take)
    if take.mode == "seated":
        skills.seated(take)
    side = take.choice(SIDES) if take.mode == "seated" else _side(take)
    sip = _sips(take, take.vary(2.8, 0.15), hold=0.8)
    skills.toward(take, side, sip, skills.landmark(take, "mouth"), elbow_hint=(0.5, -1.0, 0.2))
    take[f"{side}_elbow.pron"] = -40.0 * sip  # supinate, cup to the lips
    tip = take.vary(28.0, 0.2) * timing.keyframes(take.t, [0.0, 0.3], [0.0, 1.0]) * sip**2
    take["neck.flex"] -= 0.5 * tip
    take["head.flex"] -= 0.5 * tip


def eat(take: Take) -> None:
    skills.stand(take)
    bites = _sips(take, take.vary(1.8, 0.15), hold=0.3)
    plate = skills.landmark(take, "bowl")
    mouth = skills.landmark(take, "mouth")
    if take.mode == "both hands":  # a sandwich held in both hands
        for side in SIDES:
            skills.toward(take, side, bites, mouth + np.array([-0.03, 0.0, 0.04]), start=plate,
                          elbow_hint=(0.7, -1.0, 0.0))
            take[f"{side}_elbow.pron"] = -30.0
    else:  # a spoon in one hand, the bowl held in the other
        side = _side(take)
        skills.toward(take, side, bites, mouth, start=plate, elbow_hint=(0.6, -1.0, 0.0))
        skills.reach(take, other(side), plate + np.array([-0.06, 0.02, 0.0]))
        take[f"{other(side)}_elbow.pron"] = -60.0
    take["neck.flex"] += 12.0 * (1.0 - bites)
    take["spine2.flex"] += 4.0


def lift_dumbbell(take: Take) -> None:
    skills.stand(take)
    period = take.vary(2.0, 0.15)
    reps = skills.beats(take, period, jitter=0.1)
    lift = np.zeros(take.num_frames)
    for t0 in reps:
        up = take.vary(0.8, 0.1)
        lift = np.maximum(lift, timing.keyframes(take.t, [t0, t0 + up, t0 + up + 0.15, t0 + period * 0.9],
                                                 [0, 1, 1, 0]))
    if take.mode == "overhead press":  # from the shoulders to overhead and back
        for side in SIDES:
            skills.set_arm(take, side, 20.0 - 10.0 * lift, 75.0 + 90.0 * take.amp * lift, rot=-85.0 + 10 * lift,
                           elbow=110.0 * (1.0 - lift) + 5.0)
        take["spine1.flex"] -= 4.0 * lift
    else:  # curls: elbow 0 -> ~140 with the upper arm still; one arm or both
        arms = SIDES if take.mode == "two-arm curl" else (take.choice(SIDES),)
        for side in arms:
            take[f"{side}_elbow.flex"] = 10.0 + 125.0 * lift * take.amp
            take[f"{side}_elbow.pron"] = -70.0
            take[f"{side}_shoulder.elev"] = 8.0 + 8.0 * lift
        take["spine1.flex"] -= 3.0 * lift


def sit(take: Take) -> None:
    skills.stand(take)
    duration = take.vary(2.0, 0.15) / take.tempo
    skills.sit_transition(take, take.onset(duration + 0.5), duration, down=True,
                          hand_push=take.mode == "with hand push")


def turn_steering_wheel(take: Take) -> None:
    skills.stand(take)
    skills.seated(take)
    s = take.scale()
    centre = s * np.array([0.0, -0.08, 0.42])
    radius = s * take.vary(0.17, 0.1)
    turns = skills.beats(take, take.vary(2.0, 0.2), jitter=0.2)
    wheel = np.zeros(take.num_frames)
    for k, t0 in enumerate(turns):
        wheel += take.amp * take.vary(70.0, 0.3) * (-1.0) ** k * skills.bumps(take, [t0], take.vary(1.6, 0.15))
    angle = np.radians(wheel)
    hands = SIDES if take.mode == "both hands" else ("right",)
    for side in hands:
        grip = np.radians(30.0 if side == "left" else 150.0) + angle  # 10 and 2 o'clock
        x = radius * np.cos(grip)
        target = np.stack([(x if side == "left" else -x) + centre[0], centre[1] + radius * np.sin(grip),
                           np.full_like(x, centre[2])], axis=-1)
        skills.reach(take, side, target, elbow_hint=(0.8, -1.0, -0.2))
        take[f"{side}_elbow.pron"] = 60.0
    take["spine2.twist"] += 0.05 * wheel
    take["neck.twist"] += 0.1 * wheel


def phone(take: Take) -> None:
    skills.stand(take)
    if take.mode == "texting":
        thumbs = 6.0 * np.sin(2 * np.pi * take.vary(3.0, 0.2) * take.t) * (take.wander(1.0, 0.5) > 0)
        for side in SIDES:
            skills.reach(take, side, skills.landmark(take, "chest") + np.array([-0.03, 0.0, -0.08]),
                         elbow_hint=(0.3, -1.0, -0.2))
            take[f"{side}_elbow.pron"] = -50.0
            take[f"{side}_wrist.flex"] = -20.0 + thumbs
        take["neck.flex"] += take.vary(25.0, 0.2)
        take["head.flex"] += 10.0
    else:
        side = _side(take)
        raise_t = take.uniform(0.0, 0.3) * take.duration
        up = timing.keyframes(take.t, [raise_t, raise_t + take.vary(0.8, 0.15)], [0.0, 1.0])
        skills.toward(take, side, up, skills.landmark(take, "ear"), elbow_hint=(0.6, -0.6, 0.5))
        take[f"{side}_elbow.pron"] = -20.0 * up
        take["neck.bend"] += (4.0 if side == "left" else -4.0) * up
        gesture = skills.bumps(take, skills.beats(take, 2.5, jitter=0.4), 1.0) * take.uniform(0.0, 1.0)
        skills.set_arm(take, other(side), 10.0 + 25.0 * gesture, 10.0,
                       elbow=take.subject.arm_carry + 50.0 * gesture)


def boxing(take: Take) -> None:
    skills.stand(take, heading=take.rng.normal(20.0, 10.0))
    lead = "left"  # orthodox stance: left foot and hand forward
    take[f"{lead}_hip.flex"] += 15.0
    take[f"{other(lead)}_hip.flex"] -= 12.0
    bounce = 5.0 * (1.0 + np.sin(2 * np.pi * take.vary(2.0, 0.15) * take.t))
    for side in SIDES:
        take[f"{side}_knee.flex"] += 12.0 + bounce
        take[f"{side}_ankle.dorsi"] += 5.0 + 0.5 * bounce
        take[f"{side}_hip.flex"] += 5.0 + 0.5 * bounce
    take["spine2.twist"] -= 10.0
    take["spine1.flex"] += 6.0
    take["neck.twist"] += 10.0
    chin = skills.landmark(take, "chin")
    hooks = take.mode == "hooks"
    punches = skills.beats(take, take.vary(0.45, 0.15), jitter=0.3)
    for side in SIDES:
        guard = chin + (np.array([0.0, -0.03, 0.05]) if side == lead else np.array([-0.02, -0.05, -0.02]))
        mine = punches[(np.arange(len(punches)) % 2 == 0) == (side == lead)]
        hit = skills.bumps(take, mine, take.vary(0.32, 0.1))
        if hooks:  # elbow stays bent, the fist sweeps in from the side at head height
            sweep = np.radians(100.0 * hit)
            arc = 0.3 * take.scale()
            target = guard + np.stack([arc * np.sin(sweep) * 0.8, 0.05 * hit, arc * np.sin(0.5 * sweep)], -1)
            skills.reach(take, side, target, elbow_hint=(1.0, -0.2, -0.3))
            twist = 18.0 * hit
        else:
            straight = skills.straight_ahead(take, 0.95)
            target = guard + hit[:, None] * (straight - guard)
            skills.reach(take, side, target, elbow_hint=(0.5, -1.0, -0.2))
            twist = 15.0 * hit * (1.0 if side == other(lead) else 0.5)
        sign = 1.0 if side == "right" else -1.0  # a right punch turns the trunk to the left
        take["spine2.twist"] += sign * twist
        take["spine3.twist"] += sign * twist * 0.6
        take["pelvis.heading"] += sign * 0.4 * twist
        take[f"{side}_elbow.pron"] = 60.0 * hit


def throw(take: Take) -> None:
    skills.stand(take)
    arm = take.choice(SIDES) if take.rng.uniform() < 0.15 else "right"
    lead = other(arm)
    t0 = take.onset(1.8)
    windup, strike, follow = take.vary(0.5, 0.15), take.vary(0.2, 0.1), take.vary(0.5, 0.15)
    keys = [t0, t0 + windup, t0 + windup + strike, t0 + windup + strike + follow,
            t0 + windup + strike + follow + 0.6]

    def curve(*values):
        return timing.keyframes(take.t, keys, values)

    skills.step_out(take, lead, t0, windup + 0.5 * strike, length=take.vary(0.45, 0.2) * take.scale())
    sign = 1.0 if arm == "right" else -1.0  # throwing with the right turns the trunk right then left
    trunk = curve(0, -35, 25, 20, 5) * take.amp
    take["spine1.twist"] += sign * 0.2 * trunk
    take["spine2.twist"] += sign * 0.4 * trunk
    take["spine3.twist"] += sign * 0.4 * trunk
    take["pelvis.heading"] += sign * 0.5 * trunk
    if take.mode == "overarm":
        take["spine1.flex"] += curve(0, -8, 15, 25, 5)
        take[f"{arm}_shoulder.plane"] = curve(0, -30, 60, 120, 30)
        take[f"{arm}_shoulder.elev"] = curve(8, 95, 100, 55, 8)
        take[f"{arm}_shoulder.rot"] = curve(0, -80, 20, 40, 0)
        take[f"{arm}_elbow.flex"] = curve(15, 95, 20, 35, 15)
        skills.set_arm(take, lead, curve(0, 60, 40, 10, 0), curve(8, 30, 20, 10, 8),
                       elbow=curve(15, 40, 70, 60, 15))
    else:  # underarm: the arm swings back then forward like a pendulum, release at ~hip level
        take["spine1.flex"] += curve(0, 15, 12, 8, 0)
        for side in SIDES:
            take[f"{side}_knee.flex"] += curve(0, 25, 15, 8, 0)
            take[f"{side}_hip.flex"] += curve(0, 12, 10, 5, 0)
        skills.set_arm(take, arm, curve(3, -50, 60, 100, 3), 10.0, elbow=curve(15, 10, 10, 25, 15))
        skills.set_arm(take, lead, curve(3, 30, 15, 0, 3), 12.0, elbow=curve(15, 30, 30, 20, 15))


CLASSES = (
    ActionClass("warm_up", ("arm circles", "trunk twists", "leg swings"), warm_up),
    ActionClass("walk", tuple(WALK_MODES), walk, weight=1.1),
    ActionClass("run", tuple(RUN_MODES), run, weight=0.9),
    ActionClass("jump", ("in place", "forward"), jump),
    ActionClass("drink", ("right hand", "left hand", "seated"), drink, weight=1.1),
    ActionClass("lift_dumbbell", ("two-arm curl", "one-arm curl", "overhead press"), lift_dumbbell),
    ActionClass("sit", ("with hand push", "without hand push"), sit, weight=0.9),
    ActionClass("eat", ("right hand", "left hand", "both hands"), eat),
    ActionClass("turn steering wheel", ("both hands", "one hand"), turn_steering_wheel, weight=0.9),
    ActionClass("phone", ("right ear", "left ear", "texting"), phone, weight=1.1),
    ActionClass("boxing", ("jab-cross", "hooks"), boxing),
    ActionClass("throw", ("overarm", "underarm"), throw),
)
