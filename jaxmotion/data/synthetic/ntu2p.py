"""The 26 NTU RGB+D 120 two-person interactions (ActFormer's order: A050-A060, A106-A120) as coupled scenes.

Person 0 acts, person 1 receives (or both act alike); they face each other at a distance that suits the
class (MOTION_FACTS 5: Hall's zones, reach ~0.6-1.0 m between chests for a handshake), contact happens where
the class implies it, resolved on the posed bodies (:mod:`scene`): hands meet between the persons
(handshake, high-five, giving, exchanging), land on the partner (push, punch or slap, pat, pocket,
support) or wrap around them (hug); a kick, a shoulder charge and a stamp are aligned with the partner's
body. Hits make the receiver yield 0.1-0.3 s after contact and step back. Walking towards, apart and
following change the distance by walking. Mode names are the ground-truth style labels.

``touches`` names the parts each contact class brings together (tested: they come within 5 cm of each
other, as capsules around the bones, at some frame); classes without it keep the persons apart.
"""

from __future__ import annotations

import numpy as np

from jaxmotion.data.formats.ntu120 import ACTION_NAMES, MUTUAL_ACTIONS
from jaxmotion.data.synthetic import skills, timing
from jaxmotion.data.synthetic.scene import Scene, SceneClass, World
from jaxmotion.data.synthetic.take import SIDES, Take, other

HAND = ("wrist", "hand")
UPPER_BACK = ("spine2", "spine3", "neck")
TORSO = ("pelvis", "spine1", "spine2", "spine3")
HEAD = ("neck", "head")


def _hand(side: str) -> tuple[str, ...]:
    return tuple(f"{side}_{j}" for j in HAND)


def _face_off(scene: Scene, distance: float, *, lateral: float = 0.0) -> float:
    """Both standing, facing each other, their roots ``distance`` metres apart (template size, varied and
    scaled with the persons): person 0 at the origin facing +Z, person 1 ahead facing -Z. Returns the distance."""
    a, b = scene.takes
    skills.stand(a, heading=scene.rng.normal(0.0, 4.0))
    skills.stand(b, heading=180.0 + scene.rng.normal(0.0, 4.0))
    d = a.vary(distance, 0.06) * 0.5 * (a.scale() + b.scale())
    scene.place(0, 0.0, 0.0)
    scene.place(1, lateral + scene.rng.normal(0.0, 0.03), d)
    return d


def _side_by_side(scene: Scene, gap: float) -> None:
    """Both standing, facing +Z, person 1 ``gap`` metres to person 0's right (world -X)."""
    a, b = scene.takes
    skills.stand(a, heading=scene.rng.normal(0.0, 4.0))
    skills.stand(b, heading=scene.rng.normal(0.0, 4.0))
    scene.place(0, 0.0, 0.0)
    scene.place(1, -a.vary(gap, 0.06), scene.rng.normal(0.0, 0.05))


def _envelope(take: Take, keys, values) -> np.ndarray:
    return timing.keyframes(take.t, keys, values)


def _fit(take: Take, busy: float) -> tuple[float, float]:
    """A one-off interaction of ``busy`` seconds (tempo-scaled) squeezed into the clip: ``(start, scale)``,
    durations multiplied by ``scale`` fit."""
    busy = busy / take.tempo
    scale = min(1.0, (take.duration - 0.3) / busy)
    return take.onset(busy * scale, 0.1), scale


def _react(take: Take, time: float, *, where: str = "chest", strength: float = 1.0, back: float = 0.3) -> None:
    """Yield to a hit at ``time`` and step back ``back`` metres (one step and a closing step)."""
    skills.recoil(take, time, strength=strength, where=where)
    if back > 0:
        side = take.choice(SIDES)
        length = take.vary(back, 0.15) * take.scale()
        t1 = time + take.vary(0.15, 0.2)
        skills.stance_steps(take, [(t1, 0.4, side, -length), (t1 + 0.45, 0.4, other(side), 0.0)], lift=0.6)


def _meeting(w: World, joint: str, *, down: float = 0.0, share: float = 0.5) -> np.ndarray:
    """``[T, 3]`` the point ``share`` of the way from person 0's ``joint`` to person 1's, ``down`` metres lower."""
    return w.between(w.joint(0, joint), w.joint(1, joint), share) - np.array([0.0, down, 0.0])


def _toward(w: World, frm: int, to: int) -> np.ndarray:
    """``[T, 3]`` horizontal unit vector from person ``frm``'s pelvis toward person ``to``'s."""
    d = (w.joint(to, "pelvis") - w.joint(frm, "pelvis")) * np.array([1.0, 0.0, 1.0])
    return d / np.maximum(np.linalg.norm(d, axis=-1, keepdims=True), 1e-6)


def _hands_meet(scene: Scene, env0, env1, *, joint: str, sides=("right", "right"), down: float = 0.0,
                apart: float = 0.05, wobble=None) -> None:
    """Person 0's and person 1's hands meet between their ``joint`` s: each wrist ``apart`` metres short of the
    meeting point on its own side, so the hands overlap there; ``wobble [T, 3]`` moves the point (a shake)."""
    extra = 0.0 if wobble is None else wobble

    def target(person):
        def at(w: World):
            d = _toward(w, 0, 1)
            return _meeting(w, joint, down=down) + extra + (apart if person == 1 else -apart) * d
        return at

    scene.reach(0, sides[0], env0, target(0), elbow_hint=(0.3, -1.0, -0.5))
    scene.reach(1, sides[1], env1, target(1), elbow_hint=(0.3, -1.0, -0.5))


def _walk(take: Take, *, cadence: float, start: float = 0.0, stop: float | None = None, size: float = 1.0,
          backwards: bool = False) -> None:
    """Walk from ``start`` (s) until ``stop`` (s, None: the end), then stand in the double-support stance the
    last step left (the stride phase stops on a heel strike, so both feet bear weight)."""
    stop = take.duration if stop is None else stop
    rate = take.vary(cadence, 0.05) * take.tempo / 2.0  # strides per second
    cycles = max(round(2.0 * rate * (stop - start)) / 2.0, 0.5)  # a whole number of steps
    phase = rate * np.clip(take.t - start, 0.0, cycles / rate)
    skills.gait(take, skills.WALK, cadence=cadence, size=take.vary(size, 0.05), phase=-phase if backwards else phase)
    still = (take.t < start) | (take.t > start + cycles / rate)
    take.contact[still] = 0.5


# --- A050-A060 ----------------------------------------------------------------------------------------------


def punching_slapping(scene: Scene) -> None:
    a, b = scene.takes
    _face_off(scene, 0.6)
    side = "right"
    t0, k = _fit(a, 1.6)
    hit = t0 + 0.35 * k
    env = _envelope(a, [t0, hit, hit + 0.1 * k, hit + 0.6 * k], [0, 1, 1, 0])
    if scene.mode == "punch":  # straight to the face, the trunk turning into it
        skills.turn_trunk(a, 15.0 * env)
        scene.reach(0, side, env, lambda w: w.point(1, "head", (0.0, 0.0, 0.07)), elbow_hint=(0.5, -1.0, -0.2))
        a[f"{side}_elbow.pron"] = 60.0 * env
    else:  # an open-hand swing from the side onto the partner's cheek
        skills.turn_trunk(a, 10.0 * env)
        scene.reach(0, side, env, lambda w: w.point(1, "head", (0.05, -0.03, 0.03)), elbow_hint=(1.0, -0.3, -0.3))
    _react(b, hit, where="head", back=0.25)


def kicking(scene: Scene) -> None:
    a, b = scene.takes
    _face_off(scene, 1.0)
    side = "right" if scene.mode == "right leg" else "left"
    t0, k = _fit(a, 1.8)
    duration = 1.0 * k
    skills.kick(a, side, t0, height=0.7, duration=duration)
    impact = t0 + 0.55 * duration
    # the foot meets the partner's shin on the kicking side (the partner's other leg: they face each other)
    shin = f"{other(side)}_knee", f"{other(side)}_ankle"
    scene.strike(1, impact, lambda w: w.joint(0, f"{side}_foot"),
                 lambda w: w.between(w.joint(1, shin[0]), w.joint(1, shin[1]), 0.35), gap=0.06)
    _react(b, impact, where="stomach", back=0.3)


def pushing(scene: Scene) -> None:
    a, b = scene.takes
    _face_off(scene, 0.65)
    t0, k = _fit(a, 2.0)
    contact, shove = t0 + 0.5 * k, t0 + 0.85 * k
    env = _envelope(a, [t0, contact, shove + 0.1 * k, shove + 0.7 * k], [0, 1, 1, 0])
    sides = SIDES if scene.mode == "both hands" else ("right",)
    for side in sides:  # person 0's right hand lands on the partner's left chest (the partner's +x)
        x = 0.1 if side == "right" else -0.1
        scene.reach(0, side, env, lambda w, x=x: w.point(1, "spine3", (x, 0.02, 0.1)), elbow_hint=(0.6, -1.0, -0.4))
    skills.turn_trunk(a, (0.0 if len(sides) == 2 else 12.0) * env)
    a["spine1.flex"] += 8.0 * env
    _react(b, contact + 0.2 * k, where="chest", back=0.4)


def pat_on_back(scene: Scene) -> None:
    a, b = scene.takes
    if scene.mode == "side by side":
        _side_by_side(scene, 0.55)
        spot = (0.05, 0.08, -0.11)  # the partner's back, on the side toward person 0
    else:
        _face_off(scene, 0.45)
        spot = (0.1, 0.14, -0.1)  # over the partner's left shoulder onto the upper back
    t0, k = _fit(a, 2.6)
    on, off = t0 + 0.6 * k, t0 + 1.9 * k
    env = _envelope(a, [t0, on, off, off + 0.6 * k], [0, 1, 1, 0])
    pats = 0.05 * (1.0 - np.cos(2 * np.pi * a.vary(2.0, 0.1) * np.clip(a.t - on, 0.0, off - on)))  # ~2 Hz

    def target(w: World):
        outward = w.rotations[1, :, 9] @ np.array([0.0, 0.0, -1.0])  # away from the back (spine3's -z)
        return w.point(1, "spine3", spot) + pats[:, None] * outward
    scene.reach(0, "right", env, target, elbow_hint=(0.8, -0.6, -0.3))


def point_finger(scene: Scene) -> None:
    a, b = scene.takes
    _face_off(scene, 1.8)
    t0, k = _fit(a, 2.4)
    env = _envelope(a, [t0, t0 + 0.5 * k, t0 + 1.7 * k, t0 + 2.3 * k], [0, 1, 1, 0])
    side = "right" if scene.mode == "right hand" else "left"

    def target(w: World):  # the arm straight at the partner's face, the hand well short of it
        shoulder = w.joint(0, f"{side}_shoulder")
        d = w.joint(1, "head") - shoulder
        return shoulder + 0.6 * w.scales[0] * d / np.linalg.norm(d, axis=-1, keepdims=True)
    scene.reach(0, side, env, target, elbow_hint=(0.3, -1.0, 0.0))
    a[f"{side}_wrist.flex"] -= 15.0 * env
    b["neck.flex"] += 5.0 * env  # the partner looks at the finger


def hugging(scene: Scene) -> None:
    a, b = scene.takes
    _face_off(scene, 0.68)
    t0, k = _fit(a, 4.2)
    close, hold = t0 + 0.9 * k, t0 + 3.0 * k
    side = a.choice(SIDES)  # both lead with the same foot, so their front feet pass side by side
    for take in (a, b):  # each steps in (MOTION_FACTS 5: ~2 s approach and release, ~3 s embrace)
        step = take.vary(0.28, 0.1) * take.scale()
        skills.stance_steps(take, [(t0, 0.6 * k, side, step), (hold + 0.1 * k, 0.6 * k, side, 0.0)], lift=0.5)
    env = _envelope(a, [t0 + 0.3 * k, close, hold, hold + 0.8 * k], [0, 1, 1, 0])
    over, under = ((0.12, 0.16, -0.1), (-0.16, -0.02, -0.12))
    if scene.mode == "neck-waist":  # person 0's arms round the partner's neck, the partner's round the waist
        spots = {0: {"right": (0.1, 0.24, -0.08), "left": (-0.1, 0.24, -0.08)},
                 1: {"right": (0.15, -0.2, -0.12), "left": (-0.15, -0.2, -0.12)}}
    else:  # criss-cross: each right arm over the partner's left shoulder, each left arm under the right one
        spots = {p: {"right": over, "left": under} for p in (0, 1)}
    for p in (0, 1):
        for side in SIDES:
            spot = spots[p][side]
            scene.reach(p, side, env, lambda w, p=p, spot=spot: w.point(1 - p, "spine3", spot),
                        elbow_hint=(1.0, -0.2, 0.2))
        (a if p == 0 else b)["spine2.flex"] += 6.0 * env


def giving(scene: Scene) -> None:
    a, b = scene.takes
    _face_off(scene, 0.75)
    t0, k = _fit(a, 2.8)
    lag = a.uniform(0.2, 0.5) * k  # the receiver reaches 0.2-0.5 s later (MOTION_FACTS 5)
    meet = t0 + 0.8 * k + lag
    env0 = _envelope(a, [t0, meet, meet + 0.4 * k, meet + 1.1 * k], [0, 1, 1, 0])
    env1 = _envelope(a, [t0 + lag, meet, meet + 0.5 * k, meet + 1.2 * k], [0, 1, 1, 0])
    _hands_meet(scene, env0, env1, joint="spine3", down=0.25, apart=0.01)
    a["right_elbow.pron"] = -40.0 * env0  # palm up under the object
    b["right_elbow.pron"] = 20.0 * env1


def touch_pocket(scene: Scene) -> None:
    a, b = scene.takes
    if scene.mode == "side pocket":
        _side_by_side(scene, 0.6)
        spot = (0.13, -0.08, 0.0)  # the partner's left hip, toward person 0
    else:
        _face_off(scene, 0.48)
        spot = (0.11, -0.08, 0.05)  # front left trouser pocket
    t0, k = _fit(a, 2.4)
    env = _envelope(a, [t0, t0 + 0.7 * k, t0 + 1.5 * k, t0 + 2.2 * k], [0, 1, 1, 0])
    scene.reach(0, "right", env, lambda w: w.point(1, "pelvis", spot), elbow_hint=(0.8, -0.8, -0.4))
    skills.bend_trunk(a, -8.0 * env)
    a["spine1.flex"] += 16.0 * env


def handshaking(scene: Scene) -> None:
    a, b = scene.takes
    _face_off(scene, 0.75)
    # MOTION_FACTS 5: reach 0.92 s, contact 1.96 s (the main shake 1.31 s at ~4 Hz), return 0.75 s
    t0, k = _fit(a, 3.6)
    grip, release = t0 + 0.9 * k, t0 + 2.9 * k
    env = _envelope(a, [t0, grip, release, release + 0.7 * k], [0, 1, 1, 0])
    rate = a.vary(3.5, 0.15) if scene.mode == "vigorous" else a.vary(2.2, 0.15)
    amp = 0.04 if scene.mode == "vigorous" else 0.02
    shaking = (a.t > grip) & (a.t < grip + 1.3 * k)
    wobble = np.zeros((a.num_frames, 3))
    wobble[:, 1] = amp * np.sin(2 * np.pi * rate * (a.t - grip)) * shaking
    _hands_meet(scene, env, env, joint="right_shoulder", down=0.42, apart=0.015, wobble=wobble)


def walking_towards(scene: Scene) -> None:
    a, b = scene.takes
    speed = a.vary(0.9, 0.1)  # each, m/s: approaching walkers slow down and stop (MOTION_FACTS 5)
    stop = min(a.uniform(0.75, 0.9) * a.duration, a.uniform(1.8, 2.4))
    _face_off(scene, 1.0 + 2.0 * speed * stop)
    for take in (a, b):
        _walk(take, cadence=1.6, stop=stop, size=speed / 1.1)
    # they stop in the personal zone, ~1.1-1.3 m between their roots (Hall's 0.45-1.2 m between bodies)
    scene.strike(1, a.duration, lambda w: w.joint(0, "pelvis"), lambda w: w.joint(1, "pelvis"), gap=a.uniform(1.1, 1.3))


def walking_apart(scene: Scene) -> None:
    a, b = scene.takes
    speed = a.vary(1.0, 0.1)
    _face_off(scene, 1.3)
    for take in (a, b):  # facing away from each other, then each walks off
        take["pelvis.heading"] += 180.0
        _walk(take, cadence=1.7, start=take.uniform(0.0, 0.4), size=speed / 1.1)


# --- A106-A120 ----------------------------------------------------------------------------------------------


def hit_with_something(scene: Scene) -> None:
    a, b = scene.takes
    _face_off(scene, 1.1)
    t0, k = _fit(a, 1.8)
    hit = t0 + 0.7 * k
    env = _envelope(a, [t0, t0 + 0.4 * k, hit, hit + 0.8 * k], [0, 0.6, 1, 0])
    high = scene.mode == "overhead"

    def target(w: World):  # the hand stops a stick's length (~0.45 m) short of the partner's head or shoulder
        aim = w.point(1, "head" if high else "left_shoulder", (0.0, 0.05, 0.0))
        wind = w.point(0, "right_shoulder", (-0.1, 0.35, -0.1) if high else (-0.35, 0.05, 0.0))
        d = aim - w.joint(0, "right_shoulder")
        strike = aim - 0.45 * d / np.linalg.norm(d, axis=-1, keepdims=True)
        lift = np.clip(1.0 - (a.t - t0) / (0.4 * k), 0.0, 1.0)[:, None] * (a.t < t0 + 0.4 * k)[:, None]
        return lift * wind + (1.0 - lift) * strike
    scene.reach(0, "right", env, target, elbow_hint=(0.6, -0.5, -0.6))
    skills.turn_trunk(a, 18.0 * (env > 0.6) * env)
    _react(b, hit, where="head" if high else "chest", back=0.35)
    for side in SIDES:  # the receiver's arms come up to cover
        b[f"{side}_shoulder.elev"] += 30.0 * _envelope(b, [hit - 0.2, hit, hit + 0.6], [0, 1, 0])


def wield_knife(scene: Scene) -> None:
    a, b = scene.takes
    _face_off(scene, 1.2)
    t0, k = _fit(a, 2.2)
    env = _envelope(a, [t0, t0 + 0.35 * k, t0 + 0.55 * k, t0 + 1.0 * k], [0, 1, 1, 0])
    if scene.mode == "stab":
        reps = [0.0]
    else:
        reps = [0.0, 0.9 * k]
    total = np.zeros(a.num_frames)
    for r in reps:
        total = np.maximum(total, np.roll(env, int(round(r * a.fps))) * (a.t >= t0 + r))
    side_sweep = 0.0 if scene.mode == "stab" else 0.25

    def target(w: World):  # thrust toward the partner's stomach, stopping ~0.25 m short
        aim = w.point(1, "spine1", (0.0, 0.0, 0.1))
        d = aim - w.joint(0, "right_shoulder")
        sweep = side_sweep * np.sin(2 * np.pi * (a.t - t0) / (0.9 * k))[:, None] * np.array([1.0, 0.0, 0.0])
        return aim - 0.3 * d / np.linalg.norm(d, axis=-1, keepdims=True) + sweep
    scene.reach(0, "right", total, target, elbow_hint=(0.4, -1.0, -0.3))
    a["spine1.flex"] += 8.0 * total
    fear = _envelope(b, [t0 + 0.1, t0 + 0.4, t0 + 1.4 * k, t0 + 2.0 * k], [0, 1, 1, 0])
    b["spine2.flex"] -= 10.0 * fear  # the partner leans away, hands up in front
    for side in SIDES:
        skills.set_arm(b, side, 50.0 * fear + 3.0, 15.0, elbow=20.0 + 70.0 * fear)
    skills.stance_steps(b, [(t0 + 0.3, 0.45, "right", -0.3 * b.scale()), (t0 + 0.8, 0.45, "left", 0.0)], lift=0.5)


def knock_over(scene: Scene) -> None:
    a, b = scene.takes
    _face_off(scene, 1.3)
    t0, k = _fit(a, 2.2)
    step = a.vary(0.35, 0.1) * a.scale()
    skills.stance_steps(a, [(t0, 0.45 * k, "left", step), (t0 + 0.45 * k, 0.4 * k, "right", step)], lift=0.7)
    impact = t0 + 0.8 * k
    charge = _envelope(a, [t0, impact, impact + 0.5 * k], [0, 1, 0])
    skills.turn_trunk(a, 35.0 * charge)  # turning left brings the right shoulder forward; the head stays back
    a["neck.bend"] += 25.0 * charge
    a["neck.flex"] += 30.0 * charge  # the head tucked down and aside
    a["spine1.flex"] += 28.0 * charge  # leaning in puts the shoulder ahead of the feet
    # onto the partner's left chest (on person 0's right), so the feet stay clear of each other
    scene.strike(1, impact, lambda w: w.joint(0, "right_shoulder"), lambda w: w.point(1, "spine3", (0.08, 0.0, 0.0)),
                 gap=0.06)
    skills.recoil(b, impact, strength=1.4, where="chest")
    b["neck.twist"] += 25.0 * _envelope(b, [impact - 0.3, impact, impact + 0.8], [0, 1, 0])  # looks away
    side = b.choice(SIDES)
    back = b.vary(0.45, 0.1) * b.scale()
    t1 = impact + 0.12
    skills.stance_steps(b, [(t1, 0.35, side, -back), (t1 + 0.35, 0.35, other(side), -back),
                            (t1 + 0.75, 0.4, side, 0.0)], lift=0.6)


def grab_stuff(scene: Scene) -> None:
    a, b = scene.takes
    _face_off(scene, 0.85)
    t0, k = _fit(a, 2.4)
    skills.set_arm(b, "right", 35.0, 12.0, elbow=70.0)  # the partner holds something in front
    b["right_elbow.pron"] = -30.0
    grab = t0 + 0.7 * k
    env = _envelope(a, [t0, grab, grab + 0.2 * k], [0, 1, 1])
    pull = _envelope(a, [grab + 0.15 * k, grab + 0.8 * k], [0, 1])

    def target(w: World):  # onto the partner's hand, then pulled back toward person 0's chest
        start = w.joint(1, "right_hand") - 0.05 * _toward(w, 0, 1)
        home = w.point(0, "spine3", (-0.1, -0.1, 0.25))
        return start + pull[:, None] * (home - start)
    scene.reach(0, "right", np.maximum(env, pull), target, elbow_hint=(0.5, -1.0, -0.3))
    follow = _envelope(b, [grab + 0.1 * k, grab + 0.35 * k, grab + 0.9 * k], [0, 1, 0])
    b["right_shoulder.elev"] += 15.0 * follow
    b["spine2.flex"] += 8.0 * follow


def shoot_with_gun(scene: Scene) -> None:
    a, b = scene.takes
    _face_off(scene, 2.2)
    t0, k = _fit(a, 2.6)
    env = _envelope(a, [t0, t0 + 0.5 * k, t0 + 2.0 * k, t0 + 2.5 * k], [0, 1, 1, 0])
    shots = t0 + 0.7 * k + np.arange(1 if scene.mode == "one shot" else 3) * 0.35 * k
    kick = skills.bumps(a, shots, 0.15)

    def aim(side):
        def target(w: World):  # the arms straight at the partner's chest, jerking up at each shot
            shoulder = w.joint(0, "right_shoulder")
            d = w.joint(1, "spine3") - shoulder
            muzzle = shoulder + 0.55 * w.scales[0] * d / np.linalg.norm(d, axis=-1, keepdims=True)
            return muzzle + 0.06 * kick[:, None] * np.array([0.0, 1.0, 0.0]) + (
                0.0 if side == "right" else -0.04 * _toward(w, 0, 1))
        return target
    for side in SIDES:
        scene.reach(0, side, env, aim(side), elbow_hint=(0.5, -1.0, 0.0))
    for t in shots:
        skills.recoil(b, t, strength=0.6, where="chest")
    if scene.mode == "three shots":
        skills.stance_steps(b, [(shots[-1] + 0.1, 0.45, "left", -0.35 * b.scale()),
                                (shots[-1] + 0.6, 0.45, "right", 0.0)], lift=0.5)


def step_on_foot(scene: Scene) -> None:
    a, b = scene.takes
    _face_off(scene, 0.7)
    t0, k = _fit(a, 2.0)
    plant = t0 + 0.6 * k
    step = a.vary(0.3, 0.1) * a.scale()
    skills.stance_steps(a, [(t0, 0.6 * k, "right", step), (plant + 0.6 * k, 0.5 * k, "right", 0.0)], lift=0.8)
    # person 0's planted right foot lands on the partner's left foot (they face each other)
    scene.strike(1, plant + 0.1, lambda w: w.joint(0, "right_foot"), lambda w: w.joint(1, "left_foot"))
    a["neck.flex"] += 20.0 * _envelope(a, [t0, plant, plant + 0.6 * k], [0, 1, 0])
    ouch = plant + 0.15
    b["left_knee.flex"] += 45.0 * _envelope(b, [ouch, ouch + 0.25, ouch + 0.8], [0, 1, 0])
    b["left_hip.flex"] += 25.0 * _envelope(b, [ouch, ouch + 0.25, ouch + 0.8], [0, 1, 0])
    lifted = (b.t > ouch + 0.08) & (b.t < ouch + 0.7)
    b.contact[lifted] = (0.0, 1.0)
    b["spine1.flex"] += 15.0 * _envelope(b, [ouch, ouch + 0.3, ouch + 1.0], [0, 1, 0])
    b["neck.flex"] += 20.0 * _envelope(b, [ouch, ouch + 0.3, ouch + 1.0], [0, 1, 0])


def high_five(scene: Scene) -> None:
    a, b = scene.takes
    _face_off(scene, 0.8)
    t0, k = _fit(a, 1.8)
    slap = t0 + 0.6 * k
    env = _envelope(a, [t0, slap, slap + 0.12 * k, slap + 0.8 * k], [0, 1, 1, 0])
    up = 0.38 if scene.mode == "high" else 0.18
    _hands_meet(scene, env, env, joint="right_shoulder", down=-up, apart=0.01)
    if scene.mode == "both hands":
        _hands_meet(scene, env, env, joint="left_shoulder", down=-0.3, apart=0.01, sides=("left", "left"))


def cheers_and_drink(scene: Scene) -> None:
    a, b = scene.takes
    _face_off(scene, 0.85)
    t0, k = _fit(a, 3.2)
    clink, drink = t0 + 0.8 * k, t0 + 1.5 * k
    env = _envelope(a, [t0, clink, t0 + 2.6 * k, t0 + 3.1 * k], [0, 1, 1, 0])
    to_mouth = _envelope(a, [clink + 0.2 * k, drink], [0, 1])

    def target(person):
        def at(w: World):  # glasses touch (the wrists ~0.26 m apart), then each drinks
            d = _toward(w, 0, 1)
            meet = _meeting(w, "right_shoulder", down=0.15) + (0.13 if person else -0.13) * d
            mouth = w.point(person, "head", (-0.03, -0.12, 0.12))
            return meet + to_mouth[:, None] * (mouth - meet)
        return at
    for p in (0, 1):
        scene.reach(p, "right", env, target(p), elbow_hint=(0.6, -1.0, -0.2))
    sip = _envelope(a, [drink, drink + 0.3 * k, t0 + 2.4 * k, t0 + 2.8 * k], [0, 1, 1, 0])
    for take in (a, b):
        take["neck.flex"] -= 20.0 * sip
        take["right_wrist.flex"] -= 30.0 * sip


def carry_together(scene: Scene) -> None:
    a, b = scene.takes
    _face_off(scene, 1.1)
    t0, k = _fit(a, 3.4)
    lift = _envelope(a, [t0, t0 + 0.6 * k, t0 + 2.8 * k, t0 + 3.4 * k], [0, 1, 1, 0])
    for take in (a, b):  # squat to the object, stand up with it
        dip = _envelope(take, [t0 - 0.4 * k, t0, t0 + 0.6 * k, t0 + 2.8 * k, t0 + 3.4 * k], [0, 1, 0, 0, 1])
        skills.crouch(take, 70.0 * dip, 35.0 * dip)
    span = a.vary(0.45, 0.1)  # half the object's width, between each person's hands

    def target(person, side):
        def at(w: World):
            d = _toward(w, 0, 1)
            lateral = np.cross(d, np.array([0.0, 1.0, 0.0]))  # person 0's right
            grip = _meeting(w, "spine2", down=0.25) + (0.32 if person else -0.32) * d
            sign = -1.0 if (side == "left") == (person == 0) else 1.0
            return grip + sign * span * lateral * 0.5
        return at
    for p in (0, 1):
        for side in SIDES:
            scene.reach(p, side, lift, target(p, side), elbow_hint=(0.8, -1.0, -0.2))
    if scene.mode == "sidestep":  # both step sideways together, to person 0's left (the partner's right)
        phase = np.clip((a.t - t0 - 0.9 * k) / (0.8 * k), 0.0, 2.0)
        skills.side_steps(a, phase, width=12.0, travel=1)
        skills.side_steps(b, phase, width=12.0, travel=-1)


def take_photo(scene: Scene) -> None:
    a, b = scene.takes
    _face_off(scene, 2.0)
    t0, k = _fit(a, 2.6)
    env = _envelope(a, [t0, t0 + 0.6 * k, t0 + 2.0 * k, t0 + 2.5 * k], [0, 1, 1, 0])
    for side in SIDES:  # both hands hold a camera in front of the face
        x = -0.06 if side == "right" else 0.06
        scene.reach(0, side, env, lambda w, x=x: w.point(0, "head", (x, -0.08, 0.28)), elbow_hint=(1.0, -0.8, -0.2))
    a["neck.flex"] += 5.0 * env
    pose = _envelope(b, [t0 + 0.3 * k, t0 + 0.8 * k, t0 + 2.0 * k, t0 + 2.5 * k], [0, 1, 1, 0])
    if scene.mode == "victory sign":
        skills.set_arm(b, "right", 60.0 * pose + 3.0, 40.0 * pose + 6.0, elbow=110.0 * pose + 15.0)
        b["right_elbow.pron"] = -60.0 * pose
    else:  # the partner waves
        skills.set_arm(b, "right", 40.0 * pose + 3.0, 80.0 * pose + 6.0, elbow=90.0 * pose + 15.0)
        b["right_shoulder.rot"] += 25.0 * pose * np.sin(2 * np.pi * 2.5 * b.t)


def follow(scene: Scene) -> None:
    a, b = scene.takes
    skills.stand(a, heading=scene.rng.normal(0.0, 4.0))
    skills.stand(b, heading=scene.rng.normal(0.0, 4.0))
    scene.place(0, 0.0, 0.0)
    scene.place(1, scene.rng.normal(0.0, 0.1), -a.vary(1.6, 0.1))  # behind person 0, same direction
    speed = a.vary(1.0, 0.1)
    _walk(a, cadence=1.7, size=speed / 1.1)
    _walk(b, cadence=1.7 * a.tempo / b.tempo, start=a.uniform(0.2, 0.6), size=0.9 * speed / 1.1)  # no faster


def whisper(scene: Scene) -> None:
    a, b = scene.takes
    _side_by_side(scene, 0.9)
    t0, k = _fit(a, 2.8)
    lean = _envelope(a, [t0, t0 + 0.6 * k, t0 + 2.1 * k, t0 + 2.7 * k], [0, 1, 1, 0])
    skills.bend_trunk(a, -18.0 * lean)  # toward the partner on the right
    skills.turn_trunk(a, -20.0 * lean)
    a["neck.twist"] -= 30.0 * lean
    a["neck.bend"] -= 10.0 * lean
    skills.bend_trunk(b, 3.0 * lean)  # the partner tilts the ear toward person 0
    scene.reach(0, "right", lean, lambda w: w.point(0, "head", (-0.04, -0.08, 0.1)), elbow_hint=(0.0, -1.0, 1.0))


def exchange(scene: Scene) -> None:
    a, b = scene.takes
    _face_off(scene, 0.75)
    t0, k = _fit(a, 2.8)
    meet = t0 + 0.9 * k
    env = _envelope(a, [t0, meet, meet + 0.5 * k, meet + 1.2 * k], [0, 1, 1, 0])
    # each gives with the right hand into the other's left: two meeting points, one on each side
    _hands_meet(scene, env, env, joint="right_shoulder", down=0.3, apart=0.01, sides=("right", "left"))
    _hands_meet(scene, env, env, joint="left_shoulder", down=0.3, apart=0.01, sides=("left", "right"))


def support_somebody(scene: Scene) -> None:
    a, b = scene.takes
    _side_by_side(scene, 0.52)
    b["spine1.flex"] += 18.0  # the partner is unwell: bent over, knees soft
    b["spine2.flex"] += 10.0
    for side in SIDES:
        b[f"{side}_knee.flex"] += 12.0
        b[f"{side}_hip.flex"] += 10.0
    t0, k = _fit(a, 1.4)
    env = _envelope(a, [t0, t0 + 0.7 * k], [0, 1])
    # person 0's right hand under the partner's left arm at the shoulder, the left hand on the partner's arm
    scene.reach(0, "right", env, lambda w: w.point(1, "spine3", (0.13, 0.05, -0.1)), elbow_hint=(0.8, -0.6, -0.4))
    scene.reach(0, "left", env, lambda w: w.point(1, "spine3", (0.2, -0.05, 0.08)), elbow_hint=(0.3, -1.0, -0.3))
    if scene.mode == "walking":
        speed = a.vary(0.5, 0.1)
        start = t0 + 0.8 * k
        _walk(a, cadence=1.3, start=start, size=speed / 1.1)
        _walk(b, cadence=1.3, start=start, size=speed / 1.1)


def rock_paper_scissors(scene: Scene) -> None:
    a, b = scene.takes
    _face_off(scene, 0.9)
    t0, k = _fit(a, 2.6)
    for take in (a, b):
        env = _envelope(take, [t0, t0 + 0.4 * k, t0 + 2.2 * k, t0 + 2.6 * k], [0, 1, 1, 0])
        beat = take.vary(2.2, 0.1)  # three pumps of the fist, then the throw
        pumps = np.clip((take.t - t0 - 0.4 * k) * beat, 0.0, 3.0)
        bounce = 0.5 - 0.5 * np.cos(2 * np.pi * pumps)
        throw = _envelope(take, [t0 + 0.4 * k + 3.0 / beat, t0 + 0.4 * k + 3.2 / beat], [0, 1])
        skills.set_arm(take, "right", env * (35.0 + 10.0 * bounce) + 3.0, 10.0 * env + 6.0,
                       elbow=env * (100.0 - 40.0 * throw + 20.0 * bounce) + 15.0)
        take["right_elbow.pron"] = 90.0 * env * (1.0 - throw) - 20.0 * throw


_PERFORM = {
    50: (punching_slapping, ("punch", "slap")),
    51: (kicking, ("right leg", "left leg")),
    52: (pushing, ("both hands", "one hand")),
    53: (pat_on_back, ("side by side", "facing")),
    54: (point_finger, ("right hand", "left hand")),
    55: (hugging, ("criss-cross", "neck-waist")),
    56: (giving, ("right hand",)),
    57: (touch_pocket, ("front pocket", "side pocket")),
    58: (handshaking, ("firm", "vigorous")),
    59: (walking_towards, ("steady",)),
    60: (walking_apart, ("steady",)),
    106: (hit_with_something, ("overhead", "sideways")),
    107: (wield_knife, ("stab", "slash")),
    108: (knock_over, ("shoulder charge",)),
    109: (grab_stuff, ("snatch",)),
    110: (shoot_with_gun, ("one shot", "three shots")),
    111: (step_on_foot, ("stamp",)),
    112: (high_five, ("high", "low", "both hands")),
    113: (cheers_and_drink, ("clink and sip",)),
    114: (carry_together, ("lift", "sidestep")),
    115: (take_photo, ("victory sign", "wave")),
    116: (follow, ("walking",)),
    117: (whisper, ("right ear",)),
    118: (exchange, ("both at once",)),
    119: (support_somebody, ("standing", "walking")),
    120: (rock_paper_scissors, ("three pumps",)),
}

_R, _L = _hand("right"), _hand("left")
_TOUCHES = {
    50: (((0, _R), (1, HEAD)),),
    51: (((0, ("right_ankle", "right_foot")), (1, ("left_knee", "left_ankle"))),
         ((0, ("left_ankle", "left_foot")), (1, ("right_knee", "right_ankle")))),
    52: (((0, _R), (1, TORSO)),),
    53: (((0, _R), (1, UPPER_BACK)),),
    55: (((0, _R), (1, UPPER_BACK)), ((1, _R), (0, UPPER_BACK))),
    56: (((0, _R), (1, _R)),),
    57: (((0, _R), (1, ("pelvis", "left_hip"))),),
    58: (((0, _R), (1, _R)),),
    108: (((0, ("right_collar", "right_shoulder") + TORSO), (1, TORSO + ("neck",))),),  # the bodies meet
    109: (((0, _R), (1, _R)),),
    111: (((0, ("right_ankle", "right_foot")), (1, ("left_ankle", "left_foot"))),),
    112: (((0, _R), (1, _R)), ((0, _L), (1, _L))),
    118: (((0, _R), (1, _L)), ((0, _L), (1, _R))),
    119: (((0, _R), (1, UPPER_BACK)), ((0, _L), (1, ("left_shoulder", "left_elbow")))),
}

CLASSES = tuple(SceneClass(ACTION_NAMES[a], _PERFORM[a][1], _PERFORM[a][0], touches=_TOUCHES.get(a, ()))
                for a in MUTUAL_ACTIONS)
