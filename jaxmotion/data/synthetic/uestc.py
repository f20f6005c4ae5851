"""The 40 UESTC exercise classes (official names and order, FACTS 1.1), each a composition of skills.

UESTC subjects faced the front camera and repeated each exercise about three times per ~6 s recording,
at their own speed and style; 15 of actions 10-39 were done seated by half of the subjects, and
one-sided exercises vary left/right (MOTION_FACTS 4). So every class repeats its movement 2-3 times per
clip (:func:`skills.cycles`, within the movement's natural period), and its modes name the ground-truth
style: ``left``/``right`` for one-sided exercises, ``standing``/``seated`` for the 15 seated-capable ones
(:data:`SEATED_CAPABLE`), otherwise a style such as the depth, the arms or the tempo. Angles and tempos:
MOTION_FACTS sections 2-4 (est. where the table has none).
"""

from __future__ import annotations

import numpy as np

from jaxmotion.data.formats.uestc import CLASS_NAMES
from jaxmotion.data.synthetic import skills, timing
from jaxmotion.data.synthetic.engine import ActionClass
from jaxmotion.data.synthetic.take import SIDES, Take, other

#: The 15 classes among actions 10-39 that half of the subjects performed seated (which 15 is not
#: published: the upper-body exercises that can be done on a chair).
SEATED_CAPABLE = (
    "front-raising", "pulling-chest-expanders", "wrist-circling", "single-dumbbell-raising", "shoulder-raising",
    "elbow-circling", "dumbbell-one-arm-shoulder-pressing", "arm-circling", "dumbbell-shrugging",
    "pinching-back", "head-anticlockwise-circling", "shoulder-abduction", "deltoid-muscle-stretching",
    "overhead-stretching", "upper-back-stretching",
)
STANCES = ("standing", "seated")
SIDED_STANCES = ("left, standing", "right, standing", "left, seated", "right, seated")


def _side(take: Take) -> str | None:
    """The side a mode names first (``left ...`` / ``right ...``), None for two-sided modes."""
    return next((s for s in SIDES if take.mode.startswith(s)), None)


def _start(take: Take) -> None:
    """Facing the front camera (UESTC views are turned to the front), seated if the mode says so."""
    skills.stand(take, heading=take.rng.normal(0.0, 8.0))
    if take.mode.endswith("seated"):
        skills.seated(take)


def _hands_on_hips(take: Take, sides=SIDES) -> None:
    target = take.scale() * np.array([0.19, -0.3, 0.0])
    for side in sides:
        skills.reach(take, side, target, elbow_hint=(1.0, -0.2, -0.6))


def _hands_behind_head(take: Take, sides=SIDES) -> None:
    target = take.head_point() + take.scale() * np.array([0.07, 0.03, -0.09])
    for side in sides:
        skills.reach(take, side, target, elbow_hint=(1.0, 0.3, 0.1))


def _in_cycle(phase: np.ndarray, keys, values) -> np.ndarray:
    """``[T]`` keyframed curve over each cycle of ``phase`` (``keys`` are fractions of a cycle)."""
    return timing.keyframes(np.mod(phase, 1.0), keys, values)


# --- 0-9: whole-body exercises, standing ---------------------------------------------------------------


def punching_and_knee_lifting(take: Take) -> None:
    _start(take)
    phase = skills.cycles(take, 0.9, 1.8)
    env = skills.pulse(phase, 0.3, 0.15, 0.3)
    hip = take.vary(85.0, 0.1)
    for arm, on in skills.alternating(phase, _side(take)).items():
        skills.punch(take, arm, env * on)
        skills.lift_knee(take, other(arm), env * on, hip=hip, knee=95.0)


def marking_time_and_knee_lifting(take: Take) -> None:
    _start(take)
    phase = timing.warped_phase(take.t, take.vary(0.85, 0.12) * take.tempo, take.rng)  # strides/s
    hip = take.vary(65.0, 0.15) * take.amp
    lifts = {side: skills.pulse(phase - 0.5 * k, 0.22, 0.06, 0.22) for k, side in enumerate(SIDES)}
    for side in SIDES:
        skills.lift_knee(take, side, lifts[side], hip=hip, knee=hip + 15.0)
        if take.mode == "arms swinging":  # each arm forward with the opposite knee
            skills.set_arm(take, side, 5.0 + 45.0 * lifts[other(side)] - 15.0 * lifts[side], 8.0, elbow=80.0)
    if take.mode == "hands on hips":
        _hands_on_hips(take)


def jumping_jack(take: Take) -> None:
    _start(take)
    phase = skills.cycles(take, 0.9, 1.6)
    cycle = np.mod(phase, 1.0)
    arms = skills.pulse(phase, 0.4, 0.1, 0.4)
    for side in SIDES:
        skills.set_arm(take, side, 5.0, 6.0 + take.vary(160.0, 0.05) * arms, elbow=10.0 + 15.0 * (1 - arms))
    width = take.vary(20.0, 0.15) * take.amp
    if take.mode == "jumping":  # hop out, land wide, hop in, land together
        feet = _in_cycle(phase, [0.0, 0.15, 0.5, 0.65], [0.0, 1.0, 1.0, 0.0])
        keys = [0.0, 0.07, 0.15, 0.25, 0.4, 0.5, 0.57, 0.65, 0.75, 0.9, 1.0]
        knee = _in_cycle(phase, keys, [14, 4, 10, 25, 8, 14, 4, 10, 25, 8, 14])
        ankle = _in_cycle(phase, keys, [8, -25, -5, 12, 2, 8, -25, -5, 12, 2, 8])
        for side in SIDES:
            take[f"{side}_hip.abd"] += width * feet
            take[f"{side}_knee.flex"] += knee
            take[f"{side}_hip.flex"] += 0.5 * knee
            take[f"{side}_ankle.dorsi"] += ankle
        airborne = ((cycle > 0.02) & (cycle < 0.14)) | ((cycle > 0.52) & (cycle < 0.64))
        take.contact[airborne] = 0.0
        take.flight_carry = 0.0
    else:  # stepping: one foot steps out and back per cycle, sides alternating
        out = _in_cycle(phase, [0.0, 0.2, 0.5, 0.7], [0.0, 1.0, 1.0, 0.0])
        lifted = _in_cycle(phase, [0.0, 0.1, 0.2, 0.5, 0.6, 0.7], [0.0, 1.0, 0.0, 0.0, 1.0, 0.0])
        for side, on in skills.alternating(phase, None).items():
            take[f"{side}_hip.abd"] += 1.3 * width * out * on
            take[f"{side}_hip.flex"] += 15.0 * lifted * on
            take[f"{side}_knee.flex"] += 30.0 * lifted * on
            take.contact[:, SIDES.index(side)] *= 1.0 - np.minimum(3.0 * lifted * on, 1.0)


def squatting(take: Take) -> None:
    _start(take)
    phase = skills.cycles(take, 1.8, 3.2)
    env = skills.pulse(phase, 0.4, 0.1, 0.35)
    half = take.mode == "half squat"
    skills.crouch(take, take.vary(55.0 if half else 110.0, 0.08) * env, take.vary(20.0 if half else 35.0, 0.15) * env)
    if take.mode == "hands behind head":
        _hands_behind_head(take)
    elif half:
        _hands_on_hips(take)
    else:  # arms forward to horizontal as a counterweight
        for side in SIDES:
            skills.set_arm(take, side, 5.0 + (85.0 + skills.trunk_pitch(take)) * env, 8.0, elbow=8.0)


# Forward lunge over one cycle: step out, lower, hold, rise, step back (MOTION_FACTS 3.4).
_LUNGE_KEYS = [0.0, 0.12, 0.25, 0.45, 0.5, 0.65, 0.75, 0.85, 1.0]
_LUNGE_LEAD = {"hip.flex": [0, 50, 40, 80, 80, 40, 50, 0, 0], "knee.flex": [0, 60, 10, 90, 90, 10, 60, 0, 0],
               "ankle.dorsi": [0, 0, 0, 10, 10, 0, 0, 0, 0]}
_LUNGE_REAR = {"hip.flex": [0, -5, -20, -8, -8, -20, -5, 0, 0], "knee.flex": [0, 5, 10, 78, 78, 10, 5, 0, 0],
               "ankle.dorsi": [0, -5, -10, -35, -35, -10, -5, 0, 0]}
_LUNGE_LIFTED = ([0.0, 0.03, 0.22, 0.25, 0.65, 0.68, 0.83, 0.86], [0, 1, 1, 0, 0, 1, 1, 0])


def _lunge(take: Take, phase: np.ndarray, lead_of: dict, lead: dict, trail: dict, depth: float) -> None:
    """Keyframed lunges: ``lead_of`` ``{side: [T]}`` which leg leads each cycle; ``lead``/``trail`` the leg
    channels over :data:`_LUNGE_KEYS`, the bending ones scaled by ``depth``; the lead foot is off the floor
    while it steps out and back."""
    lifted = _in_cycle(phase, *_LUNGE_LIFTED)
    for side, on in lead_of.items():
        for channel, values in lead.items():
            scale = 1.0 if channel.endswith("abd") else depth
            take[f"{side}_{channel}"] += scale * on * _in_cycle(phase, _LUNGE_KEYS, values)
        for channel, values in trail.items():
            scale = 1.0 if channel.endswith("abd") else depth
            take[f"{other(side)}_{channel}"] += scale * on * _in_cycle(phase, _LUNGE_KEYS, values)
        take.contact[:, SIDES.index(side)] *= 1.0 - lifted * on


def forward_lunging(take: Take) -> None:
    _start(take)
    phase = skills.cycles(take, 2.0, 3.5)
    _lunge(take, phase, skills.alternating(phase, _side(take)), _LUNGE_LEAD, _LUNGE_REAR, take.vary(1.0, 0.08))
    _hands_on_hips(take)


# Side lunge: the lead thigh turns out (external rotation) so the bent knee points over the foot.
_SIDE_LUNGE_LEAD = {"hip.abd": [0, 20, 35, 35, 35, 35, 20, 0, 0], "hip.flex": [0, 20, 5, 60, 60, 5, 20, 0, 0],
                    "hip.rot": [0, 0, -10, -25, -25, -10, 0, 0, 0], "knee.flex": [0, 40, 5, 90, 90, 5, 40, 0, 0],
                    "ankle.dorsi": [0, 0, 0, 20, 20, 0, 0, 0, 0]}
_SIDE_LUNGE_TRAIL = {"hip.abd": [0, 0, 5, 25, 25, 5, 0, 0, 0], "hip.flex": [0, 0, 0, 25, 25, 0, 0, 0, 0]}


def left_lunging(take: Take) -> None:
    _start(take)
    phase = skills.cycles(take, 2.0, 3.5)
    depth = take.vary(1.0, 0.1)
    _lunge(take, phase, skills.alternating(phase, "left"), _SIDE_LUNGE_LEAD, _SIDE_LUNGE_TRAIL, depth)
    down = _in_cycle(phase, _LUNGE_KEYS, [0, 0, 0, 1, 1, 0, 0, 0, 0])
    take["pelvis.tilt"] += 25.0 * depth * down  # hips back, chest over the bent knee
    if take.mode == "arms forward":
        for side in SIDES:
            skills.set_arm(take, side, 10.0 + (80.0 + skills.trunk_pitch(take)) * down, 8.0, elbow=10.0)
    else:
        _hands_on_hips(take)


def left_stretching(take: Take) -> None:
    _start(take)
    phase = skills.cycles(take, 2.5, 4.0)
    keys = [0.0, 0.15, 0.35, 0.6, 0.8, 0.95]
    arms = _in_cycle(phase, keys, [0, 1, 1, 1, 1, 0])
    bend = _in_cycle(phase, keys, [0, 0, 1, 1, 0, 0])
    skills.bend_trunk(take, take.vary(30.0, 0.12) * take.amp * bend)
    raised = SIDES if take.mode == "both arms overhead" else ("right",)
    for side in raised:  # up the side, over the head
        skills.set_arm(take, side, 10.0, 8.0 + 160.0 * arms, elbow=10.0 + 20.0 * bend)
    if take.mode != "both arms overhead":
        _hands_on_hips(take, ("left",))


def raising_hand_and_jumping(take: Take) -> None:
    _start(take)
    phase = skills.cycles(take, 1.2, 2.2)
    starts = np.flatnonzero(np.diff(np.floor(phase)) > 0) / take.fps
    raised = {side: np.zeros(take.num_frames) for side in SIDES}
    t_free, k = 0.0, 0
    for t0 in starts:
        if t0 < t_free or t0 + 1.3 > take.duration:
            continue
        t_free = skills.jump(take, t0, height=take.vary(0.12, 0.3), dip=0.5, arm_swing=0.0)
        arms = SIDES if take.mode == "both arms" else (SIDES[k % 2],)
        for side in arms:
            raised[side] = np.maximum(raised[side], timing.keyframes(take.t, [t0, t0 + 0.45, t_free - 0.3, t_free],
                                                                     [0, 1, 1, 0]))
        k += 1
    for side in SIDES:
        skills.set_arm(take, side, 3.0 + 165.0 * raised[side], 8.0, elbow=15.0 - 10.0 * raised[side])


def left_kicking(take: Take) -> None:
    _start(take)
    high = take.mode == "high kick"
    period = take.vary(1.9, 0.12) / take.tempo
    t = take.uniform(0.1, 0.5)
    while t + 1.1 < take.duration:
        end = skills.kick(take, "left", t, height=take.vary(1.05 if high else 0.6, 0.08),
                          duration=take.vary(1.0, 0.1) / take.tempo)
        t = max(end + 0.2, t + period)
    for side in SIDES:  # arms held out for balance
        skills.set_arm(take, side, 20.0, 30.0, elbow=45.0)


def rotation_clapping(take: Take) -> None:
    _start(take)
    phase = skills.cycles(take, 1.6, 3.0)
    reach = take.vary(40.0 if take.mode == "wide" else 18.0, 0.12) * take.amp
    turn = np.sin(2 * np.pi * phase)
    skills.turn_trunk(take, reach * turn)
    together = turn**2  # hands meet at each end of the turn
    s = take.scale()
    for side in SIDES:
        target = take.shoulder_point() * np.array([0.0, 1.0, 0.0]) + s * np.stack(
            [0.03 + 0.32 * (1 - together), np.full_like(turn, -0.08), 0.42 - 0.1 * (1 - together)], -1)
        skills.reach(take, side, target, elbow_hint=(0.6, -1.0, -0.2))
        take[f"{side}_elbow.pron"] = -70.0  # palms facing


# --- 10-23: upper body, standing or seated ---------------------------------------------------------------


def front_raising(take: Take) -> None:
    _start(take)
    env = skills.pulse(skills.cycles(take, 1.8, 3.0), 0.35, 0.1, 0.35)
    for side in SIDES:
        skills.set_arm(take, side, 5.0 + take.vary(85.0, 0.08) * env, 8.0, elbow=5.0)
        take[f"{side}_elbow.pron"] = 70.0  # palms down


def pulling_chest_expanders(take: Take) -> None:
    _start(take)
    env = skills.pulse(skills.cycles(take, 1.6, 3.0), 0.35, 0.1, 0.35)
    for side in SIDES:
        if take.mode == "overhead":  # from overhead, pulled apart and down to shoulder level
            take[f"{side}_shoulder.plane"] = 60.0 - 70.0 * env
            take[f"{side}_shoulder.elev"] = 165.0 - 70.0 * env
        else:  # arms forward at shoulder height, pulled apart sideways
            take[f"{side}_shoulder.plane"] = 88.0 - 85.0 * env
            take[f"{side}_shoulder.elev"] = 88.0
        take[f"{side}_shoulder.rot"] = 0.0
        take[f"{side}_elbow.flex"] = 5.0
    take["spine3.flex"] -= 5.0 * env  # chest out


def punching(take: Take) -> None:
    _start(take)
    phase = skills.cycles(take, 0.5, 1.0, reps=(4.0, 8.0))
    env = skills.pulse(phase, 0.35, 0.05, 0.35)
    skills.crouch(take, 10.0, 3.0)  # soft knees
    for arm, on in skills.alternating(phase, _side(take)).items():
        skills.punch(take, arm, env * on)


def wrist_circling(take: Take) -> None:
    _start(take)
    phase = timing.warped_phase(take.t, take.vary(0.9, 0.15) * take.tempo * take.choice((1.0, -1.0)), take.rng)
    cycle = 2 * np.pi * phase
    for side in SIDES:  # forearms forward, hands circling at the wrists
        skills.set_arm(take, side, 25.0, 12.0, elbow=85.0)
        take[f"{side}_elbow.pron"] = 10.0 * np.sin(cycle)
        take[f"{side}_wrist.flex"] = 40.0 * np.cos(cycle)
        take[f"{side}_wrist.dev"] = -5.0 + 22.0 * np.sin(cycle)


def single_dumbbell_raising(take: Take) -> None:
    _start(take)
    side = _side(take)
    env = skills.pulse(skills.cycles(take, 1.6, 3.0), 0.4, 0.1, 0.4)
    take[f"{side}_elbow.flex"] = 8.0 + take.vary(125.0, 0.06) * env  # a curl: the upper arm stays still
    take[f"{side}_elbow.pron"] = -70.0
    take[f"{side}_shoulder.elev"] = 8.0 + 10.0 * env
    take["spine2.bend"] += (-3.0 if side == "left" else 3.0) * env  # leaning away from the weight


def shoulder_raising(take: Take) -> None:
    _start(take)
    phase = skills.cycles(take, 1.5, 3.0)
    for side in SIDES:  # shoulder rolls: up, back, down, forward
        take[f"{side}_collar.elev"] += 15.0 - 15.0 * np.cos(2 * np.pi * phase)
        take[f"{side}_collar.protr"] += 15.0 * np.sin(2 * np.pi * phase)


def elbow_circling(take: Take) -> None:
    _start(take)
    phase = timing.warped_phase(take.t, take.vary(0.6, 0.15) * take.tempo * take.choice((1.0, -1.0)), take.rng)
    for side in SIDES:  # fingertips on the shoulders, elbows drawing circles
        skills.circle_arm(take, side, phase, flex=40.0, abd=50.0, radius=take.vary(35.0, 0.15), elbow=145.0)
        take[f"{side}_shoulder.rot"] = -30.0


def dumbbell_one_arm_shoulder_pressing(take: Take) -> None:
    _start(take)
    side = _side(take)
    press = skills.pulse(skills.cycles(take, 1.6, 3.0), 0.4, 0.1, 0.4)
    # From the shoulder (upper arm out to the side, forearm up) to overhead with the elbow straight.
    skills.set_arm(take, side, 20.0 - 10.0 * press, 75.0 + 90.0 * take.amp * press, rot=-85.0 + 10.0 * press,
                   elbow=110.0 * (1.0 - press) + 5.0)
    take["spine2.bend"] += (3.0 if side == "left" else -3.0) * press


def arm_circling(take: Take) -> None:
    _start(take)
    phase = timing.warped_phase(take.t, take.vary(1.0, 0.15) * take.tempo * take.choice((1.0, -1.0)), take.rng)
    for side in SIDES:  # straight arms out to the sides, small circles
        skills.circle_arm(take, side, phase, flex=0.0, abd=85.0, radius=take.vary(25.0, 0.2), elbow=5.0)


def dumbbell_shrugging(take: Take) -> None:
    _start(take)
    env = skills.pulse(skills.cycles(take, 1.5, 2.5), 0.3, 0.2, 0.3)
    for side in SIDES:  # straight arms with the weights hang; the collars go straight up
        skills.set_arm(take, side, 5.0, 8.0, elbow=3.0)
        take[f"{side}_collar.elev"] += take.vary(30.0, 0.1) * env


def pinching_back(take: Take) -> None:
    _start(take)
    env = skills.pulse(skills.cycles(take, 1.8, 3.2), 0.3, 0.3, 0.3)
    for side in SIDES:  # elbows drawn back, shoulder blades squeezed together, chest out
        skills.set_arm(take, side, 10.0 - 35.0 * env, 15.0 + 15.0 * env, elbow=90.0)
        take[f"{side}_collar.protr"] -= 18.0 * env
    take["spine3.flex"] -= 8.0 * env
    take["spine2.flex"] -= 5.0 * env


def head_anticlockwise_circling(take: Take) -> None:
    _start(take)
    phase = skills.cycles(take, 2.5, 4.0, reps=(1.5, 2.5))
    size = take.vary(30.0, 0.15)
    # Seen from the camera, anticlockwise: up (extension), the subject's right, down, the subject's left.
    angle = 2 * np.pi * phase
    for joint, share in (("neck", 0.6), ("head", 0.4)):
        take[f"{joint}.flex"] -= share * size * np.cos(angle)
        take[f"{joint}.bend"] -= share * size * np.sin(angle)


def shoulder_abduction(take: Take) -> None:
    _start(take)
    env = skills.pulse(skills.cycles(take, 1.8, 3.0), 0.4, 0.1, 0.4)
    top = take.vary(take.choice((90.0, 160.0)), 0.08)
    for side in SIDES:
        skills.set_arm(take, side, 3.0, 6.0 + top * env, elbow=5.0)


def deltoid_muscle_stretching(take: Take) -> None:
    _start(take)
    side, helper = _side(take), other(_side(take))
    env = skills.pulse(skills.cycles(take, 3.0, 5.0, reps=(1.5, 2.5)), 0.2, 0.5, 0.2)
    skills.set_arm(take, side, 90.0 * env, 6.0 - 51.0 * env, elbow=5.0)  # straight arm across the chest
    upper, _ = take.arm_lengths()
    elbow = take.shoulder_point() + upper * np.array([-0.707, 0.0, 0.707])  # where the stretched elbow is
    held = np.array([-elbow[0], elbow[1] - 0.03, elbow[2] + 0.03])  # the helper hand's side is mirrored
    skills.toward(take, helper, env, held, elbow_hint=(0.5, -1.0, 0.0))


# --- 24-39: trunk, legs and whole body, standing ----------------------------------------------------------


def straight_forward_flexion(take: Take) -> None:
    _start(take)
    env = skills.pulse(skills.cycles(take, 2.5, 4.5), 0.35, 0.2, 0.35)
    lean = take.vary(110.0 if take.mode == "hands to floor" else 70.0, 0.08)
    skills.crouch(take, 3.0 * env, lean * env)
    for side in SIDES:
        skills.hang_arm(take, side, forward=10.0 * env)


def spinal_stretching(take: Take) -> None:
    _start(take)
    phase = skills.cycles(take, 2.0, 3.5)
    skills.crouch(take, 20.0, take.vary(40.0, 0.1))
    curl = np.sin(2 * np.pi * phase)  # + rounds the back (head down), - arches it (head up)
    for joint, share in (("spine1", 8.0), ("spine2", 9.0), ("spine3", 7.0), ("neck", 15.0)):
        take[f"{joint}.flex"] += share * curl
    pitch = skills.trunk_pitch(take)
    for side in SIDES:
        if take.mode == "hands on thighs":
            skills.set_arm(take, side, pitch + 5.0, 10.0, elbow=10.0)
        else:  # hands together reaching forward, further as the back rounds
            skills.set_arm(take, side, pitch + 55.0 - 10.0 * curl, 0.0, elbow=15.0)
        take[f"{side}_collar.protr"] += 10.0 * curl


def dumbbell_side_bend(take: Take) -> None:
    _start(take)
    side = _side(take)
    sign = 1.0 if side == "left" else -1.0
    s = np.sin(2 * np.pi * skills.cycles(take, 2.0, 3.5))
    bend = take.vary(25.0, 0.12) * np.maximum(s, 0.0) - 10.0 * np.maximum(-s, 0.0)  # toward the weight
    skills.bend_trunk(take, sign * bend)
    skills.set_arm(take, side, 3.0, 6.0 + bend, elbow=5.0)  # the weight hangs plumb
    _hands_behind_head(take, (other(side),))


def standing_opposite_elbow_to_knee_crunch(take: Take) -> None:
    _start(take)
    phase = skills.cycles(take, 1.0, 2.0, reps=(2.0, 4.0))
    env = skills.pulse(phase, 0.35, 0.1, 0.35)
    _hands_behind_head(take)
    for knee, on in skills.alternating(phase, _side(take)).items():
        skills.lift_knee(take, knee, env * on, hip=take.vary(95.0, 0.08), knee=95.0)
        skills.turn_trunk(take, (30.0 if knee == "left" else -30.0) * env * on)  # opposite elbow to the knee
    take["spine1.flex"] += 15.0 * env
    take["spine2.flex"] += 12.0 * env


def standing_rotation(take: Take) -> None:
    _start(take)
    skills.turn_trunk(take, take.vary(42.0, 0.12) * take.amp * np.sin(2 * np.pi * skills.cycles(take, 2.0, 3.5)))
    if take.mode == "arms out":
        for side in SIDES:
            skills.set_arm(take, side, 0.0, 88.0, elbow=5.0)
    else:  # hands crossed on the chest, elbows out
        for side in SIDES:
            skills.reach(take, side, skills.landmark(take, "chest") * np.array([-0.3, 1.0, 0.8]),
                         elbow_hint=(1.0, -0.3, 0.0))


def overhead_stretching(take: Take) -> None:
    _start(take)
    env = skills.pulse(skills.cycles(take, 2.5, 4.0), 0.25, 0.4, 0.25)
    for side in SIDES:  # hands together, pushed overhead
        skills.set_arm(take, side, 165.0 * env + 3.0, 6.0 * (1 - env) + 2.0, elbow=5.0 + 10.0 * (1 - env))
        if take.mode == "standing":
            take[f"{side}_ankle.dorsi"] -= 18.0 * env  # up on the toes
    take["spine2.flex"] -= 5.0 * env


def upper_back_stretching(take: Take) -> None:
    _start(take)
    env = skills.pulse(skills.cycles(take, 2.5, 4.0), 0.25, 0.4, 0.25)
    hands = skills.straight_ahead(take, 0.85) * np.array([0.0, 1.0, 1.0]) + np.array([0.03, 0.0, 0.0])
    for side in SIDES:  # hands clasped forward, shoulder blades spread, upper back rounded, head down
        skills.toward(take, side, env, hands, elbow_hint=(0.6, -1.0, 0.0))
        take[f"{side}_collar.protr"] += 22.0 * env
    for joint, flex in (("spine2", 14.0), ("spine3", 10.0), ("neck", 20.0)):
        take[f"{joint}.flex"] += flex * env


def knee_to_chest(take: Take) -> None:
    _start(take)
    phase = skills.cycles(take, 2.0, 3.5)
    env = skills.pulse(phase, 0.3, 0.3, 0.25)
    s = take.scale()
    for knee, on in skills.alternating(phase, _side(take)).items():
        lift = env * on
        skills.lift_knee(take, knee, lift, hip=take.vary(115.0, 0.06), knee=120.0)
        # Both hands clasp the shin below the knee: the knee's own hand from outside, the other across.
        skills.toward(take, knee, lift, s * np.array([0.12, -0.32, 0.38]), elbow_hint=(0.8, -1.0, 0.0))
        skills.toward(take, other(knee), lift, s * np.array([-0.03, -0.3, 0.4]), elbow_hint=(0.8, -1.0, 0.0))
    take["spine1.flex"] += 10.0 * env


def knee_circling(take: Take) -> None:
    _start(take)
    turn = 1.0 if take.mode == "clockwise" else -1.0  # seen from above
    angle = 2 * np.pi * timing.warped_phase(take.t, take.vary(0.5, 0.15) * take.tempo, take.rng)
    skills.crouch(take, 35.0 + 10.0 * np.sin(turn * angle), take.vary(55.0, 0.1))
    sway = take.vary(10.0, 0.15) * np.cos(angle)  # both knees to the subject's left, then right
    take["left_hip.abd"] += sway
    take["right_hip.abd"] -= sway
    for side in SIDES:  # hands on the knees
        skills.hang_arm(take, side, forward=15.0)


def alternate_knee_lifting(take: Take) -> None:
    _start(take)
    phase = skills.cycles(take, 1.0, 1.8, reps=(3.0, 5.0))
    env = skills.pulse(phase, 0.3, 0.2, 0.3)
    for knee, on in skills.alternating(phase, None).items():
        skills.lift_knee(take, knee, env * on, hip=take.vary(95.0, 0.08), knee=95.0)
    if take.mode == "arms forward":  # palms held level for the knees to reach
        for side in SIDES:
            skills.set_arm(take, side, 80.0, 6.0, elbow=10.0)
            take[f"{side}_elbow.pron"] = 70.0
    else:
        _hands_on_hips(take)


def bent_over_twist(take: Take) -> None:
    _start(take)
    low, high = (1.2, 2.0) if take.mode == "fast" else (2.5, 4.0)
    phase = skills.cycles(take, low, high, reps=(1.5, 3.0))
    for side in SIDES:  # wide stance
        take[f"{side}_hip.abd"] += 15.0
    skills.crouch(take, 10.0, take.vary(80.0, 0.1))
    skills.turn_trunk(take, take.vary(45.0, 0.1) * np.sin(2 * np.pi * phase))  # one hand down to the other foot
    for side in SIDES:
        skills.set_arm(take, side, 0.0, 88.0, elbow=5.0)


def rope_skipping(take: Take) -> None:
    _start(take)
    phase = timing.warped_phase(take.t, take.vary(2.0, 0.1) * take.tempo, take.rng, wobble=0.03)  # turns/s
    cycle = np.mod(phase, 1.0)
    for side in SIDES:  # elbows in, wrists turning the rope
        skills.set_arm(take, side, 10.0, 25.0, elbow=50.0)
        take[f"{side}_wrist.flex"] = 25.0 * np.cos(2 * np.pi * phase)
        take[f"{side}_shoulder.elev"] += 6.0 * np.sin(2 * np.pi * phase)
    if take.mode == "both feet":  # one small hop per turn
        keys = [0.0, 0.15, 0.35, 0.55, 0.75, 1.0]
        for side in SIDES:
            take[f"{side}_knee.flex"] += _in_cycle(phase, keys, [10, 22, 12, 5, 8, 10])
            take[f"{side}_hip.flex"] += _in_cycle(phase, keys, [5, 10, 6, 2, 4, 5])
            take[f"{side}_ankle.dorsi"] += _in_cycle(phase, keys, [0, 10, 0, -25, -15, 0])
        take.contact[(cycle > 0.55) & (cycle < 0.95)] = 0.0
    else:  # boxer skip: landing on alternate feet, the free foot just off the floor
        for side, on in skills.alternating(2 * phase, None).items():
            lift = skills.pulse(2 * phase, 0.25, 0.1, 0.25) * on
            skills.lift_knee(take, side, lift, hip=25.0, knee=45.0)
            take[f"{side}_ankle.dorsi"] += 10.0 * (1.0 - lift) - 10.0
        take.contact[np.mod(2 * phase, 1.0) > 0.85] = 0.0
    take.flight_carry = 0.0


def standing_toe_touches(take: Take) -> None:
    _start(take)
    phase = skills.cycles(take, 1.6, 3.0)
    env = skills.pulse(phase, 0.35, 0.1, 0.35)
    for side in SIDES:
        take[f"{side}_hip.abd"] += 14.0
    skills.crouch(take, 5.0 * env, take.vary(100.0, 0.08) * env)
    if take.mode == "both hands":
        for side in SIDES:
            skills.hang_arm(take, side, forward=8.0 * env)
        return
    for hand, on in skills.alternating(phase, None).items():  # a hand to the opposite foot, the other arm up
        skills.turn_trunk(take, (25.0 if hand == "right" else -25.0) * env * on)
    pitch = skills.trunk_pitch(take)
    for hand, on in skills.alternating(phase, None).items():
        skills.set_arm(take, hand, on * (pitch + 5.0 * env), 6.0 + 84.0 * env * (1.0 - on), elbow=8.0)


def standing_gastrocnemius_calf(take: Take) -> None:
    _start(take)
    back = "left" if take.mode.startswith("left") else "right"
    front = other(back)
    lean = take.vary(15.0, 0.15) * skills.pulse(skills.cycles(take, 2.5, 4.5, reps=(1.5, 2.5)), 0.3, 0.4, 0.2)
    # The back leg and trunk form one line leaning on the wall: the back ankle dorsiflexes by the lean.
    take["pelvis.tilt"] += lean
    take[f"{back}_hip.flex"] += lean - 18.0
    take[f"{back}_ankle.dorsi"] += 8.0 + lean
    take[f"{front}_hip.flex"] += 35.0 + lean - 0.8 * lean
    take[f"{front}_knee.flex"] += 35.0
    take[f"{front}_ankle.dorsi"] += 5.0
    for side in SIDES:  # hands on the wall at shoulder height
        skills.set_arm(take, side, 80.0 + skills.trunk_pitch(take), 10.0, elbow=25.0)
        take[f"{side}_wrist.flex"] = -60.0


def single_leg_lateral_hopping(take: Take) -> None:
    _start(take)
    leg = "left" if take.mode.startswith("left") else "right"
    free = other(leg)
    phase = timing.warped_phase(take.t, take.vary(1.3, 0.12) * take.tempo, take.rng, wobble=0.03)  # hops/s
    direction = np.where(np.floor(phase) % 2 == 0, 1.0, -1.0)  # to the subject's left, then back
    sweep = take.vary(9.0, 0.15) * direction * _in_cycle(phase, [0.0, 0.7], [1.0, -1.0])
    take[f"{leg}_hip.abd"] += sweep if leg == "left" else -sweep  # the hip travels over the foot, sideways
    take[f"{leg}_knee.flex"] += _in_cycle(phase, [0.0, 0.25, 0.55, 0.65, 1.0], [12, 35, 10, 8, 12])
    take[f"{leg}_hip.flex"] += _in_cycle(phase, [0.0, 0.25, 0.55, 0.65, 1.0], [8, 25, 6, 5, 8])
    take[f"{leg}_ankle.dorsi"] += _in_cycle(phase, [0.0, 0.25, 0.55, 0.65, 1.0], [2, 15, -20, -25, 2])
    take[f"{free}_knee.flex"] += 80.0  # the free foot held up behind
    take[f"{free}_hip.flex"] += 15.0
    take.contact[:, SIDES.index(free)] = 0.0
    take.contact[:, SIDES.index(leg)] = (np.mod(phase, 1.0) < 0.6).astype(float)
    for side in SIDES:
        skills.set_arm(take, side, 20.0, 35.0, elbow=40.0)


def high_knees_running(take: Take) -> None:
    _start(take)
    skills.gait(take, skills.SPOT_RUN, cadence=take.vary(3.4, 0.08), size=take.vary(1.8, 0.06))
    skills.in_place(take)
    if take.mode == "hands at hip height":  # palms down in front of the hips, the knees come up to them
        for side in SIDES:
            skills.reach(take, side, take.scale() * np.array([0.2, -0.28, 0.33]), elbow_hint=(0.8, -1.0, -0.3))
            take[f"{side}_elbow.pron"] = 70.0


_PERFORMERS = (
    (punching_and_knee_lifting, ("alternating", "right punch, left knee", "left punch, right knee")),
    (marking_time_and_knee_lifting, ("arms swinging", "hands on hips")),
    (jumping_jack, ("jumping", "stepping")),
    (squatting, ("arms forward", "hands behind head", "half squat")),
    (forward_lunging, ("left leg", "right leg", "alternating")),
    (left_lunging, ("hands on hips", "arms forward")),
    (left_stretching, ("right arm overhead", "both arms overhead")),
    (raising_hand_and_jumping, ("both arms", "alternate arms")),
    (left_kicking, ("high kick", "low kick")),
    (rotation_clapping, ("wide", "narrow")),
    (front_raising, STANCES),
    (pulling_chest_expanders, STANCES + ("overhead",)),
    (punching, ("alternating", "right hand", "left hand")),
    (wrist_circling, STANCES),
    (single_dumbbell_raising, SIDED_STANCES),
    (shoulder_raising, STANCES),
    (elbow_circling, STANCES),
    (dumbbell_one_arm_shoulder_pressing, SIDED_STANCES),
    (arm_circling, STANCES),
    (dumbbell_shrugging, STANCES),
    (pinching_back, STANCES),
    (head_anticlockwise_circling, STANCES),
    (shoulder_abduction, STANCES),
    (deltoid_muscle_stretching, SIDED_STANCES),
    (straight_forward_flexion, ("hands to floor", "hands to shins")),
    (spinal_stretching, ("hands on thighs", "arms forward")),
    (dumbbell_side_bend, ("left hand", "right hand")),
    (standing_opposite_elbow_to_knee_crunch, ("alternating", "left knee", "right knee")),
    (standing_rotation, ("arms out", "hands on chest")),
    (overhead_stretching, STANCES),
    (upper_back_stretching, STANCES),
    (knee_to_chest, ("left", "right", "alternating")),
    (knee_circling, ("clockwise", "anticlockwise")),
    (alternate_knee_lifting, ("hands on hips", "arms forward")),
    (bent_over_twist, ("fast", "slow")),
    (rope_skipping, ("both feet", "alternate feet")),
    (standing_toe_touches, ("alternating", "both hands")),
    (standing_gastrocnemius_calf, ("left leg back", "right leg back")),
    (single_leg_lateral_hopping, ("left leg", "right leg")),
    (high_knees_running, ("arms pumping", "hands at hip height")),
)

CLASSES = tuple(ActionClass(name, modes, perform)
                for name, (perform, modes) in zip(CLASS_NAMES, _PERFORMERS, strict=True))
