"""NTU RGB+D 120's single-person additions, actions A061-A105 (45 classes, NTU order and names).

Part of the 94-class single-person set ``synth-ntu1p``; A001-A049 live in another module. Five actions are
NTU-13's (squat down, shake fist, running on the spot, butt kicks, side kick) and two are served by UESTC
exercises (arm circles: its arm-circling; cross toe touch: its alternating toe touches or its bent-over
twist): their perform functions and modes are imported, not copied. Every other class composes skills into
a new perform function with 2-3 named modes (the ground-truth style label: hand, stance, stroke, style).

The data is seen as Kinect's 25 joints placed on the SMPL body (:mod:`jaxmotion.geometry.markers`): the
thumb and hand-tip markers ride on the wrist's frame, so forearm twist (``elbow.pron``) and wrist flexion
are visible through them, fingers are not. So classes that differ only in the fingers in reality (thumb up
/ down / OK / victory; hush vs sniff) are made to differ in where the hand is, how the forearm is turned,
which arm, and how it is held or moved; each near pair says how in a comment. NTU's skeletons are smoothed
over time (sigma 3 frames, :class:`~noise.KinectNoise`), which all but removes movements faster than ~2 Hz,
so a class's signature is also carried by its postures and slower paths, not only by a fast flick.

Timing: 30 fps clips of 2-5 s; one-off actions start at :meth:`Take.onset` and are compressed to fit the
clip (:func:`_keys`), repeated ones cycle. Wrist targets are points in the thorax (spine3) frame,
side-normalised (x away from the midline, y up, z forward; metres at template size, see
:func:`skills.reach`); points at the face are offsets from :meth:`Take.head_point` fitted so that the named
marker lands on the face point on the template body (:data:`_FACE`). Figures: MOTION_FACTS 2-4 (est. where
the tables have none: everyday manipulation happens at 0.2-0.4 m in front of the lower chest, with the
gaze down 15-30 degrees).
"""

from __future__ import annotations

import dataclasses

import numpy as np

from jaxmotion.data.formats.ntu120 import ACTION_NAMES
from jaxmotion.data.synthetic import ntu13, skills, timing, uestc
from jaxmotion.data.synthetic.engine import ActionClass
from jaxmotion.data.synthetic.take import SIDES, Take, other
from jaxmotion.geometry.skeletons import SMPL24

#: NTU action ids of this module's classes, in order.
ACTION_IDS = tuple(range(61, 106))
STANCES = ("standing", "seated")
HANDS = ("right hand", "left hand")


# --- helpers ---------------------------------------------------------------------------------------------


def _side(take: Take) -> str:
    """The acting side the mode names first (``left ...``), else the right (most people's working hand)."""
    return "left" if take.mode.startswith("left") else "right"


def _any_side(take: Take, left_share: float = 0.12) -> str:
    """The working hand where the mode does not name one: right, left for about ``left_share`` of takes."""
    return "left" if take.rng.uniform() < left_share else "right"


def _begin(take: Take, heading: float | None = None) -> None:
    """Relaxed standing, on a chair if the mode says ``seated``."""
    skills.stand(take, heading=heading)
    if "seated" in take.mode:
        skills.seated(take)


#: The most a one-off movement is sped up to fit a short clip; beyond it the clip ends mid-movement.
MAX_SQUEEZE = 0.55


def _place(take: Take, durations: np.ndarray, fit: float) -> np.ndarray:
    """Key times of consecutive phases lasting ``durations`` s (real time), compressed (down to
    :data:`MAX_SQUEEZE`) to fit ``fit`` of the clip, from a random onset."""
    d = durations * max(min(1.0, fit * take.duration / durations.sum()), MAX_SQUEEZE)
    return take.onset(d.sum()) + np.concatenate([[0.0], np.cumsum(d)])


def _keys(take: Take, *durations: float, fit: float = 0.9) -> np.ndarray:
    """Key times (``len(durations) + 1``) of a one-off movement made of consecutive phases of about these
    natural durations (s, over the subject's tempo), compressed (down to :data:`MAX_SQUEEZE`) to fit ``fit``
    of the clip if longer, from a random onset."""
    return _place(take, np.array([take.vary(x, 0.12) for x in durations]) / take.tempo, fit)


def _spell(take: Take, enter: float = 0.5, leave: float = 0.5, share=(0.6, 0.85)) -> np.ndarray:
    """Keys (4) of an activity spell: the hands come in over ``enter`` s, work for what makes ``share`` of
    the clip, and go back over ``leave`` s."""
    enter, leave = take.vary(enter, 0.12) / take.tempo, take.vary(leave, 0.12) / take.tempo
    work = max(take.duration * take.uniform(*share) - enter - leave, 0.6)
    return _place(take, np.array([enter, work, leave]), 0.95)


def _curve(take: Take, keys, *values) -> np.ndarray:
    return timing.keyframes(take.t, keys, values)


def _at(take: Take, x: float, y: float, z: float, jitter: float = 0.012) -> np.ndarray:
    """``[3]`` a wrist target in the thorax frame (template metres, scaled to the body), a little different
    in every take."""
    return take.scale() * (np.array([x, y, z]) + take.rng.normal(0.0, jitter, 3))


def _path(take: Take, keys, points) -> np.ndarray:
    """``[T, 3]`` a wrist path through ``points`` (``None`` = the relaxed hanging wrist) at ``keys``."""
    rest = skills.relaxed_wrist(take)
    return timing.keyframes(take.t, keys, np.stack([rest if p is None else np.asarray(p, float) for p in points]))


def _orient(take: Take, side: str, weight, pron: float, flex: float = 0.0, dev: float = 0.0) -> None:
    """Blend ``side``'s forearm twist and wrist angles toward ``pron``/``flex``/``dev`` by ``weight [T]``."""
    w = np.asarray(weight, float)
    take[f"{side}_elbow.pron"] += w * (pron - take[f"{side}_elbow.pron"])
    take[f"{side}_wrist.flex"] += w * flex
    take[f"{side}_wrist.dev"] += w * dev


def _lean(take: Take, degrees) -> None:
    """Lean the trunk forward over the hips, as over a table (feet and knees left as they are)."""
    d = np.asarray(degrees, float)
    take["pelvis.tilt"] += 0.4 * d
    take["spine1.flex"] += 0.35 * d
    take["spine2.flex"] += 0.25 * d
    for side in SIDES:
        take[f"{side}_hip.flex"] += 0.4 * d
        take[f"{side}_ankle.dorsi"] += 0.05 * d


def _below(take: Take, drop: float, forward: float = 0.0, out: float = 0.0) -> np.ndarray:
    """``[T, 3]`` a wrist target ``drop`` m straight down (in the world) from the shoulder and ``forward`` m
    ahead (horizontally), whatever the trunk's lean so far: the thorax frame turned by the trunk pitch."""
    p = np.radians(skills.trunk_pitch(take))
    s = take.scale()
    down = np.stack([np.zeros_like(p), -np.cos(p), np.sin(p)], -1)
    ahead = np.stack([np.zeros_like(p), np.sin(p), np.cos(p)], -1)
    return take.shoulder_point() + s * (drop * down + forward * ahead + np.array([out, 0.0, 0.0]))


@dataclasses.dataclass(frozen=True)
class _Spot:
    """A hand placement at the face: the wrist ``offset`` from :meth:`Take.head_point` (side-normalised,
    template metres) that, with this elbow hint, forearm twist and wrist flexion, puts a marker on a face
    point of the template body (fitted by iterating the reach; see the names)."""

    offset: tuple[float, float, float]
    hint: tuple[float, float, float]
    pron: float
    flex: float


# Face points relative to NTU's head marker (mid-head, ~eye level), est. from Drillis-Contini heights (MOTION
# FACTS 1.1: chin 0.870 H, eyes 0.936 H): mouth 5.5 cm below and 9-10 cm in front, nose tip 3-4 cm below and
# 11-12 cm in front, cheeks 7 cm to the side, ears 10 cm to the side.
_FACE = {
    "lips": _Spot((0.043, -0.12, 0.094), (0.3, -1.0, -0.1), 0.0, -10.0),  # index fingertip on the lips, hand up
    "mouth": _Spot((0.062, -0.049, 0.14), (0.7, -1.0, 0.1), -10.0, 0.0),  # palm over the mouth
    "nose": _Spot((0.092, -0.079, 0.149), (0.5, -1.0, 0.2), -50.0, 0.0),  # fingertips (a held object) under the nose
    "nose palm": _Spot((0.075, -0.015, 0.154), (0.6, -1.0, 0.1), -20.0, 10.0),  # palm cupped over the nose
    "cheek": _Spot((0.11, -0.035, 0.106), (0.6, -1.0, 0.1), -20.0, -10.0),  # palm flat on the same-side cheek
    "forehead": _Spot((0.079, 0.089, 0.12), (1.0, -0.2, 0.2), 20.0, 0.0),  # palm on the forehead
    "ear": _Spot((0.168, 0.03, 0.021), (1.0, -0.3, -0.1), 0.0, -15.0),  # palm over the ear
    "over head": _Spot((0.149, 0.173, 0.0), (1.0, -0.2, 0.0), 0.0, 0.0),  # hands 10 cm above the ears, spread
    "crown": _Spot((0.097, 0.147, 0.0), (1.0, 0.0, 0.0), 0.0, 0.0),  # palm on top of the head
}


def _face(take: Take, spot: str, shift=(0.0, 0.0, 0.0), jitter: float = 0.006) -> np.ndarray:
    """``[3]`` the wrist target of a face spot (plus ``shift``, template metres) on this body."""
    o = np.asarray(_FACE[spot].offset) + np.asarray(shift, float)
    return take.head_point() + _at(take, *o, jitter=jitter)


def _hands_together(take: Take, sides, env, point, hint=(0.5, -1.0, -0.2), bulge: float = 0.1) -> None:
    """Both hands (``sides``) to the same side-normalised ``point`` (``[3]`` or ``[T, 3]``): mirror-symmetric
    about the midline, e.g. holding something in front of the chest, as ``env [T]`` goes 0 -> 1."""
    for side in sides:
        skills.toward(take, side, env, point, elbow_hint=hint, bulge=bulge)


_ARM_JOINTS = [j for j, name in enumerate(SMPL24.joint_names)
               if any(part in name for part in ("collar", "shoulder", "elbow", "wrist", "hand"))]


def _steps(take: Take, weight: np.ndarray, *, cadence: float, size: float) -> None:
    """Walk (MOTION_FACTS 3.1) while ``weight [T]`` is 1, standing where it is 0: the legs, pelvis, trunk
    and foot support of a gait blended in (the arms stay as they are: they carry or push)."""
    walker = Take(take.num_frames, take.fps, take.rng, take.subject, take.mode)
    skills.gait(walker, skills.WALK, cadence=cadence, size=size)
    w = np.asarray(weight, float)
    walker.angles[:, _ARM_JOINTS] = 0.0
    take.angles += w[:, None, None] * walker.angles
    take.contact[:] = (1.0 - w)[:, None] * take.contact + w[:, None] * walker.contact


# --- A061-A068: head and face ------------------------------------------------------------------------------


def put_on_headphone(take: Take) -> None:
    """Look at the headphones held in front, spread them over the head, bring the cups down onto the ears,
    settle them there (the longest phase), then the hands leave the ears DOWNWARD to the sides.

    vs take off (A062): same arc reversed in spirit but not in detail: here the clip starts with the hands
    in front and ends with them hanging; there it starts at the ears and ends carrying the headphones low in
    front with one hand."""
    _begin(take)
    k = _keys(take, 0.6, 0.35, 0.6, 0.45, 0.9, 0.55)
    held, over, ear = _at(take, 0.11, -0.12, 0.30), _face(take, "over head"), _face(take, "ear")
    settle = (take.t > k[4]) & (take.t < k[5])
    for side in SIDES:
        path = _path(take, k, [None, held, held, over, ear, ear, None])
        path[:, 1] += settle * 0.012 * take.scale() * np.sin(2 * np.pi * 3.0 * take.t)  # pressing the cups on
        skills.reach(take, side, path, elbow_hint=_FACE["ear"].hint)
        _orient(take, side, _curve(take, k, 0, 1, 1, 1, 1, 1, 0), -30.0, -10.0)
    skills.turn_head(take, _curve(take, k, 0, 18, 18, 8, 0, -3, 0))  # eyes on the headphones, then straight ahead


def take_off_headphone(take: Take) -> None:
    """Hands straight up the sides to the cups, lift the band up and out over the head (the head ducks),
    bring the headphones down in front and look at them, then one hand carries them low in front (to the
    clip's end) while the other drops. See :func:`put_on_headphone` for how the pair differs."""
    _begin(take)
    carrier = _any_side(take, 0.3)
    k = _keys(take, 0.5, 0.25, 0.5, 0.55, 0.7, 0.6)
    ear, over = _face(take, "ear"), _face(take, "over head", (0.03, 0.03, 0.02))
    front, low = _at(take, 0.10, -0.08, 0.32), _at(take, 0.13, -0.30, 0.24)
    for side in SIDES:
        end = low if side == carrier else None
        skills.reach(take, side, _path(take, k, [None, ear, ear, over, front, front, end]),
                     elbow_hint=_FACE["ear"].hint)
        _orient(take, side, _curve(take, k, 0, 1, 1, 1, 1, 1, 1 if side == carrier else 0), -30.0, -10.0)
    skills.turn_head(take, _curve(take, k, 0, 0, 0, 12, 22, 22, 12))


def shoot_at_the_basket(take: Take) -> None:
    """Basketball shot: the ball at the chest, raised to the set point above the forehead as the knees dip,
    then legs and arms extend together up and forward, the shooting wrist flicks (extension -> flexion) and
    the follow-through is held; the guide hand comes off. ``jump shot``: a jump (MOTION_FACTS 3.3) whose
    take-off is the release. The gaze is up at the rim throughout."""
    skills.stand(take)
    shooter = _any_side(take)
    k = _keys(take, 0.5, 0.4, 0.45, 0.22, 0.5, 0.6)
    if take.mode == "jump shot":
        skills.jump(take, k[4] - 0.6, height=take.vary(0.2, 0.25), dip=0.55, arm_swing=0.0)
    else:
        dip = _curve(take, k, 0, 0, 0, 1, 0, 0, 0)
        skills.crouch(take, take.vary(40.0, 0.2) * dip, 8.0 * dip)
        for side in SIDES:
            take[f"{side}_ankle.dorsi"] -= 12.0 * _curve(take, k, 0, 0, 0, 0, 1, 0.5, 0)  # onto the toes
    chest, set_point = _at(take, 0.09, -0.08, 0.30), take.head_point() + _at(take, 0.10, 0.10, 0.18)
    release = take.head_point() + _at(take, 0.06, 0.24, 0.42)  # up and out toward the rim
    for side in SIDES:
        if side == shooter:
            points = [None, chest, chest, set_point, release, release, None]
            take[f"{side}_wrist.flex"] = _curve(take, k, 0, 0, 0, -50, 45, 40, 0)
        else:  # the guide hand on the side of the ball, off at the release
            lateral = np.array([0.05, -0.02, -0.02]) * take.scale()
            points = [None, chest + lateral, chest + lateral, set_point + lateral,
                      release - take.scale() * np.array([0.0, 0.1, 0.05]), None, None]
        skills.reach(take, side, _path(take, k, points), elbow_hint=(0.6, -1.0, -0.1))
        _orient(take, side, _curve(take, k, 0, 1, 1, 1, 1, 1, 0), -20.0)
    skills.turn_head(take, _curve(take, k, 0, 5, -12, -15, -18, -15, 0))


def bounce_ball(take: Take) -> None:
    """Dribbling: one palm pushes the ball down at the side-front of the hip ~1.8 times/s (the wrist flexes
    with each push), knees soft, trunk over the ball, eyes down. ``both hands``: a two-handed push down in
    front and catch, ~0.8 times/s."""
    skills.stand(take)
    skills.crouch(take, take.vary(22.0, 0.2), take.vary(14.0, 0.2))
    k = _spell(take, 0.5, 0.5, (0.75, 0.95))
    env = _curve(take, k, 0, 1, 1, 0)
    if take.mode == "both hands":
        phase = timing.warped_phase(take.t, take.vary(0.8, 0.1) * take.tempo, take.rng)
        push = skills.pulse(phase, 0.18, 0.05, 0.45) * env
        hold = _at(take, 0.11, -0.22, 0.32)
        target = hold + take.scale() * push[:, None] * np.array([0.0, -0.16, 0.04])
        _hands_together(take, SIDES, env, target)
        for side in SIDES:
            _orient(take, side, env, 20.0, 25.0 * push)
    else:
        side = _side(take)
        phase = timing.warped_phase(take.t, take.vary(1.8, 0.1) * take.tempo, take.rng)
        down = (0.5 - 0.5 * np.cos(2 * np.pi * phase)) * env
        target = _at(take, 0.2, -0.3, 0.26) + take.scale() * take.amp * down[:, None] * np.array([0.0, -0.12, 0.02])
        skills.toward(take, side, env, target, elbow_hint=(0.6, -1.0, -0.4))
        _orient(take, side, env, 75.0, -15.0 + 35.0 * down)
        skills.hang_arm(take, other(side), forward=15.0 * env)
        take[f"{other(side)}_elbow.flex"] += 30.0 * env
    skills.turn_head(take, 18.0 * env)


# Tennis strokes: right-hand wrist keyframes (thorax frame), trunk turn (+ = to the left) at the same keys:
# ready, take-back, held, contact, follow-through, ready. MOTION_FACTS 3.5: the swing goes proximal to distal,
# the trunk turning ahead of the arm.
_STROKES = {
    "forehand": ([(0.1, -0.15, 0.35), (0.45, -0.05, -0.2), (0.45, -0.08, -0.22), (0.3, -0.1, 0.42),
                  (-0.25, 0.15, 0.25), (0.1, -0.15, 0.35)], (0, -45, -45, 0, 40, 0)),
    "backhand": ([(0.1, -0.15, 0.35), (-0.2, -0.2, 0.12), (-0.22, -0.22, 0.1), (0.15, -0.12, 0.42),
                  (0.5, 0.1, 0.05), (0.1, -0.15, 0.35)], (0, 40, 40, 0, -35, 0)),
}


def tennis_bat_swing(take: Take) -> None:
    """A tennis stroke from the ready stance (knees bent, feet apart): ``forehand`` (take-back to the racket
    side, swing across the body to the other shoulder), ``backhand`` (take-back across the body to the other
    hip, swing out to the racket side) or ``serve`` (ball toss with the free hand overhead, racket behind the
    head, swing up and over, follow-through down across the body)."""
    skills.stand(take, heading=take.rng.normal(0.0, 15.0))
    arm = _any_side(take, 0.1)
    sign = 1.0 if arm == "right" else -1.0  # the trunk turns are written for a right-hander
    for side in SIDES:
        take[f"{side}_hip.abd"] += 7.0
    if take.mode == "serve":
        skills.crouch(take, take.vary(12.0, 0.2), 5.0)
    else:  # the ready stance: knees bent, bouncing lightly on the balls of the feet between strokes
        bounce = 0.5 - 0.5 * np.cos(2 * np.pi * timing.warped_phase(take.t, take.vary(1.8, 0.1) * take.tempo, take.rng))
        skills.crouch(take, take.vary(20.0, 0.2) + 10.0 * bounce, 10.0, heel=10.0 * bounce)
    if take.mode == "serve":
        k = _keys(take, 0.5, 0.35, 0.3, 0.2, 0.45, 0.6)
        racket = [(0.1, -0.15, 0.35), (0.3, 0.0, 0.1), (0.35, 0.25, -0.12), (0.15, 0.15, -0.25),
                  (0.1, 0.62, 0.25), (-0.2, -0.35, 0.2), (0.1, -0.15, 0.35)]
        toss = [(0.08, -0.15, 0.33), (0.12, 0.3, 0.3), (0.1, 0.5, 0.25), (0.1, 0.2, 0.3), (0.15, -0.1, 0.3),
                None, None]
        bend = _curve(take, k, 0, 0.5, 1, 0.4, 0, 0, 0)
        skills.crouch(take, 25.0 * bend, 0.0)
        take["spine2.flex"] += _curve(take, k, 0, -3, -8, -5, 8, 18, 0)
        take["spine1.flex"] += _curve(take, k, 0, 0, -5, 0, 10, 15, 0)
        skills.turn_trunk(take, sign * take.amp * _curve(take, k, 0, -25, -35, -20, 10, 35, 0))
        skills.reach(take, arm, _path(take, k, [_at(take, *p) for p in racket]), elbow_hint=(1.0, -0.2, -0.3))
        skills.reach(take, other(arm), _path(take, k, [None if p is None else _at(take, *p) for p in toss]),
                     elbow_hint=(0.5, -1.0, 0.0))
        skills.turn_head(take, _curve(take, k, 0, -10, -30, -25, -15, 10, 0))
    else:  # shadow strokes, one after another, for as long as the clip lasts (1-2)
        racket, turn = _STROKES[take.mode]
        if take.mode == "forehand":  # the free hand points ahead at the ball, then comes across
            free = [(0.08, -0.15, 0.33), (0.0, -0.05, 0.38), (0.0, -0.05, 0.38), (0.2, -0.2, 0.2), None, None]
        else:  # on the racket's throat through the take-back
            free = [(0.08, -0.15, 0.33), (-0.12, -0.18, 0.18), (-0.12, -0.2, 0.16), (0.25, -0.15, 0.1), None, None]
        strokes = 2 if take.duration > 3.0 else 1
        one = [0.6, 0.2, 0.28, 0.4, 0.5]
        k = _keys(take, *(one * strokes), fit=0.95)
        racket_pts = [_at(take, *p) for p in racket[:-1]] * strokes + [_at(take, *racket[-1])]
        free_pts = [None if p is None else _at(take, *p) for p in free[:-1]] * strokes + [None]
        skills.turn_trunk(take, sign * take.amp * _curve(take, k, *(list(turn[:-1]) * strokes + [0])))
        skills.reach(take, arm, _path(take, k, racket_pts), elbow_hint=(0.6, -1.0, -0.3))
        skills.reach(take, other(arm), _path(take, k, free_pts), elbow_hint=(0.6, -1.0, -0.2))
        skills.turn_head(take, 5.0, sign * _curve(take, k, *([0, 30, 30, 0, -10] * strokes + [0])))  # eyes on the ball
    _orient(take, arm, 1.0, 20.0, -10.0)


def juggling_table_tennis_balls(take: Take) -> None:
    """``cascade``: both hands at the waist in front each loop a small vertical ellipse (scoop in, toss,
    catch out) half a cycle apart, ~1.7 loops/s per hand, with a flick of the wrist at each toss, eyes up at
    the top of the arcs. ``one hand``: one hand loops faster while the other holds the spare ball low."""
    skills.stand(take)
    k = _spell(take, 0.5, 0.5, (0.8, 0.95))
    env = _curve(take, k, 0, 1, 1, 0)
    s = take.scale() * take.amp
    if take.mode == "cascade":
        phase = timing.warped_phase(take.t, take.vary(1.7, 0.1) * take.tempo, take.rng, wobble=0.03)
        loops = {"left": phase, "right": phase + 0.5}
    else:
        side = _side(take)
        loops = {side: timing.warped_phase(take.t, take.vary(2.2, 0.1) * take.tempo, take.rng, wobble=0.03)}
        skills.toward(take, other(side), env, _at(take, 0.15, -0.3, 0.24), elbow_hint=(0.5, -1.0, -0.3))
        _orient(take, other(side), env, -50.0)
    for side, phase in loops.items():
        c = 2 * np.pi * phase
        base = _at(take, 0.16, -0.26, 0.3)  # at the waist, below where signs are shown
        target = base + s * np.stack([-0.04 * np.sin(c), 0.055 * np.cos(c), 0.01 * np.sin(c)], -1)
        skills.toward(take, side, env, target, elbow_hint=(0.6, -1.0, -0.3))
        _orient(take, side, env, -45.0, 18.0 * np.maximum(np.sin(c), 0.0) - 5.0)
        take["neck.twist"] += env * (2.5 if side == "left" else -2.5) * np.cos(c)  # eyes follow the balls
    skills.turn_head(take, -14.0 * env)


def hush(take: Take) -> None:
    """"Shh": the index finger up against the lips (the hand upright in front of the mouth, the forearm
    steep), held still 1-2 s with a slight forward lean of the head; nothing else moves.

    vs sniff (A079: palm up below the nose, the head dips to it and the chest rises), yawn (A103: the palm
    over the mouth, the head tips back), drink (the forearm supinated, the head tips back)."""
    _begin(take)
    side = _side(take)
    spot = _FACE["lips"]
    k = _keys(take, 0.5, take.uniform(1.2, 2.2), 0.5)
    env = _curve(take, k, 0, 1, 1, 0)
    skills.toward(take, side, env, _face(take, "lips"), elbow_hint=spot.hint, bulge=0.06)
    _orient(take, side, env, spot.pron, spot.flex)
    skills.turn_head(take, 4.0 * env)


def flick_hair(take: Take) -> None:
    """One or two quick flicks: the hand comes up to the forehead, then sweeps fast (~0.25 s) over the side
    of the head to behind it as the head tosses back and away, and drops. vs brushing hair (repeated slow
    strokes on the side of the head) and touch head (held)."""
    skills.stand(take)
    side = _side(take)
    sign = 1.0 if side == "left" else -1.0
    flicks = 2 if take.duration > 3.2 and take.rng.uniform() < 0.6 else 1
    one = [0.4, 0.12, 0.25, 0.12, 0.4]
    k = _keys(take, *(one + [0.35] + one)[: 6 * flicks - 1])
    forehead, behind = _face(take, "forehead"), _face(take, "over head", (0.02, -0.07, -0.07))
    points = ([None, forehead, forehead, behind, behind] + [None]) * flicks
    skills.reach(take, side, _path(take, k, points[: len(k)]), elbow_hint=(1.0, 0.1, 0.0))
    touch = _curve(take, k, *([0, 1, 1, 1, 1] + [0]) * flicks)
    _orient(take, side, touch, 30.0, -10.0)
    toss = _curve(take, k, *([0, 0, 0, 1, 0.4] + [0]) * flicks)
    skills.turn_head(take, -14.0 * toss, sign * 10.0 * toss, -sign * 8.0 * toss)


# --- A069-A072: hand signs ----------------------------------------------------------------------------------


def _sign(take: Take, target, hint, *, pron: float, flex: float = 0.0, rise: float = 0.5,
          hold=(1.0, 1.8)) -> tuple[np.ndarray, np.ndarray, tuple[str, ...]]:
    """A hand sign shown by the mode's hands (``both hands``: both): up to ``target`` (the same
    side-normalised point for each), forearm turned to ``pron`` and wrist to ``flex``, held, lowered.
    Returns (the envelope, its keys, the hands); ``target`` may be ``[T, 3]`` (a held movement)."""
    sides = SIDES if take.mode.startswith("both") else (_side(take),)
    k = _keys(take, rise, take.uniform(*hold), rise)
    env = _curve(take, k, 0, 1, 1, 0)
    for side in sides:
        skills.toward(take, side, env, target, elbow_hint=hint, bulge=0.08)
        _orient(take, side, env, pron, flex)
    return env, k, sides


# The four signs differ in the fingers, which Kinect does not see, so they differ in what it sees:
# thumb up   fist forward at mid-chest height, forearm about horizontal, unturned: the thumb marker points UP; a
#            small push forward-up as it is shown;
# thumb down arm nearly straight forward and lower, elbow turned out, forearm fully pronated: the thumb
#            marker points DOWN; two small downward jabs;
# OK sign    hand upright at shoulder height in front of the shoulder, palm forward, held quite still;
# victory    hand upright beside the face (head height, out to the side), palm forward, a little waggle at
#            ~2.5 Hz and the head tilted toward it, as in a photo pose.


def thumb_up(take: Take) -> None:
    _begin(take)
    base = _at(take, 0.12, 0.03, 0.4)
    env, k, _ = _sign(take, base, (0.3, -1.0, -0.2), pron=0.0, flex=-5.0, hold=(1.2, 2.2))
    push = timing.keyframes(take.t, [k[1], k[1] + 0.2, k[1] + 0.45], [0.0, 1.0, 0.0])
    for side in (SIDES if take.mode.startswith("both") else (_side(take),)):
        take[f"{side}_shoulder.elev"] += 8.0 * push
        take[f"{side}_elbow.flex"] -= 12.0 * push
    skills.turn_head(take, 5.0 * env)


def thumb_down(take: Take) -> None:
    _begin(take)
    base = _at(take, 0.06, -0.13, 0.44)
    env, k, sides = _sign(take, base, (1.0, 0.6, -0.2), pron=80.0)
    jabs = skills.bumps(take, [k[1] + 0.05, k[1] + 0.45], 0.3) * (take.t < k[2])
    for side in sides:
        take[f"{side}_shoulder.elev"] -= 7.0 * jabs
    skills.turn_head(take, 6.0 * env)


def make_ok_sign(take: Take) -> None:
    _begin(take)
    _sign(take, _at(take, 0.15, 0.1, 0.28), (0.3, -1.0, -0.1), pron=80.0, flex=-30.0, hold=(1.2, 2.0))


def make_victory_sign(take: Take) -> None:
    _begin(take)
    side = _side(take)
    waggle = np.sin(2 * np.pi * take.vary(2.5, 0.15) * take.tempo * take.t)
    target = _at(take, 0.22, 0.26, 0.10) + take.scale() * 0.012 * waggle[:, None] * np.array([1.0, 0.3, 0.0])
    env, _, sides = _sign(take, target, (0.8, -0.6, 0.0), pron=40.0, flex=-20.0)
    for s in sides:
        take[f"{s}_wrist.dev"] += 8.0 * waggle * env
    tilt = 0.0 if len(sides) == 2 else (7.0 if side == "left" else -7.0)
    skills.turn_head(take, -3.0 * env, 0.0, tilt * env)


# --- A073-A086: hands at work in front of the body -------------------------------------------------------


def staple_book(take: Take) -> None:
    """Standing at a table (or seated at it), leaning over it: one hand holds the book flat, the other
    palm hovers over the stapler and gives 2-3 sharp presses (down ~6 cm in ~0.1 s, a short hold, up),
    the trunk dipping with each; between presses the book is shifted a few cm."""
    _begin(take)
    seated = "seated" in take.mode
    side = _any_side(take)
    _lean(take, take.vary(10.0 if seated else 18.0, 0.2))
    y = -0.2 if seated else -0.36
    k = _spell(take, 0.6, 0.5, (0.7, 0.9))
    env = _curve(take, k, 0, 1, 1, 0)
    presses = np.zeros(take.num_frames)
    t = k[1] + take.uniform(0.1, 0.3)
    while t + 0.45 < k[2]:
        presses = np.maximum(presses, timing.keyframes(take.t, [t, t + 0.1, t + 0.25, t + 0.45], [0, 1, 1, 0]))
        t += take.vary(0.9, 0.15) / take.tempo
    shift = take.scale() * np.stack([0.03 * np.sin(2 * np.pi * 0.5 * (take.t - k[1])), np.zeros_like(take.t),
                                     np.zeros_like(take.t)], -1) * env[:, None]
    book = _at(take, 0.1, y, 0.3) + shift
    press = _at(take, 0.03, y + 0.07, 0.34) + shift
    press = press + take.scale() * presses[:, None] * np.array([0.0, -0.065, 0.0])
    skills.toward(take, other(side), env, book, elbow_hint=(0.6, -1.0, -0.3))
    skills.toward(take, side, env, press, elbow_hint=(0.6, -0.6, -0.3))
    _orient(take, other(side), env, 75.0, -20.0)
    _orient(take, side, env, 80.0, -35.0)
    take["spine2.flex"] += 4.0 * presses
    skills.turn_head(take, 20.0 * env + 3.0 * presses)


def counting_money(take: Take) -> None:
    """One hand holds a stack of notes palm up at the lower chest; the thumb of the other slides notes off
    it, ~2.5 per second: a small, fast sideways stroke of that wrist (with deviation and a little twist), in
    runs with short pauses, and every ~2 s that hand lays the counted notes down to the side; eyes down on
    the money. vs magic cube (A084: big alternating forearm turns of
    both hands) and playing with a phone (both hands still, thumbs tapping)."""
    _begin(take)
    side = _any_side(take)
    k = _spell(take, 0.5, 0.5, (0.75, 0.95))
    env = _curve(take, k, 0, 1, 1, 0)
    phase = timing.warped_phase(take.t, take.vary(2.5, 0.12) * take.tempo, take.rng, wobble=0.05)
    running = np.clip(0.8 + take.wander(1.0, 0.4), 0.0, 1.0) * env
    slide = skills.pulse(phase, 0.3, 0.0, 0.5) * running
    # Every few notes the counting hand lays the counted ones down out to the side (a slow, big movement
    # that survives the skeleton smoothing, unlike the thumb's).
    piles = skills.bumps(take, skills.beats(take, take.vary(2.0, 0.15), jitter=0.15), take.vary(0.7, 0.1)) * env
    stack = _at(take, 0.06, -0.18, 0.27)
    counting = _at(take, 0.03, -0.14, 0.3) + take.scale() * (
        slide[:, None] * np.array([0.05, -0.005, 0.01]) + piles[:, None] * np.array([0.16, -0.08, 0.02]))
    skills.toward(take, other(side), env, stack, elbow_hint=(0.5, -1.0, -0.2))
    skills.toward(take, side, env, counting, elbow_hint=(0.5, -1.0, -0.2))
    _orient(take, other(side), env, -55.0, 10.0)
    _orient(take, side, env, 25.0 + 10.0 * slide, 5.0 * slide, -10.0 + 20.0 * slide)
    skills.turn_head(take, 24.0 * env)


def cutting_nails(take: Take) -> None:
    """Both hands close together low in front (over the lap when seated), the trunk bent over them and the
    head down; the clipper hand squeezes ~1.2 times/s (a small wrist flexion) and moves on to the next
    finger every two squeezes, the other hand turning a little to present it."""
    _begin(take)
    side = _any_side(take)
    seated = "seated" in take.mode
    _lean(take, take.vary(14.0 if seated else 20.0, 0.2))
    take["spine2.flex"] += 6.0
    k = _spell(take, 0.6, 0.5, (0.75, 0.95))
    env = _curve(take, k, 0, 1, 1, 0)
    phase = timing.warped_phase(take.t, take.vary(1.2, 0.12) * take.tempo, take.rng)
    squeeze = skills.pulse(phase, 0.12, 0.08, 0.2) * env
    finger = np.floor(np.maximum(phase, 0.0) / 2.0) % 5  # the next finger every two squeezes
    y = -0.3 if seated else -0.24
    held = _at(take, 0.04, y, 0.28) + take.scale() * np.stack(
        [0.008 * finger, np.zeros_like(finger), np.zeros_like(finger)], -1)
    clipper = _at(take, -0.02, y + 0.04, 0.31) + take.scale() * np.stack(
        [-0.012 * finger, -0.01 * squeeze, np.zeros_like(finger)], -1)
    skills.toward(take, other(side), env, held, elbow_hint=(0.6, -1.0, -0.3))
    skills.toward(take, side, env, clipper, elbow_hint=(0.6, -1.0, -0.3))
    _orient(take, other(side), env, -30.0 + 8.0 * finger, 5.0)
    _orient(take, side, env, 40.0, 15.0 * squeeze)
    skills.turn_head(take, 28.0 * env)


def cutting_paper(take: Take) -> None:
    """Scissors in one hand at chest height, the paper in the other: the scissors open and close ~2.5
    times/s (wrist and forearm bob) while advancing forward along the cut (~12 cm per cut, then back for the
    next); the paper hand turns the sheet slowly (forearm twist) and follows the cut."""
    _begin(take)
    side = _side(take)
    k = _spell(take, 0.5, 0.5, (0.75, 0.95))
    env = _curve(take, k, 0, 1, 1, 0)
    snip = np.sin(2 * np.pi * timing.warped_phase(take.t, take.vary(2.5, 0.12) * take.tempo, take.rng))
    cut_phase = timing.warped_phase(take.t, take.vary(0.55, 0.15) * take.tempo, take.rng)
    progress = timing.keyframes(np.mod(cut_phase, 1.0), [0.0, 0.8, 1.0], [0.0, 1.0, 0.0])
    s = take.scale() * take.amp
    scissors = _at(take, 0.05, -0.13, 0.22) + s * np.stack(
        [-0.02 * progress, 0.008 * snip, 0.13 * progress], -1)
    paper = _at(take, 0.08, -0.15, 0.3) + s * np.stack(
        [np.zeros_like(progress), np.zeros_like(progress), 0.04 * progress], -1)
    skills.toward(take, side, env, scissors, elbow_hint=(0.6, -1.0, -0.3))
    skills.toward(take, other(side), env, paper, elbow_hint=(0.6, -1.0, -0.3))
    _orient(take, side, env, 5.0 + 6.0 * snip, 8.0 * snip)
    _orient(take, other(side), env, -20.0 + take.wander(25.0, 0.4))
    skills.turn_head(take, 16.0 * env)


def snapping_fingers(take: Take) -> None:
    """A hand raised beside the shoulder, forearm up, snapping in time (~1.7 snaps/s, in runs): each snap a
    quick wrist flick (cocked back, then forward in ~0.08 s) with a small twist and drop of the hand, the
    head nodding to the beat. ``both hands``: the hands alternate. vs shake fist (a continuous 3-5 Hz shake
    of a raised fist) and hand waving (side-to-side sweeps)."""
    _begin(take)
    sides = SIDES if take.mode == "both hands" else (_side(take),)
    k = _spell(take, 0.5, 0.5, (0.75, 0.95))
    env = _curve(take, k, 0, 1, 1, 0)
    period = take.vary(0.6, 0.12) / take.tempo
    beat = np.zeros(take.num_frames)
    for n, side in enumerate(sides):
        snaps = np.zeros(take.num_frames)
        t = k[1] + take.uniform(0.0, 0.2) + n * period / 2
        while t + 0.3 < k[2]:
            snaps = np.maximum(snaps, timing.keyframes(take.t, [t - 0.15, t, t + 0.08, t + 0.3], [0, -1, 1, 0]))
            t += period * len(sides) * (1.0 + take.rng.normal(0.0, 0.05))
        flick = snaps * env
        target = _at(take, 0.26, 0.04, 0.16) + take.scale() * np.maximum(flick, 0.0)[:, None] * np.array(
            [0.0, -0.02, 0.01])
        skills.toward(take, side, env, target, elbow_hint=(1.0, -0.5, -0.3))
        _orient(take, side, env, 10.0 + 15.0 * flick, 25.0 * flick)
        beat = np.maximum(beat, np.maximum(flick, 0.0))
    skills.turn_head(take, 4.0 * beat - 3.0 * env)


def open_bottle(take: Take) -> None:
    """One hand holds the bottle upright at the lower chest, the other grips the cap above it and twists it
    off: 3-4 forearm turns (~1.3/s: turn ~70 degrees, regrip), the holding hand countering a little, then the
    cap is lifted away. The twisting forearm's rotation oscillation is the signature."""
    _begin(take)
    side = _side(take)
    k = _keys(take, 0.6, take.uniform(2.0, 3.0), 0.4, 0.4, 0.6)
    env = _curve(take, k, 0, 1, 1, 1, 1, 0)
    turning = _curve(take, k, 0, 1, 1, 0, 0, 0) * (take.t > k[1]) * (take.t < k[2])
    phase = timing.warped_phase(take.t, take.vary(1.3, 0.12) * take.tempo, take.rng)
    twist = np.sin(2 * np.pi * phase) * turning
    lift = _curve(take, k, 0, 0, 0, 1, 1, 0)
    bottle = _at(take, 0.06, -0.22, 0.27)
    cap = _at(take, 0.03, -0.09, 0.28) + take.scale() * (
        lift[:, None] * np.array([0.1, 0.08, 0.04]) + 0.01 * np.abs(twist)[:, None] * np.array([0.0, 1.0, 0.0]))
    skills.toward(take, other(side), env, bottle, elbow_hint=(0.5, -1.0, -0.3))
    skills.toward(take, side, env, cap, elbow_hint=(0.8, -0.6, -0.2))
    _orient(take, other(side), env, 0.0 - 8.0 * twist)
    _orient(take, side, env, 40.0 + take.amp * 35.0 * twist, -10.0)
    skills.turn_head(take, 15.0 * env)


def sniff(take: Take) -> None:
    """Something held in the fingertips (palm up) is brought under the nose; the head dips to meet it and
    the chest rises with two or three short sniffs (small head jerks, thorax extension, shoulders up), then
    it is taken away. ``both hands``: a cup or flower held in both. See :func:`hush` for its neighbours."""
    _begin(take)
    sides = SIDES if take.mode == "both hands" else (_side(take),)
    spot = _FACE["nose"]
    k = _keys(take, 0.6, 0.3, take.uniform(0.8, 1.4), 0.5)
    env = _curve(take, k, 0, 1, 1, 1, 0)
    dip = _curve(take, k, 0, 0, 1, 1, 0)
    for side in sides:
        shift = (0.0, -0.01, 0.0) if len(sides) == 1 else (-0.02, -0.02, 0.0)
        skills.toward(take, side, env, _face(take, "nose", shift), elbow_hint=spot.hint, bulge=0.06)
        _orient(take, side, env, spot.pron, spot.flex)
    sniffs = skills.bumps(take, k[2] + np.array([0.1, 0.45, 0.8])[: 2 + int(take.rng.uniform() < 0.5)], 0.25)
    sniffs = sniffs * (take.t < k[3])
    skills.turn_head(take, 14.0 * dip - 3.0 * sniffs)
    take["spine3.flex"] -= 4.0 * dip + 2.0 * sniffs
    for side in SIDES:
        take[f"{side}_collar.elev"] += 4.0 * dip + 3.0 * sniffs


def toss_a_coin(take: Take) -> None:
    """The coin on the thumb of a fist at the waist: a sharp upward flick (the hand jerks up ~6 cm, the wrist
    snaps), the head follows it up and down (~0.5 s), the hand catches it lower, then either opens palm up
    to show it (``catch``) or slaps it onto the back of the other hand (``slap on hand back``); eyes down
    on the result. vs throw up cap (A094): small, one hand, the arm stays below the chest."""
    _begin(take)
    side = _any_side(take)
    k = _keys(take, 0.5, 0.35, 0.1, 0.5, 0.25, take.uniform(0.7, 1.1), 0.5)
    ready, flicked = _at(take, 0.1, -0.2, 0.28), _at(take, 0.1, -0.13, 0.31)
    caught = _at(take, 0.09, -0.18, 0.33)
    if take.mode == "slap on hand back":
        onto = _at(take, -0.02, -0.17, 0.3)
        skills.reach(take, side, _path(take, k, [None, ready, ready, flicked, flicked, caught, onto, None]),
                     elbow_hint=(0.5, -1.0, -0.2))
        take[f"{side}_elbow.pron"] = _curve(take, k, 10, 0, 0, -20, -60, -60, 80, 10)
        back = _curve(take, k, 0, 0, 0, 0, 0, 1, 1, 0)
        skills.toward(take, other(side), back, _at(take, 0.03, -0.21, 0.29), elbow_hint=(0.5, -1.0, -0.3))
        _orient(take, other(side), back, 80.0)
    else:
        show = _at(take, 0.08, -0.14, 0.33)
        skills.reach(take, side, _path(take, k, [None, ready, ready, flicked, flicked, caught, show, None]),
                     elbow_hint=(0.5, -1.0, -0.2))
        take[f"{side}_elbow.pron"] = _curve(take, k, 10, 0, 0, -20, -60, -40, -70, 10)
    take[f"{side}_wrist.flex"] = _curve(take, k, 0, 0, -25, 15, 0, 10, 0, 0)
    skills.turn_head(take, _curve(take, k, 0, 10, 10, -25, -5, 25, 25, 0))


def fold_paper(take: Take) -> None:
    """Two folds of a sheet held at both edges: one hand turns over (forearm twist ~120 degrees) and carries
    its edge up, over and across onto the other, the fold is creased with a pressing slide of that palm all
    the way back along it, and the sheet (now smaller) is opened out again. ``on a table``: lower, leaning
    over it, palms pressing down. vs tear up paper (hands pulled apart fore and aft) and open a box."""
    _begin(take)
    side = _any_side(take)
    table = take.mode == "on a table"
    if table:
        _lean(take, take.vary(18.0, 0.2))
    y = -0.36 if table else -0.12
    folds = 2 if take.duration > 3.0 else 1
    # Keys: rest, the sheet held by its edges; per fold: the edge lifted up and over in an arc, laid onto
    # the other edge, creased, crease held, opened out (the sheet half as wide); rest.
    k = _keys(take, *([0.45] + [0.25, 0.25, 0.45, 0.3, 0.35] * folds + [0.45]))
    holder_pts, folder_pts = [None, _at(take, 0.2, y, 0.3)], [None, _at(take, 0.2, y, 0.3)]
    turn, crease = [0.0, 0.0], [0.0, 0.0]
    for n in range(folds):
        gap = 0.2 - 0.07 * n
        pressed = _at(take, gap, y - 0.01, 0.3)
        holder_pts += [pressed, pressed, pressed, pressed, _at(take, gap - 0.07, y, 0.3)]
        # the crease: the palm runs back along the fold, pressing, from the far edge to its own side
        creased = _at(take, gap - 0.03, y - 0.02, 0.31)
        folder_pts += [_at(take, 0.03, y + 0.1, 0.34), _at(take, -gap + 0.05, y + 0.02, 0.3),
                       creased, creased, _at(take, gap - 0.07, y, 0.3)]
        turn += [0.6, 1.0, 1.0, 1.0, 0.0]
        crease += [0.0, 0.0, 1.0, 1.0, 0.0]
    holder_pts.append(None)
    folder_pts.append(None)
    turn.append(0.0)
    crease.append(0.0)
    on = _curve(take, k, *([0.0] + [1.0] * (len(k) - 2) + [0.0]))
    skills.reach(take, other(side), _path(take, k, holder_pts), elbow_hint=(0.6, -1.0, -0.3))
    skills.reach(take, side, _path(take, k, folder_pts), elbow_hint=(0.7, -0.8, -0.3))
    _orient(take, other(side), on, 60.0 if table else -20.0, -10.0 if table else 0.0)
    _orient(take, side, on, -40.0 + 120.0 * _curve(take, k, *turn), -20.0 * _curve(take, k, *crease))
    skills.turn_head(take, 22.0 * on)


def ball_up_paper(take: Take) -> None:
    """Both hands crumple a sheet in front of the chest: they squeeze in pulses (~1.5/s, ~3 cm) around a
    ball that shrinks, the gap between them closing from ~30 cm to ~8 cm, the forearms kneading in opposite
    twists, elbows held out wide. vs rubbing the hands together (hands touching, sliding)."""
    _begin(take)
    k = _spell(take, 0.45, 0.5, (0.75, 0.95))
    env = _curve(take, k, 0, 1, 1, 0)
    shrink = timing.minimum_jerk((take.t - k[1]) / max(k[2] - k[1], 1e-3))
    phase = timing.warped_phase(take.t, take.vary(1.5, 0.12) * take.tempo, take.rng)
    squeeze = skills.pulse(phase, 0.25, 0.1, 0.3)
    gap = 0.15 - 0.11 * shrink - 0.03 * squeeze * (1.0 - 0.5 * shrink)
    for n, side in enumerate(SIDES):
        target = _at(take, 0.0, -0.06, 0.3) + take.scale() * np.stack(
            [gap, 0.015 * squeeze, np.zeros_like(gap)], -1)
        skills.toward(take, side, env, target, elbow_hint=(1.0, -0.3, -0.2))
        knead = np.sin(2 * np.pi * (phase + 0.5 * n))
        _orient(take, side, env, -10.0 + 25.0 * knead, 15.0 * squeeze)
    skills.turn_head(take, 15.0 * env)


def play_magic_cube(take: Take) -> None:
    """A Rubik's cube held up in both hands (~15 cm apart) below the chin: moves ~2/s, each a quick ~60-degree forearm
    turn of one hand (a face turned) or both together (the whole cube re-gripped, wrists flexing), with
    pauses to look; eyes down on the cube. See :func:`counting_money`."""
    _begin(take)
    k = _spell(take, 0.5, 0.5, (0.8, 0.95))
    env = _curve(take, k, 0, 1, 1, 0)
    turns = {side: np.zeros(take.num_frames) for side in SIDES}
    regrip = np.zeros(take.num_frames)
    t = k[1] + take.uniform(0.0, 0.3)
    while t + 0.35 < k[2]:
        move = take.rng.uniform()
        bump = timing.keyframes(take.t, [t, t + 0.15, t + 0.35], [0.0, 1.0, 0.0]) * take.choice((1.0, -1.0))
        if move < 0.65:
            turns[take.choice(SIDES)] += bump
        else:
            regrip += bump
        t += take.vary(0.5, 0.25) / take.tempo + (take.uniform(0.5, 1.0) if take.rng.uniform() < 0.12 else 0.0)
    for side in SIDES:
        target = _at(take, 0.07, -0.04, 0.25) + take.scale() * regrip[:, None] * np.array([0.0, 0.05, 0.02])
        skills.toward(take, side, env, target, elbow_hint=(0.7, -1.0, -0.2))
        _orient(take, side, env, 10.0 + take.amp * 55.0 * turns[side] + 30.0 * regrip, 25.0 * regrip)
    skills.turn_head(take, 22.0 * env)


def apply_cream_on_face(take: Take) -> None:
    """Palms on the cheeks rubbing cream in with circles (~1.2/s, ~3 cm), moving up to the forehead
    and back; the head tilts gently into the hands. ``one hand``: one hand circles on its cheek, then the
    other cheek and the forehead, while the other holds the jar at the chest. vs wipe face (long downward
    strokes over the whole face)."""
    _begin(take)
    k = _spell(take, 0.5, 0.5, (0.8, 0.95))
    env = _curve(take, k, 0, 1, 1, 0)
    phase = timing.warped_phase(take.t, take.vary(1.2, 0.12) * take.tempo, take.rng)
    c = 2 * np.pi * phase
    circle = take.scale() * take.amp * 0.03 * np.stack([np.cos(c), np.sin(c), np.zeros_like(c)], -1)
    span = k[2] - k[1]
    forehead = timing.keyframes(take.t, k[1] + span * np.array([0.35, 0.45, 0.65, 0.75]), [0, 1, 1, 0])
    cheek, brow = _face(take, "cheek"), _face(take, "forehead", (0.0, -0.03, 0.0))
    if take.mode == "one hand":
        side = _any_side(take)
        across = timing.keyframes(take.t, k[1] + span * np.array([0.7, 0.8]), [0.0, 1.0])
        far = _face(take, "cheek", (-0.19, 0.0, 0.02))
        spot = cheek + forehead[:, None] * (brow - cheek) + across[:, None] * (far - cheek)
        skills.toward(take, side, env, spot + circle, elbow_hint=_FACE["cheek"].hint, bulge=0.05)
        _orient(take, side, env, _FACE["cheek"].pron, _FACE["cheek"].flex)
        skills.toward(take, other(side), env, _at(take, 0.08, -0.15, 0.28), elbow_hint=(0.5, -1.0, -0.3))
        _orient(take, other(side), env, -60.0)
    else:
        spot = cheek + forehead[:, None] * (brow - cheek)
        for side in SIDES:
            skills.toward(take, side, env, spot + circle, elbow_hint=_FACE["cheek"].hint, bulge=0.05)
            _orient(take, side, env, _FACE["cheek"].pron, _FACE["cheek"].flex)
    skills.turn_head(take, -4.0 * env + 3.0 * np.sin(c) * env)


def apply_cream_on_hand_back(take: Take) -> None:
    """One hand held palm down in front of the lower chest; the other palm on its back rubs cream in with
    short strokes along the hand and forearm (~2/s, ~5 cm) and small circles, eyes on the hands. The mode
    names the rubbing hand. vs rub two hands (palm against palm, hands level)."""
    _begin(take)
    side = _side(take)
    k = _spell(take, 0.5, 0.5, (0.8, 0.95))
    env = _curve(take, k, 0, 1, 1, 0)
    phase = timing.warped_phase(take.t, take.vary(2.0, 0.12) * take.tempo, take.rng)
    c = 2 * np.pi * phase
    circling = timing.keyframes(take.t, [k[1], k[1] + 0.5 * (k[2] - k[1]), k[1] + 0.6 * (k[2] - k[1])],
                                [0.0, 0.0, 1.0])
    s = take.scale() * take.amp
    stroke = s * np.stack([0.012 * np.sin(c) * circling, 0.004 * np.cos(2 * c),
                           0.045 * np.cos(c) * (1.0 - 0.6 * circling)], -1)
    skills.toward(take, other(side), env, _at(take, 0.03, -0.2, 0.3), elbow_hint=(0.6, -1.0, -0.3))
    _orient(take, other(side), env, 80.0, 5.0)
    skills.toward(take, side, env, _at(take, -0.05, -0.15, 0.31) + stroke, elbow_hint=(0.7, -0.8, -0.2))
    _orient(take, side, env, 80.0, 10.0)
    skills.turn_head(take, 20.0 * env)


# --- A087-A092: bags, boxes and loads ----------------------------------------------------------------------


def _strap(take: Take) -> np.ndarray:
    """``[3]`` a wrist holding a bag strap at the front of its shoulder (elbow down), side-normalised."""
    return _at(take, 0.13, 0.02, 0.12)


def put_on_bag(take: Take) -> None:
    """The bag hangs from one hand at the side; it is swung up in front and onto that shoulder (the trunk
    turning toward it), the hand keeping the strap at the front of the shoulder; ``backpack``: the other
    arm then reaches behind the back (shoulder extension, elbow back) into the second strap and comes round
    to it; a shrug settles the load. The clip ends with the hand(s) on the strap(s).

    vs take off bag (A088): starts with the hands on the straps and ends bent to the floor, putting the bag
    down, then standing empty-handed."""
    skills.stand(take)
    side = _any_side(take, 0.25)
    sign = 1.0 if side == "left" else -1.0
    backpack = take.mode == "backpack"
    durations = [0.35, 0.6, 0.3] + ([0.6, 0.5, 0.6] if backpack else [0.7])
    k = _keys(take, *durations)
    carry = skills.relaxed_wrist(take) + take.scale() * np.array([0.05, 0.04, 0.0])
    swing, strap = _at(take, 0.22, -0.02, 0.3), _strap(take)
    rest = [strap] * (3 if backpack else 1)
    skills.reach(take, side, _path(take, k, [carry, carry, swing, strap] + rest), elbow_hint=(0.5, -1.0, -0.2))
    swing_env = _curve(take, k, *([0, 0, 1, 0.3] + [0] * len(rest)))
    skills.turn_trunk(take, sign * 20.0 * swing_env)
    if backpack:
        behind, other_strap = _at(take, 0.2, -0.25, -0.22), _strap(take)
        skills.reach(take, other(side), _path(take, k, [None, None, None, None, behind, other_strap, other_strap]),
                     elbow_hint=(0.4, -0.4, -1.0))
        skills.turn_trunk(take, -sign * 25.0 * _curve(take, k, 0, 0, 0, 0, 1, 0.2, 0))
    loaded = _curve(take, k, *([0, 0, 1, 1] + [1] * len(rest)))
    settle = skills.bumps(take, [k[-2], k[-2] + 0.3], 0.3)
    for s in SIDES:
        take[f"{s}_collar.elev"] += 10.0 * settle
        take[f"{s}_knee.flex"] += 8.0 * settle
    take["spine2.flex"] += 4.0 * loaded
    for s in ((side, other(side)) if backpack else (side,)):
        _orient(take, s, loaded, -20.0)


def take_off_bag(take: Take) -> None:
    """Hands on the strap(s) at the front of the shoulders; ``backpack``: the free arm slips out of its strap
    backwards (the elbow drawn back, the trunk turning away); the bag slides off the other shoulder, is
    swung to the front and lowered to the floor with a bend of the knees and trunk, and the body straightens
    empty-handed. See :func:`put_on_bag` for the pair."""
    skills.stand(take)
    side = _any_side(take, 0.25)
    sign = 1.0 if side == "left" else -1.0
    backpack = take.mode == "backpack"
    durations = ([0.4, 0.5, 0.5] if backpack else [0.4]) + [0.5, 0.5, 0.7, 0.3, 0.7]
    k = _keys(take, *durations)
    strap, front = _strap(take), _at(take, 0.15, -0.18, 0.35)
    n_pre = 3 if backpack else 1
    bend = _curve(take, k, *([0] * (n_pre + 3) + [1, 1, 0]))
    skills.crouch(take, take.vary(95.0, 0.12) * bend, take.vary(50.0, 0.12) * bend, heel=5.0 * bend)
    floor = _below(take, 0.55, 0.2, 0.0)  # hanging toward the floor in front of the feet
    path = _path(take, k, [strap] * n_pre + [strap, _at(take, 0.3, -0.2, 0.12), front, front, front, None])
    low = bend[:, None]
    skills.reach(take, side, (1.0 - low) * path + low * floor, elbow_hint=(0.5, -1.0, -0.2))
    if backpack:
        out, behind = _at(take, 0.28, -0.05, 0.05), _at(take, 0.2, -0.3, -0.16)
        skills.reach(take, other(side), _path(take, k, [_strap(take), _strap(take), out,
                                                        behind, None, None, None, None, None]),
                     elbow_hint=(0.4, -0.4, -1.0))
        skills.turn_trunk(take, sign * 25.0 * _curve(take, k, 0, 0, 0.6, 1, 0, 0, 0, 0, 0))
    else:
        skills.hang_arm(take, other(side))
    skills.turn_trunk(take, -sign * 15.0 * _curve(take, k, *([0] * n_pre + [0, 1, 0.3, 0, 0, 0])))
    loaded = _curve(take, k, *([1] * n_pre + [1, 0.5, 0, 0, 0, 0]))
    take["spine2.flex"] += 4.0 * loaded
    skills.turn_head(take, 20.0 * bend)


def _bag_hand(take: Take, side: str, height: float) -> None:
    """``side`` holds a bag open by its rim in front of the hip at ``height`` (thorax frame, m)."""
    skills.reach(take, side, _at(take, 0.08, height, 0.28), elbow_hint=(0.6, -1.0, -0.4))
    _orient(take, side, 1.0, 0.0, 10.0)


def put_something_into_a_bag(take: Take) -> None:
    """The bag held open in front of the hip with one hand (brought up at the start); the other hand fetches
    an object from out to the side at table height, carries it over the bag, lowers it INTO the bag (the
    wrist below the rim), lets go and comes back out empty and quick; once or twice; eyes on the bag.

    vs take something out (A090): there the hand goes in empty and rummages, comes out slowly with the object
    and raises it to the chest to look at it; the bag is held higher."""
    skills.stand(take)
    side = _side(take)
    _bag_hand(take, other(side), -0.32)
    times = 2 if take.duration > 3.5 else 1
    one = [0.5, 0.25, 0.45, 0.35, 0.2, 0.35]
    k = _keys(take, *(one * times + [0.45]))
    fetch, over = _at(take, 0.38, -0.25, 0.22), _at(take, 0.02, -0.14, 0.33)
    inside, out = _at(take, 0.04, -0.4, 0.3), _at(take, 0.12, -0.22, 0.32)
    points = [None] + [fetch, fetch, over, inside, inside, out] * times + [None]
    skills.reach(take, side, _path(take, k, points), elbow_hint=(0.6, -1.0, -0.3))
    _orient(take, side, _curve(take, k, *([0] + [1] * (6 * times) + [0])), 30.0)
    skills.turn_head(take, _curve(take, k, *([10] + [15, 10, 22, 25, 25, 20] * times + [10])))


def take_something_out_of_a_bag(take: Take) -> None:
    """The bag held in front with one hand; the other goes in (the wrist below the rim), rummages there
    (~1 s of small quick movements), comes out slowly with the object and raises it to the chest, turning
    it to look at it (held), then lowers it. See :func:`put_something_into_a_bag`."""
    skills.stand(take)
    side = _side(take)
    _bag_hand(take, other(side), -0.26)
    k = _keys(take, 0.5, take.uniform(0.8, 1.3), 0.5, take.uniform(0.6, 1.0), 0.5)
    inside, shown = _at(take, 0.05, -0.33, 0.3), _at(take, 0.1, -0.04, 0.34)
    path = _path(take, k, [None, inside, inside, shown, shown, None])
    rummage = ((take.t > k[1]) & (take.t < k[2])) * take.scale()
    path += rummage[:, None] * timing.smooth_noise(take.t, take.rng, 0.018, max_hz=3.0, channels=3)
    skills.reach(take, side, path, elbow_hint=(0.6, -1.0, -0.3))
    _orient(take, side, _curve(take, k, 0, 1, 1, 1, 1, 0), -40.0 + 30.0 * _curve(take, k, 0, 1, 1, 0, 0, 0))
    skills.turn_head(take, _curve(take, k, 15, 25, 25, 12, 10, 5))


def open_a_box(take: Take) -> None:
    """A box on a table at waist height, leaning over it, eyes down: ``flaps``: the hands start together on
    the top and open the four flaps in turn (right and left out to the sides, forearms turning up, then the
    front and back ones pushed away and pulled back with both hands); ``lid``: both hands grip the lid's sides,
    lift it ~20 cm and set it aside, then look in."""
    skills.stand(take)
    _lean(take, take.vary(15.0, 0.2))
    y = -0.34
    if take.mode == "lid":
        k = _keys(take, 0.6, 0.3, 0.5, 0.5, 0.3, 0.6)
        sides_pt = _at(take, 0.19, y, 0.36)
        lifted = sides_pt + take.scale() * np.array([0.0, 0.2, 0.0])
        aside = take.scale() * np.array([0.22, -0.06, -0.05])  # to the subject's right, side-normalised below
        for side in SIDES:
            toward_right = np.array([-1.0, 1.0, 1.0]) if side == "left" else np.array([1.0, 1.0, 1.0])
            put = lifted + aside * toward_right
            skills.reach(take, side, _path(take, k, [None, sides_pt, sides_pt, lifted, put, put, None]),
                         elbow_hint=(0.8, -1.0, -0.3))
            _orient(take, side, _curve(take, k, 0, 1, 1, 1, 1, 1, 0), 10.0)
        skills.turn_trunk(take, -10.0 * _curve(take, k, 0, 0, 0, 0, 1, 1, 0))
        skills.turn_head(take, _curve(take, k, 10, 22, 22, 15, 15, 30, 10))
    else:
        k = _keys(take, 0.55, 0.4, 0.4, 0.4, 0.4, 0.35, 0.35, 0.55)
        centre, out = _at(take, 0.04, y, 0.36), _at(take, 0.24, y + 0.08, 0.34)
        far, near = _at(take, 0.08, y - 0.02, 0.48), _at(take, 0.08, y + 0.03, 0.22)
        first = _any_side(take, 0.5)
        for side in SIDES:  # keys: rest, centre, first side's flap, second side's flap, centre, far, near, near, rest
            mine = [out, centre, centre] if side == first else [centre, out, centre]
            skills.reach(take, side, _path(take, k, [None, centre] + mine + [far, near, near, None]),
                         elbow_hint=(0.6, -1.0, -0.3))
            flap = _curve(take, k, *((0, 0, 1, 0, 0, 0, 0, 0, 0) if side == first else (0, 0, 0, 1, 0, 0, 0, 0, 0)))
            _orient(take, side, _curve(take, k, 0, 1, 1, 1, 1, 1, 1, 1, 0), 70.0 - 80.0 * flap)
        skills.turn_head(take, _curve(take, k, 10, 25, 25, 25, 25, 25, 25, 30, 10))


def move_heavy_objects(take: Take) -> None:
    """Effortful whole-body work: ``lift and carry``: squat to a box on the floor (knees ~115 degrees, trunk
    ~48), grip it with both hands at its sides, stand up with it held at the waist (leaning back a little
    against the load) and carry it a few slow, short steps; ``lift and put down``: squat, lift, hold, squat
    again and set it down a little further round, stand up; ``push``: lean into the load with the arms
    forward at chest height and walk it forward in short, slow steps. The root lowers in the squats."""
    skills.stand(take)
    if take.mode == "push":
        k = _keys(take, 0.6, take.duration, 0.6, fit=0.95)
        on = _curve(take, k, 0, 1, 1, 0)
        _lean(take, take.vary(28.0, 0.15) * on)
        for side in SIDES:
            take[f"{side}_knee.flex"] += 15.0 * on
        _steps(take, _curve(take, k, 0, 1, 1, 0), cadence=take.vary(1.3, 0.1), size=take.vary(0.6, 0.1))
        _hands_together(take, SIDES, on, _at(take, 0.16, -0.0, 0.45), hint=(0.6, -1.0, -0.3))
        for side in SIDES:
            _orient(take, side, on, 60.0, -40.0)
        skills.turn_head(take, -10.0 * on)
        return
    carry = take.mode == "lift and carry"
    if carry:
        k = _keys(take, 0.4, 1.0, 0.3, 1.0, 0.3, take.uniform(1.2, 2.0), 0.3)
        fold = _curve(take, k, 0, 0, 1, 1, 0, 0, 0, 0)
        walking = _curve(take, k, 0, 0, 0, 0, 0, 1, 1, 0)
        held = _curve(take, k, 0, 0, 0, 1, 1, 1, 1, 1)
    else:
        k = _keys(take, 0.4, 1.0, 0.3, 1.0, 0.5, 1.0, 0.3, 0.9)
        fold = _curve(take, k, 0, 0, 1, 1, 0, 0, 1, 1, 0)
        walking = np.zeros(take.num_frames)
        held = _curve(take, k, 0, 0, 0, 1, 1, 1, 1, 0, 0)
    skills.crouch(take, take.vary(115.0, 0.1) * fold, take.vary(48.0, 0.12) * fold, heel=5.0 * fold)
    take["spine1.flex"] -= 6.0 * held * (1.0 - fold)  # leaning back against the load
    if carry:
        _steps(take, walking, cadence=take.vary(1.5, 0.1), size=take.vary(0.6, 0.1))
    box_low = _below(take, 0.53, 0.16, -0.02)  # the box's sides near the floor in front of the feet
    box_high = _at(take, 0.19, -0.32, 0.3)
    low = fold[:, None]
    target = low * box_low + (1.0 - low) * box_high
    reach_env = np.maximum(fold, held)
    for side in SIDES:
        skills.toward(take, side, reach_env, target, elbow_hint=(0.8, -1.0, -0.2), bulge=0.05)
        _orient(take, side, reach_env, 0.0, 10.0)
    if not carry:
        skills.turn_trunk(take, take.choice((-1.0, 1.0)) * 25.0 * _curve(take, k, 0, 0, 0, 0, 0, 1, 1, 0, 0))
    skills.turn_head(take, 20.0 * fold)


# --- A094-A105: whole-arm and whole-body ------------------------------------------------------------------


def throw_up_cap(take: Take) -> None:
    """The cap held at the chest (both hands, or one), a short dip of the knees, then a fast throw straight
    up (the arms extend overhead in ~0.25 s with the legs), the head tips back to watch it rise and fall
    (~1 s), the hands wait overhead-forward to catch it at the face and bring it down. vs hands up (A095:
    held) and cheer up (rhythmic)."""
    skills.stand(take)
    sides = SIDES if take.mode == "both hands" else (_any_side(take, 0.15),)
    k = _keys(take, 0.5, 0.25, 0.25, 0.25, take.uniform(0.6, 0.9), 0.3, 0.6)
    dip = _curve(take, k, 0, 0, 1, 0, 0, 0, 0, 0)
    skills.crouch(take, take.vary(30.0, 0.2) * dip, 5.0 * dip)
    for side in SIDES:
        take[f"{side}_ankle.dorsi"] -= 12.0 * _curve(take, k, 0, 0, 0, 1, 0, 0, 0, 0)
    chest = _at(take, 0.09 if len(sides) == 2 else 0.14, -0.1, 0.3)
    top = take.head_point() + _at(take, 0.14, 0.42, 0.08)  # straight up, arms vertical
    wait, catch = take.head_point() + _at(take, 0.12, 0.2, 0.3), take.head_point() + _at(take, 0.08, -0.02, 0.3)
    for side in sides:
        skills.reach(take, side, _path(take, k, [None, chest, chest, top, wait, catch, catch, None]),
                     elbow_hint=(0.7, -1.0, -0.1))
        _orient(take, side, _curve(take, k, 0, 1, 1, 1, 1, 1, 1, 0), -40.0,
                0.0)
        take[f"{side}_wrist.flex"] += _curve(take, k, 0, 0, -20, 30, 0, 0, 0, 0)
    skills.turn_head(take, _curve(take, k, 0, 10, 5, -30, -35, -5, 5, 0))


def hands_up(take: Take) -> None:
    """Both arms raised and held (1.5-3 s), palms forward, very still: ``straight``: arms straight overhead
    (~165 degrees, shoulder width); ``bent elbows``: the surrender pose, upper arms out sideways a little
    above the shoulders and forearms vertical, hands above the head. vs cross arms, arm circles, arm swings
    and stretch oneself (A104: hands together, trunk arched, on the toes, arms swept down sideways)."""
    _begin(take)
    k = _keys(take, 0.6, take.uniform(1.5, 3.0), 0.6)
    env = _curve(take, k, 0, 1, 1, 0)
    for side in SIDES:
        if take.mode == "straight":
            skills.set_arm(take, side, take.vary(165.0, 0.03) * env + 3.0, 6.0 * (1.0 - env),
                           elbow=take.subject.arm_carry * (1.0 - env) + 5.0)
            _orient(take, side, env, -60.0)
        else:
            skills.set_arm(take, side, 15.0 * env + 3.0, take.vary(112.0, 0.05) * env + 6.0, rot=-85.0 * env,
                           elbow=take.subject.arm_carry + (95.0 - take.subject.arm_carry) * env)
            _orient(take, side, env, 0.0, -15.0)


def cross_arms(take: Take) -> None:
    """Arms folded over the chest and held: the forearms cross in front of the lower chest, each hand at the
    other arm's elbow (the mode names the arm on top), shoulders a little forward; weight shifts while
    waiting. vs cross hands in front ("stop": arms forward, crossed at the wrists) and hands up."""
    _begin(take)
    top = _side(take)
    k = _keys(take, 0.6, take.duration, 0.6, fit=0.92)
    env = _curve(take, k, 0, 1, 1, 1 if take.rng.uniform() < 0.6 else 0)  # many keep them folded to the end
    for side in SIDES:
        target = _at(take, -0.14, -0.07, 0.19) if side == top else _at(take, -0.1, -0.13, 0.17)
        skills.toward(take, side, env, target, elbow_hint=(0.8, -1.0, 0.3), bulge=0.06)
        _orient(take, side, env, 30.0 if side == top else -10.0)
        take[f"{side}_collar.protr"] += 6.0 * env
    sway = take.wander(3.0, 0.3) * env
    take["left_hip.abd"] += sway
    take["right_hip.abd"] -= sway
    take["pelvis.obliquity"] += 0.5 * sway


def arm_swings(take: Take) -> None:
    """Warm-up swings of straight arms (~0.9/s): ``forward and back`` (both arms together from ~40 degrees
    behind to above shoulder height in front, the knees bobbing with each), ``across the body`` (arms at
    shoulder height swung open to the sides and crossed in front), ``alternating`` (one forward as the
    other goes back)."""
    _begin(take)
    phase = timing.warped_phase(take.t, take.vary(0.9, 0.12) * take.tempo, take.rng)
    k = _keys(take, 0.4, take.duration, 0.4, fit=0.95)
    env = _curve(take, k, 0, 1, 1, 0)
    size = take.amp * take.vary(1.0, 0.1)
    swing = np.sin(2 * np.pi * phase)
    if take.mode == "across the body":
        for side in SIDES:  # plane 0 = out to the side, above 90 = across the chest
            take[f"{side}_shoulder.plane"] = 55.0 + 75.0 * size * swing
            take[f"{side}_shoulder.elev"] = 6.0 + 80.0 * env
            take[f"{side}_shoulder.rot"] = 0.0
            take[f"{side}_elbow.flex"] = 8.0
    else:
        for n, side in enumerate(SIDES):
            s = swing if take.mode == "forward and back" or n == 0 else -swing
            skills.set_arm(take, side, env * size * (30.0 + 70.0 * s), 8.0, elbow=10.0)
        if take.mode == "forward and back":
            bob = (0.5 + 0.5 * np.cos(4 * np.pi * phase)) * env
            skills.crouch(take, 12.0 * bob, 3.0 * bob)
        else:
            skills.turn_trunk(take, 8.0 * swing * env)


def cross_toe_touch(take: Take) -> None:
    """Alternate hand to the opposite foot: UESTC's standing toe touches (``alternating``: up between touches,
    the free arm raised) or its bent-over twist (``windmill``: bent over with the arms out, turning from one
    touch to the other)."""
    (uestc.bent_over_twist if take.mode == "windmill" else uestc.standing_toe_touches)(take)


def yawn(take: Take) -> None:
    """A yawn (~2.5 s): a deep breath in (chest up, shoulders up) as the head tips back ~25 degrees and the
    mouth opens: ``hand over mouth``: one palm comes up over the mouth for the yawn; ``with arm stretch``:
    the elbows lift out to the sides, bent, fists near the shoulders, in a short stretch, and the back
    arches. vs stretch oneself (A104: longer, arms straight up, on the toes), hush, sniff."""
    _begin(take)
    k = _keys(take, 0.7, take.uniform(0.9, 1.4), 0.7)
    env = _curve(take, k, 0, 1, 1, 0)
    skills.turn_head(take, -take.vary(26.0, 0.15) * env)
    take["spine3.flex"] -= 5.0 * env
    take["spine2.flex"] -= 4.0 * env
    for side in SIDES:
        take[f"{side}_collar.elev"] += 8.0 * env
    if take.mode == "with arm stretch":
        for side in SIDES:
            skills.set_arm(take, side, 25.0 * env + 3.0, take.vary(110.0, 0.08) * env + 6.0, rot=-60.0 * env,
                           elbow=take.subject.arm_carry + (110.0 - take.subject.arm_carry) * env)
            take[f"{side}_wrist.flex"] += -20.0 * env
        take["spine1.flex"] -= 5.0 * env
    else:
        side = _any_side(take, 0.2)
        spot = _FACE["mouth"]
        cover = _curve(take, [k[0] + 0.3 * (k[1] - k[0]), k[1], k[2], k[3]], 0, 1, 1, 0)
        skills.toward(take, side, cover, _face(take, "mouth", (0.0, 0.01, 0.02)), elbow_hint=spot.hint, bulge=0.06)
        _orient(take, side, cover, spot.pron, spot.flex)


def stretch_oneself(take: Take) -> None:
    """A single whole-body stretch after sitting (~3 s): ``overhead``: the hands come together and push
    straight up overhead, the trunk arches, up on the toes, held, then the arms sweep out and down
    sideways; ``arms out and back``: elbows at shoulder height drawn back (chest open, head back), then
    straightened out to the sides; ``side bends``: arms overhead, leaning to one side then the other. UESTC's
    overhead stretching repeats 2-3 times per clip, an exercise, not this; so it is not reused."""
    _begin(take)
    k = _keys(take, 0.7, take.uniform(0.9, 1.6), 0.8)
    env = _curve(take, k, 0, 1, 1, 0)
    if take.mode == "arms out and back":
        hold = _curve(take, k, 0, 1, 0.2, 0)
        out = _curve(take, k, 0, 0, 1, 0)
        for side in SIDES:
            take[f"{side}_shoulder.plane"] = -25.0 * hold + 5.0 * out
            take[f"{side}_shoulder.elev"] = 6.0 + 84.0 * env
            take[f"{side}_shoulder.rot"] = -50.0 * hold
            take[f"{side}_elbow.flex"] = take.subject.arm_carry * (1.0 - env) + 100.0 * hold + 5.0 * out
            take[f"{side}_collar.protr"] -= 15.0 * hold
        take["spine3.flex"] -= 8.0 * hold
        take["spine2.flex"] -= 6.0 * hold
        skills.turn_head(take, -15.0 * hold)
        return
    # Up in front to overhead with the arms a little across (hands together), down out to the sides.
    sweep = timing.minimum_jerk((take.t - k[2]) / max(k[3] - k[2], 1e-3))
    top = take.vary(166.0, 0.03)
    for side in SIDES:
        take[f"{side}_shoulder.plane"] = 125.0 - 125.0 * sweep
        take[f"{side}_shoulder.elev"] = 6.0 + (top - 6.0) * env
        take[f"{side}_shoulder.rot"] = 0.0
        take[f"{side}_elbow.flex"] = take.subject.arm_carry * (1.0 - env) + 5.0
        _orient(take, side, env, 60.0, -20.0)
    hold = _curve(take, k, 0, 1, 0.3, 0)
    if take.mode == "side bends":
        span = k[2] - k[1]
        bend = timing.keyframes(take.t, k[1] + span * np.array([0.0, 0.3, 0.5, 0.8, 1.0]), [0, 1, 0, -1, 0])
        skills.bend_trunk(take, take.choice((1.0, -1.0)) * take.vary(22.0, 0.15) * bend)
    else:
        for side in SIDES:
            take[f"{side}_ankle.dorsi"] -= 20.0 * hold  # up on the toes
    take["spine3.flex"] -= 6.0 * hold
    take["spine2.flex"] -= 6.0 * hold
    skills.turn_head(take, -12.0 * hold)


def blow_nose(take: Take) -> None:
    """Both hands hold a tissue at the nose (palms over it, hands together); two or three blows, each a
    small sharp forward jerk of the head and hands with the chest, then a pinching wipe pulling the tissue
    down and away, a fold of it at the chest, sometimes a second wipe. vs sneeze/cough (one hand or elbow,
    a big trunk jerk), sniff (palm up, one dip)."""
    _begin(take)
    spot = _FACE["nose palm"]
    k = _keys(take, 0.6, take.uniform(0.8, 1.2), 0.4, 0.5, 0.5)
    at_nose = _curve(take, k, 0, 1, 1, 0.6, 0, 0)
    blows = skills.bumps(take, k[1] + np.array([0.1, 0.45, 0.8])[: 2 + int(take.rng.uniform() < 0.5)], 0.18)
    blows = blows * (take.t < k[2])
    nose = _face(take, "nose palm", (-0.025, 0.0, 0.0))
    folded = _at(take, 0.06, -0.12, 0.28)
    wiped = nose + take.scale() * np.array([0.01, -0.06, 0.04])
    path = _path(take, k, [None, nose, nose, wiped, folded, None])
    path += take.scale() * blows[:, None] * np.array([0.0, -0.01, 0.015])
    for side in SIDES:
        skills.reach(take, side, path, elbow_hint=spot.hint)
        _orient(take, side, _curve(take, k, 0, 1, 1, 1, 1, 0), spot.pron, spot.flex)
    skills.turn_head(take, 6.0 * at_nose + 6.0 * blows)
    take["spine2.flex"] += 4.0 * blows


_PERFORMERS = {
    61: (put_on_headphone, STANCES),
    62: (take_off_headphone, STANCES),
    63: (shoot_at_the_basket, ("set shot", "jump shot")),
    64: (bounce_ball, ("right hand", "left hand", "both hands")),
    65: (tennis_bat_swing, ("forehand", "backhand", "serve")),
    66: (juggling_table_tennis_balls, ("cascade", "right hand", "left hand")),
    67: (hush, HANDS + ("right hand, seated",)),
    68: (flick_hair, HANDS),
    69: (thumb_up, HANDS + ("both hands",)),
    70: (thumb_down, HANDS + ("both hands",)),
    71: (make_ok_sign, HANDS),
    72: (make_victory_sign, HANDS + ("both hands",)),
    73: (staple_book, STANCES),
    74: (counting_money, STANCES),
    75: (cutting_nails, STANCES),
    76: (cutting_paper, ("right hand cuts", "left hand cuts")),
    77: (snapping_fingers, HANDS + ("both hands",)),
    78: (open_bottle, ("right hand twists", "left hand twists")),
    79: (sniff, HANDS + ("both hands",)),
    80: (ntu13.squat_down, tuple(ntu13.SQUATS)),
    81: (toss_a_coin, ("catch", "slap on hand back")),
    82: (fold_paper, ("in the air", "on a table")),
    83: (ball_up_paper, STANCES),
    84: (play_magic_cube, STANCES),
    85: (apply_cream_on_face, ("both hands", "one hand")),
    86: (apply_cream_on_hand_back, ("right rubs left", "left rubs right")),
    87: (put_on_bag, ("backpack", "one shoulder")),
    88: (take_off_bag, ("backpack", "one shoulder")),
    89: (put_something_into_a_bag, HANDS),
    90: (take_something_out_of_a_bag, HANDS),
    91: (open_a_box, ("flaps", "lid")),
    92: (move_heavy_objects, ("lift and carry", "lift and put down", "push")),
    93: (ntu13.shake_fist, ("right raised", "left raised", "right forward")),
    94: (throw_up_cap, ("both hands", "one hand")),
    95: (hands_up, ("straight", "bent elbows")),
    96: (cross_arms, ("right over left", "left over right")),
    97: (uestc.arm_circling, uestc.STANCES),
    98: (arm_swings, ("forward and back", "across the body", "alternating")),
    99: (ntu13.running_on_the_spot, tuple(ntu13.SPOT_RUNS)),
    100: (ntu13.butt_kicks, ("arms swinging", "hands behind")),
    101: (cross_toe_touch, ("alternating", "windmill")),
    102: (ntu13.side_kick, ("right", "left")),
    103: (yawn, ("hand over mouth", "with arm stretch")),
    104: (stretch_oneself, ("overhead", "arms out and back", "side bends")),
    105: (blow_nose, STANCES),
}

CLASSES = tuple(ActionClass(ACTION_NAMES[i], modes, perform) for i, (perform, modes) in _PERFORMERS.items())
