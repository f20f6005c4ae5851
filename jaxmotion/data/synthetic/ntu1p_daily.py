"""NTU RGB+D 120's single-person daily actions A001-A049 (synth-ntu1p's first 49 classes, NTU id order).

Each class is a ``perform(take)`` composition of skills; modes are ground-truth style labels (the acting
hand, standing or seated, tempo or height). Classes that exist elsewhere reuse their code: pickup, throw,
sitting down, standing up, cheer up, hand waving, kicking something and salute are NTU-13's; drink, eat and
the phone call are HumanAct12's. NTU clips are 30 fps, 2-5 s: one-off movements start at ``take.onset`` and
are compressed where the real action takes longer, repeated ones cycle.

The data is seen as Kinect joints (NTU-25 markers on the body): wrists, hands, hand tips and thumbs (the last
two move with the wrist's frame, so forearm twist and wrist flexion show), head, spine and legs. Each class
must differ from every other of the 94 single-person classes in some joint's motion; near pairs are told
apart deliberately, as the comments at each say (reading / writing / phone / keyboard; jacket and shoe on /
off; glasses / hat; touch head / chest / back / neck; cough / wipe face / nausea; clap / rub / palms /
cross). Hand targets are wrist positions in the thorax (spine3) frame, side-normalised (x away from the
midline, y up, z forward; negative x crosses the midline), metres at template size times ``take.scale()``.
Figures: MOTION_FACTS sections 2-4 (est. where the tables have none).
"""

from __future__ import annotations

import numpy as np

from jaxmotion.data.formats.ntu120 import ACTION_NAMES
from jaxmotion.data.synthetic import humanact12, ntu13, skills, timing
from jaxmotion.data.synthetic.engine import ActionClass
from jaxmotion.data.synthetic.take import SIDES, Take, other
from jaxmotion.geometry.skeletons import SMPL24

# --- helpers ---------------------------------------------------------------------------------------------


def _side(take: Take) -> str:
    """The acting side named by the mode, else the right (most people use their right hand)."""
    return "left" if "left" in take.mode else "right"


def _leftward(side: str) -> float:
    """+1 for the left side, -1 for the right: the sign of trunk bend / twist and heading toward ``side``."""
    return 1.0 if side == "left" else -1.0


def _start(take: Take) -> None:
    """Relaxed standing, seated on a chair if the mode says so (NTU has seated and standing performers)."""
    skills.stand(take)
    if "seated" in take.mode:
        skills.seated(take)


def _fit(take: Take, durations) -> np.ndarray:
    """Phase durations (s) of a one-off movement at the take's tempo (each varied 10%), compressed where they
    would not fit in 90% of the clip: the recognisable part of a long action is kept, faster."""
    d = np.array([take.vary(x, 0.1) for x in durations]) / take.tempo
    return d * min(1.0, 0.9 * take.duration / d.sum())


def _keys(take: Take, *durations: float) -> np.ndarray:
    """Keyframe times of a one-off movement whose phases last ``durations`` s, placed so it fits."""
    d = _fit(take, durations)
    return take.onset(d.sum()) + np.concatenate([[0.0], np.cumsum(d)])


def _curve(take: Take, keys, *values) -> np.ndarray:
    return timing.keyframes(take.t, keys, values)


def _held(take: Take, rise: float, fall: float, share: float) -> np.ndarray:
    """``[T]`` 0 -> 1 over ``rise`` s, held for ``share`` of the clip, back to 0 over ``fall`` s."""
    rise, fall = take.vary(rise, 0.15) / take.tempo, take.vary(fall, 0.15) / take.tempo
    hold = take.vary(share, 0.1) * take.duration
    scale = min(1.0, 0.95 * take.duration / (rise + hold + fall))
    rise, hold, fall = rise * scale, hold * scale, fall * scale
    t0 = take.onset(rise + hold + fall)
    return _curve(take, [t0, t0 + rise, t0 + rise + hold, t0 + rise + hold + fall], 0.0, 1.0, 1.0, 0.0)


def _lean(take: Take, angle) -> None:
    """Flex the trunk forward ``angle [T]`` degrees over the lumbar and thoracic spine (negative: arch back)."""
    for joint, share in (("spine1", 0.45), ("spine2", 0.35), ("spine3", 0.2)):
        take[f"{joint}.flex"] += share * np.asarray(angle)


def _rest(take: Take) -> np.ndarray:
    return skills.relaxed_wrist(take)


def _path(take: Take, side: str, keys, points, *, hint=(0.4, -1.0, -0.3), hands=None) -> None:
    """``side``'s wrist through ``points`` (``None`` = the relaxed hanging wrist) at the times ``keys``,
    minimum-jerk between them (a hold is two equal points); ``hands``: per key ``None`` (the hand follows the
    forearm) or ``(fingers, palm)`` directions for :func:`_orient`, blended in and out between keys."""
    pts = np.stack([_rest(take) if p is None else np.asarray(p, float) for p in points])
    skills.reach(take, side, timing.keyframes(take.t, keys, pts), elbow_hint=hint)
    if hands is None or all(h is None for h in hands):
        return
    known = [k for k, h in enumerate(hands) if h is not None]
    nearest = [hands[min(known, key=lambda j: abs(j - k))] for k in range(len(hands))]
    fingers = timing.keyframes(take.t, keys, np.stack([_unit(h[0]) for h in nearest]))
    palms = timing.keyframes(take.t, keys, np.stack([_unit(h[1]) for h in nearest]))
    weight = timing.keyframes(take.t, keys, [0.0 if h is None else 1.0 for h in hands])
    _orient(take, side, fingers, palms, weight)


def _at(take: Take, *xyz) -> np.ndarray:
    """A thorax-frame point (template metres) scaled to the subject."""
    return take.scale() * np.array(xyz, float)


# Where the hand goes on the head: the knuckles (the Kinect hand joint) relative to the head joint (the skull
# base), the direction of the fingers and the way the palm faces; side-normalised thorax frame, template metres
# (est. from head proportions: the face ~10 cm ahead of the skull base, the mouth level with it, the eyes ~8 cm
# above, the crown ~18 cm).
_HEAD_SPOTS = {
    "mouth": ((-0.03, 0.03, 0.14), (-0.8, 0.5, 0.2), (0.2, 0.0, -1.0)),  # the palm over mouth and nose
    "brush": ((0.04, 0.0, 0.17), (-0.7, 0.1, 0.7), (-0.3, -0.6, -0.6)),  # a toothbrush in the fist at the mouth
    "forehead": ((-0.04, 0.135, 0.115), (-0.95, 0.1, -0.1), (0.0, 0.0, -1.0)),  # the palm across the forehead
    "temple": ((0.09, 0.115, 0.02), (0.0, 0.95, -0.3), (-1.0, 0.0, 0.0)),  # palm on the side of the head
    "lens": ((0.08, 0.06, 0.14), (-0.3, 0.5, 0.8), (-0.7, 0.0, -0.7)),  # holding the glasses before the eye
    "hinge": ((0.09, 0.06, 0.03), (-0.2, 0.5, 0.85), (-1.0, 0.0, -0.2)),  # at the temple arm above the ear
    "crown": ((0.07, 0.19, 0.02), (-0.5, 0.85, 0.1), (-0.6, -0.8, 0.0)),  # the sides of the top of the head
    "above": ((0.09, 0.3, 0.06), (-0.4, 0.9, 0.2), (-0.5, -0.8, 0.1)),  # over the head, holding a cap
    "brim": ((0.03, 0.16, 0.15), (-0.5, 0.4, 0.75), (0.0, -0.7, -0.7)),  # a cap's brim at the forehead
    "nape": ((-0.04, -0.03, -0.09), (-0.9, 0.2, -0.3), (0.2, 0.0, 1.0)),  # the palm on the back of the neck
    "brow": ((0.03, 0.15, 0.125), (-0.1, 0.95, 0.1), (0.0, 0.0, -1.0)),  # palm on the forehead, fingers up
    "chin": ((0.03, 0.0, 0.115), (-0.1, 0.95, 0.1), (0.0, 0.0, -1.0)),  # the palm over the chin, fingers up
    "ear": ((0.09, 0.07, -0.01), (0.0, 0.95, -0.2), (-1.0, 0.0, 0.0)),  # the palm over the ear
    "bridge": ((-0.02, 0.09, 0.15), (-0.5, 0.8, 0.2), (0.0, 0.0, -1.0)),  # a finger on the glasses' bridge
}
_HAND = 0.085  # wrist to knuckles, template metres (MOTION_FACTS 1.2)


def _unit(v) -> np.ndarray:
    v = np.asarray(v, float)
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


def _spot(take: Take, name: str, shift=(0.0, 0.0, 0.0)) -> np.ndarray:
    """Wrist target that puts the hand at a :data:`_HEAD_SPOTS` place (shifted by ``shift``, template m)
    with its fingers along the spot's direction."""
    knuckles, fingers, _ = _HEAD_SPOTS[name]
    return take.head_point() + take.scale() * (np.asarray(knuckles) + np.asarray(shift, float)
                                               - _HAND * _unit(fingers))


def _hand(name: str) -> tuple:
    """``(fingers, palm)`` of a :data:`_HEAD_SPOTS` place, for :func:`_path`."""
    return _HEAD_SPOTS[name][1:]


def _to_head(take: Take, side: str, env: np.ndarray, name: str, *, hint, shift=(0.0, 0.0, 0.0),
             bulge: float = 0.05) -> None:
    """``side``'s hand to a :data:`_HEAD_SPOTS` place as ``env [T]`` goes 0 -> 1 (``shift`` may be ``[T, 3]``),
    oriented as the spot says."""
    skills.toward(take, side, env, _spot(take, name, shift), elbow_hint=hint, bulge=bulge)
    _orient(take, side, *_hand(name), env)


def _thorax_point(take: Take, side: str, joint: str, offset=(0.0, 0.0, 0.0)) -> np.ndarray:
    """``[T, 3]`` where ``joint`` (plus ``offset`` in its own frame, template m) is in the thorax frame,
    side-normalised for ``side``'s arm: a wrist target on the body itself."""
    rot, pos = skills.posed(take)
    j, chest = SMPL24.index(joint), SMPL24.index("spine3")
    point = pos[:, j] + rot[:, j] @ (take.scale() * np.asarray(offset, float))
    local = np.einsum("tba,tb->ta", rot[:, chest], point - pos[:, chest])
    if side == "right":
        local[:, 0] *= -1.0
    return local


_PRONATIONS = np.arange(-80.0, 80.1, 5.0)  # candidate forearm twists (the elbow.pron limits)


def _orient(take: Take, side: str, fingers, palm, weight=1.0) -> None:
    """Turn ``side``'s hand (forearm pronation, wrist flexion and deviation, within their limits) so that its
    fingers point along ``fingers`` and its palm faces ``palm`` (``[3]`` or ``[T, 3]``, side-normalised thorax
    frame) where ``weight [T]`` is 1, blending with the current angles elsewhere.

    Per frame, every pronation on a 5-degree grid gets the wrist angles that aim the fingers (closed form,
    then clipped to the limits); the one with the least finger error plus half the palm error wins, and the
    winners are smoothed over ~0.1 s so the forearm does not flick between near-equal choices."""
    rot, _ = skills.posed(take)
    mirror = np.diag([-1.0 if side == "right" else 1.0, 1.0, 1.0])  # the right arm is the left's mirror image
    q = mirror @ np.einsum("tba,tbc->tac", rot[:, SMPL24.index("spine3")],
                           rot[:, SMPL24.index(f"{side}_elbow")]) @ mirror  # elbow frame in the thorax's
    x = np.array(np.broadcast_to(_unit(fingers), (take.num_frames, 3)))
    n = np.array(np.broadcast_to(_unit(palm), (take.num_frames, 3)))
    now = take[f"{side}_elbow.pron"].copy()

    def solve(pron):
        """Wrist angles aiming the fingers for forearm twists ``pron [..., T]``, and the (fingers, palm) errors."""
        d = np.radians(pron - now)
        c, s_ = np.cos(d), np.sin(d)
        zero, one = np.zeros_like(d), np.ones_like(d)
        twist = np.stack([np.stack([one, zero, zero], -1), np.stack([zero, c, -s_], -1),
                          np.stack([zero, s_, c], -1)], -2)
        frame = q @ twist  # [..., T, 3, 3]
        u = np.einsum("...ba,...b->...a", frame, x)
        flex = np.clip(-np.degrees(np.arctan2(u[..., 1], u[..., 0])) + _REST_TURN, -70.0, 80.0)
        dev = np.clip(np.degrees(np.arcsin(np.clip(-u[..., 2], -1, 1))) - _REST_TIP, -30.0, 20.0)
        f, t = np.radians(-flex), np.radians(dev)
        cf, sf, ct, st = np.cos(f), np.sin(f), np.cos(t), np.sin(t)
        wrist = np.stack([np.stack([cf * ct, -sf, cf * st], -1), np.stack([sf * ct, cf, sf * st], -1),
                          np.stack([-st, zero, ct], -1)], -2)  # Rz(-flex) Ry(dev)
        hand = frame @ wrist @ _REST_HAND
        err = (np.arccos(np.clip(np.sum(hand[..., 0] * x, -1), -1, 1))
               + 0.5 * np.arccos(np.clip(-np.sum(hand[..., 1] * n, -1), -1, 1)))
        return flex, dev, err

    _, _, err = solve(np.broadcast_to(_PRONATIONS[:, None], (len(_PRONATIONS), take.num_frames)))
    best = _PRONATIONS[np.argmin(err, axis=0)]
    taps = np.exp(-0.5 * (np.arange(-6, 7) / 2.0) ** 2)
    best = np.convolve(np.pad(best, 6, mode="edge"), taps / taps.sum(), mode="valid")
    flex, dev, _ = solve(best)
    w = np.broadcast_to(np.asarray(weight, float), take.t.shape)
    for name, value in (("elbow.pron", best), ("wrist.flex", flex), ("wrist.dev", dev)):
        take[f"{side}_{name}"] = w * value + (1.0 - w) * take[f"{side}_{name}"]


def _rest_hand_frame() -> np.ndarray:
    """``[3, 3]`` the left hand's rest frame in its wrist's: columns = bone direction, palm-down normal's
    opposite, thumb side."""
    x = _unit(SMPL24.offsets[SMPL24.index("left_hand")])
    y = _unit(np.array([0.0, 1.0, 0.0]) - x[1] * x)
    return np.stack([x, y, np.cross(x, y)], -1)


_REST_HAND = _rest_hand_frame()
_REST_TURN = float(np.degrees(np.arctan2(_REST_HAND[1, 0], _REST_HAND[0, 0])))  # the bone's own slant
_REST_TIP = float(np.degrees(np.arcsin(-_REST_HAND[2, 0])))


def _oscillation(take: Take, rate: float, *, wobble: float = 0.08) -> np.ndarray:
    """``[T]`` sin of a rhythm at ``rate`` /s (tempo-scaled, drifting a little)."""
    return np.sin(2 * np.pi * timing.warped_phase(take.t, rate * take.tempo, take.rng, wobble=wobble))


# --- A003-A005: brushing, drop ---------------------------------------------------------------------------


def brushing_teeth(take: Take) -> None:
    """A fist held before the mouth scrubbing side to side at 3-4 Hz (est.), drifting from one side of the
    mouth to the other. Unlike drink / eat (the hand travels to the mouth and back) or a cough (a jerk) the
    hand stays and shakes; unlike hush (other module: a still finger at the lips) it scrubs."""
    _start(take)
    side = _side(take)
    up = _held(take, 0.5, 0.5, 0.75)
    scrub = take.amp * take.vary(0.025, 0.2) * _oscillation(take, take.vary(3.5, 0.12))
    drift = take.vary(0.025, 0.3) * np.sin(2 * np.pi * take.uniform(0.2, 0.4) * take.t + take.uniform(0, 6.3))
    shift = np.stack([scrub + drift, 0.3 * scrub, np.zeros_like(scrub)], -1)
    _to_head(take, side, up, "brush", hint=(0.9, -0.6, -0.1), shift=shift)
    take[f"{side}_wrist.dev"] += 300.0 * scrub * up  # the wrist waggles with the strokes
    skills.turn_head(take, flex=take.vary(8.0, 0.4) * up)


def brushing_hair(take: Take) -> None:
    """Strokes over the head ~1 /s (est.): the hand runs from the hairline over the top to the back of the head
    (``long hair``: from the top down the side to the shoulder), then lifts off and comes round again; the
    elbow high and out, the head tilting into the stroke. Unlike touch head / neck it moves; unlike flick
    hair (other module) it repeats."""
    _start(take)
    side = _side(take)
    up = _held(take, 0.6, 0.6, 0.7)
    phase = timing.warped_phase(take.t, take.vary(0.9, 0.15) * take.tempo, take.rng)
    if take.mode == "long hair":  # the brush handle held forward, bristles to the head, combing down
        knots = (0.0, 0.25, 0.5, 0.75)
        points = [(0.08, 0.2, 0.03), (0.13, 0.05, 0.02), (0.17, -0.1, 0.04), (0.17, 0.16, 0.08)]
        fingers, palm = (0.0, 0.2, 1.0), (-1.0, 0.0, 0.0)
    else:  # hairline -> top -> back of the head, then lifted off and round to the front
        knots = (0.0, 0.2, 0.4, 0.55, 0.8)
        points = [(0.04, 0.16, 0.1), (0.07, 0.21, 0.0), (0.08, 0.14, -0.1), (0.14, 0.19, -0.04), (0.11, 0.25, 0.1)]
        fingers, palm = (-0.5, 0.8, 0.0), (-0.6, -0.8, 0.0)
    knuckles = timing.periodic(phase, knots, np.asarray(points))
    target = take.head_point() + take.scale() * (knuckles - _HAND * _unit(fingers))
    skills.toward(take, side, up, target, elbow_hint=(1.0, 0.4, 0.0), bulge=0.05)
    _orient(take, side, fingers, palm, up)
    skills.turn_head(take, flex=6.0 * up, bend=-_leftward(side) * take.vary(8.0, 0.3) * up)


def drop(take: Take) -> None:
    """Holding an object out in front, letting it go: the fingers spring open (the hand tips up, the arm
    rebounds a little as the load goes), the head and trunk bend to look at it on the floor, the arm drops.
    Unlike throw there is no swing; unlike pickup no crouch."""
    _start(take)
    both = take.mode == "both hands"
    hands = SIDES if both else (_side(take),)
    keys = _keys(take, 0.6, 0.7, 0.15, 0.35, 0.7, 0.5)  # raise, hold, release, look, watch, lower
    hold = _curve(take, keys, 0, 1, 1, 1, 1, 1, 0)
    release = _curve(take, keys, 0, 0, 0, 1, 1, 1, 1)
    rebound = _curve(take, keys, 0, 0, 0, 1, 0.3, 0.3, 0)
    for side in hands:
        grip = _at(take, 0.13 if both else 0.1, -0.17, 0.32) + _at(take, 0.0, 0.035, 0.0) * rebound[:, None]
        skills.toward(take, side, hold, grip, elbow_hint=(0.4, -1.0, -0.3))
        if both:  # a box between the palms
            _orient(take, side, (0.0, 0.0, 1.0), (-1.0, 0.0, 0.0), hold)
        else:  # gripped from above, then the fingers open forward and up
            r = release[:, None]
            _orient(take, side, (1 - r) * _unit((0.0, -0.4, 0.9)) + r * _unit((0.0, 0.4, 0.9)),
                    (0.0, -1.0, 0.2), hold)
    look = _curve(take, keys, 0, 0, 0, 0, 1, 1, 0.3)
    skills.turn_head(take, flex=take.vary(30.0, 0.2) * look)
    _lean(take, take.vary(10.0, 0.3) * look)


# --- A010-A013: clapping, reading, writing, tearing -----------------------------------------------------


def clapping(take: Take) -> None:
    """Palms clapping 2-3.5 times/s (est.) in front of the chest (``face height``: raised before the face),
    the hands opening 15-30 cm. Unlike rubbing hands (in contact, sliding fore-aft) or palms together (still)
    the hands part and meet sideways; unlike cross hands the wrists never pass the midline."""
    _start(take)
    high = take.mode == "face height"
    up = _held(take, 0.4, 0.4, 0.8)
    phase = timing.warped_phase(take.t, take.vary(2.2 if high else 2.9, 0.12) * take.tempo, take.rng)
    apart = (0.5 - 0.5 * np.cos(2 * np.pi * phase)) ** 0.8  # 0 at each clap
    gap = take.amp * take.vary(0.1, 0.15) * take.scale()
    centre = _at(take, 0.0, 0.2, 0.34) if high else _at(take, 0.0, -0.08, 0.3)
    for side in SIDES:
        target = centre + np.stack([0.035 * take.scale() + gap * apart, 0.01 * apart, -0.03 * apart], -1)
        skills.toward(take, side, up, target, elbow_hint=(0.7, -1.0, -0.2))
        _orient(take, side, (-0.25, 0.55, 0.8), (-1.0, 0.0, 0.1), up)


# Holding something to look at, two-handed (wrist targets, palm directions): a book at reading distance
# (~35 cm from the eyes, below them), a phone held close, low.
_HOLDS = {"book": ((0.15, -0.01, 0.3), (-0.2, 0.6, 0.75), (-0.8, 0.5, 0.0)),
          "phone": ((0.06, -0.12, 0.27), (-0.4, 0.2, 0.9), (-0.5, 0.85, 0.0))}


def _hold_object(take: Take, env: np.ndarray, kind: str, sides=SIDES) -> np.ndarray:
    """Both hands (or ``sides``) hold a :data:`_HOLDS` object as ``env`` goes 0 -> 1; returns the wrist target
    ``[T, 3]`` (side-normalised) with its slow sway."""
    at, fingers, palm = _HOLDS[kind]
    target = _at(take, *at) + take.scale() * timing.smooth_noise(take.t, take.rng, 0.006, max_hz=0.5, channels=3)
    for side in sides:
        skills.toward(take, side, env, target, elbow_hint=(0.5, -1.0, -0.3), bulge=0.06)
        _orient(take, side, fingers, palm, env)
    return target


def reading(take: Take) -> None:
    """A book held in both hands at reading distance (hands ~28 cm apart at lower-chest height, palms in),
    the head bent 15-30 degrees and scanning the lines; every 2-4 s one hand turns a page, sweeping across
    to the other hand and back. Near pairs: writing has one hand still and the other scribbling, lower; the
    phone is held closer and lower with the hands together; the keyboard is low, palms down, both hands
    tapping, the head up."""
    _start(take)
    up = _held(take, 0.6, 0.6, 0.85)
    book = _hold_object(take, up, "book")
    turner = take.choice(SIDES)
    turns = skills.bumps(take, skills.beats(take, take.vary(3.0, 0.2), jitter=0.25), take.vary(0.8, 0.15)) * up
    sweep = book + np.stack([-0.22 * turns, 0.04 * turns, 0.04 * turns], -1) * take.scale()
    skills.reach(take, turner, (1.0 - up)[:, None] * _rest(take) + up[:, None] * sweep, elbow_hint=(0.5, -1.0, -0.3))
    _orient(take, turner, *_HOLDS["book"][1:], up)
    scan = take.vary(4.0, 0.3) * np.sin(2 * np.pi * take.uniform(0.25, 0.45) * take.t)  # along the lines
    skills.turn_head(take, flex=take.vary(22.0, 0.2) * up, twist=scan * up + _leftward(other(turner)) * 5.0 * turns)


def writing(take: Take) -> None:
    """Writing: one hand holds a notepad low before the body, palm up (``seated at a table``: lies flat on
    the table), the pen hand scribbles on it with 4-6 Hz wiggles (est.) moving along a line and jumping back
    to the next; the head bent ~30 degrees. The pen hand is the right."""
    _start(take)
    pen, pad = "right", "left"
    table = "table" in take.mode
    if table:
        _lean(take, take.vary(12.0, 0.2))
    up = _held(take, 0.6, 0.6, 0.85)
    s = take.scale()
    skills.toward(take, pad, up, _at(take, 0.14, -0.3, 0.36) if table else _at(take, 0.1, -0.2, 0.3),
                  elbow_hint=(0.5, -1.0, -0.3))
    _orient(take, pad, (-0.3, 0.0, 0.95) if table else (-0.2, 0.2, 0.95), (0, -1, 0) if table else (0, 1, 0), up)
    line = np.mod(timing.warped_phase(take.t, take.vary(0.55, 0.15) * take.tempo, take.rng), 1.0)
    along = timing.keyframes(line, [0.0, 0.85, 1.0], [0.0, 1.0, 0.0])  # write along, jump back
    wiggle = np.stack([_oscillation(take, take.vary(5.0, 0.15)), _oscillation(take, take.vary(4.0, 0.15)),
                       np.zeros_like(line)], -1) * 0.008 * s
    start = _at(take, -0.05, -0.27, 0.4) if table else _at(take, -0.04, -0.16, 0.33)
    nib = start + s * np.stack([0.11 * along, np.zeros_like(along), 0.01 * along], -1) + wiggle  # rightward
    skills.toward(take, pen, up, nib, elbow_hint=(0.6, -1.0, -0.2))
    _orient(take, pen, (-0.5, -0.5, 0.7), (-0.6, -0.8, 0.0), up)
    take[f"{pen}_wrist.flex"] += 250.0 * wiggle[:, 1] / s * up
    skills.turn_head(take, flex=take.vary(30.0, 0.15) * up, twist=-4.0 * (along - 0.5) * up)


def tear_up_paper(take: Take) -> None:
    """Paper held at the chest in both hands, torn 2-4 times: a quick pull (``twisting``: one hand forward
    and down, the other back and up, the forearms turning opposite ways; ``pulling apart``: sideways), then
    the pieces brought together and gripped again (~1.2 s a tear, est.); the head looks down at them. Unlike
    clapping the hands are slow to part and quick to pull, palms down."""
    _start(take)
    up = _held(take, 0.5, 0.5, 0.8)
    phase = timing.warped_phase(take.t, take.vary(0.8, 0.15) * take.tempo, take.rng)
    tear = timing.keyframes(np.mod(phase, 1.0), [0.0, 0.2, 0.6, 0.95], [0.0, 1.0, 1.0, 0.0]) * up
    s = take.scale()
    centre = _at(take, 0.04, -0.16, 0.28)
    twist = take.mode == "twisting"
    for k, side in enumerate(SIDES):
        sign = 1.0 if k == 0 else -1.0
        if twist:
            shift = np.stack([0.02 * tear, 0.04 * sign * tear, 0.08 * sign * tear], -1)
        else:
            shift = np.stack([take.vary(0.13, 0.15) * tear, 0.02 * tear, -0.02 * tear], -1)
        skills.toward(take, side, up, centre + s * shift, elbow_hint=(0.6, -1.0, -0.2))
        _orient(take, side, (-0.3, 0.4, 0.85), (-0.5, -0.85, 0.0), up)
        if twist:
            take[f"{side}_elbow.pron"] += 40.0 * sign * tear
    skills.turn_head(take, flex=take.vary(22.0, 0.2) * up)


# --- A014-A021: jacket, shoe, glasses, hat on and off ----------------------------------------------------


def wear_jacket(take: Take) -> None:
    """Putting a jacket on (~3.5 s, compressed to fit): both hands pick it up by the collar before the chest;
    the first arm goes down, out and back into its sleeve while the other hand holds the collar at the first
    shoulder; that hand swings the jacket round behind and its arm goes back into the second sleeve; a
    shrug with both hands at the lapels, then they pull the fronts down and come down. Take off jacket runs
    the arm paths in the other order (lapels first, sleeves last) and ends holding the jacket out; here the
    hands end down and the shrug comes late."""
    _start(take)
    first = _side(take)
    second = other(first)
    keys = _keys(take, 0.5, 0.7, 0.6, 0.7, 0.5, 0.5, 0.5)
    p = lambda *xyz: _at(take, *xyz)  # noqa: E731
    _path(take, first, keys, [None, p(0.12, -0.05, 0.3), p(0.33, -0.36, -0.06), p(0.28, -0.3, 0.05),
                              p(0.08, -0.12, 0.22), p(0.08, 0.0, 0.2), p(0.08, -0.25, 0.22), None],
          hint=(0.8, -1.0, -0.2))
    _path(take, second, keys, [None, p(0.12, -0.05, 0.3), p(-0.12, 0.05, 0.1), p(0.22, 0.1, -0.08),
                               p(0.3, -0.38, -0.12), p(0.08, 0.0, 0.2), p(0.08, -0.25, 0.22), None],
          hint=(0.8, -0.6, -0.4))
    toward_first = _leftward(first)
    skills.turn_trunk(take, toward_first * _curve(take, keys, 0, 0, 12, 0, -12, 0, 0, 0) * take.amp)
    shrug = _curve(take, keys, 0, 0, 0, 0, 0.5, 1, 0, 0)
    for side in SIDES:
        take[f"{side}_collar.elev"] += 12.0 * shrug
    skills.turn_head(take, flex=_curve(take, keys, 5, 15, 10, 5, 5, 10, 20, 5),
          twist=toward_first * _curve(take, keys, 0, 0, 20, 0, -20, 0, 0, 0))


def take_off_jacket(take: Take) -> None:
    """Taking a jacket off: both hands at the lapels, pushing it back off the shoulders (shoulder blades drawn
    back, chest out), both arms drop back out of the sleeves, the first comes forward free, that hand pulls
    the other sleeve off at the cuff in front, then holds the jacket out to the side to the end (wear jacket:
    the reverse order of the arm paths, ending with the hands down)."""
    _start(take)
    first = _side(take)
    second = other(first)
    keys = _keys(take, 0.5, 0.6, 0.6, 0.6, 0.6, 0.6)
    p = lambda *xyz: _at(take, *xyz)  # noqa: E731
    hold = p(0.28, -0.22, 0.3)
    _path(take, first, keys, [None, p(0.09, 0.0, 0.2), p(0.2, 0.1, -0.02), p(0.22, -0.42, -0.16),
                              p(0.15, -0.3, 0.25), p(-0.1, -0.32, 0.32), hold], hint=(0.8, -1.0, -0.2))
    _path(take, second, keys, [None, p(0.09, 0.0, 0.2), p(0.2, 0.1, -0.02), p(0.22, -0.42, -0.16),
                               p(0.2, -0.44, -0.16), p(0.18, -0.36, 0.3), None], hint=(0.8, -1.0, -0.2))
    back = _curve(take, keys, 0, 0, 1, 1, 0.3, 0, 0)
    for side in SIDES:
        take[f"{side}_collar.protr"] -= 15.0 * back
    take["spine3.flex"] -= 6.0 * back
    skills.turn_trunk(take, _leftward(first) * _curve(take, keys, 0, 0, 0, 10, -8, -12, 0) * take.amp)
    skills.turn_head(take, flex=_curve(take, keys, 0, 10, 0, 5, 10, 20, 10),
          twist=_leftward(second) * _curve(take, keys, 0, 0, 0, 0, 15, 15, 0))


def _sit_lean(take: Take, lean: np.ndarray) -> None:
    """Seated, lean the trunk forward ``lean [T]`` degrees from the hips, the thighs staying on the seat."""
    tilt = 0.5 * lean
    take["pelvis.tilt"] += tilt
    _lean(take, 0.5 * lean)
    for side in SIDES:
        take[f"{side}_hip.flex"] -= tilt


def wear_a_shoe(take: Take) -> None:
    """Putting a shoe on: bend down, both hands take the shoe from the floor beside the foot, the foot
    lifts forward and low into it, the hands tug at the heel twice, the foot goes down and stamps twice,
    upright again (``standing``: stooping with the foot forward, one hand at the heel). Take off a shoe lifts
    the foot high across the other knee (or behind) and carries the shoe away; here the foot stays low and
    forward, and stamps."""
    seated = take.mode == "seated"
    _start(take)
    foot = take.choice(SIDES) if take.rng.uniform() < 0.3 else "right"
    keys = _keys(take, 0.6, 0.5, 0.7, 0.4, 0.5, 0.6)  # reach shoe, to the foot, tug, foot down, stamp, up
    lift = _curve(take, keys, 0, 0, 1, 1, 0, 0, 0)
    stamp = np.zeros_like(lift)
    for t0 in (keys[4], keys[4] + 0.5 * (keys[5] - keys[4])):
        stamp += skills.bumps(take, [t0], 0.5 * (keys[5] - keys[4]))
    if seated:
        _sit_lean(take, take.vary(45.0, 0.1) * _curve(take, keys, 0, 1, 1, 1, 0.8, 0.4, 0))
        take[f"{foot}_hip.flex"] += 18.0 * lift + 8.0 * stamp
        take[f"{foot}_knee.flex"] -= 28.0 * lift + 8.0 * stamp
        take.contact[:, SIDES.index(foot)] *= 1.0 - 0.9 * np.minimum(lift + stamp, 1.0)
    else:
        bend = _curve(take, keys, 0, 1, 1, 1, 0.6, 0.3, 0)
        take[f"{foot}_hip.flex"] += 15.0 * lift + 10.0 * stamp
        take[f"{foot}_knee.flex"] += 20.0 * lift + 25.0 * stamp
        skills.crouch(take, take.vary(30.0, 0.2) * bend, take.vary(70.0, 0.1) * bend)
        take.contact[:, SIDES.index(foot)] *= 1.0 - np.minimum(lift + stamp, 1.0)
    ankle = f"{foot}_ankle"
    tug = skills.bumps(take, [keys[2], keys[2] + 0.5 * (keys[3] - keys[2])], 0.5 * (keys[3] - keys[2]))
    env = _curve(take, keys, 0, 1, 1, 1, 0, 0, 0)
    for hand in SIDES if seated else (foot,):
        beside = _thorax_point(take, hand, ankle, (0.0, -0.02, 0.0))
        heel = _thorax_point(take, hand, ankle, (0.0, 0.04, -0.05))
        floor = beside + take.scale() * np.array([0.12 if hand == foot else 0.05, 0.03, 0.1])
        shoe = np.where(take.t[:, None] < keys[2], floor, heel + take.scale() * np.array([0.0, 0.05, 0.0])
                        * tug[:, None])
        skills.toward(take, hand, env, shoe, elbow_hint=(0.6, -1.0, -0.2), bulge=0.05)
    skills.turn_head(take, flex=20.0 * _curve(take, keys, 0, 1, 1, 1, 1, 1, 0))


def take_off_a_shoe(take: Take) -> None:
    """Taking a shoe off: the foot comes up across the other knee (``standing``: lifted behind, the hand
    reaching back to it), both hands at the shoe pull it off up and away, one hand puts it down on the floor
    out to the side, the foot returns. Unlike wear a shoe the foot rises high and the hands end away from it."""
    seated = take.mode == "seated"
    _start(take)
    foot = take.choice(SIDES) if take.rng.uniform() < 0.3 else "right"
    keys = _keys(take, 0.6, 0.4, 0.6, 0.7, 0.5, 0.5)  # foot up, hands on, pull off, put aside, foot down, up
    up = _curve(take, keys, 0, 1, 1, 1, 1, 0, 0)
    sign = _leftward(foot)
    if seated:
        take[f"{foot}_hip.flex"] += 22.0 * up
        take[f"{foot}_hip.abd"] -= 8.0 * up  # across toward the other knee
        take[f"{foot}_hip.rot"] -= 35.0 * up  # turned out: the ankle rests on the other thigh
        take[f"{foot}_knee.flex"] += 22.0 * up
        _sit_lean(take, take.vary(25.0, 0.15) * _curve(take, keys, 0, 0.6, 1, 0.8, 1, 0.4, 0))
        take.contact[:, SIDES.index(foot)] *= 1.0 - up
    else:
        take[f"{foot}_knee.flex"] += 95.0 * up
        take[f"{foot}_hip.flex"] += 5.0 * up
        take[f"{other(foot)}_knee.flex"] += 10.0 * up
        take["pelvis.tilt"] += 15.0 * up
        skills.turn_trunk(take, -sign * 20.0 * up)  # turning to reach back to the heel
        take.contact[:, SIDES.index(foot)] *= 1.0 - np.minimum(3.0 * up, 1.0)
    pull = _curve(take, keys, 0, 0, 0, 1, 1, 1, 1)
    aside = _curve(take, keys, 0, 0, 0, 0, 1, 1, 0)
    on = _curve(take, keys, 0, 0.3, 1, 1, 1, 0, 0)
    if not seated:
        skills.crouch(take, 10.0 * aside, 40.0 * aside)
    heel = _thorax_point(take, foot, f"{foot}_ankle", (0.0, 0.02, -0.04))
    away = take.scale() * np.array([0.08, 0.1, 0.18 if seated else -0.1])
    floor = _thorax_point(take, foot, f"{foot}_ankle") + take.scale() * np.array([0.25, 0.05, 0.1])
    target = heel + pull[:, None] * away + aside[:, None] * (floor - heel - away)
    skills.toward(take, foot, np.maximum(on, aside), target, elbow_hint=(0.6, -1.0, -0.3), bulge=0.05)
    if seated:
        helper = _thorax_point(take, other(foot), f"{foot}_ankle", (0.0, 0.04, 0.06))
        skills.toward(take, other(foot), on * (1.0 - aside), helper + pull[:, None] * away * [-1, 1, 1],
                      elbow_hint=(0.6, -1.0, -0.3), bulge=0.05)
    skills.turn_head(take, flex=25.0 * np.maximum(on, aside), twist=-sign * (0.0 if seated else 25.0) * up)


_CHEST_GRIP = ((-0.3, 0.3, 0.9), (-0.7, -0.7, 0.0))  # holding something small before the chest


def wear_on_glasses(take: Take) -> None:
    """Putting glasses on: held in both hands at the chest and unfolded (hands part a little), raised before
    the eyes, slid back onto the ears (the hands glide ~10 cm back along the temples), released, the hands
    come down; often a finger then pushes the bridge up. Take off glasses runs the other way, ending with the
    folded glasses held at the chest. Unlike a hat the hands stay at eye height; unlike headphones (other
    module: from above, onto the ears) they come from the front."""
    _start(take)
    keys = _keys(take, 0.5, 0.35, 0.5, 0.4, 0.15, 0.5, 0.3, 0.3, 0.3)
    chest, unfold = _at(take, 0.07, -0.06, 0.28), _at(take, 0.11, -0.04, 0.3)
    push = take.rng.uniform() < 0.6  # then the right index pushes the bridge up
    bridge = [_spot(take, "bridge")] * 2 if push else [None, None]
    bridge_hand = [_hand("bridge")] * 2 if push else [None, None]
    if take.mode == "one hand":  # the right hand holds the frame by the bridge and a temple arm
        _path(take, "right", keys, [None, chest, chest, _spot(take, "lens", (-0.05, 0.0, 0.02)),
                                    _spot(take, "lens", (-0.03, 0.0, -0.05)), None, None] + bridge + [None],
              hint=(0.6, -1.0, -0.2), hands=[None, _CHEST_GRIP, _CHEST_GRIP, _hand("lens"), _hand("lens"), None, None]
              + bridge_hand + [None])
    else:
        for side in SIDES:
            extra = bridge if side == "right" else [None, None]
            _path(take, side, keys, [None, chest, unfold, _spot(take, "lens"), _spot(take, "hinge"),
                                     _spot(take, "hinge"), None] + extra + [None], hint=(0.8, -1.0, -0.1),
                  hands=[None, _CHEST_GRIP, _CHEST_GRIP, _hand("lens"), _hand("hinge"), _hand("hinge"), None]
                  + (bridge_hand if side == "right" else [None, None]) + [None])
    skills.turn_head(take, flex=_curve(take, keys, 0, 15, 20, 0, 8, 0, 0, 0, 0, 0))


def take_off_glasses(take: Take) -> None:
    """Taking glasses off: one or both hands up to the temple arms from the sides, pulling the glasses forward
    off the face and down to the chest, where both hands fold them (small turns of the hands, the head looking
    down) and keep holding them to the end (wear on glasses: the reverse, ending with the hands down)."""
    _start(take)
    one = take.mode == "one hand"
    keys = _keys(take, 0.5, 0.25, 0.35, 0.5, 0.9)
    off = _spot(take, "lens", (0.0, -0.02, 0.06))
    chest = _at(take, 0.06, -0.1, 0.28)
    for side in ("right",) if one else SIDES:
        grip = _spot(take, "hinge", (-0.04, 0.0, 0.05)) if one else _spot(take, "hinge")
        _path(take, side, keys, [None, grip, grip, off, chest, chest], hint=(0.8, -1.0, -0.1),
              hands=[None, _hand("hinge"), _hand("hinge"), _hand("lens"), _CHEST_GRIP, _CHEST_GRIP])
    if one:  # the other hand comes to help fold at the chest
        _path(take, "left", keys, [None, None, None, None, chest, chest], hint=(0.5, -1.0, -0.2),
              hands=[None, None, None, None, _CHEST_GRIP, _CHEST_GRIP])
    fold = _curve(take, keys, 0, 0, 0, 0, 1, 1)
    twiddle = 25.0 * np.sin(2 * np.pi * take.vary(1.5, 0.2) * take.t) * fold
    take["left_elbow.pron"] += twiddle
    take["right_elbow.pron"] -= twiddle
    skills.turn_head(take, flex=_curve(take, keys, 0, 0, 0, 5, 25, 25))


_CAP_GRIP = ((-0.3, 0.2, 0.95), (-1.0, 0.0, 0.0))  # a cap held by its sides before the chest


def put_on_a_hat(take: Take) -> None:
    """Putting a cap on: held in both hands before the chest, raised over the head, pulled down onto the top
    of the head, the brim tugged by the right hand, then the hands come down from it. Take off a hat starts
    with the hands going up to the head and ends carrying the cap down and away. Unlike glasses the hands go
    over the top of the head."""
    _start(take)
    keys = _keys(take, 0.5, 0.3, 0.5, 0.4, 0.3, 0.35, 0.5)
    chest = _at(take, 0.13, -0.08, 0.32)
    if take.mode == "one hand":
        brim = _spot(take, "brim")
        _path(take, "right", keys, [None, chest, chest, _spot(take, "brim", (0.0, 0.12, 0.04)), brim,
                                    _spot(take, "brim", (0.0, -0.02, 0.02)), brim, None], hint=(0.6, -0.8, 0.2),
              hands=[None, _CAP_GRIP, _CAP_GRIP] + [_hand("brim")] * 4 + [None])
    else:
        for side in SIDES:
            adjust = "brim" if side == "right" else "crown"
            _path(take, side, keys, [None, chest, chest, _spot(take, "above"), _spot(take, "crown"),
                                     _spot(take, adjust), _spot(take, adjust), None], hint=(0.9, -0.4, 0.1),
                  hands=[None, _CAP_GRIP, _CAP_GRIP, _hand("above"), _hand("crown"), _hand(adjust), _hand(adjust),
                         None])
    skills.turn_head(take, flex=_curve(take, keys, 0, 10, 10, 0, 8, 5, 5, 0))


def take_off_a_hat(take: Take) -> None:
    """Taking a cap off: one or both hands up to the top of the head, lifting the cap off upward, then
    carrying it forward and down to the side of the waist, held there to the end (put on a hat: the
    reverse, the hands coming down empty)."""
    _start(take)
    keys = _keys(take, 0.55, 0.2, 0.35, 0.6, 1.0)
    carry = _at(take, 0.16, -0.25, 0.3)
    if take.mode == "one hand":
        brim = _spot(take, "brim")
        _path(take, "right", keys, [None, brim, brim, _spot(take, "brim", (0.0, 0.1, 0.06)), carry, carry],
              hint=(0.6, -0.8, 0.2), hands=[None] + [_hand("brim")] * 3 + [_CAP_GRIP] * 2)
    else:
        for side in SIDES:
            _path(take, side, keys, [None, _spot(take, "crown"), _spot(take, "crown"),
                                     _spot(take, "above", (0.0, -0.04, 0.02)), carry, carry], hint=(0.9, -0.4, 0.1),
                  hands=[None, _hand("crown"), _hand("crown"), _hand("above"), _CAP_GRIP, _CAP_GRIP])
    skills.turn_head(take, flex=_curve(take, keys, 0, 8, 8, -5, 10, 5))


# --- A025-A027: pocket, hopping, jump --------------------------------------------------------------------


def reach_into_pocket(take: Take) -> None:
    """One hand into a trouser pocket (front: at the hip, the hand sliding in, the trunk leaning a little to
    that side; ``back pocket``: behind the buttock, the elbow back, the trunk turning), a rummage, then out
    with something brought up before the chest and looked at, then put back. Unlike touch back it moves on;
    unlike put something into a bag (other module) the hand goes to the body."""
    _start(take)
    side = _side(take)
    back = take.mode == "back pocket"
    keys = _keys(take, 0.6, 0.6, 0.5, 0.8, 0.5, 0.4)  # in, rummage, out and up, look, back in, down
    pocket = _at(take, 0.14, -0.4, -0.12) if back else _at(take, 0.17, -0.33, 0.07)
    look = _at(take, 0.08, -0.15, 0.32)
    inside = _curve(take, keys, 0, 1, 1, 0, 0, 1, 0)
    rummage = 0.015 * take.scale() * np.sin(2 * np.pi * 4.0 * take.t)[:, None] * _curve(
        take, keys, 0, 1, 1, 0, 0, 0, 0)[:, None] * np.array([0.3, 1.0, 0.5])
    target = timing.keyframes(take.t, keys, np.stack([_rest(take), pocket, pocket, look, look, pocket,
                                                      _rest(take)])) + rummage
    skills.reach(take, side, target, elbow_hint=(0.6, -0.6, -1.0) if back else (0.7, -0.8, -0.6))
    holding = _curve(take, keys, 0, 0, 0, 1, 1, 0, 0)
    fingers = (1 - holding)[:, None] * _unit((0.1, -1.0, 0.2)) + holding[:, None] * _unit((-0.3, 0.3, 0.9))
    palm = (1 - holding)[:, None] * _unit((-1.0, 0.0, 0.0)) + holding[:, None] * _unit((0.0, 1.0, 0.2))
    _orient(take, side, fingers, palm, np.maximum(inside, holding))
    sign = _leftward(side)
    skills.bend_trunk(take, sign * 6.0 * inside)
    if back:
        skills.turn_trunk(take, -sign * 15.0 * inside)
    skills.turn_head(take, flex=_curve(take, keys, 0, 15, 15, 20, 25, 10, 0), twist=sign * 10.0 * inside)


def hopping(take: Take) -> None:
    """Hopping on one foot in place (~2 hops/s, 3-6 cm, est.), the other foot held up behind with the knee
    bent, arms out a little for balance. Unlike jump up: one foot, small quick hops, no countermovement."""
    _start(take)
    leg = "left" if take.mode.startswith("left") else "right"
    free = other(leg)
    phase = timing.warped_phase(take.t, take.vary(2.0, 0.12) * take.tempo, take.rng, wobble=0.04)
    knots = [0.0, 0.2, 0.45, 0.6, 0.85, 0.93]  # land, absorb, push, off, in the air, touch
    take[f"{leg}_knee.flex"] += timing.periodic(phase, knots, [15, 32, 8, 6, 8, 12])
    take[f"{leg}_hip.flex"] += timing.periodic(phase, knots, [10, 22, 5, 4, 6, 8])
    take[f"{leg}_ankle.dorsi"] += timing.periodic(phase, knots, [0, 14, -25, -30, -15, -8])
    take[f"{leg}_hip.abd"] -= 4.0  # the hips over the standing foot
    take["pelvis.obliquity"] -= _leftward(leg) * 3.0
    take[f"{free}_knee.flex"] += take.vary(80.0, 0.15)
    take[f"{free}_hip.flex"] += take.vary(15.0, 0.4) + 5.0 * np.sin(2 * np.pi * phase)
    cycle = np.mod(phase, 1.0)
    take.contact[:, SIDES.index(free)] = 0.0
    take.contact[:, SIDES.index(leg)] = ((cycle < 0.55) | (cycle > 0.93)).astype(float)
    take.flight_carry = 0.0
    lift = 0.5 + 0.5 * np.sin(2 * np.pi * (phase - 0.3))
    for side in SIDES:
        skills.set_arm(take, side, 15.0 + 10.0 * lift, take.vary(30.0, 0.2) + 8.0 * lift, elbow=45.0)


def jump_up(take: Take) -> None:
    """A vertical countermovement jump (MOTION_FACTS 3.3: dip, push, 15-35 cm flight, land and absorb), arms
    swinging back then up (``arms at the sides``: no swing); a second one if the clip leaves room. Unlike
    hopping: both feet, one big jump; unlike cheer up's jumps the fists do not pump overhead."""
    _start(take)
    swing = 0.0 if take.mode == "arms at the sides" else 1.0
    t = take.onset(1.9)
    jumps = 0
    while t + 1.6 < take.duration and jumps < 2:
        t = skills.jump(take, t, height=take.vary(0.25, 0.2), arm_swing=swing, dip=take.vary(1.0, 0.1))
        t += take.uniform(0.3, 0.8)
        jumps += 1
    if jumps == 0:
        skills.jump(take, 0.05, height=take.vary(0.22, 0.15), arm_swing=swing)


# --- A029-A034: phone/tablet, keyboard, pointing, selfie, watch, rubbing hands ---------------------------


def playing_with_phone(take: Take) -> None:
    """A phone held in both hands close together at the lower chest, thumbs tapping (small 3-5 Hz wrist
    twitches, in bursts), the head bent 30-45 degrees; ``one hand``: held and thumbed in one hand; ``tablet``:
    held by one hand at the chest while the other's finger swipes across it and taps. Near pairs: reading
    holds a book higher and wider, still; writing scribbles in lines; the keyboard is low and forward."""
    _start(take)
    up = _held(take, 0.5, 0.5, 0.85)
    burst = (take.wander(1.0, 0.6) > -0.3).astype(float)
    if take.mode == "tablet":
        holder = take.choice(SIDES)
        tapper = other(holder)
        skills.toward(take, holder, up, _at(take, 0.1, -0.12, 0.27), elbow_hint=(0.5, -1.0, -0.3))
        _orient(take, holder, (-0.6, 0.3, 0.7), (-0.2, 0.95, 0.1), up)
        swipes = skills.bumps(take, skills.beats(take, take.vary(1.1, 0.2), jitter=0.3), take.vary(0.35, 0.15))
        finger = _at(take, -0.02, -0.08, 0.3) + take.scale() * np.stack(
            [0.1 * swipes - 0.05, 0.02 * np.abs(_oscillation(take, 1.5)), -0.015 * swipes], -1)
        skills.toward(take, tapper, up, finger, elbow_hint=(0.5, -1.0, -0.3))
        _orient(take, tapper, (-0.3, -0.4, 0.85), (0.0, -0.9, 0.3), up)
        pitch = 28.0
    else:
        hands = (_side(take),) if take.mode == "one hand" else SIDES
        _hold_object(take, up, "phone", hands)
        for side in hands:
            tap = burst * _oscillation(take, take.vary(4.0, 0.15))
            take[f"{side}_wrist.flex"] += 8.0 * tap * up
            take[f"{side}_collar.protr"] += 8.0 * up
        pitch = 38.0
    skills.turn_head(take, flex=take.vary(pitch, 0.15) * up)
    _lean(take, 5.0 * up)


def typing_on_a_keyboard(take: Take) -> None:
    """Both hands low before the body on a keyboard (forearms about level, palms down, ~25 cm apart; at a desk
    when ``seated``, at a counter when ``standing``), the hands tapping out of step at 3-6 Hz (est.) with small
    shifts across the keys, the head nearly level, looking ahead at a screen. Unlike the phone or reading the
    head is up and the palms face down; unlike writing both hands work."""
    _start(take)
    seated = take.mode == "seated"
    up = _held(take, 0.6, 0.5, 0.85)
    s = take.scale()
    home = _at(take, 0.12, -0.27, 0.38) if seated else _at(take, 0.13, -0.33, 0.33)
    for side in SIDES:
        tap = np.maximum(_oscillation(take, take.vary(4.5, 0.2), wobble=0.2), 0.0)
        drift = timing.smooth_noise(take.t, take.rng, 0.02, max_hz=0.8)
        skills.toward(take, side, up, home + s * np.stack([drift, 0.012 * tap, 0.3 * drift], -1),
                      elbow_hint=(0.5, -1.0, -0.3))
        _orient(take, side, (0.0, -0.25, 0.95), (0.0, -1.0, 0.1), up)
        take[f"{side}_wrist.flex"] += 15.0 * tap * up
    skills.turn_head(take, flex=take.vary(8.0, 0.5) * up, twist=take.wander(4.0, 0.4) * up)
    if seated:
        _lean(take, 6.0 * up)


def _raise_arm(take: Take, side: str, env: np.ndarray, plane, elev, *, elbow: float) -> None:
    """Raise ``side``'s arm from hanging to the direction (``plane``: 90 forward, 0 sideways; ``elev``: 90
    horizontal) as ``env [T]`` goes 0 -> 1, the elbow to ``elbow`` degrees."""
    take[f"{side}_shoulder.plane"] = env * plane + (1.0 - env) * take[f"{side}_shoulder.plane"]
    take[f"{side}_shoulder.elev"] = env * elev + (1.0 - env) * take[f"{side}_shoulder.elev"]
    take[f"{side}_shoulder.rot"] *= 1.0 - env
    take[f"{side}_elbow.flex"] = env * elbow + (1.0 - env) * take[f"{side}_elbow.flex"]


def pointing(take: Take) -> None:
    """Pointing at something: the arm straight out toward it at about shoulder height (forward to sideways;
    ``pointing up``: 130-150 degrees, at the ceiling), palm down, index along the arm, held 1-2 s while the head
    turns to it; once or twice. Unlike the selfie the elbow is straight and the hand points away from the face;
    unlike waving it is still."""
    _start(take)
    side = _side(take)
    high = take.mode == "pointing up"
    n = 2 if take.duration > 3.2 and take.rng.uniform() < 0.5 else 1
    keys = _keys(take, *([0.45, 1.2, 0.5] * n))
    env = np.zeros(take.num_frames)
    plane, elev = np.zeros(take.num_frames), np.zeros(take.num_frames)
    for k in range(n):
        e = _curve(take, keys[3 * k: 3 * k + 4], 0, 1, 1, 0)
        azimuth = take.uniform(0.0, 60.0)  # 0 forward, 60 out to the side
        elevation = take.uniform(130.0, 150.0) if high else take.uniform(75.0, 105.0)
        env = np.maximum(env, e)
        plane, elev = np.where(e > 0, 90.0 - azimuth, plane), np.where(e > 0, elevation, elev)
    _raise_arm(take, side, env, plane, elev, elbow=12.0)
    take[f"{side}_elbow.pron"] = 70.0 * env
    take[f"{side}_wrist.flex"] = -5.0 * env
    yaw = _leftward(side) * 0.6 * (90.0 - plane)
    skills.turn_head(take, flex=(-20.0 if high else 0.0) * env, twist=yaw * env)
    skills.turn_trunk(take, 0.3 * yaw * env)


def taking_a_selfie(take: Take) -> None:
    """Taking a selfie: a phone held out up and in front at arm's length (40-50 cm before the face, a little
    above it and to the side), the screen and palm turned to the face, the head tilted up toward it,
    posing (head tilts) with a tap or two, held 2-3 s. Unlike pointing the hand faces the face and the head
    looks at it."""
    _start(take)
    side = _side(take)
    up = _held(take, 0.7, 0.6, 0.65)
    phone = take.head_point() + _at(take, take.uniform(0.05, 0.2), take.uniform(0.08, 0.2), take.uniform(0.4, 0.48))
    skills.toward(take, side, up, phone, elbow_hint=(0.7, -1.0, -0.1), bulge=0.0)
    face = _thorax_point(take, side, "head", (0.0, 0.05, 0.1))
    hand = _thorax_point(take, side, f"{side}_wrist")
    _orient(take, side, (0.0, 0.95, 0.2), face - hand, up)
    tap = skills.bumps(take, skills.beats(take, take.vary(1.3, 0.2)), 0.25) * up
    take[f"{side}_wrist.flex"] += 10.0 * tap
    pose = take.wander(6.0, 0.5)
    skills.turn_head(take, flex=-take.vary(15.0, 0.2) * up, twist=_leftward(side) * take.vary(20.0, 0.25) * up,
          bend=(_leftward(side) * 8.0 + pose) * up)


def check_time(take: Take) -> None:
    """Checking a wristwatch: the left forearm comes up across the front of the chest (elbow ~100-120, forearm
    level, watch face up) while the head pitches down 25-35 degrees to it, held (``glance``: ~0.6 s; ``pull
    back the sleeve``: the right hand first draws the sleeve back from the watch, then a longer look), then
    down."""
    _start(take)
    sleeve = take.mode == "pull back the sleeve"
    keys = _keys(take, 0.5, 0.6 if sleeve else 0.0, take.vary(1.4 if sleeve else 0.6, 0.2), 0.5)
    up = _curve(take, keys, 0, 1, 1, 1, 0)
    skills.toward(take, "left", up, _at(take, 0.02, 0.02, 0.3), elbow_hint=(0.8, -0.7, -0.1))
    _orient(take, "left", (-1.0, 0.1, 0.2), (0.0, -1.0, 0.2), up)
    if sleeve:  # the right hand crosses to the left wrist and slides the sleeve back toward the elbow
        cuff = _at(take, -0.02, 0.05, 0.28)
        _path(take, "right", keys, [None, cuff + _at(take, 0.06, 0.0, 0.0), cuff, _rest(take), None],
              hint=(0.5, -1.0, -0.2))
    look = _curve(take, keys, 0, 0.6, 1, 1, 0)
    skills.turn_head(take, flex=take.vary(30.0, 0.15) * look, twist=8.0 * look)


def rub_two_hands(take: Take) -> None:
    """Hands in contact before the lower chest, palm on palm, rubbing: the hands slide fore and aft in opposite
    directions (``washing``: each circling round the other) 2-3 times/s, 3-5 cm (est.), the head looking at
    them. Unlike clapping they never part; unlike palms together they move; unlike cream on the back of a hand
    (other module) both hands move, in opposite phase."""
    _start(take)
    up = _held(take, 0.5, 0.5, 0.8)
    washing = take.mode == "washing"
    phase = timing.warped_phase(take.t, take.vary(2.0 if washing else 2.6, 0.15) * take.tempo, take.rng)
    size = take.amp * take.vary(0.045, 0.2) * take.scale()
    centre = _at(take, 0.03, -0.27, 0.24)
    for k, side in enumerate(SIDES):
        c, sn = np.cos(2 * np.pi * phase + np.pi * k), np.sin(2 * np.pi * phase + np.pi * k)
        shift = np.stack([np.zeros_like(c), 0.6 * sn if washing else 0.1 * sn, c], -1) * size
        skills.toward(take, side, up, centre + shift, elbow_hint=(0.6, -1.0, -0.3))
        _orient(take, side, (-0.5, 0.2, 0.85) if washing else (-0.3, 0.4, 0.85), (-1.0, 0.0, 0.0), up)
        if washing:
            take[f"{side}_elbow.pron"] += 20.0 * sn * up
    skills.turn_head(take, flex=take.vary(15.0, 0.3) * up)


# --- A035-A041: head gestures, face, palms, crossed hands, cough ------------------------------------------


def nod_head(take: Take) -> None:
    """``nod``: 3-5 nods (neck and head pitch down 20-30 degrees and back, ~2 /s, est.) in one or two bursts;
    ``bow``: the trunk bends 25-45 degrees from the hips with the head, held briefly, and comes up. Shake head
    turns the head (yaw) instead of pitching it."""
    _start(take)
    if take.mode == "bow":
        keys = _keys(take, 0.7, 0.5, 0.8)
        bow = _curve(take, keys, 0, 1, 1, 0) * take.vary(35.0, 0.2)
        take["pelvis.tilt"] += 0.5 * bow
        _lean(take, 0.5 * bow)
        for side in SIDES:
            take[f"{side}_hip.flex"] += 0.5 * bow
            skills.hang_arm(take, side, forward=-0.3 * bow)
        skills.turn_head(take, flex=0.6 * bow)
        return
    bursts = 2 if take.duration > 3.0 and take.rng.uniform() < 0.5 else 1
    rate = take.vary(2.0, 0.15) * take.tempo
    env = np.zeros(take.num_frames)
    for k in range(bursts):
        length = take.uniform(3.0, 5.0) / rate / bursts ** 0.5
        t0 = (k + take.uniform(0.1, 0.3)) * take.duration / bursts
        t0 = min(t0, max(take.duration - length - 0.1, 0.0))
        env = np.maximum(env, _curve(take, [t0, t0 + 0.5 / rate, t0 + length - 0.5 / rate, t0 + length], 0, 1, 1, 0))
    nods = 0.5 - 0.5 * np.cos(2 * np.pi * rate * take.t)
    skills.turn_head(take, flex=take.amp * take.vary(26.0, 0.2) * nods * env)
    take["spine3.flex"] += 3.0 * nods * env  # the upper back joins in a little


def shake_head(take: Take) -> None:
    """Shaking the head: neck and head turn (yaw) side to side, 2-4 times (``small fast``: +-15-25 degrees at
    ~3 /s; ``wide slow``: +-30-40 at ~1.5 /s), est. Nod pitches instead."""
    _start(take)
    fast = take.mode == "small fast"
    rate = take.vary(3.0 if fast else 1.6, 0.12) * take.tempo
    size = take.amp * take.vary(20.0 if fast else 35.0, 0.15)
    env = _held(take, 0.4 / rate, 0.4 / rate, take.vary(0.6, 0.15))
    turn = np.sin(2 * np.pi * rate * take.t) * env
    skills.turn_head(take, twist=size * turn, flex=3.0 * env)
    take["neck.bend"] += 0.15 * size * turn  # the head shifts a little toward the side it turns to,
    take["head.bend"] -= 0.15 * size * turn  # staying upright


def wipe_face(take: Take) -> None:
    """Wiping the face: both palms laid on the forehead and drawn down over the face to the chin, 1-3 strokes
    (the hands coming up again between them), the head bowing into the hands (``one hand``: one palm down the
    middle of the face). Unlike sneeze/cough there is no jerk and the hands
    cover the whole face; unlike hush or blowing the nose (other module) they stroke."""
    _start(take)
    strokes = take.choice((1, 2, 2, 3))
    keys = _keys(take, 0.5, *([0.5, 0.35] * strokes), 0.5)
    one = take.mode == "one hand"
    centred = (-0.03, 0.0, 0.01) if one else (0.0, 0.0, 0.0)  # one palm covers the middle of the face
    brow, chin = _spot(take, "brow", centred), _spot(take, "chin", centred)
    points = [None, brow] + [chin, brow] * strokes
    points[-1] = _spot(take, "brow", (0.02, -0.05, 0.1))  # off the face
    hands = [None] + [_hand("brow"), _hand("chin")] * strokes + [_hand("brow")]
    for side in (("right" if take.rng.uniform() < 0.8 else "left",) if one else SIDES):
        _path(take, side, keys, points + [None], hint=(0.6, -1.0, -0.1), hands=hands + [None])
    on = _curve(take, keys, *([0] + [1] * (2 * strokes + 1) + [0]))
    skills.turn_head(take, flex=_curve(take, keys, *([0] + [10, 20] * strokes + [10, 0])))
    _lean(take, 5.0 * on)


def put_palms_together(take: Take) -> None:
    """Palms pressed together before the sternum, fingers up (elbows out, forearms level, wrists bent back),
    held still 1-3 s (``with a bow``: a small bow of the head and trunk while held), as in a greeting or
    prayer. Unlike clapping or rubbing the hands are still."""
    _start(take)
    keys = _keys(take, 0.6, take.vary(1.8, 0.2), 0.6)
    up = _curve(take, keys, 0, 1, 1, 0)
    for side in SIDES:
        skills.toward(take, side, up, _at(take, 0.03, -0.1, 0.18), elbow_hint=(1.0, -0.8, 0.0), bulge=0.05)
        _orient(take, side, (-0.05, 1.0, 0.1), (-1.0, 0.0, 0.0), up)
    if take.mode == "with a bow":
        bow = take.vary(20.0, 0.2) * _curve(take, [keys[1], 0.5 * (keys[1] + keys[2]), keys[2]], 0, 1, 0)
        take["pelvis.tilt"] += 0.4 * bow
        _lean(take, 0.6 * bow)
        skills.turn_head(take, flex=0.8 * bow)


def cross_hands_in_front(take: Take) -> None:
    """Saying stop: the forearms crossed in an X before the chest (``face height``: before the face), each
    wrist past the midline, hands open and up, palms out, held 1-2 s. Unlike clapping or palms together the
    wrists cross over; unlike cross arms (other module: folded on the chest, hands tucked) they are raised
    forward."""
    _start(take)
    high = take.mode == "face height"
    keys = _keys(take, 0.45, take.vary(1.5, 0.25), 0.5)
    up = _curve(take, keys, 0, 1, 1, 0)
    for side in SIDES:
        # the left forearm in front of the right: different depths keep them from passing through each other
        target = _at(take, -0.09, 0.14 if high else -0.03, 0.36 + (0.03 if side == "left" else 0.0))
        skills.toward(take, side, up, target, elbow_hint=(0.7, -1.0, -0.2), bulge=0.1)
        _orient(take, side, (0.2, 0.95, 0.2), (0.0, 0.0, 1.0), up)
    skills.turn_head(take, flex=-3.0 * up)
    _lean(take, -3.0 * up)


def sneeze_cough(take: Take) -> None:
    """A hand (``cough into elbow``: the bent arm) comes to the mouth and the trunk jerks forward: ``sneeze``:
    a breath in (head back a little), then one fast flexion of the trunk and head (~20 degrees in ~0.12 s, est.)
    and a slower recovery; ``cough``: 2-4 smaller jerks ~3 /s. Unlike wipe face the hand stays at the mouth;
    unlike nausea the trunk stays upright between jerks."""
    _start(take)
    side = _side(take)
    sneeze = take.mode == "sneeze"
    jerks = 1 if sneeze else take.choice((2, 3, 4))
    gap = take.vary(0.33, 0.15)
    keys = _keys(take, 0.45, 0.45 if sneeze else 0.15, gap * jerks + 0.3, 0.5)
    up = _curve(take, keys, 0, 1, 1, 1, 0)
    if take.mode == "cough into elbow":  # the forearm across the face, the crook of the elbow at the mouth
        cover = take.head_point() + take.scale() * np.array([-0.2, -0.05, 0.16])
        skills.toward(take, side, up, cover, elbow_hint=(0.2, 0.3, 1.0), bulge=0.05)
    else:
        _to_head(take, side, up, "mouth", hint=(0.5, -1.0, 0.1), bulge=0.06)
    jerk = np.zeros(take.num_frames)
    for t0 in keys[2] + np.arange(jerks) * gap:
        jerk = np.maximum(jerk, _curve(take, [t0, t0 + 0.12, t0 + 0.12 + gap * (1.5 if sneeze else 0.7)], 0, 1, 0))
    size = take.vary(22.0 if sneeze else 11.0, 0.2) * take.amp
    breath = _curve(take, keys, 0, 0, 1, 0, 0) if sneeze else 0.0
    _lean(take, size * jerk - 6.0 * breath)
    skills.turn_head(take, flex=0.6 * size * jerk - 10.0 * breath)
    for s in SIDES:
        take[f"{s}_knee.flex"] += 0.3 * size * jerk
        take[f"{s}_hip.flex"] += 0.3 * size * jerk
        take[f"{s}_collar.elev"] += 0.3 * size * jerk


# --- A042-A043: staggering, falling ----------------------------------------------------------------------


def staggering(take: Take) -> None:
    """Staggering: short, irregular steps (cadence wobbling 30%) on a meandering heading, the trunk swaying
    side to side and forward, arms out and groping for balance (``losing balance``: slower, bigger lurches and
    arm flails, travelling less). Unlike walking it wanders and sways; unlike falling it stays up."""
    _start(take)
    lurching = take.mode == "losing balance"
    cadence = take.vary(1.3 if lurching else 1.7, 0.1)
    phase = timing.warped_phase(take.t, cadence / 2.0 * take.tempo, take.rng, wobble=0.3)
    skills.gait(take, skills.WALK, cadence=cadence, size=take.vary(0.5 if lurching else 0.62, 0.1), phase=phase)
    skills.steer(take, take.wander(45.0 if lurching else 35.0, 0.5))
    sway = take.wander(9.0 if lurching else 7.0, 0.7)
    skills.bend_trunk(take, sway)
    _lean(take, 8.0 + take.wander(6.0, 0.6))
    take["pelvis.obliquity"] += 0.3 * sway
    flail = 2.0 if lurching else 1.0
    for side in SIDES:
        skills.set_arm(take, side, 15.0 + take.wander(12.0 * flail, 0.9),
                       25.0 + take.wander(12.0 * flail, 0.9) - _leftward(side) * sway, elbow=30.0 + take.wander(10.0, 0.8))
    skills.turn_head(take, flex=take.wander(8.0, 0.6), bend=-0.5 * sway, twist=take.wander(8.0, 0.5))


def _floor_reach(take: Take, side: str, ahead: float, out: float, above: float = 0.06
                 ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A wrist target on the floor under the body built so far (side-normalised thorax frame ``[T, 3]``):
    ``above`` m over the lowest sole point, ``ahead`` m in front of (negative: behind) the shoulder along the
    pelvis's heading and ``out`` m beyond it sideways (template m); the floor is where the feet stand. Also
    returns the heading and the downward direction in the same frame ``[T, 3]`` (to lay the hand flat)."""
    rot, pos = skills.posed(take)
    s = take.scale()
    shoulder = pos[:, SMPL24.index(f"{side}_shoulder")]
    feet = np.concatenate([pos[:, [SMPL24.index("left_foot"), SMPL24.index("right_foot")], 1],
                           pos[:, [SMPL24.index("left_ankle"), SMPL24.index("right_ankle")], 1] - 0.06 * s], 1)
    forward = _unit(rot[:, 0, :, 2] * np.array([1.0, 0.0, 1.0]))  # the pelvis's heading
    lateral = np.cross(np.array([0.0, 1.0, 0.0]), forward) * _leftward(side)  # +x is the subject's left
    world = shoulder + s * (ahead * forward + out * lateral)
    world[:, 1] = feet.min(axis=1) + above * s
    chest = rot[:, SMPL24.index("spine3")]
    mirror = np.array([-1.0 if side == "right" else 1.0, 1.0, 1.0])
    local = np.einsum("tba,tb->ta", chest, world - pos[:, SMPL24.index("spine3")]) * mirror
    ahead_dir = np.einsum("tba,tb->ta", chest, forward) * mirror
    down = np.einsum("tba,b->ta", chest, np.array([0.0, -1.0, 0.0])) * mirror
    return local, ahead_dir, down


def falling(take: Take) -> None:
    """Falling down and staying down (MOTION_FACTS 2 limits; est. timing ~1.3 s): ``forward``: a stumble, the
    knees buckle onto the floor, the hands go out and land under the shoulders, then the body slumps flat on
    its front onto the forearms (the pelvis ~0.2 m up); ``backward``: a quick crouch, the pelvis drops behind
    the feet and the legs shoot forward, landing seated on the floor leaning back on the hands (pelvis
    ~0.25 m). It ends at least ~0.5 s before the clip does. The feet stay the supports (the floor under the
    knees, hands and body is not modelled; their joints are kept above it)."""
    skills.stand(take)
    forward = take.mode == "forward"
    busy = _fit(take, (0.3, 0.4, 0.35, 0.5, 0.6) if forward else (0.3, 0.35, 0.35, 0.6))
    keys = take.onset(busy.sum(), margin=0.1) + np.concatenate([[0.0], np.cumsum(busy)])
    if forward:  # stand, stumble, kneel, hands down, flat, lie
        thigh = _curve(take, keys, 0, 20, 15, 5, -75, -75)  # forward from plumb, degrees
        knee = _curve(take, keys, 0, 30, 105, 95, 8, 8)
        tilt = _curve(take, keys, 0, 10, 20, 45, 80, 80)
        bend = _curve(take, keys, 0, 5, 5, 25, 8, 8)
        dorsi = _curve(take, keys, 0, 10, 10, 10, -40, -40)
        head = _curve(take, keys, 0, 10, 0, -20, -30, -30)
    else:  # stand, stumble, crouch down, seated, sit
        thigh = _curve(take, keys, 0, 40, 60, 88, 88)
        knee = _curve(take, keys, 0, 60, 100, 8, 8)
        tilt = _curve(take, keys, 0, 15, 5, -28, -28)
        bend = _curve(take, keys, 0, 10, 10, 0, 0)
        dorsi = _curve(take, keys, 0, 15, 15, -5, -5)
        head = _curve(take, keys, 0, 10, 15, 20, 20)
    take["pelvis.tilt"] += tilt
    _lean(take, bend)
    for side in SIDES:
        take[f"{side}_hip.flex"] += thigh + tilt
        take[f"{side}_knee.flex"] += knee
        take[f"{side}_ankle.dorsi"] += dorsi
    skills.turn_head(take, flex=head)
    if forward:  # thrown forward, planted under the shoulders, then forearms on the floor
        throw, plant = _curve(take, keys, 0, 1, 1, 0, 0, 0), _curve(take, keys, 0, 0, 0, 1, 0, 0)
        flat = _curve(take, keys, 0, 0, 0, 0, 1, 1)
        for side in SIDES:
            under, ahead, down = _floor_reach(take, side, 0.08, 0.02, above=0.09)
            before, _, _ = _floor_reach(take, side, 0.25, 0.08, above=0.07)
            target = (throw[:, None] * _at(take, 0.2, 0.05, 0.45) + plant[:, None] * under
                      + flat[:, None] * before + (1 - throw - plant - flat)[:, None] * _rest(take))
            skills.reach(take, side, target, elbow_hint=(0.7, -0.2, -0.7))
            _orient(take, side, ahead, down, plant + flat)
    else:  # thrown forward, then back to the floor behind the hips
        throw, behind = _curve(take, keys, 0, 1, 0.5, 0, 0), _curve(take, keys, 0, 0, 0.5, 1, 1)
        for side in SIDES:
            floor, ahead, down = _floor_reach(take, side, -0.22, 0.05, above=0.08)
            target = (throw[:, None] * _at(take, 0.18, -0.1, 0.4) + behind[:, None] * floor
                      + (1 - throw - behind)[:, None] * _rest(take))
            skills.reach(take, side, target, elbow_hint=(0.6, -0.3, -1.0))
            _orient(take, side, -ahead, down, behind)


# --- A044-A049: touching where it hurts, nausea, fanning -------------------------------------------------


def touch_head(take: Take) -> None:
    """Headache: a palm held on the forehead (``both hands on temples``: palms on the sides of the head, rubbing
    small circles) for most of the clip, the head bowed 10-20 degrees and rocking slowly. Unlike glasses the
    hands stay long, higher and further back; unlike brushing hair they do not stroke."""
    _start(take)
    up = _held(take, 0.6, 0.6, 0.75)
    if take.mode == "both hands on temples":
        circle = 0.012 * np.stack([np.zeros_like(take.t), np.sin(3.0 * take.t), np.cos(3.0 * take.t)], -1)
        for side in SIDES:
            _to_head(take, side, up, "temple", hint=(0.8, -1.0, 0.3), shift=circle)
    else:
        rub = timing.smooth_noise(take.t, take.rng, 0.01, max_hz=1.2, channels=3)
        _to_head(take, _side(take), up, "forehead", hint=(1.0, -0.3, 0.3), shift=rub)
    skills.turn_head(take, flex=(take.vary(15.0, 0.3) + take.wander(5.0, 0.3)) * up, bend=take.wander(6.0, 0.3) * up)
    _lean(take, 6.0 * up)


def touch_chest(take: Take) -> None:
    """Chest or stomach pain: ``hand on heart``: one palm held on the left chest (the right hand crossing over,
    or the left), the trunk hunched 10-15 degrees, breathing heavily; ``hands on stomach``: both palms on the
    belly, hunched 15-25 degrees, knees soft, rocking slowly. Unlike nausea no deep bend and no retching."""
    _start(take)
    up = _held(take, 0.6, 0.6, 0.75)
    if take.mode == "hands on stomach":
        for side in SIDES:
            skills.toward(take, side, up, _at(take, 0.08, -0.1, 0.16), elbow_hint=(0.6, -1.0, -0.2))  # the navel
            _orient(take, side, (-0.9, -0.2, 0.1), (0.0, 0.0, -1.0), up)
        hunch = take.vary(20.0, 0.2) + take.wander(4.0, 0.4)
        skills.crouch(take, 12.0 * up, 0.0 * up)
    else:
        side = _side(take)
        x = 0.09 if side == "left" else -0.05  # on the heart side
        skills.toward(take, side, up, _at(take, x, -0.03, 0.16), elbow_hint=(0.6, -1.0, 0.1))
        _orient(take, side, (-0.7, 0.6, 0.0), (0.0, 0.0, -1.0), up)
        breath = np.sin(2 * np.pi * 0.5 * take.t)
        hunch = take.vary(12.0, 0.2) + 3.0 * breath
        for s in SIDES:
            take[f"{s}_collar.elev"] += 4.0 * breath * up
    _lean(take, hunch * up)
    skills.turn_head(take, flex=12.0 * up)


def touch_back(take: Take) -> None:
    """Backache: one hand (``both hands``: both) held on the lower back, the elbow(s) back, the trunk arching
    back a little and bending to the side, rubbing slowly. Unlike reach into the back pocket the hand is higher
    (the waist) and stays."""
    _start(take)
    up = _held(take, 0.7, 0.6, 0.75)
    hands = SIDES if take.mode == "both hands" else (_side(take),)
    for side in hands:
        rub = 0.02 * take.scale() * np.sin(2 * np.pi * take.vary(0.8, 0.2) * take.t)
        target = _at(take, 0.1, -0.32, -0.15) + np.stack([np.zeros_like(rub), rub, np.zeros_like(rub)], -1)
        skills.toward(take, side, up, target, elbow_hint=(0.6, -0.4, -1.0), bulge=-0.05)
        _orient(take, side, (-0.9, 0.2, 0.0), (0.0, 0.0, 1.0), up)
    _lean(take, -take.vary(10.0, 0.3) * up)
    skills.bend_trunk(take, (take.wander(5.0, 0.3) + (0.0 if len(hands) == 2 else -_leftward(hands[0]) * 5.0)) * up)
    skills.turn_head(take, flex=-5.0 * up)


def touch_neck(take: Take) -> None:
    """Neckache: a palm held on the back of the neck, the elbow up and forward, the head rolling slowly forward
    and to the side, stretching. Unlike touch head the hand is low and behind; unlike brushing hair it does not
    stroke."""
    _start(take)
    side = _side(take)
    up = _held(take, 0.6, 0.6, 0.75)
    squeeze = 0.01 * np.sin(2 * np.pi * take.vary(0.7, 0.2) * take.t)
    _to_head(take, side, up, "nape", hint=(0.8, 0.2, 0.6),
             shift=np.stack([squeeze, np.zeros_like(squeeze), np.zeros_like(squeeze)], -1))
    roll = take.vary(12.0, 0.3) * np.sin(2 * np.pi * take.uniform(0.25, 0.45) * take.t + take.uniform(0, 6.3))
    skills.turn_head(take, flex=(10.0 + 0.5 * np.abs(roll)) * up, bend=-_leftward(side) * np.abs(roll) * up)


def nausea(take: Take) -> None:
    """Nausea or vomiting: bent forward 35-55 degrees (knees soft), the head hanging, retching 2-4 times (trunk
    and head jerk down, shoulders up, ~1 /s, est.); ``hand at mouth``: one hand over the mouth, the other on the
    stomach; ``hands on knees``: both hands propped on the knees. Unlike a cough the trunk stays deeply bent;
    unlike touch chest it retches."""
    _start(take)
    keys = _keys(take, 0.7, 2.0, 0.7)
    down = _curve(take, keys, 0, 1, 1, 0)
    retch = np.zeros(take.num_frames)
    t = keys[1] + 0.2
    while t + 0.4 < keys[2]:
        retch = np.maximum(retch, _curve(take, [t, t + 0.15, t + 0.55], 0, 1, 0))
        t += take.vary(0.9, 0.15) / take.tempo
    on_knees = take.mode == "hands on knees"
    skills.crouch(take, (take.vary(25.0, 0.3) + (10.0 if on_knees else 0.0)) * down,
                  take.vary(45.0, 0.15) * down + 8.0 * retch)
    skills.turn_head(take, flex=(25.0 + 10.0 * retch) * down)
    for side in SIDES:
        take[f"{side}_collar.elev"] += 8.0 * retch
    if on_knees:
        for side in SIDES:
            skills.toward(take, side, down, _thorax_point(take, side, f"{side}_knee", (0.0, 0.08, 0.06)),
                          elbow_hint=(0.6, -1.0, -0.2))
            _orient(take, side, (-0.3, -0.8, 0.5), (0.0, -1.0, 0.0), down)
    else:
        side = _side(take)
        _to_head(take, side, down, "mouth", hint=(0.5, -1.0, 0.1))
        skills.toward(take, other(side), down, _at(take, 0.08, -0.3, 0.17), elbow_hint=(0.6, -1.0, -0.2))
        _orient(take, other(side), (-0.9, -0.2, 0.1), (0.0, 0.0, -1.0), down)


def use_a_fan(take: Take) -> None:
    """Fanning oneself: a hand (or a paper fan) held ~20 cm before the face at chin height, palm to the face,
    flapping at the wrist toward and away from it, 3-5 Hz small strokes (``paper fan``: 2-3 Hz, larger, a little
    further out), the head raised a little. Unlike waving the hand is close to the face and flaps fore-aft."""
    _start(take)
    side = _side(take)
    paper = take.mode == "paper fan"
    up = _held(take, 0.5, 0.5, 0.8)
    flap = _oscillation(take, take.vary(2.5 if paper else 4.0, 0.12))
    target = take.head_point() + take.scale() * np.array([0.1, -0.12, 0.24 if paper else 0.2])
    skills.toward(take, side, up, target, elbow_hint=(0.6, -1.0, -0.1))
    angle = np.radians(take.vary(40.0 if paper else 25.0, 0.15) * flap)  # forward of upright
    fingers = np.stack([np.zeros_like(angle), np.cos(angle), np.sin(angle)], -1)
    palm = np.stack([np.full_like(angle, -0.3), np.sin(angle), -np.cos(angle)], -1)
    _orient(take, side, fingers, palm, up)
    skills.turn_head(take, flex=-6.0 * up, twist=_leftward(side) * 8.0 * up)


# --- the 49 classes, NTU id order -------------------------------------------------------------------------

_ONE_HAND = ("right hand", "left hand")
_PERFORMERS = {
    1: (humanact12.drink, ("right hand", "left hand", "seated")),
    2: (humanact12.eat, ("right hand", "left hand", "both hands")),
    3: (brushing_teeth, _ONE_HAND),
    4: (brushing_hair, _ONE_HAND + ("long hair",)),
    5: (drop, _ONE_HAND + ("both hands",)),
    6: (ntu13.pickup, tuple(ntu13.PICKUP_FOLDS)),
    7: (humanact12.throw, ("overarm", "underarm")),
    8: (humanact12.sit, ("with hand push", "without hand push")),
    9: (ntu13.standing_up, ("with hand push", "without hand push")),
    10: (clapping, ("chest height", "face height")),
    11: (reading, ("standing", "seated")),
    12: (writing, ("notepad in hand", "seated at a table")),
    13: (tear_up_paper, ("twisting", "pulling apart")),
    14: (wear_jacket, ("right arm first", "left arm first")),
    15: (take_off_jacket, ("right arm first", "left arm first")),
    16: (wear_a_shoe, ("seated", "standing")),
    17: (take_off_a_shoe, ("seated", "standing")),
    18: (wear_on_glasses, ("both hands", "one hand")),
    19: (take_off_glasses, ("both hands", "one hand")),
    20: (put_on_a_hat, ("both hands", "one hand")),
    21: (take_off_a_hat, ("both hands", "one hand")),
    22: (ntu13.cheer_up, ("fist pumps", "open hands with bounce", "jumping")),
    23: (ntu13.hand_waving, ("right", "left", "high", "low")),
    24: (ntu13.kicking_something, ("right", "left")),
    25: (reach_into_pocket, ("right front pocket", "left front pocket", "back pocket")),
    26: (hopping, ("left foot", "right foot")),
    27: (jump_up, ("arms swinging", "arms at the sides")),
    28: (humanact12.phone, ("right ear", "left ear")),  # not its texting mode: that is A029
    29: (playing_with_phone, ("both thumbs", "one hand", "tablet")),
    30: (typing_on_a_keyboard, ("seated", "standing")),
    31: (pointing, ("right hand", "left hand", "pointing up")),
    32: (taking_a_selfie, _ONE_HAND),
    33: (check_time, ("glance", "pull back the sleeve")),
    34: (rub_two_hands, ("palm on palm", "washing")),
    35: (nod_head, ("nod", "bow")),
    36: (shake_head, ("small fast", "wide slow")),
    37: (wipe_face, ("both hands", "one hand")),
    38: (ntu13.salute, ("crisp", "relaxed")),
    39: (put_palms_together, ("held", "with a bow")),
    40: (cross_hands_in_front, ("chest height", "face height")),
    41: (sneeze_cough, ("sneeze", "cough", "cough into elbow")),
    42: (staggering, ("drunk", "losing balance")),
    43: (falling, ("forward", "backward")),
    44: (touch_head, ("one hand on forehead", "both hands on temples")),
    45: (touch_chest, ("hand on heart", "hands on stomach")),
    46: (touch_back, ("one hand", "both hands")),
    47: (touch_neck, _ONE_HAND),
    48: (nausea, ("hand at mouth", "hands on knees")),
    49: (use_a_fan, ("right hand", "left hand", "paper fan")),
}

#: NTU RGB+D 120 actions A001-A049, in id order, named as the dataset names them.
CLASSES = tuple(ActionClass(ACTION_NAMES[i], modes, perform) for i, (perform, modes) in sorted(_PERFORMERS.items()))
