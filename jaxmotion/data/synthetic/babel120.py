"""BABEL-120's 120 action categories (ActFormer's long-tailed set of AMASS segments), procedurally.

The classes follow :data:`jaxmotion.data.formats.babel.CATEGORIES` (BABEL's own index, most frequent first) and
are named exactly as it names them. Each class is a ``perform(take)`` with 2-3 named style modes; where a
category matches a class of another stand-in its perform function is imported and run in one of its modes
(:func:`_as`), not copied: walk, run, jump, sit, stand up, pick up, throw, kick, squat, lunge, jumping jacks,
jump rope, dance, the stairs of "move up/down incline", wave, clap, point, hop, drink, the phone call,
stretches, punches and the ball games. BABEL's abstract categories ("t pose", "hand movements", "raising body
part", "forward movement", ...) get one concrete reading each, stated in the perform function's docstring.

**Class shares.** BABEL is long-tailed ("walk" has thousands of segments, the 120th category a few dozen), so the
class weights follow Zipf's law over BABEL's frequency rank: ``weight_i = 1 / (i + 1) ** ZIPF_EXPONENT`` with
exponent 1, the most frequent class 120 times the rarest.

**Timing.** 30 fps, clips of 1-8 s: one-off movements are placed at a random onset and compressed to fit short
clips (:func:`_keys`, down to :data:`MAX_SQUEEZE` of their natural duration; the reused one-off classes are sped
up by :func:`_hurried`), repeated ones cycle, locomotion keeps going.

**Distinctness.** Every class differs from every other in some joint's motion (where, which limb, what path,
what tempo, how the root travels); near groups are told apart deliberately, as the comment at each group says.
Wrist targets are points in the thorax (spine3) frame, side-normalised (x away from the midline, y up, z
forward), metres at template size times ``take.scale()``; targets on the floor are found on the body posed so
far (:func:`skills.posed`). Figures: MOTION_FACTS sections 2-4 (est. where the tables have none).
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from jaxmotion.data.formats.babel import CATEGORIES
from jaxmotion.data.synthetic import (cmu, humanact12, ntu1p_daily, ntu1p_extended, ntu13, skills, timing,
                                      uestc)
from jaxmotion.data.synthetic.engine import ActionClass
from jaxmotion.data.synthetic.take import SIDES, Take, other
from jaxmotion.geometry.skeletons import SMPL24

#: Class weights: Zipf's law over BABEL's frequency rank, ``1 / (rank + 1) ** ZIPF_EXPONENT``.
ZIPF_EXPONENT = 1.0
#: The most a one-off movement is sped up to fit a short clip; beyond it the clip ends mid-movement.
MAX_SQUEEZE = 0.5
_J = {name: i for i, name in enumerate(SMPL24.joint_names)}

# --- helpers ---------------------------------------------------------------------------------------------


def _as(perform: Callable[[Take], None], mode: str) -> Callable[[Take], None]:
    """Another class's ``perform`` run in its style ``mode`` (the take's own mode name is kept)."""

    def run(take: Take) -> None:
        own, take.mode = take.mode, mode
        try:
            perform(take)
        finally:
            take.mode = own

    run.__name__ = f"{perform.__name__}[{mode}]"
    return run


def _hurried(perform: Callable[[Take], None], busy: float) -> Callable[[Take], None]:
    """``perform`` (a one-off movement of about ``busy`` seconds) sped up, by at most 2x, to fit a short clip."""

    def run(take: Take) -> None:
        factor = float(np.clip(busy / take.tempo / (0.9 * take.duration), 1.0, 2.0))
        take.tempo *= factor
        try:
            perform(take)
        finally:
            take.tempo /= factor

    run.__name__ = perform.__name__
    return run


def _hand(take: Take, left_share: float = 0.15) -> str:
    """The acting side the mode names, else the right for most takes (left for ``left_share``)."""
    for side in SIDES:
        if side in take.mode:
            return side
    return "left" if take.rng.uniform() < left_share else "right"


def _leftward(side: str) -> float:
    """+1 for the left, -1 for the right: the sign of a twist, bend or heading change toward ``side``."""
    return 1.0 if side == "left" else -1.0


def _keys(take: Take, *durations: float, fit: float = 0.9) -> np.ndarray:
    """Key times (``len(durations) + 1``) of a one-off movement whose phases last about ``durations`` s (over the
    subject's tempo, varied 12%), compressed (down to :data:`MAX_SQUEEZE`) to fit ``fit`` of the clip, from a
    random onset."""
    d = np.array([take.vary(x, 0.12) for x in durations]) / take.tempo
    d = d * max(min(1.0, fit * take.duration / d.sum()), MAX_SQUEEZE)
    return take.onset(d.sum()) + np.concatenate([[0.0], np.cumsum(d)])


def _curve(take: Take, keys, *values) -> np.ndarray:
    return timing.keyframes(take.t, keys, values)


def _spell(take: Take, enter: float = 0.5, leave: float = 0.5, share=(0.65, 0.9)) -> np.ndarray:
    """``[T]`` 0 -> 1 over ``enter`` s, held for what makes ``share`` of the clip, back to 0 over ``leave`` s: the
    envelope of an activity that goes on for most of the clip."""
    enter, leave = take.vary(enter, 0.12) / take.tempo, take.vary(leave, 0.12) / take.tempo
    work = max(take.duration * take.uniform(*share) - enter - leave, 0.3)
    d = np.array([enter, work, leave])
    d = d * min(1.0, 0.97 * take.duration / d.sum())
    k = take.onset(d.sum(), margin=0.05) + np.concatenate([[0.0], np.cumsum(d)])
    return _curve(take, k, 0, 1, 1, 0)


def _at(take: Take, x: float, y: float, z: float, jitter: float = 0.01) -> np.ndarray:
    """``[3]`` a thorax-frame wrist target (template metres) scaled to the body, a little different per take."""
    return take.scale() * (np.array([x, y, z]) + take.rng.normal(0.0, jitter, 3))


def _lean(take: Take, degrees) -> None:
    """Lean the trunk forward ``degrees [T]`` from the hips and the spine, the legs staying vertical."""
    d = np.asarray(degrees, float)
    take["pelvis.tilt"] += 0.45 * d
    take["spine1.flex"] += 0.3 * d
    take["spine2.flex"] += 0.15 * d
    take["spine3.flex"] += 0.1 * d
    for side in SIDES:
        take[f"{side}_hip.flex"] += 0.45 * d


def _orient(take: Take, side: str, weight, pron: float, flex: float = 0.0) -> None:
    """Blend ``side``'s forearm twist toward ``pron`` and add wrist flexion ``flex``, by ``weight [T]``."""
    w = np.asarray(weight, float)
    take[f"{side}_elbow.pron"] += w * (pron - take[f"{side}_elbow.pron"])
    take[f"{side}_wrist.flex"] += w * flex


def _oscillation(take: Take, rate: float, *, wobble: float = 0.06) -> np.ndarray:
    """``[T]`` sin of a rhythm at ``rate`` /s (tempo-scaled, drifting a little)."""
    return np.sin(2 * np.pi * timing.warped_phase(take.t, rate * take.tempo, take.rng, wobble=wobble))


def _floor(take: Take, rot: np.ndarray, pos: np.ndarray) -> np.ndarray:
    """``[T]`` height of the floor in the root-at-origin frame of :func:`skills.posed`: the grounding puts the lowest sole
    point (heel or ball, :mod:`grounding`) of either foot on it."""
    lows = []
    for side in SIDES:
        ankle, toe = _J[f"{side}_ankle"], _J[f"{side}_foot"]
        off = take.subject.offsets[toe]
        heel = pos[:, ankle] + rot[:, ankle] @ np.array([off[0], off[1], -0.045 * take.scale()])
        lows.append(np.minimum(heel[:, 1], pos[:, toe, 1]))
    return np.minimum(*lows)


def _to_thorax(side: str, points: np.ndarray, rot: np.ndarray, pos: np.ndarray) -> np.ndarray:
    """``[T, 3]`` root-frame points -> side-normalised thorax-frame wrist targets for ``side``'s arm."""
    chest = _J["spine3"]
    local = np.einsum("tba,tb->ta", rot[:, chest], points - pos[:, chest])
    if side == "right":
        local[:, 0] *= -1.0
    return local


def _hands_to_floor(take: Take, weight, *, forward: float = 0.25, out: float = 0.05, lift=0.0,
                    sides=SIDES, hint=(0.5, -1.0, -0.3)) -> None:
    """Both hands (``sides``) down to the floor ``forward`` m ahead of and ``out`` m outside the shoulders
    (horizontally, template m), ``lift [T]`` m above it, blended in from the relaxed arm by ``weight [T]`` (call
    after the legs and trunk are posed)."""
    rot, pos = skills.posed(take)
    floor = _floor(take, rot, pos)
    heading = np.radians(take["pelvis.heading"])
    ahead = np.stack([np.sin(heading), np.zeros_like(heading), np.cos(heading)], -1)
    across = np.stack([np.cos(heading), np.zeros_like(heading), -np.sin(heading)], -1)  # the subject's left
    w = np.broadcast_to(np.asarray(weight, float), take.t.shape)
    s = take.scale()
    for side in sides:
        shoulder = pos[:, _J[f"{side}_shoulder"]]
        fw = np.broadcast_to(np.asarray(forward, float), take.t.shape)[:, None]
        point = shoulder + s * fw * ahead + s * out * _leftward(side) * across
        point[:, 1] = floor + 0.11 * s + np.asarray(lift, float)
        target = _to_thorax(side, point, rot, pos)
        rest = skills.relaxed_wrist(take)
        skills.reach(take, side, rest + w[:, None] * (target - rest), elbow_hint=hint)


_ARM_JOINTS = np.array([any(part in name for part in ("collar", "shoulder", "elbow", "wrist", "hand"))
                        for name in SMPL24.joint_names])


def _gait_blend(take: Take, weight, curves: skills.GaitCurves, *, cadence: float, size: float,
                arms: bool = True, phase: np.ndarray | None = None) -> np.ndarray:
    """A gait (legs, pelvis, trunk, foot support; the arms too if ``arms``) blended in where ``weight [T]`` is 1,
    standing as posed so far where it is 0: walking that starts or stops inside the clip. Returns its phase."""
    walker = Take(take.num_frames, take.fps, take.rng, take.subject, take.mode)
    walker.tempo, walker.amp = take.tempo, take.amp
    phase = skills.gait(walker, curves, cadence=cadence, size=size, phase=phase)
    w = np.broadcast_to(np.asarray(weight, float), take.t.shape)[:, None, None]
    take.angles[:, ~_ARM_JOINTS] += w * walker.angles[:, ~_ARM_JOINTS]
    if arms:
        take.angles[:, _ARM_JOINTS] = (1.0 - w) * take.angles[:, _ARM_JOINTS] + w * walker.angles[:, _ARM_JOINTS]
    take.contact[:] = (1.0 - w[:, :, 0]) * take.contact + w[:, :, 0] * walker.contact
    return phase


def _swing_clearance(take: Take, *, knee: float, dorsi: float) -> None:
    """More knee flexion and toes-up in each foot's swing (where it bears no weight), so that slow, short-stride
    gaits clear the floor."""
    for k, side in enumerate(SIDES):
        free = (1.0 - take.contact[:, k]) ** 2
        take[f"{side}_knee.flex"] += knee * free
        take[f"{side}_ankle.dorsi"] += dorsi * free


def _step_series(take: Take, start: float, count: int, reach: float, *, step: float, pause: float,
                 first: str, close: bool = True, lift: float = 1.0) -> float:
    """``count`` discrete steps of ``reach`` m (template size; negative: backwards), feet alternating from
    ``first``, each lasting ``step`` s with ``pause`` s of standing between, then (``close``) the trailing foot
    closes beside the other; returns the end time."""
    steps, t, side = [], start, first
    r = reach * take.scale()
    for _ in range(count):
        steps.append((t, step, side, r))
        t += step + pause
        side = other(side)
    if close and count:
        steps.append((t, step, side, 0.0))
        t += step
    skills.stance_steps(take, steps, lift=lift)
    for start_, dur, foot, reach_ in steps:  # toes up and a higher knee in the air: the foot clears the floor
        clear = timing.keyframes(take.t, start_ + dur * np.array([0.05, 0.4, 0.85]), [0.0, 1.0, 0.0])
        take[f"{foot}_ankle.dorsi"] += 12.0 * clear
        take[f"{foot}_knee.flex"] += (25.0 if reach_ < 0 else 12.0) * clear * lift
    return t


def _paced_steps(take: Take, step: float, pause: float, *, length: float) -> None:
    """Slow discrete steps of ``step`` s with ``pause`` s between, as many as fill the clip (squeezed into 95% of
    it), each ``length`` m (varied 12%), the first foot drawn at random; the feet do not close."""
    count = max(1, int(take.duration // (step + pause)))
    squeeze = min(1.0, 0.95 * take.duration / (count * (step + pause)))
    _step_series(take, take.uniform(0.0, 0.1), count, take.vary(length, 0.12), step=step * squeeze,
                 pause=pause * squeeze, first=take.choice(SIDES), close=False)


def _turn_steps(take: Take, start: float, angle: float, step: float) -> float:
    """Turn on the spot by ``angle`` degrees (+ = to the left) in small steps from ``start``: each step lifts one
    foot (the one on the turning side first) while the body pivots on the other; returns the end time."""
    n = max(2, int(np.ceil(abs(angle) / 60.0)))
    lead = "left" if angle > 0 else "right"
    times, values = [start], [0.0]
    for i in range(n):
        side = lead if i % 2 == 0 else other(lead)
        t0 = start + i * step
        env = timing.keyframes(take.t, [t0, t0 + 0.5 * step, t0 + step], [0.0, 1.0, 0.0])
        take[f"{side}_hip.flex"] += 15.0 * env
        take[f"{side}_knee.flex"] += 30.0 * env
        take[f"{side}_ankle.dorsi"] += 5.0 * env
        lifted = (take.t > t0 + 0.1 * step) & (take.t < t0 + 0.9 * step)
        take.contact[lifted, SIDES.index(side)] = 0.0
        take.contact[lifted, SIDES.index(other(side))] = 1.0
        times += [t0 + 0.12 * step, t0 + 0.88 * step]
        values += [values[-1], angle * (i + 1) / n]
    take["pelvis.heading"] += timing.keyframes(take.t, times, values)
    skills.turn_head(take, twist=0.25 * angle * timing.keyframes(take.t, [start - 0.2, start + 0.3, start + n * step,
                                                                start + n * step + 0.4], [0, 1, 1, 0]))
    return start + n * step


# --- locomotion --------------------------------------------------------------------------------------------
# Near group walk / jog / run / forward movement / stop / shuffle / sneak / limp: walk is a steady gait (1.8
# steps/s, full stride, arm swing; CMU's straight, curving and changing-speed paths); jog is the running
# pattern with flight at 2.4 steps/s and short strides (~2 m/s); run is the fast running gait (3 steps/s, long
# strides, more lean, ~4 m/s). Forward movement is a few slow discrete steps (one foot at a time, pauses, arms
# hanging without swing) and a stop; stop is a normal walk that brakes to standing inside the clip and stays;
# shuffle is small quick steps with bent knees and feet barely lifting; sneak is a slow crouched or tiptoe
# walk with the arms held up in front; limp is an asymmetric gait (one stiff, briefly loaded leg, hip hike).


def run(take: Take) -> None:
    """Running fast (HumanAct12's fast run: 3 steps/s, long strides, ~4 m/s); ``curving``: along a bend."""
    _as(humanact12.run, "fast")(take)
    if take.mode == "curving":
        skills.steer(take, take.choice((1.0, -1.0)) * take.uniform(25.0, 45.0) + take.wander(8.0, 0.3))


def jog(take: Take) -> None:
    """Jogging: the running pattern (flight phases) at ~2.4 steps/s with short strides and low arms, ~2 m/s;
    ``on the spot``: without travel (the feet land where they took off)."""
    skills.stand(take)
    slow = take.mode == "slow"
    skills.gait(take, skills.RUN, cadence=take.vary(2.25 if slow else 2.45, 0.05),
                size=take.vary(0.62 if slow else 0.75, 0.05))
    if take.mode == "on the spot":
        skills.in_place(take)
    for side in SIDES:
        take[f"{side}_elbow.flex"] -= 10.0


def forward_movement(take: Take) -> None:
    """A few slow, discrete steps forward (0.6-0.8 s each, one foot at a time, short pauses, arms hanging still),
    then the feet close and the body stands; ``careful``: shorter steps, looking down at the floor."""
    skills.stand(take)
    careful = take.mode == "careful"
    step, pause = take.vary(0.75 if careful else 0.62, 0.1) / take.tempo, take.uniform(0.05, 0.35)
    reach = take.vary(0.2 if careful else 0.3, 0.12) * take.amp
    count = int(np.clip((take.duration * take.uniform(0.55, 0.8)) // (step + pause), 1, 6))
    squeeze = min(1.0, 0.95 * take.duration / ((count + 1) * (step + pause)))
    step, pause = step * squeeze, pause * squeeze
    start = take.onset((count + 1) * (step + pause), margin=0.05)
    end = _step_series(take, start, count, reach, step=step, pause=pause, first=take.choice(SIDES))
    going = _curve(take, [start - 0.2, start + 0.2, end - 0.2, end + 0.3], 0, 1, 1, 0)
    if careful:
        skills.turn_head(take, flex=25.0 * going)
        _lean(take, 6.0 * going)
    for side in SIDES:
        take[f"{side}_elbow.flex"] += 8.0 * going


def backwards_movement(take: Take) -> None:
    """Moving backwards: ``walking backwards`` is the walking cycle run in reverse (toes land first, ~0.7 m/s,
    short strides, looking over a shoulder now and then); ``steps back`` is 2-5 separate steps back with pauses,
    arms still."""
    skills.stand(take)
    if take.mode == "steps back":
        step, pause = take.vary(0.6, 0.1) / take.tempo, take.uniform(0.1, 0.4)
        count = int(np.clip((take.duration * take.uniform(0.6, 0.85)) // (step + pause), 1, 5))
        squeeze = min(1.0, 0.95 * take.duration / ((count + 1) * (step + pause)))
        start = take.onset((count + 1) * (step + pause) * squeeze, margin=0.05)
        _step_series(take, start, count, -take.vary(0.25, 0.12), step=step * squeeze, pause=pause * squeeze,
                     first=take.choice(SIDES))
        return
    cadence = take.vary(1.55, 0.06)
    phase = -timing.warped_phase(take.t, cadence / 2.0 * take.tempo, take.rng, wobble=0.04)
    skills.gait(take, skills.WALK, cadence=cadence, size=take.vary(0.68, 0.06), phase=phase, knee_boost=(20.0, 0.78))
    for side, offset in (("left", 0.0), ("right", 0.5)):  # the toes lift as the foot reaches back
        take[f"{side}_ankle.dorsi"] += 10.0 * np.exp(3.0 * np.cos(2 * np.pi * (phase - offset - 0.8)) - 3.0)
    glance = skills.bumps(take, skills.beats(take, 2.5, jitter=0.3), take.vary(1.2, 0.15))
    skills.turn_head(take, twist=take.choice((1.0, -1.0)) * 45.0 * glance)
    take["spine1.flex"] += 3.0


def up_low_steps(take: Take) -> None:
    """Up a stepped ramp or low stairs (10-13 cm rises, 28-32 cm treads, est.), foot over foot at ~1.4 moves/s,
    the trunk upright: the engine's ground is one height per foot support, so a ramp is walked as its low
    steps. Unlike up stairs (CMU's high steps: 15-22 cm) the knees lift less and the pace is quicker."""
    skills.stand(take)
    rate = take.vary(1.4, 0.1) * take.tempo
    phase = timing.warped_phase(take.t, 0.5 * rate, take.rng, wobble=0.04, start=-0.5 * rate * take.uniform(0.1, 0.4))
    skills.stairs(take, phase, rise=take.uniform(0.1, 0.13), tread=take.uniform(0.28, 0.32))
    take["spine1.flex"] += take.vary(3.0, 0.3)


def sideways_movement(take: Take) -> None:
    """Side steps travelling to one side (~1 step/s): the leading foot lifts and steps out, the other closes."""
    skills.stand(take, heading=take.rng.normal(0.0, 15.0))
    phase = timing.warped_phase(take.t, take.vary(1.1, 0.12) * take.tempo, take.rng)
    skills.side_steps(take, phase, width=take.vary(16.0, 0.15), travel=1 if take.mode == "to the left" else -1)
    skills.turn_head(take, twist=(20.0 if take.mode == "to the left" else -20.0) * take.uniform(0.0, 1.0))


def stop(take: Take) -> None:
    """A normal walk that brakes to a stop inside the clip (the last step shortens, the trunk rocks back a
    little) and stands; ``from a jog``: from the running pattern."""
    skills.stand(take)
    jogging = take.mode == "from a jog"
    stop_at = take.duration * take.uniform(0.35, 0.6)
    brake = take.vary(0.45 if jogging else 0.55, 0.12)
    moving = _curve(take, [stop_at - brake, stop_at], 1.0, 0.0)
    if jogging:
        _gait_blend(take, moving, skills.RUN, cadence=take.vary(2.5, 0.05), size=take.vary(0.75, 0.05))
    else:
        _gait_blend(take, moving, skills.WALK, cadence=take.vary(1.85, 0.05), size=take.vary(1.0, 0.05))
    rock = _curve(take, [stop_at - 0.2, stop_at + 0.05, stop_at + 0.6], 0, 1, 0)
    take["spine1.flex"] -= 5.0 * rock
    take["pelvis.tilt"] -= 3.0 * rock


def shuffle(take: Take) -> None:
    """Shuffling: small quick steps (~2.8/s, strides a third of a walk's) on bent knees, the feet barely
    leaving the floor, arms close; ``sideways``: quick small side steps."""
    skills.stand(take)
    skills.crouch(take, take.vary(18.0, 0.2), 8.0)
    if take.mode == "sideways":
        phase = timing.warped_phase(take.t, take.vary(2.4, 0.1) * take.tempo, take.rng)
        skills.side_steps(take, phase, width=take.vary(8.0, 0.15), travel=take.choice((1, -1)))
        for side in SIDES:
            take[f"{side}_hip.flex"] -= 0.0
    else:
        skills.gait(take, skills.WALK, cadence=take.vary(2.7, 0.06), size=take.vary(0.55, 0.06))
    for side in SIDES:
        skills.set_arm(take, side, 10.0 + take.wander(3.0), 8.0, elbow=40.0)


def sneak(take: Take) -> None:
    """Sneaking: ``crouched`` (a slow walk, 1.3 steps/s, on bent knees ~40 with the trunk forward ~30 and the arms
    held bent in front) or on ``tiptoe`` (one slow, short step at a time on the balls of the feet, heels up, the
    arms out a little for balance, the head turning to listen), going on for the whole clip."""
    skills.stand(take)
    if take.mode == "crouched":
        skills.gait(take, skills.WALK, cadence=take.vary(1.3, 0.08), size=take.vary(0.75, 0.08))
        _swing_clearance(take, knee=10.0, dorsi=8.0)
        skills.crouch(take, take.vary(40.0, 0.15), take.vary(30.0, 0.15))
        skills.turn_head(take, flex=-20.0)
        for side in SIDES:
            skills.reach(take, side, _at(take, 0.12, -0.12, 0.3), elbow_hint=(0.6, -1.0, -0.2))
        return
    _paced_steps(take, take.vary(0.6, 0.1) / take.tempo, take.uniform(0.1, 0.3), length=0.2)
    for side in SIDES:
        take[f"{side}_ankle.dorsi"] -= take.vary(18.0, 0.15)
        skills.set_arm(take, side, 15.0, take.vary(30.0, 0.15), elbow=60.0)
    skills.crouch(take, 10.0, 8.0)
    skills.turn_head(take, twist=take.wander(20.0, 0.3))


def limp(take: Take) -> None:
    """Limping: a slow walk favouring one leg: on the painful leg the knee stays stiff in swing, its stance is
    brief and light (the weight hurries to the good leg) and the pelvis hikes to clear it; the trunk dips
    toward the good side."""
    skills.stand(take)
    bad = "left" if "left" in take.mode else "right"
    phase = skills.gait(take, skills.WALK, cadence=take.vary(1.45, 0.06), size=take.vary(0.8, 0.06))
    p = phase - (0.0 if bad == "left" else 0.5)
    swing = np.exp(3.0 * np.cos(2 * np.pi * (p - 0.8)) - 3.0)  # the bad leg's swing
    take[f"{bad}_knee.flex"] -= 30.0 * swing  # stiff: it swings nearly straight ...
    take[f"{bad}_hip.abd"] += 8.0 * swing  # ... circling out (circumduction)
    take["pelvis.obliquity"] += _leftward(bad) * 9.0 * swing  # with the hip hiked to clear the floor
    take[f"{bad}_ankle.dorsi"] += 12.0 * swing
    take[f"{other(bad)}_hip.abd"] += 7.0 * swing
    dip = np.exp(3.0 * np.cos(2 * np.pi * (p - 0.3)) - 3.0)  # mid-stance of the bad leg
    skills.bend_trunk(take, -_leftward(bad) * 8.0 * dip)


# Near group hop / jump / leap / skip: hop is quick small hops on one foot in place (the other held up); jump is
# a two-footed countermovement jump; leap is one long bound from one foot to the other with the legs split in
# the air and ~1.2 m of travel; skip is a travelling step-hop on alternate feet with a high knee and big arm
# swing.


def leap(take: Take) -> None:
    """A leap: a step to gather, push off the rear foot, fly ~0.4-0.5 s with the legs split (front leg reaching
    forward straight, rear leg trailing), land on the front foot and absorb; the mode names the leading leg."""
    skills.stand(take)
    lead = "left" if take.mode.startswith("left") else "right"
    rear = other(lead)
    height = take.vary(0.25, 0.15)
    flight = np.sqrt(8.0 * height / 9.81)
    k = _keys(take, 0.35, 0.25, 0.0, 0.25, 0.5, fit=0.95)  # gather, push, (take-off), ..., land, recover
    t_off = k[2]
    t_land = t_off + flight
    keys = [k[0], k[1], t_off, t_off + 0.45 * flight, t_land, t_land + 0.2, t_land + 0.2 + (k[5] - k[3])]

    def curve(*values):
        return timing.keyframes(take.t, keys, values)

    take[f"{lead}_hip.flex"] += curve(0, 25, 45, 70, 45, 30, 0)
    take[f"{lead}_knee.flex"] += curve(0, 40, 60, 15, 10, 45, 0)
    take[f"{lead}_ankle.dorsi"] += curve(0, 0, 0, -10, -15, 15, 0)
    take[f"{rear}_hip.flex"] += curve(0, 25, -20, -25, -20, -10, 0)
    take[f"{rear}_knee.flex"] += curve(0, 45, 10, 45, 50, 35, 0)
    take[f"{rear}_ankle.dorsi"] += curve(0, 15, -35, -30, -25, -10, 0)
    _lean(take, curve(0, 20, 15, 10, 15, 25, 0))
    for side in SIDES:  # the arm opposite the lead leg forward, the other back and out
        fwd = 1.0 if side == rear else -0.6
        skills.set_arm(take, side, 5.0 + fwd * curve(0, -20, 70, 90, 60, 20, 0), 10.0 + curve(0, 5, 25, 35, 30, 10, 0),
                       elbow=curve(15, 40, 20, 15, 25, 30, 15))
    airborne = (take.t > t_off) & (take.t < t_land)
    take.contact[:] = 0.5
    take.contact[(take.t > k[1]) & (take.t <= t_off), SIDES.index(lead)] = 0.0
    take.contact[(take.t > k[1]) & (take.t <= t_off), SIDES.index(rear)] = 1.0
    take.contact[airborne] = 0.0
    landing = (take.t >= t_land) & (take.t < keys[5])
    take.contact[landing, SIDES.index(lead)] = 1.0
    take.contact[landing, SIDES.index(rear)] = 0.0
    take.flight_speed = take.vary(1.2, 0.15) * take.scale() / flight
    take.flight_carry = 0.3


def skip(take: Take) -> None:
    """Skipping: a step-hop on each foot in turn (~1.4 strides/s), the free knee swinging up to ~70 degrees and
    the opposite arm high; ``forward`` travels, ``in place`` lands where it took off."""
    skills.stand(take)
    phase = timing.warped_phase(take.t, take.vary(1.35, 0.06) * take.tempo, take.rng, wobble=0.03)
    knots = (0.0, 0.12, 0.3, 0.42, 0.5, 0.7, 0.9)
    for side, offset in (("left", 0.0), ("right", 0.5)):
        p = phase - offset
        take[f"{side}_hip.flex"] += take.amp * timing.periodic(p, knots, [22, 18, 0, -12, -5, 70, 40])
        take[f"{side}_knee.flex"] += timing.periodic(p, knots, [15, 30, 12, 15, 60, 90, 35])
        take[f"{side}_ankle.dorsi"] += timing.periodic(p, knots, [0, 10, 5, -25, -20, -15, 0])
        cycle = np.mod(p, 1.0)
        take.contact[:, SIDES.index(side)] = ((cycle < 0.4) | (cycle > 0.97)).astype(float)
        swing = np.cos(2 * np.pi * (p - 0.75))  # forward with the other leg's knee lift
        skills.set_arm(take, side, 20.0 + 55.0 * take.amp * swing, 12.0, elbow=70.0 + 10.0 * swing)
    take["pelvis.tilt"] += 4.0
    if take.mode == "in place":
        skills.in_place(take)


# Near group turn / circular movement / spin / twist / walk (curving): turn changes the facing by 90-180 degrees
# once, on the spot, in small pivoting steps (~0.5 s each), then stands; circular movement keeps walking round a
# small circle (60-90 degrees/s, travelling), or circles straight arms; spin is one (or two) fast full turns in
# under a second on one foot with the other lifted and the arms in; twist turns only the trunk over still feet;
# walk's curving path bends at 15-35 degrees/s.


def circular_movement(take: Take) -> None:
    """``walk a circle``: walking round a small circle (radius ~0.8-1.2 m, 60-90 degrees/s, the trunk leaning
    in); ``arm circles``: HumanAct12's warm-up arm circles (both straight arms out to the sides, circling)."""
    if take.mode == "arm circles":
        _as(humanact12.warm_up, "arm circles")(take)
        return
    skills.stand(take)
    rate = take.choice((1.0, -1.0)) * take.uniform(60.0, 90.0)
    skills.gait(take, skills.WALK, cadence=take.vary(1.6, 0.06), size=take.vary(0.75, 0.06), turn=rate)
    skills.turn_head(take, twist=0.15 * rate)


def turn(take: Take) -> None:
    """Turning on the spot by 90-180 degrees in small steps (one foot lifted while the body pivots on the
    other), once; the mode names the direction."""
    skills.stand(take)
    angle = (1.0 if take.mode == "to the left" else -1.0) * take.uniform(90.0, 180.0)
    n = max(2, int(np.ceil(abs(angle) / 60.0)))
    step = min(take.vary(0.5, 0.1) / take.tempo, 0.9 * take.duration / n)
    _turn_steps(take, take.onset(n * step), angle, step)


def spin(take: Take) -> None:
    """A spin: a fast full turn (360 degrees in 0.7-1 s, ``two turns`` when the clip allows) pivoting on one
    foot, the other foot lifted beside the ankle and the arms pulled in to the chest."""
    skills.stand(take)
    turns = 2 if take.mode == "two turns" and take.duration > 2.2 else 1
    per = min(take.vary(0.85, 0.12) / take.tempo, 0.8 * take.duration / turns)
    prep = min(0.3, 0.1 * take.duration)
    t0 = take.onset(prep + turns * per + 0.2)
    t1 = t0 + prep
    sign = take.choice((1.0, -1.0))
    pivot = "left" if sign > 0 else "right"
    free = other(pivot)
    take["pelvis.heading"] += sign * 360.0 * turns * timing.keyframes(take.t, [t1, t1 + turns * per], [0.0, 1.0])
    on = _curve(take, [t0, t1, t1 + turns * per, t1 + turns * per + 0.3], 0, 1, 1, 0)
    take[f"{free}_hip.flex"] += 25.0 * on
    take[f"{free}_knee.flex"] += 60.0 * on
    take[f"{free}_hip.rot"] -= 15.0 * on
    skills.crouch(take, 12.0 * _curve(take, [t0, t1, t1 + 0.1], 0, 1, 0), 0.0)
    lifted = (take.t > t1 - 0.05) & (take.t < t1 + turns * per + 0.1)
    take.contact[lifted, SIDES.index(free)] = 0.0
    take.contact[lifted, SIDES.index(pivot)] = 1.0
    for side in SIDES:
        skills.toward(take, side, on, _at(take, 0.08, -0.12, 0.26), elbow_hint=(1.0, -0.3, 0.0))
    take[f"{pivot}_ankle.dorsi"] -= 10.0 * on  # up on the ball of the foot


def crawl(take: Take) -> None:
    """Crawling on hands and knees: the trunk about level (pelvis ~0.45 m up), thighs near vertical, shins on the
    floor, hands under the shoulders; diagonal limbs move together (~0.7 cycles/s), the head up; ``slow``
    crawls at half the pace with smaller moves."""
    skills.stand(take, heading=take.rng.normal(0.0, 20.0))
    slow = take.mode == "slow"
    phase = timing.warped_phase(take.t, take.vary(0.4 if slow else 0.65, 0.08) * take.tempo, take.rng, wobble=0.05)
    size = take.amp * (0.6 if slow else 1.0)
    take["pelvis.tilt"] += take.vary(78.0, 0.03)
    take["spine1.flex"] -= 5.0
    take["spine2.flex"] -= 5.0
    for side, offset in (("left", 0.0), ("right", 0.5)):
        p = phase - offset
        cycle = np.mod(p, 1.0)
        swing = timing.keyframes(cycle, [0.0, 0.6, 0.8, 1.0], [0.0, 0.0, 1.0, 0.0])  # knee lifts and moves forward
        drive = timing.keyframes(cycle, [0.0, 0.6, 1.0], [1.0, -1.0, 1.0])  # hip forward (+1) to back (-1)
        take[f"{side}_hip.flex"] += 80.0 + size * 12.0 * drive + 8.0 * swing
        take[f"{side}_knee.flex"] += 85.0 + 12.0 * swing
        take[f"{side}_ankle.dorsi"] -= 32.0
        take.contact[:, SIDES.index(side)] = 1.0 - np.minimum(1.0, 4.0 * swing)
    take.contact[take.contact.sum(axis=1) < 1e-3] = 0.5
    take["pelvis.obliquity"] += 2.0 * np.sin(2 * np.pi * phase)
    skills.turn_head(take, flex=-30.0)
    for side, offset in (("left", 0.5), ("right", 0.0)):  # each hand with the opposite knee
        cycle = np.mod(phase - offset, 1.0)
        reach = timing.keyframes(cycle, [0.0, 0.6, 0.8, 1.0], [0.15, -0.05, 0.06, 0.15]) * size
        lift = 0.07 * take.scale() * timing.keyframes(cycle, [0.6, 0.75, 0.9], [0.0, 1.0, 0.0])
        _hands_to_floor(take, 1.0, forward=0.05 + reach, out=0.03, lift=lift, sides=(side,), hint=(0.6, -0.3, -1.0))
        take[f"{side}_wrist.flex"] -= 60.0


# --- standing postures ---------------------------------------------------------------------------------------
# Near group stand / wait / t pose / a pose / poses / stances / balance: stand is relaxed standing with the arms
# hanging (sway, weight on one leg, or slow weight shifts); wait keeps the hands held (behind the back or
# clasped in front) with glances around; t pose and a pose hold the straight arms out at 90 and ~45 degrees;
# poses is a sequence of different held arm (and body) poses, changing every 1-2 s; stances hold a fighting,
# sports-ready or horse stance (legs bent, staggered or wide); balance stands on one leg or walks heel to toe
# with the arms out.


def stand(take: Take) -> None:
    """Standing: ``relaxed`` (sway, arms hanging), ``weight on one leg`` (the other knee bent, the pelvis dropping
    to its side), ``shifting weight`` (from one leg to the other every few seconds)."""
    skills.stand(take)
    if take.mode == "weight on one leg":
        loaded = take.choice(SIDES)
        free = other(loaded)
        take[f"{free}_knee.flex"] += take.vary(15.0, 0.2)
        take[f"{free}_hip.flex"] += 6.0
        take[f"{free}_ankle.dorsi"] -= 5.0
        shift = take.vary(5.0, 0.2)
        take["pelvis.obliquity"] -= _leftward(loaded) * shift
        take[f"{loaded}_hip.abd"] += shift
        take[f"{free}_hip.abd"] -= shift
        take.contact[:, SIDES.index(loaded)] = 0.85
        take.contact[:, SIDES.index(free)] = 0.15
        skills.bend_trunk(take, _leftward(loaded) * 3.0)
    elif take.mode == "shifting weight":
        shift = take.vary(5.0, 0.2) * _oscillation(take, take.vary(0.3, 0.2))
        take["pelvis.obliquity"] -= shift
        take["left_hip.abd"] += shift
        take["right_hip.abd"] -= shift
        take.contact[:, 0] = 0.5 + 0.35 * shift / max(np.abs(shift).max(), 1e-6)
        take.contact[:, 1] = 1.0 - take.contact[:, 0]
    else:
        for side in SIDES:
            take[f"{side}_ankle.dorsi"] += take.wander(1.0, 0.3)
    skills.turn_head(take, twist=take.wander(6.0, 0.2))


def _arms_out(take: Take, abd: float, *, pron: float) -> None:
    """Straight arms held out ``abd`` degrees from the sides: for the whole clip (``held``) or raised into it
    early in the clip and held to its end (``raised into it``)."""
    skills.stand(take, heading=take.rng.normal(0.0, 10.0))
    if take.mode == "held":
        env = np.ones(take.num_frames)
    else:
        rise = min(take.vary(0.7, 0.15) / take.tempo, 0.35 * take.duration)
        t0 = take.uniform(0.0, 0.2) * take.duration
        env = _curve(take, [t0, t0 + rise], 0.0, 1.0)
    for side in SIDES:
        skills.set_arm(take, side, take.vary(3.0, 0.5) * env + 3.0 * (1 - env) + take.wander(1.5),
                       take.vary(abd, 0.04) * env + 6.0 * (1 - env) + take.wander(1.5),
                       elbow=take.subject.arm_carry * (1 - env) + take.vary(4.0, 0.3) * env)
        _orient(take, side, env, pron)
    for side in SIDES:  # feet a little apart, standing straight
        take[f"{side}_hip.abd"] += 3.0


def t_pose(take: Take) -> None:
    """The T pose: both straight arms out sideways at shoulder height, palms down, held."""
    _arms_out(take, 88.0, pron=70.0)


def a_pose(take: Take) -> None:
    """The A pose: both straight arms ~45 degrees down and out from the sides, held."""
    _arms_out(take, 45.0, pron=30.0)


def poses(take: Take) -> None:
    """A sequence of held poses: every 1-2 s the arms (``whole body``: also the trunk and knees) move in ~0.4 s to
    a new random pose and hold it still."""
    skills.stand(take)
    whole = take.mode == "whole body"
    move, hold = take.vary(0.4, 0.15) / take.tempo, take.vary(1.2, 0.25)
    count = max(1, int(np.ceil(take.duration / (move + hold))))
    keys, t = [], take.uniform(0.0, 0.3) * min(take.duration, move + hold)
    for _ in range(count):
        keys += [t, t + move]
        t += move + take.vary(hold, 0.2)
    values = {}
    for side in SIDES:
        rest = [3.0, 6.0, take.subject.arm_carry]
        pts = [rest] + [[take.uniform(-20.0, 160.0), take.uniform(0.0, 110.0), take.uniform(0.0, 110.0)]
                        for _ in range(count)]
        values[side] = np.array([pts[0]] + [p for q in pts[1:] for p in (q, q)])[: len(keys)]
    for side in SIDES:
        v = timing.keyframes(take.t, keys, values[side])
        skills.set_arm(take, side, v[:, 0], v[:, 1], elbow=v[:, 2])
        take[f"{side}_wrist.flex"] += take.uniform(-20.0, 20.0)
    if whole:
        trunk = [[0.0, 0.0, 0.0]] + [[take.uniform(-15, 15), take.uniform(-25, 25), take.uniform(0, 35)]
                                     for _ in range(count)]
        v = timing.keyframes(take.t, keys, np.array([trunk[0]] + [p for q in trunk[1:] for p in (q, q)])[: len(keys)])
        skills.bend_trunk(take, v[:, 0])
        skills.turn_trunk(take, v[:, 1])
        skills.crouch(take, v[:, 2], 0.3 * v[:, 2])


def stances(take: Take) -> None:
    """Held stances: ``fighting stance`` (boxer's guard: feet staggered, knees bent, fists by the chin, a light
    bounce), ``ready stance`` (sports ready: feet wide, knees bent, trunk forward, hands before the waist,
    weight shifting), ``horse stance`` (martial arts: very wide, knees ~60, fists chambered at the hips)."""
    if take.mode == "fighting stance":
        skills.stand(take, heading=take.rng.normal(25.0, 10.0))
        lead = take.choice(SIDES)
        take[f"{lead}_hip.flex"] += 15.0
        take[f"{other(lead)}_hip.flex"] -= 12.0
        bounce = 4.0 * (1.0 + _oscillation(take, take.vary(1.8, 0.15)))
        skills.crouch(take, 15.0 + bounce, 6.0)
        take["spine2.twist"] -= 10.0 * _leftward(lead)
        guard = skills.landmark(take, "chin")
        for side in SIDES:
            shift = np.array([0.0, -0.03, 0.06]) if side == lead else np.array([-0.02, -0.05, -0.01])
            skills.reach(take, side, guard + shift,
                         elbow_hint=(0.4, -1.0, 0.0))
        skills.turn_head(take, twist=10.0 * _leftward(lead))
        return
    skills.stand(take)
    if take.mode == "horse stance":
        for side in SIDES:
            take[f"{side}_hip.abd"] += take.vary(22.0, 0.1)
            take[f"{side}_ankle.out"] += 10.0
        skills.crouch(take, take.vary(60.0, 0.1), 8.0)
        for side in SIDES:
            skills.reach(take, side, _at(take, 0.16, -0.3, 0.0), elbow_hint=(0.3, -0.3, -1.0))
            _orient(take, side, 1.0, -60.0)
        return
    for side in SIDES:  # ready stance
        take[f"{side}_hip.abd"] += take.vary(10.0, 0.15)
    skills.crouch(take, take.vary(35.0, 0.12), take.vary(25.0, 0.15), heel=6.0)
    shift = take.vary(4.0, 0.2) * _oscillation(take, take.vary(0.6, 0.2))
    take["left_hip.abd"] += shift
    take["right_hip.abd"] -= shift
    for side in SIDES:
        skills.reach(take, side, _at(take, 0.16, -0.22, 0.32), elbow_hint=(0.6, -1.0, -0.2))


def wait(take: Take) -> None:
    """Waiting: standing with the hands held (``hands behind back`` or ``hands clasped in front``), the weight
    shifting slowly, glancing around (the head turns 30-45 degrees every few seconds and back)."""
    skills.stand(take)
    if take.mode == "hands behind back":
        for side in SIDES:
            skills.reach(take, side, _at(take, 0.07, -0.4, -0.15), elbow_hint=(0.3, -0.2, -1.0))
    else:
        for side in SIDES:
            skills.reach(take, side, _at(take, 0.035, -0.42, 0.17), elbow_hint=(0.5, -1.0, -0.2))
    shift = take.wander(4.0, 0.25)
    take["pelvis.obliquity"] -= shift
    take["left_hip.abd"] += shift
    take["right_hip.abd"] -= shift
    glances = np.zeros(take.num_frames)
    for t0 in skills.beats(take, take.vary(2.8, 0.2), jitter=0.3):
        glances += take.choice((1.0, -1.0)) * take.uniform(30.0, 45.0) * skills.bumps(take, [t0], take.vary(1.4, 0.2))
    skills.turn_head(take, twist=glances, flex=take.wander(4.0, 0.3))


def balance(take: Take) -> None:
    """Balancing: ``one leg`` (standing on one leg, the other knee lifted, arms out sideways, wobbling and
    correcting) or ``beam walk`` (slow heel-to-toe steps on a line, arms out, wobbling)."""
    skills.stand(take)
    wobble = take.wander(5.0, 1.2)
    for side in SIDES:
        skills.set_arm(take, side, 5.0 + take.wander(6.0, 1.0), take.vary(70.0, 0.12) + _leftward(side) * 2.0 * wobble,
                       elbow=15.0)
    if take.mode == "one leg":
        free = take.choice(SIDES)
        stance = other(free)
        up = _curve(take, [0.1 * take.duration, 0.1 * take.duration + 0.5], 0.0, 1.0) if take.duration > 1.5 else 1.0
        skills.lift_knee(take, free, np.broadcast_to(up, take.t.shape), hip=take.vary(50.0, 0.2),
                         knee=take.vary(80.0, 0.15))
        take["pelvis.obliquity"] += _leftward(free) * 2.0 + 0.5 * wobble
        take[f"{stance}_hip.abd"] -= 3.0 + 0.4 * wobble
        take.contact[:, SIDES.index(stance)] = 1.0
        take.contact[:, SIDES.index(free)] = 0.0
        skills.bend_trunk(take, wobble)
    else:  # one careful step at a time along a line
        _paced_steps(take, take.vary(0.75, 0.1) / take.tempo, take.uniform(0.15, 0.4), length=0.16)
        for side in SIDES:
            take[f"{side}_hip.abd"] -= 4.0  # feet on one line
            skills.set_arm(take, side, 5.0 + take.wander(6.0, 1.0),
                           take.vary(75.0, 0.1) + _leftward(side) * 2.0 * wobble,
                           elbow=15.0)
        skills.bend_trunk(take, 0.8 * wobble)
        skills.turn_head(take, flex=25.0)


def lean(take: Take) -> None:
    """Leaning and holding it: ``sideways`` (the trunk bent 15-25 degrees to one side over a shifted hip, the arm
    on that side hanging away) or ``forward on a table`` (trunk forward ~35, both straight arms down to a table
    at hip height, weight on the hands)."""
    skills.stand(take)
    env = _spell(take, 0.7, 0.7, (0.7, 0.95))
    if take.mode == "sideways":
        sign = take.choice((1.0, -1.0))
        skills.bend_trunk(take, sign * take.vary(20.0, 0.2) * env)
        take["left_hip.abd"] -= sign * 5.0 * env
        take["right_hip.abd"] += sign * 5.0 * env
        take["pelvis.obliquity"] -= sign * 4.0 * env
        return
    _lean(take, take.vary(35.0, 0.15) * env)
    for side in SIDES:
        target = _at(take, 0.16, -0.42, 0.3)
        skills.toward(take, side, env, target, elbow_hint=(0.5, -1.0, -0.3))
        _orient(take, side, env, 70.0, -50.0)


def crossing_legs(take: Take) -> None:
    """Standing with the legs crossed: one foot steps across in front of the other and rests on its toes, the
    weight on the standing leg, held."""
    skills.stand(take)
    free = take.choice(SIDES)
    k = _keys(take, 0.6, take.duration, fit=0.95)
    env = _curve(take, k, 0.0, 1.0, 1.0)
    take[f"{free}_hip.abd"] -= 22.0 * env
    take[f"{free}_hip.flex"] += 8.0 * env
    take[f"{free}_knee.flex"] += 12.0 * env
    take[f"{free}_ankle.dorsi"] -= 20.0 * env
    take[f"{free}_hip.rot"] += 8.0 * env
    lifted = np.abs(np.gradient(env)) > 1e-3
    take.contact[lifted, SIDES.index(free)] = 0.0
    take.contact[lifted, SIDES.index(other(free))] = 1.0
    take.contact[~lifted & (env > 0.5), SIDES.index(free)] = 0.2
    take.contact[~lifted & (env > 0.5), SIDES.index(other(free))] = 0.8


def support(take: Take) -> None:
    """Supporting oneself: ``hand on wall`` (one arm straight out sideways at shoulder height, palm flat on a wall,
    leaning on it, the feet crossed) or ``hands on knees`` (bent over resting, hands on the knees, breathing
    hard)."""
    skills.stand(take)
    env = _spell(take, 0.6, 0.6, (0.7, 0.95))
    if take.mode == "hand on wall":
        side = _hand(take, 0.4)
        skills.set_arm(take, side, 5.0 * env, 3.0 + 85.0 * env, elbow=take.subject.arm_carry * (1 - env) + 12.0 * env)
        _orient(take, side, env, 0.0, -60.0)
        skills.bend_trunk(take, _leftward(side) * 10.0 * env)
        take[f"{side}_hip.abd"] -= 6.0 * env
        take[f"{other(side)}_hip.abd"] += 6.0 * env
        take["pelvis.obliquity"] += _leftward(side) * 3.0 * env
        return
    skills.crouch(take, take.vary(30.0, 0.15) * env, take.vary(55.0, 0.1) * env)
    breath = 0.5 + 0.5 * np.sin(2 * np.pi * take.vary(0.7, 0.1) * take.t)
    take["spine3.flex"] -= 4.0 * breath * env
    for side in SIDES:
        take[f"{side}_collar.elev"] += 6.0 * breath * env
        skills.set_arm(take, side, skills.trunk_pitch(take) * 0.7 + 18.0 * env, 8.0 + 6.0 * env,
                       elbow=take.subject.arm_carry + 10.0 * env)
    skills.turn_head(take, flex=-20.0 * env)


# Near group sit / kneel / crouch / squat / stand up: sit lowers onto a seat behind (thighs horizontal, trunk
# upright); kneel goes down onto one knee (or both) on the floor, the trunk upright; crouch folds low onto the
# balls of the feet with the trunk far forward and the hands touching the floor, and stays; squat is NTU's squat
# (trunk upright-ish, arms forward or hands on knees) or repeated UESTC squats; stand up rises from the seat.


def kneel(take: Take) -> None:
    """Kneeling down and staying: ``one knee`` (a step back with one leg, then down onto that knee, the front
    shin vertical) or ``both knees`` (upright kneeling, thighs vertical, shins and insteps on the floor)."""
    skills.stand(take)
    k = _keys(take, 0.5, 0.9, fit=0.7)
    down = _curve(take, k, 0.0, 0.3, 1.0)
    if take.mode == "one knee":
        front = take.choice(SIDES)
        rear = other(front)
        for ch, v in (("hip.flex", 95.0), ("knee.flex", 110.0), ("ankle.dorsi", 10.0)):
            take[f"{front}_{ch}"] += v * down
        for ch, v in (("hip.flex", -10.0), ("knee.flex", 75.0), ("ankle.dorsi", -20.0)):
            take[f"{rear}_{ch}"] += v * down
        take["pelvis.tilt"] += 5.0 * down
        moving = (take.t > k[0]) & (take.t < k[2])
        take.contact[moving, SIDES.index(front)] = 0.85
        take.contact[moving, SIDES.index(rear)] = 0.15
        take.contact[take.t >= k[2], SIDES.index(front)] = 0.6
        take.contact[take.t >= k[2], SIDES.index(rear)] = 0.4
        skills.set_arm(take, front, 3.0 + 40.0 * down, 8.0, elbow=take.subject.arm_carry + 40.0 * down)  # on the knee
    else:
        for side in SIDES:
            take[f"{side}_hip.flex"] += -5.0 * down
            take[f"{side}_knee.flex"] += 77.0 * down
            take[f"{side}_ankle.dorsi"] -= 50.0 * down
        take["spine1.flex"] += 12.0 * _curve(take, k, 0.0, 1.0, 0.0)
    skills.turn_head(take, flex=8.0 * down)


def crouch(take: Take) -> None:
    """Crouching low and staying: on the balls of the feet (knees ~130, heels up), the trunk far forward, the
    hands down on the floor in front (``hands on the floor``) or the forearms on the knees, looking around
    (``hiding``)."""
    skills.stand(take)
    k = _keys(take, 0.8, fit=0.5)
    down = _curve(take, k, 0.0, 1.0)
    skills.crouch(take, take.vary(130.0, 0.05) * down, take.vary(80.0 if take.mode == "hands on the floor" else 55.0,
                                                                  0.08) * down, heel=25.0 * down)
    if take.mode == "hands on the floor":
        _hands_to_floor(take, down, forward=0.08, out=-0.05)
        skills.turn_head(take, flex=-15.0 * down)
    else:
        for side in SIDES:
            skills.toward(take, side, down, _at(take, 0.1, -0.3, 0.3), elbow_hint=(0.6, -1.0, 0.0))
        skills.turn_head(take, flex=-20.0 * down, twist=take.wander(25.0, 0.4) * down)


def _on_body(take: Take, side: str, weights: dict, offset=(0.0, 0.0, 0.0)) -> np.ndarray:
    """``[T, 3]`` side-normalised thorax-frame target at a weighted mix of joint positions (``{joint: weight}``) of
    the pose built so far, plus ``offset`` (template m along the subject's facing: x left, y up, z forward)."""
    rot, pos = skills.posed(take)
    point = sum(w * pos[:, _J[j]] for j, w in weights.items())
    h = np.radians(take["pelvis.heading"])
    o = np.asarray(offset, float) * take.scale()
    point = point + np.stack([o[0] * np.cos(h) + o[2] * np.sin(h), np.full_like(h, o[1]),
                              -o[0] * np.sin(h) + o[2] * np.cos(h)], -1)
    return _to_thorax(side, point, rot, pos)


def _held_from(take: Take, rise: float, *, early: float = 0.6) -> np.ndarray:
    """``[T]`` 0 -> 1 over ``rise`` s (fitted to the clip) starting in the first ``early`` of the clip, then held."""
    rise = min(take.vary(rise, 0.15) / take.tempo, 0.4 * take.duration)
    t0 = take.uniform(0.05, early) * max(take.duration - rise, 0.0)
    return _curve(take, [t0, t0 + rise], 0.0, 1.0)


# --- arms and hands ----------------------------------------------------------------------------------------------
# Near group hand movements / interact with object / gesture / misc. abstract action / move misc. body part:
# hand movements drift the hands smoothly in front of the chest (no target, no rhythm); interacting with an
# object keeps the hands low at a work surface, one holding, one turning or striking rhythmically, the eyes
# down; gestures are a beckon (palm up, forearm curling at 1.5/s), a thumbs up or talking beats; misc. abstract
# action is a slow whole-arm (and trunk) wander, both sides, never still; move misc. body part moves one limb
# at a time between random postures.


def hand_movements(take: Take) -> None:
    """Hands moving in front of the body: wrists drifting smoothly ~5 cm about a point before the lower chest
    (``both hands`` or ``one hand``), the forearms turning, eyes on the hands."""
    skills.stand(take)
    env = _spell(take, 0.5, 0.5, (0.75, 0.97))
    hands = SIDES if take.mode == "both hands" else (_hand(take),)
    for side in hands:
        drift = take.scale() * timing.smooth_noise(take.t, take.rng, 0.05, max_hz=1.3, channels=3)
        skills.toward(take, side, env, _at(take, 0.12, -0.17, 0.3) + drift, elbow_hint=(0.6, -1.0, -0.3))
        take[f"{side}_elbow.pron"] = (20.0 + take.wander(35.0, 1.0)) * env
        take[f"{side}_wrist.flex"] += take.wander(15.0, 1.2) * env
    skills.turn_head(take, flex=12.0 * env)


def arm_movements(take: Take) -> None:
    """Whole-arm movements, both straight arms, repeated (~0.6/s): ``forward raises`` (down to ~120 degrees in
    front and back), ``side raises`` (out to the sides above shoulder height and back), ``alternating swings``
    (one arm up in front as the other swings back)."""
    skills.stand(take)
    phase = timing.warped_phase(take.t, take.vary(0.6, 0.12) * take.tempo, take.rng)
    env = _spell(take, 0.3, 0.3, (0.85, 1.0))
    size = take.amp * take.vary(1.0, 0.08)
    if take.mode == "alternating swings":
        swing = np.sin(2 * np.pi * phase)
        for n, side in enumerate(SIDES):
            swung = swing if n == 0 else -swing
            skills.set_arm(take, side, 5.0 + env * size * (30.0 + 75.0 * swung), 8.0, elbow=10.0)
        return
    up = skills.pulse(phase, 0.4, 0.1, 0.4) * env
    for side in SIDES:
        if take.mode == "forward raises":
            skills.set_arm(take, side, 5.0 + 115.0 * size * up, 8.0, elbow=8.0)
        else:
            skills.set_arm(take, side, 5.0, 6.0 + 105.0 * size * up, elbow=8.0)


def _raised_limb(take: Take, env: np.ndarray, *, sideways: bool = False) -> None:
    """One arm raised forward-up to ~150 degrees (``arm``; ``sideways``: up the side to ~160) or one leg raised
    (``leg``: straight forward ~45 degrees; ``sideways``: the knee lifted to hip height), as ``env [T]`` goes 0 -> 1."""
    side = _hand(take, 0.3)
    if "leg" in take.mode:
        take[f"{side}_hip.flex"] += take.vary(75.0 if sideways else 45.0, 0.12) * env
        take[f"{side}_knee.flex"] += (90.0 if sideways else 8.0) * env
        take[f"{side}_ankle.dorsi"] -= 10.0 * env
        take[f"{other(side)}_knee.flex"] += 5.0 * env
        take.contact[:, SIDES.index(side)] *= 1.0 - timing.minimum_jerk(env / 0.15)
        take.contact[:, SIDES.index(other(side))] = 1.0 - take.contact[:, SIDES.index(side)]
        for arm in SIDES:
            skills.set_arm(take, arm, 5.0, 8.0 + 25.0 * env, elbow=take.subject.arm_carry)
        take["spine1.flex"] -= 5.0 * env
    elif sideways:
        skills.set_arm(take, side, 3.0 + 10.0 * env, 6.0 + take.vary(155.0, 0.05) * env,
                       elbow=take.subject.arm_carry * (1 - env) + 5.0)
        _orient(take, side, env, -60.0)
    else:
        skills.set_arm(take, side, 3.0 + take.vary(150.0, 0.06) * env, 6.0 + 10.0 * env,
                       elbow=take.subject.arm_carry * (1 - env) + 5.0)
        _orient(take, side, env, 0.0)


def raising_body_part(take: Take) -> None:
    """Raising one arm (forward and up) or one leg (straight, forward), once, and keeping it up."""
    skills.stand(take)
    _raised_limb(take, _held_from(take, 0.7))


def lowering_body_part(take: Take) -> None:
    """Lowering one arm (down the side from overhead) or one leg (a knee lifted to hip height) to rest, once: the
    limb is up when the clip starts."""
    skills.stand(take)
    _raised_limb(take, 1.0 - _held_from(take, 0.8), sideways=True)


def to_lower_a_body_part(take: Take) -> None:
    """Lowering symmetrically, once: ``both arms down`` (both straight arms from forward horizontal down to the
    sides) or ``head down`` (the head and upper back bowing to look at the floor, and staying)."""
    skills.stand(take)
    down = _held_from(take, 0.9)
    if take.mode == "both arms down":
        for side in SIDES:
            skills.set_arm(take, side, 3.0 + take.vary(88.0, 0.06) * (1 - down), 6.0,
                           elbow=5.0 + (take.subject.arm_carry - 5.0) * down)
            _orient(take, side, 1 - down, 60.0)
    else:
        skills.turn_head(take, flex=take.vary(40.0, 0.15) * down)
        take["spine3.flex"] += 8.0 * down
        take["spine2.flex"] += 8.0 * down


def gesture(take: Take) -> None:
    """Gestures: ``beckon`` (come here: the forearm forward at waist height, palm up, curling up toward the body
    and out again ~1.3/s), ``thumbs up`` (NTU's), ``talking`` (one or both hands making short downward beats at
    chest height, palms up, at irregular times)."""
    if take.mode == "thumbs up":
        _as(ntu1p_extended.thumb_up, take.choice(("right hand", "both hands")))(take)
        return
    skills.stand(take)
    env = _spell(take, 0.4, 0.4, (0.6, 0.9))
    side = _hand(take)
    if take.mode == "beckon":
        curl = 0.5 - 0.5 * _oscillation(take, take.vary(1.3, 0.12))
        skills.set_arm(take, side, 3.0 + 25.0 * env, 10.0 + 10.0 * env,
                       elbow=take.subject.arm_carry + env * (25.0 + 80.0 * curl))
        _orient(take, side, env, -75.0, 30.0 * curl)
        skills.turn_head(take, twist=_leftward(side) * 5.0 * env)
        return
    for arm in (SIDES if take.rng.uniform() < 0.6 else (side,)):
        beats = skills.bumps(take, skills.beats(take, take.vary(0.8, 0.2), jitter=0.35), take.vary(0.3, 0.15))
        target = _at(take, 0.2, -0.15, 0.3) + take.scale() * np.stack(
            [0.04 * beats, -0.06 * beats, 0.05 * beats], -1)
        skills.toward(take, arm, env, target, elbow_hint=(0.7, -1.0, -0.2))
        _orient(take, arm, env, -60.0)
    skills.turn_head(take, flex=-5.0 * env, twist=take.wander(8.0, 0.4))


# Near group wave / greet / gesture / communicate: wave swings the raised forearm side to side (NTU's waves);
# greet is a handshake (hand forward at waist height pumping up and down) or a still raised hand with a nod;
# communicate (vocalise) cups one or both hands at the mouth and leans into each call.


def greet(take: Take) -> None:
    """Greeting: ``handshake`` (the right hand forward at waist height, pumped up and down ~3/s for ~1.5 s, a
    small lean and nod) or ``raised hand`` (a hand raised beside the head, palm forward, held still, a nod)."""
    skills.stand(take)
    if take.mode == "handshake":
        k = _keys(take, 0.8, 1.5, 0.7)
        env = _curve(take, k, 0, 1, 1, 0)
        shaking = _curve(take, [k[1], k[1] + 0.15, k[2] - 0.15, k[2]], 0, 1, 1, 0)
        pump = 0.03 * take.scale() * shaking * _oscillation(take, take.vary(3.0, 0.15))
        target = _at(take, 0.06, -0.22, 0.47) + np.stack([0 * pump, pump, 0 * pump], -1)
        skills.toward(take, "right", env, target, elbow_hint=(0.5, -1.0, -0.3))
        _orient(take, "right", env, -10.0)
        _lean(take, 8.0 * env)
        skills.turn_head(take, flex=8.0 * shaking)
        return
    side = _hand(take)
    k = _keys(take, 0.5, 1.3, 0.5)
    env = _curve(take, k, 0, 1, 1, 0)
    skills.set_arm(take, side, 3.0 + 20.0 * env, 6.0 + 110.0 * env, rot=-70.0 * env,
                   elbow=take.subject.arm_carry + (55.0 - take.subject.arm_carry) * env)
    _orient(take, side, env, -20.0)
    skills.turn_head(take, flex=12.0 * skills.bumps(take, [k[1]], 0.6))


def communicate(take: Take) -> None:
    """Calling out: ``both hands`` (or ``one hand``) cupped at the mouth, the head up a little, the body leaning
    into each call (every ~1.5 s)."""
    skills.stand(take)
    env = _spell(take, 0.5, 0.5, (0.7, 0.95))
    calls = skills.bumps(take, skills.beats(take, take.vary(1.5, 0.15), jitter=0.25), take.vary(0.6, 0.15)) * env
    hands = SIDES if take.mode == "both hands" else (_hand(take),)
    for side in hands:
        skills.toward(take, side, env, skills.landmark(take, "mouth") + take.scale() * np.array([0.05, 0.0, 0.02]),
                      elbow_hint=(1.0, -0.5, 0.2))
        _orient(take, side, env, -40.0)
    _lean(take, 10.0 * calls)
    skills.turn_head(take, flex=-12.0 * env - 5.0 * calls, twist=take.wander(10.0, 0.3) * env)


# Near group clap / rub / spread / shake: clap parts and meets the palms sideways (NTU's); rub slides palm on
# palm, never parting (NTU's); spread opens the arms from together in front out wide to the sides (or the feet
# apart) and holds; shake flaps loose hands at ~5/s with the forearms forward, or shimmies the shoulders.


def spread(take: Take) -> None:
    """Spreading: ``arms`` (both hands together in front of the chest, then swept open wide, palms up, a little
    below shoulder height and forward of the sides, held) or ``legs`` (each foot in turn steps out sideways to a
    wide stance, held)."""
    skills.stand(take)
    if take.mode == "legs":
        k = _keys(take, 0.5, 0.1, 0.5, fit=0.8)
        first = take.choice(SIDES)
        for n, side in enumerate((first, other(first))):
            a, b = k[2 * n], k[2 * n + 1]
            out = _curve(take, [a, b], 0.0, 1.0)
            lift = _curve(take, [a, 0.5 * (a + b), b], 0.0, 1.0, 0.0)
            take[f"{side}_hip.abd"] += take.vary(14.0, 0.15) * out
            take[f"{side}_hip.flex"] += 12.0 * lift
            take[f"{side}_knee.flex"] += 25.0 * lift
            lifted = (take.t > a + 0.1 * (b - a)) & (take.t < b - 0.1 * (b - a))
            take.contact[lifted, SIDES.index(side)] = 0.0
            take.contact[lifted, SIDES.index(other(side))] = 1.0
        return
    k = _keys(take, 0.5, 0.3, 0.7, fit=0.8)
    front = _curve(take, k, 0, 1, 1, 0)
    wide = _curve(take, k, 0, 0, 0, 1)
    for side in SIDES:  # from straight ahead to wide open (~70 out, ~30 forward: not the T pose), palms up
        skills.set_arm(take, side, 3.0 + 82.0 * front + 30.0 * wide, 6.0 - 6.0 * front + 65.0 * wide,
                       elbow=take.subject.arm_carry * (1 - front - wide) + 10.0 * front + 20.0 * wide)
        _orient(take, side, front + wide, -60.0)
    take["spine3.flex"] -= 5.0 * wide


def shake(take: Take) -> None:
    """Shaking: ``shake out hands`` (forearms forward, both loose hands flapping ~5/s in bursts) or ``shimmy``
    (the shoulders alternately forward and back ~3/s, the knees bouncing)."""
    skills.stand(take)
    env = _spell(take, 0.3, 0.3, (0.7, 0.95))
    if take.mode == "shimmy":
        osc = _oscillation(take, take.vary(3.0, 0.1))
        take["spine3.twist"] += 10.0 * osc * env
        take["spine2.twist"] += 6.0 * osc * env
        for side in SIDES:
            take[f"{side}_collar.protr"] += _leftward(side) * 12.0 * osc * env
            skills.set_arm(take, side, 20.0 * env, 30.0 * env + 6.0, elbow=take.subject.arm_carry + 60.0 * env)
        skills.crouch(take, (10.0 + 6.0 * np.abs(osc)) * env, 3.0 * env)
        return
    burst = np.clip(0.8 + take.wander(0.7, 0.5), 0.0, 1.0) * env
    for side in SIDES:
        flap = _oscillation(take, take.vary(5.0, 0.12))
        skills.set_arm(take, side, 3.0 + 30.0 * env, 6.0 + 12.0 * env, elbow=take.subject.arm_carry + 65.0 * env)
        take[f"{side}_wrist.flex"] += 35.0 * flap * burst
        take[f"{side}_elbow.pron"] += 20.0 * flap * burst
        take[f"{side}_elbow.flex"] += 8.0 * flap * burst


def wrist_flexing(take: Take) -> None:
    """Wrists bending up and down together (~1/s, +-50 degrees), the forearms held forward, palms down."""
    skills.stand(take)
    env = _spell(take, 0.4, 0.4, (0.75, 0.97))
    bend = _oscillation(take, take.vary(1.0, 0.15))
    for side in SIDES:
        skills.set_arm(take, side, 3.0 + 30.0 * env, 6.0 + 6.0 * env, elbow=take.subject.arm_carry + 70.0 * env)
        _orient(take, side, env, 75.0, 50.0 * bend)


def shrug(take: Take) -> None:
    """A shrug (once or twice): the shoulders up ~25 degrees quickly, held, down; ``palms up``: the forearms
    open outward, palms up, the head tilting."""
    skills.stand(take)
    n = 2 if take.duration > 3.0 and take.rng.uniform() < 0.4 else 1
    k = _keys(take, *([0.25, 0.45, 0.45, 0.3] * n), fit=0.85)
    env = sum(_curve(take, k[4 * i: 4 * i + 4], 0, 1, 1, 0) for i in range(n))
    for side in SIDES:
        take[f"{side}_collar.elev"] += take.vary(25.0, 0.15) * env
        if take.mode == "palms up":
            skills.set_arm(take, side, 3.0 + 12.0 * env, 6.0 + 20.0 * env, rot=-30.0 * env,
                           elbow=take.subject.arm_carry + 75.0 * env)
            _orient(take, side, env, -75.0)
    skills.turn_head(take, bend=take.choice((1.0, -1.0)) * 10.0 * env, flex=-5.0 * env)


# Near group punch / hit / knock / tap / press / martial art / sports move: punch is straight punches at shoulder
# height (UESTC's, or boxing's jab-cross); hit is a big arm swing (hammer fist down from overhead, or a
# backhand swipe across); knock is a raised fist making small quick forearm taps at a door (face height) or a
# table; tap is a hand patting someone's shoulder at arm's length or fingertips tapping a screen; press pushes
# and holds (a button at arm's length, or both hands against a door, leaning in); martial art is a horse-stance
# kata of crisp hip-chambered punches, or side kicks; sports move is a tennis stroke.


def knock(take: Take) -> None:
    """Knocking on a door: ``knuckles`` (the fist raised at face height ahead, two bursts of 2-4 quick knocks, ~4/s,
    the forearm tapping ~8 cm) or ``pound`` (the side of the fist hammering at head height, ~2.5/s, ~12 cm, the
    forearm upright)."""
    skills.stand(take)
    side = _hand(take)
    k = _keys(take, 0.6, 2.0, 0.6)
    env = _curve(take, k, 0, 1, 1, 0)
    door = take.mode == "knuckles"
    base = _at(take, 0.1, 0.16, 0.36) if door else take.head_point() + _at(take, 0.12, 0.05, 0.32)
    taps = np.zeros(take.num_frames)
    rate = take.vary(4.0 if door else 2.5, 0.15)
    for start in (k[1] + 0.1 * (k[2] - k[1]), k[1] + 0.55 * (k[2] - k[1])):
        n = int(take.rng.integers(2, 5))
        on = (take.t >= start) & (take.t < start + n / rate)
        taps += on * (0.5 - 0.5 * np.cos(2 * np.pi * rate * (take.t - start)))
    direction = np.array([0.0, 0.0, 1.0]) if door else np.array([0.0, -0.6, 0.8])
    target = base + (0.08 if door else 0.12) * take.scale() * taps[:, None] * direction
    skills.toward(take, side, env, target, elbow_hint=(0.6, -1.0, -0.2) if door else (0.8, -0.8, -0.2))
    _orient(take, side, env, 20.0 if door else -10.0, -15.0)
    skills.turn_head(take, flex=-5.0 * env)


def tap(take: Take) -> None:
    """Tapping: ``shoulder`` (the hand out to the side at shoulder height, patting the shoulder of someone beside
    2-4 times at ~2.5/s, the head turned to them) or ``screen`` (fingertips tapping quickly on a screen held low
    before the chest, moving to a new spot between taps)."""
    skills.stand(take)
    side = _hand(take)
    k = _keys(take, 0.6, 1.6, 0.6)
    env = _curve(take, k, 0, 1, 1, 0)
    working = _curve(take, [k[1], k[1] + 0.1, k[2] - 0.1, k[2]], 0, 1, 1, 0)
    if take.mode == "shoulder":
        pats = (0.5 - 0.5 * np.cos(2 * np.pi * take.vary(2.5, 0.15) * (take.t - k[1]))) * working
        target = _at(take, 0.5, 0.02, 0.25) + 0.04 * take.scale() * pats[:, None] * np.array([0.0, -1.0, 0.0])
        skills.toward(take, side, env, target, elbow_hint=(0.2, -1.0, -0.4))
        _orient(take, side, env, 70.0, 10.0 * pats)
        skills.turn_head(take, twist=_leftward(side) * 35.0 * env)
        skills.turn_trunk(take, _leftward(side) * 10.0 * env)
        return
    taps = skills.bumps(take, skills.beats(take, take.vary(0.45, 0.2), jitter=0.3), 0.2) * working
    spot = take.scale() * timing.smooth_noise(take.t, take.rng, 0.04, max_hz=0.6, channels=3)
    spot *= np.array([1.0, 1.0, 0.2])
    target = _at(take, 0.1, -0.2, 0.3) + spot + 0.03 * take.scale() * taps[:, None] * np.array([0.0, -0.6, 0.8])
    skills.toward(take, side, env, target, elbow_hint=(0.5, -1.0, -0.3))
    _orient(take, side, env, 40.0, -10.0 - 15.0 * taps)
    skills.turn_head(take, flex=10.0 * env)


def press_something(take: Take) -> None:
    """Pressing: ``button`` (one arm reaching straight ahead at shoulder height, pressing 3 cm and holding ~0.6 s,
    once or twice) or ``push with both hands`` (both palms against a door at chest height, one foot back, leaning
    in hard and holding)."""
    skills.stand(take)
    if take.mode == "button":
        side = _hand(take)
        n = 2 if take.duration > 3.0 and take.rng.uniform() < 0.5 else 1
        k = _keys(take, *([0.5, 0.15, 0.6, 0.5] * n))
        env = sum(_curve(take, k[4 * i: 4 * i + 5], 0, 1, 1, 1, 0) for i in range(n))
        push = sum(_curve(take, k[4 * i + 1: 4 * i + 4], 0, 1, 1) * _curve(take, k[4 * i + 3: 4 * i + 5], 1, 0)
                   for i in range(n))
        target = take.shoulder_point() + _at(take, -0.04, 0.08, 0.5) + 0.03 * take.scale() * push[:, None] * np.array(
            [0.0, 0.0, 1.0])
        skills.toward(take, side, np.minimum(env, 1.0), target, elbow_hint=(0.5, -1.0, -0.3))
        _orient(take, side, np.minimum(env, 1.0), 60.0, -20.0)
        return
    back = take.choice(SIDES)
    k = _keys(take, 0.6, take.duration, 0.5, fit=0.95)
    env = _curve(take, k, 0, 1, 1, 0)
    take[f"{back}_hip.flex"] -= 15.0 * env
    take[f"{other(back)}_hip.flex"] += 12.0 * env
    take[f"{other(back)}_knee.flex"] += 15.0 * env
    take[f"{back}_ankle.dorsi"] += 10.0 * env
    take["pelvis.tilt"] += 15.0 * env
    effort = 0.5 + 0.5 * _oscillation(take, take.vary(0.8, 0.2))
    for side in SIDES:
        target = _at(take, 0.15, 0.02, 0.42) + 0.03 * take.scale() * effort[:, None] * np.array([0.0, 0.0, 1.0])
        skills.toward(take, side, env, target, elbow_hint=(0.8, -1.0, -0.3))
        _orient(take, side, env, 60.0, -50.0)
    skills.turn_head(take, flex=-10.0 * env)


def hit(take: Take) -> None:
    """Hitting with a big arm swing, once or twice: ``downward strike`` (the fist raised overhead, then driven down
    fast to waist height, the trunk folding into it) or ``backhand swipe`` (the arm across the chest, then whipped
    out sideways at shoulder height, the trunk turning)."""
    skills.stand(take)
    side = _hand(take)
    n = 2 if take.duration > 3.2 and take.rng.uniform() < 0.5 else 1
    k = _keys(take, *([0.45, 0.15, 0.18, 0.45] * n), fit=0.85)

    def curve(*values):
        return sum(_curve(take, k[4 * i: 4 * i + 5], *values) for i in range(n))

    if take.mode == "downward strike":
        skills.set_arm(take, side, 3.0 + curve(0, 160, 160, 45, 0), 6.0 + curve(0, 15, 15, 10, 0),
                       elbow=take.subject.arm_carry + curve(0, 80, 80, 5, 0))
        take["spine1.flex"] += curve(0, -8, -8, 18, 0)
        take["spine2.flex"] += curve(0, -4, -4, 10, 0)
        skills.crouch(take, curve(0, 5, 5, 18, 0), 0.0)
        _orient(take, side, curve(0, 1, 1, 1, 0), 0.0, -15.0)
    else:
        take[f"{side}_shoulder.plane"] = curve(0, 125, 125, 5, 0) + 90.0 * (1 - curve(0, 1, 1, 1, 0))
        take[f"{side}_shoulder.elev"] = 8.0 + curve(0, 75, 75, 82, 0)
        take[f"{side}_shoulder.rot"] = 0.0
        take[f"{side}_elbow.flex"] = take.subject.arm_carry + curve(0, 70, 70, 0, 0)
        skills.turn_trunk(take, _leftward(side) * curve(0, -25, -25, 25, 0))
    skills.turn_head(take, flex=curve(0, 0, 0, 10, 0))


def kata(take: Take) -> None:
    """Martial-arts kata: a wide low stance (knees ~45), fists chambered at the hips, crisp straight punches at
    chest height (out in ~0.12 s) alternating every ~0.7 s while the other fist pulls back to the hip, a shout-like
    tension of the trunk on each."""
    skills.stand(take)
    for side in SIDES:
        take[f"{side}_hip.abd"] += take.vary(16.0, 0.1)
    skills.crouch(take, take.vary(45.0, 0.12), 8.0)
    times = skills.beats(take, take.vary(0.75, 0.12), jitter=0.1)
    chamber, out = _at(take, 0.16, -0.3, 0.0), _at(take, 0.03, -0.02, 0.52)
    for n, side in enumerate(SIDES):
        mine = times[(np.arange(len(times)) % 2 == n)]
        strike = np.zeros(take.num_frames)
        for t0 in mine:
            strike = np.maximum(strike, timing.keyframes(take.t, [t0, t0 + 0.12, t0 + 0.6, t0 + 0.8], [0, 1, 1, 0]))
        skills.reach(take, side, chamber + strike[:, None] * (out - chamber), elbow_hint=(0.3, -0.6, -1.0))
        take[f"{side}_elbow.pron"] = -60.0 + 140.0 * strike  # the fist turns over as it lands
        skills.turn_trunk(take, -_leftward(side) * 10.0 * strike)
    skills.turn_head(take, flex=-5.0)


def protect(take: Take) -> None:
    """Protecting oneself, quickly and held: ``cover head`` (both hands over the head, elbows forward, ducking a
    little, head down) or ``shield face`` (forearms up crossed before the face, leaning back and turning away)."""
    skills.stand(take)
    env = _curve(take, _keys(take, 0.3, fit=0.4), 0.0, 1.0)
    if take.mode == "cover head":
        for side in SIDES:
            skills.toward(take, side, env, take.head_point() + _at(take, 0.07, 0.1, 0.03), elbow_hint=(0.4, -0.2, 1.0))
            _orient(take, side, env, 0.0)
        skills.crouch(take, 35.0 * env, 25.0 * env)
        skills.turn_head(take, flex=25.0 * env)
        return
    away = take.choice((1.0, -1.0))
    for side in SIDES:
        skills.toward(take, side, env, _at(take, -0.02, 0.2, 0.3), elbow_hint=(0.2, -1.0, 0.2))
        _orient(take, side, env, 30.0)
    take["spine2.flex"] -= 8.0 * env
    take["spine3.flex"] -= 6.0 * env
    skills.turn_trunk(take, away * 20.0 * env)
    skills.turn_head(take, twist=away * 25.0 * env, flex=10.0 * env)


# Near group evade / protect / sudden movement / stumble / trip / get injured: evade is a deliberate quick duck or
# sideways dodge and recovery; protect raises the arms over the head or face and stays; sudden movement is a
# ~0.15 s startle jerk (shoulders up, arms flinching in, trunk back) that relaxes; stumble is a forward (or
# sideways) lurch from standing caught by one quick long step; trip happens while walking: a foot catches, the
# trunk pitches forward, one quick step and a stop; get injured recoils from a hit and clutches the hit place.


def evade(take: Take) -> None:
    """Evading: ``duck`` (a fast crouch, knees ~75 and trunk forward in ~0.3 s, a pause, back up) or ``dodge
    sideways`` (a quick side step with the trunk bending away, a pause, back)."""
    skills.stand(take)
    k = _keys(take, 0.3, 0.4, 0.5, fit=0.8)
    env = _curve(take, k, 0, 1, 1, 0)
    if take.mode == "duck":
        skills.crouch(take, take.vary(75.0, 0.12) * env, take.vary(35.0, 0.15) * env)
        for side in SIDES:
            skills.set_arm(take, side, 3.0 + 45.0 * env, 6.0 + 25.0 * env, elbow=take.subject.arm_carry + 60.0 * env)
        skills.turn_head(take, flex=15.0 * env)
        return
    side = take.choice(SIDES)
    take[f"{side}_hip.abd"] += take.vary(18.0, 0.15) * env
    lifted = (take.t > k[0] + 0.03) & (take.t < k[1] - 0.03)
    lift = _curve(take, [k[0], 0.5 * (k[0] + k[1]), k[1]], 0, 1, 0)
    take[f"{side}_hip.flex"] += 12.0 * lift
    take[f"{side}_knee.flex"] += 25.0 * lift
    take.contact[lifted, SIDES.index(side)] = 0.0
    take.contact[lifted, SIDES.index(other(side))] = 1.0
    skills.bend_trunk(take, _leftward(side) * 20.0 * env)
    skills.crouch(take, 20.0 * env, 10.0 * env)
    for arm in SIDES:
        skills.set_arm(take, arm, 3.0 + 20.0 * env, 6.0 + 30.0 * env, elbow=take.subject.arm_carry + 40.0 * env)


def sudden_movement(take: Take) -> None:
    """A sudden movement: ``startle`` (in ~0.15 s the shoulders jerk up, the arms flinch up and in, the trunk
    jerks back and the knees dip; then it relaxes over ~1 s) or ``jerk to the side`` (the trunk and arms jerk to
    one side in ~0.15 s and come back)."""
    skills.stand(take)
    t0 = take.onset(1.3)
    jolt = timing.keyframes(take.t, [t0, t0 + 0.13, t0 + 0.35, t0 + 1.2], [0.0, 1.0, 0.8, 0.0])
    if take.mode == "startle":
        for side in SIDES:
            take[f"{side}_collar.elev"] += 25.0 * jolt
            skills.set_arm(take, side, 3.0 + 35.0 * jolt, 6.0 + 25.0 * jolt, elbow=take.subject.arm_carry + 70.0 * jolt)
        take["spine2.flex"] -= 8.0 * jolt
        take["spine3.flex"] -= 6.0 * jolt
        skills.crouch(take, 15.0 * jolt, 0.0)
        skills.turn_head(take, flex=-15.0 * jolt)
        return
    sign = take.choice((1.0, -1.0))
    skills.bend_trunk(take, sign * 18.0 * jolt)
    take["left_hip.abd"] -= sign * 6.0 * jolt
    take["right_hip.abd"] += sign * 6.0 * jolt
    for side in SIDES:
        skills.set_arm(take, side, 3.0 + 20.0 * jolt, 6.0 + (45.0 if _leftward(side) == -sign else 15.0) * jolt,
                       elbow=take.subject.arm_carry + 30.0 * jolt)
    skills.turn_head(take, twist=-sign * 25.0 * jolt)


def get_injured(take: Take) -> None:
    """Getting hurt: a hit makes the body recoil (:func:`skills.recoil`), then the hands clutch the hit place and
    stay: ``stomach`` (both hands on the belly, folding forward, knees giving), ``shoulder`` (one hand grips the
    other shoulder, that arm hanging, a step back), ``leg`` (the leg buckles, the weight comes off it and both
    hands go to the thigh)."""
    skills.stand(take)
    t_hit = take.onset(1.4, margin=0.1)
    hurt = _curve(take, [t_hit + 0.1, t_hit + 0.5], 0.0, 1.0)
    if take.mode == "stomach":
        skills.recoil(take, t_hit, strength=1.2, where="stomach")
        skills.crouch(take, 22.0 * hurt, 25.0 * hurt)
        for side in SIDES:
            skills.toward(take, side, hurt, _at(take, 0.06, -0.3, 0.2), elbow_hint=(0.8, -1.0, 0.0))
        skills.turn_head(take, flex=15.0 * hurt)
    elif take.mode == "shoulder":
        skills.recoil(take, t_hit, strength=1.0, where="chest")
        side = take.choice(SIDES)
        skills.toward(take, other(side), hurt, _at(take, -0.12, 0.06, 0.07), elbow_hint=(0.6, -1.0, 0.3))
        skills.set_arm(take, side, 3.0 + 10.0 * hurt, 6.0, elbow=take.subject.arm_carry + 25.0 * hurt)
        skills.bend_trunk(take, _leftward(side) * 10.0 * hurt)
        skills.stance_steps(take, [(t_hit + 0.15, 0.4, take.choice(SIDES), -0.2 * take.scale())])
        skills.turn_head(take, twist=_leftward(side) * 25.0 * hurt, flex=10.0 * hurt)
    else:
        skills.recoil(take, t_hit, strength=0.6, where="chest")
        leg = take.choice(SIDES)
        take[f"{leg}_knee.flex"] += 30.0 * hurt
        take[f"{leg}_hip.flex"] += 15.0 * hurt
        take[f"{leg}_ankle.dorsi"] -= 15.0 * hurt
        take[f"{other(leg)}_knee.flex"] += 12.0 * hurt
        _lean(take, 30.0 * hurt)
        k = SIDES.index(leg)
        take.contact[:, k] = 0.5 - 0.35 * hurt
        take.contact[:, 1 - k] = 0.5 + 0.35 * hurt
        pts = {"left": _on_body(take, "left", {f"{leg}_knee": 0.65, f"{leg}_hip": 0.35}, (0.0, 0.0, 0.08)),
               "right": _on_body(take, "right", {f"{leg}_knee": 0.65, f"{leg}_hip": 0.35}, (0.0, 0.0, 0.08))}
        for side in SIDES:
            skills.toward(take, side, hurt, pts[side], elbow_hint=(0.6, -1.0, 0.0))
        skills.turn_head(take, flex=25.0 * hurt)


def stumble(take: Take) -> None:
    """A stumble from standing: a sudden lurch (``forward``: the trunk pitches ~25 degrees in 0.2 s, arms thrown
    forward, one quick long step catches it, the other foot closes; ``sideways``: the body tips to one side, arms
    out, a quick crossing side step) and recovery upright."""
    skills.stand(take)
    t0 = take.onset(1.6, margin=0.1)
    lurch = timing.keyframes(take.t, [t0, t0 + 0.2, t0 + 0.5, t0 + 1.3], [0.0, 1.0, 0.7, 0.0])
    side = take.choice(SIDES)
    if take.mode == "forward":
        _lean(take, 25.0 * lurch)
        skills.stance_steps(take, [(t0 + 0.08, 0.32, side, 0.45 * take.scale()),
                                   (t0 + 0.75, 0.45, other(side), 0.0)], lift=0.7)
        for arm in SIDES:
            skills.set_arm(take, arm, 3.0 + 65.0 * lurch, 6.0 + 30.0 * lurch,
                           elbow=take.subject.arm_carry + 20.0 * lurch)
    else:
        sign = _leftward(side)
        skills.bend_trunk(take, sign * 15.0 * lurch)
        take["pelvis.obliquity"] -= sign * 5.0 * lurch
        step = _curve(take, [t0 + 0.1, t0 + 0.4], 0.0, 1.0)
        lift = _curve(take, [t0 + 0.1, t0 + 0.25, t0 + 0.4], 0, 1, 0)
        take[f"{side}_hip.abd"] += 15.0 * step * (1 - _curve(take, [t0 + 0.8, t0 + 1.3], 0, 1))
        take[f"{side}_hip.flex"] += 15.0 * lift
        take[f"{side}_knee.flex"] += 30.0 * lift
        lifted = (take.t > t0 + 0.12) & (take.t < t0 + 0.38)
        take.contact[lifted, SIDES.index(side)] = 0.0
        take.contact[lifted, SIDES.index(other(side))] = 1.0
        for arm in SIDES:
            skills.set_arm(take, arm, 3.0 + 15.0 * lurch, 6.0 + 60.0 * lurch,
                           elbow=take.subject.arm_carry + 15.0 * lurch)
    skills.turn_head(take, flex=10.0 * lurch)


def trip(take: Take) -> None:
    """Tripping while walking: a normal walk; then, in mid-swing, one foot catches (the walk freezes there, the
    knee folds back), the trunk pitches forward ~35 degrees with the arms flung forward, the caught foot makes one
    quick long step to catch the body, the other foot closes and the walker stands; the mode names the catching
    foot. The walk fades while the caught foot is in the air, so the standing foot never slides."""
    skills.stand(take)
    caught = "left" if take.mode.startswith("left") else "right"
    cadence = take.vary(1.8, 0.05)
    phase = timing.warped_phase(take.t, cadence / 2.0 * take.tempo, take.rng, wobble=0.04)
    wanted = take.duration * take.uniform(0.3, 0.5) if take.duration > 2.0 else 0.25 * take.duration
    p = np.mod(phase - (0.0 if caught == "left" else 0.5), 1.0)
    swinging = np.flatnonzero((take.t >= wanted) & (p > 0.7) & (p < 0.8))
    if not len(swinging):
        swinging = np.flatnonzero((p > 0.7) & (p < 0.8))
    i0 = int(swinging[0]) if len(swinging) else take.num_frames // 3
    t0 = take.t[i0]
    frozen = np.where(take.t > t0, phase[i0], phase)
    walking = _curve(take, [t0 + 0.05, t0 + 0.3], 1.0, 0.0)
    _gait_blend(take, walking, skills.WALK, cadence=cadence, size=take.vary(0.95, 0.05), phase=frozen)
    air = (take.t >= t0) & (take.t < t0 + 0.4)
    take.contact[air, SIDES.index(caught)] = 0.0
    take.contact[air, SIDES.index(other(caught))] = 1.0
    pitch = timing.keyframes(take.t, [t0, t0 + 0.18, t0 + 0.5, t0 + 1.3], [0.0, 1.0, 0.6, 0.0])
    snag = _curve(take, [t0, t0 + 0.12, t0 + 0.3], 0, 1, 0)
    take[f"{caught}_knee.flex"] += 35.0 * snag
    _lean(take, 35.0 * pitch)
    skills.stance_steps(take, [(t0 + 0.1, 0.32, caught, 0.5 * take.scale()),
                               (t0 + 0.8, 0.45, other(caught), 0.0)], lift=0.6)
    for arm in SIDES:
        flung = 3.0 + 75.0 * pitch
        take[f"{arm}_shoulder.plane"] = (1 - pitch) * take[f"{arm}_shoulder.plane"] + pitch * 80.0
        take[f"{arm}_shoulder.elev"] = (1 - pitch) * take[f"{arm}_shoulder.elev"] + pitch * flung
        take[f"{arm}_elbow.flex"] = (1 - pitch) * take[f"{arm}_elbow.flex"] + pitch * 25.0
    skills.turn_head(take, flex=-15.0 * pitch)


# --- head, trunk and legs ---------------------------------------------------------------------------------------
# Near group look / head movements / turn: look turns the head (and a little the trunk) to glance somewhere
# 40-70 degrees away, holding each glance ~1 s; head movements are rhythmic small nods, shakes or side tilts;
# turn turns the whole body on the feet.


def head_movements(take: Take) -> None:
    """Rhythmic head movements for most of the clip, the body still: ``nod`` (pitching down 15-25 degrees and up,
    ~1.8/s), ``shake`` (turning +-25-35 degrees, ~1.5/s) or ``tilts`` (toward the shoulders +-15-25 degrees, ~0.6/s)."""
    skills.stand(take)
    env = _spell(take, 0.3, 0.3, (0.75, 0.97))
    if take.mode == "nod":
        skills.turn_head(take, flex=take.vary(20.0, 0.15) * (0.5 + 0.5 * _oscillation(take, take.vary(1.8, 0.15))) * env)
    elif take.mode == "shake":
        skills.turn_head(take, twist=take.vary(30.0, 0.15) * _oscillation(take, take.vary(1.5, 0.15)) * env)
    else:
        skills.turn_head(take, bend=take.vary(20.0, 0.2) * _oscillation(take, take.vary(0.6, 0.15)) * env)


def look(take: Take) -> None:
    """Looking: ``around`` (glances left and right 40-70 degrees, the trunk joining a little, each held ~1 s) or
    ``up and down`` (looking up ~35 degrees at something, then down ~35 at the floor)."""
    skills.stand(take)
    if take.mode == "around":
        yaw = np.zeros(take.num_frames)
        sign = take.choice((1.0, -1.0))
        for t0 in skills.beats(take, take.vary(1.7, 0.15), jitter=0.2, first=take.uniform(0.0, 0.4)):
            yaw += sign * take.uniform(40.0, 70.0) * skills.bumps(take, [t0], take.vary(1.5, 0.15))
            sign = -sign
        skills.turn_head(take, twist=0.75 * yaw, flex=take.wander(6.0, 0.4))
        skills.turn_trunk(take, 0.25 * yaw)
        return
    k = _keys(take, 0.5, 0.7, 0.6, 0.7, 0.5)
    pitch = _curve(take, k, 0, -1, -1, 1, 1, 0) * take.vary(35.0, 0.15)
    skills.turn_head(take, flex=pitch)
    take["spine3.flex"] += 0.15 * pitch
    take["spine2.flex"] += 0.1 * pitch


def leg_movements(take: Take) -> None:
    """One leg moving while standing on the other (hands on hips): ``side raises`` (the straight leg out to the
    side ~35 degrees and back, ~0.6/s) or ``leg shake`` (the foot lifted, the lower leg shaken loose ~4/s)."""
    skills.stand(take)
    leg = take.choice(SIDES)
    env = _spell(take, 0.3, 0.3, (0.8, 1.0))
    uestc._hands_on_hips(take)
    if take.mode == "side raises":
        up = skills.pulse(timing.warped_phase(take.t, take.vary(0.6, 0.12) * take.tempo, take.rng), 0.35, 0.1, 0.35)
        take[f"{leg}_hip.abd"] += take.vary(35.0, 0.12) * up * env
        take["pelvis.obliquity"] += _leftward(leg) * 6.0 * up * env
        lift = up * env
    else:
        shake_ = _oscillation(take, take.vary(4.0, 0.12))
        lift = env
        take[f"{leg}_hip.flex"] += 30.0 * env
        take[f"{leg}_knee.flex"] += (40.0 + 15.0 * shake_) * env
        take[f"{leg}_ankle.dorsi"] += 10.0 * shake_ * env
    take[f"{other(leg)}_hip.abd"] -= 3.0 * env
    k = SIDES.index(leg)
    take.contact[:, k] = 0.5 * (1.0 - np.minimum(1.0, 5.0 * lift))
    take.contact[:, 1 - k] = 1.0 - take.contact[:, k]


def knee_bends(take: Take) -> None:
    """Knee bends: both knees flexing to ~40 degrees and straightening (~1/s), heels down, trunk upright, arms
    relaxed (shallower and faster than a squat)."""
    skills.stand(take)
    bend = skills.pulse(timing.warped_phase(take.t, take.vary(1.0, 0.12) * take.tempo, take.rng), 0.4, 0.05, 0.4)
    skills.crouch(take, take.vary(40.0, 0.15) * bend * _spell(take, 0.2, 0.2, (0.85, 1.0)), 5.0 * bend)


def foot_movements(take: Take) -> None:
    """One foot moving, the weight on the other: ``toe taps`` (the heel down, the toes tapping up and down ~2.5/s)
    or ``ankle circles`` (the foot lifted forward a little, the ankle circling)."""
    skills.stand(take)
    foot = take.choice(SIDES)
    env = _spell(take, 0.3, 0.3, (0.8, 1.0))
    k = SIDES.index(foot)
    take.contact[:, k] = 0.5 * (1.0 - env)
    take.contact[:, 1 - k] = 1.0 - take.contact[:, k]
    if take.mode == "toe taps":
        taps = 0.5 - 0.5 * _oscillation(take, take.vary(2.5, 0.12))
        take[f"{foot}_hip.flex"] += 10.0 * env
        take[f"{foot}_knee.flex"] += 8.0 * env
        take[f"{foot}_ankle.dorsi"] += (18.0 * taps - 4.0) * env
    else:
        phase = 2 * np.pi * timing.warped_phase(take.t, take.vary(0.8, 0.15) * take.tempo, take.rng)
        take[f"{foot}_hip.flex"] += 25.0 * env
        take[f"{foot}_knee.flex"] += 30.0 * env
        take[f"{foot}_ankle.dorsi"] += (15.0 * np.sin(phase) - 10.0) * env
        take[f"{foot}_ankle.inv"] += (20.0 * np.cos(phase) + 5.0) * env
    skills.turn_head(take, flex=25.0 * env)


# Near group waist movements / upper body movements / twist / sway / swing body part / side to side movement:
# waist movements move the pelvis (hip circles or sway) under a still chest, hands on hips; upper body movements
# circle or rock the trunk over still hips; twist rotates the trunk (UESTC's standing rotation); sway tips the
# whole straight body gently from the ankles; swing body part swings loose arms round the body (or a leg, as a
# pendulum); side to side movement shifts the weight over wide-apart feet or steps side to side slowly.


def waist_movements(take: Take) -> None:
    """The pelvis moving under a still chest, hands on hips: ``hip circles`` (the pelvis circling ~0.6/s) or ``hip
    sway`` (the hips swaying side to side ~1/s)."""
    skills.stand(take)
    uestc._hands_on_hips(take)
    env = _spell(take, 0.3, 0.3, (0.85, 1.0))
    angle = 2 * np.pi * timing.warped_phase(take.t, take.vary(0.6 if take.mode == "hip circles" else 1.0, 0.12)
                                            * take.tempo, take.rng)
    side = take.vary(9.0, 0.15) * np.sin(angle) * env
    tilt = (take.vary(10.0, 0.15) * np.cos(angle) if take.mode == "hip circles" else 0.0) * env
    take["pelvis.obliquity"] += side
    take["left_hip.abd"] -= side
    take["right_hip.abd"] += side
    take["spine1.bend"] += 0.6 * side
    take["spine2.bend"] += 0.4 * side
    take["pelvis.tilt"] += tilt
    take["spine1.flex"] -= 0.7 * tilt
    take["spine2.flex"] -= 0.3 * tilt
    for leg in SIDES:
        take[f"{leg}_hip.flex"] -= tilt
    shift = take.vary(6.0, 0.15) * np.cos(angle if take.mode == "hip circles" else angle) * env
    take["left_hip.abd"] += shift
    take["right_hip.abd"] -= shift


def upper_body_movements(take: Take) -> None:
    """The trunk moving over still hips: ``torso circles`` (the chest circling forward, to a side, back, ~0.4/s,
    hands on hips) or ``rocking`` (the upper trunk rocking forward and back ~0.7/s, arms hanging)."""
    skills.stand(take)
    env = _spell(take, 0.3, 0.3, (0.85, 1.0))
    if take.mode == "torso circles":
        uestc._hands_on_hips(take)
        rate = take.vary(0.4, 0.12) * take.tempo * take.choice((1, -1))
        angle = 2 * np.pi * timing.warped_phase(take.t, rate, take.rng)
        skills.bend_trunk(take, take.vary(18.0, 0.15) * np.sin(angle) * env)
        fwd = take.vary(18.0, 0.15) * np.cos(angle) * env
        take["spine1.flex"] += 0.5 * fwd + 6.0 * env
        take["spine2.flex"] += 0.3 * fwd
        take["spine3.flex"] += 0.2 * fwd
        return
    rock = take.vary(15.0, 0.15) * _oscillation(take, take.vary(0.7, 0.12)) * env
    take["spine1.flex"] += 0.5 * rock + 5.0 * env
    take["spine2.flex"] += 0.3 * rock
    take["spine3.flex"] += 0.2 * rock
    for side in SIDES:
        skills.hang_arm(take, side)


def swing_arms(take: Take) -> None:
    """Loose arms swinging round the body as the trunk turns side to side (~0.7/s, +-30 degrees), the arms
    flopping against the body at each end."""
    skills.stand(take)
    env = _spell(take, 0.3, 0.3, (0.85, 1.0))
    swing = _oscillation(take, take.vary(0.7, 0.12))
    skills.turn_trunk(take, take.vary(32.0, 0.12) * swing * env)
    for side in SIDES:
        ahead = _leftward(side) * -swing  # the arm on the side turned away from leads round the front
        take[f"{side}_shoulder.plane"] = 40.0 + 70.0 * ahead * env
        take[f"{side}_shoulder.elev"] = 8.0 + (25.0 + 20.0 * np.abs(swing)) * env
        take[f"{side}_shoulder.rot"] = 0.0
        take[f"{side}_elbow.flex"] = take.subject.arm_carry + 15.0 * env


def side_to_side(take: Take) -> None:
    """Side to side: ``weight shift`` (feet wide, the hips moving over one bent knee, then the other, ~0.4/s) or
    ``step-touch`` (a slow step to one side, the other foot touches beside it, then back, ~1 step/s, arms
    relaxed)."""
    skills.stand(take)
    if take.mode == "step-touch":
        phase = timing.warped_phase(take.t, take.vary(0.9, 0.12) * take.tempo, take.rng)
        skills.side_steps(take, phase, width=take.vary(14.0, 0.15), travel=0)
        return
    for side in SIDES:
        take[f"{side}_hip.abd"] += take.vary(14.0, 0.12)
    shift = _oscillation(take, take.vary(0.4, 0.15))
    for side in SIDES:
        over = np.maximum(_leftward(side) * shift, 0.0)  # the hips over this leg
        take[f"{side}_knee.flex"] += 30.0 * over
        take[f"{side}_hip.flex"] += 18.0 * over
        take[f"{side}_ankle.dorsi"] += 12.0 * over
        take[f"{side}_hip.abd"] -= 8.0 * over
        take[f"{other(side)}_hip.abd"] += 8.0 * over
    take.contact[:, 0] = 0.5 + 0.4 * shift
    take.contact[:, 1] = 0.5 - 0.4 * shift


def sway(take: Take) -> None:
    """Swaying: the whole body tipping gently from the ankles (``side to side`` ~0.4/s, or ``forward and back``
    ~0.3/s), arms loose, eyes closed-calm (head still)."""
    skills.stand(take)
    osc = _oscillation(take, take.vary(0.4 if take.mode == "side to side" else 0.3, 0.15))
    env = _spell(take, 0.5, 0.5, (0.85, 1.0))
    size = take.vary(8.0, 0.15) * osc * env
    if take.mode == "side to side":
        for side in SIDES:
            take[f"{side}_ankle.inv"] += _leftward(side) * size
            take[f"{side}_hip.abd"] -= _leftward(side) * size
        take.contact[:, 0] = np.clip(0.5 + 0.04 * size, 0.1, 0.9)
        take.contact[:, 1] = 1.0 - take.contact[:, 0]
        skills.bend_trunk(take, 0.6 * size)
    else:
        for side in SIDES:
            take[f"{side}_ankle.dorsi"] += size
        take["pelvis.tilt"] += 0.5 * size
        for side in SIDES:
            take[f"{side}_hip.flex"] -= 0.5 * size
    for side in SIDES:  # the loose arms swing a little with the body
        take[f"{side}_shoulder.elev"] += 6.0 * np.abs(osc) * env


def slide(take: Take) -> None:
    """Sliding sideways: the lead foot glides out along the floor (no lift) to a wide stance on bent knees, the
    weight moves over, then the other foot glides in; each slide ~1.2 s, ~0.5 m, repeated with pauses."""
    skills.stand(take)
    travel = 1 if take.mode == "to the left" else -1
    period = take.vary(1.7, 0.12) / take.tempo
    phase = np.maximum(take.t - take.uniform(0.0, 0.3), 0.0) / period
    lead, trail = ("left", "right") if travel > 0 else ("right", "left")
    p = np.mod(phase, 1.0)
    keys = [0.0, 0.35, 0.5, 0.8, 1.0]
    w = take.vary(26.0, 0.12)
    take[f"{lead}_hip.abd"] += timing.keyframes(p, keys, [0, w, 0.6 * w, 0, 0])
    take[f"{trail}_hip.abd"] += timing.keyframes(p, keys, [0, 0, 0.4 * w, 0, 0])
    skills.crouch(take, 20.0 + timing.keyframes(p, keys, [0, 15, 15, 0, 0]), 8.0)
    weight = timing.keyframes(p, keys, [0.5, 0.0, 1.0, 1.0, 0.5])  # the lead foot's share
    k = SIDES.index(lead)
    take.contact[:, k] = weight
    take.contact[:, 1 - k] = 1.0 - weight
    for side in SIDES:
        skills.set_arm(take, side, 10.0, 20.0 + 15.0 * timing.keyframes(p, keys, [0, 1, 1, 0, 0]), elbow=30.0)
    skills.turn_head(take, twist=travel * 20.0)


def rolling_movement(take: Take) -> None:
    """Rolling movements: ``forearm roll`` (the forearms rolling round each other before the chest, ~1.5/s) or
    ``body roll`` (a wave rolling up the body: knees, hips, chest, head in turn, ~0.6/s)."""
    skills.stand(take)
    env = _spell(take, 0.4, 0.4, (0.8, 1.0))
    if take.mode == "forearm roll":
        angle = 2 * np.pi * timing.warped_phase(take.t, take.vary(1.5, 0.12) * take.tempo, take.rng)
        r = 0.07 * take.scale() * take.amp
        for n, side in enumerate(SIDES):
            a = angle + np.pi * n
            target = _at(take, 0.07, -0.1, 0.3) + np.stack([0.0 * a, r * np.sin(a), r * np.cos(a)], -1)
            skills.toward(take, side, env, target, elbow_hint=(0.8, -1.0, -0.2))
            _orient(take, side, env, 40.0)
        return
    angle = 2 * np.pi * timing.warped_phase(take.t, take.vary(0.6, 0.12) * take.tempo, take.rng)
    skills.crouch(take, (18.0 + 15.0 * np.sin(angle)) * env, 0.0)
    take["pelvis.tilt"] += 10.0 * np.sin(angle - 0.8) * env
    for joint, lag, size in (("spine1", 1.4, 8.0), ("spine2", 2.0, 8.0), ("spine3", 2.6, 8.0), ("neck", 3.2, 15.0)):
        take[f"{joint}.flex"] += size * np.sin(angle - lag) * env
    for side in SIDES:
        skills.set_arm(take, side, 15.0 + 10.0 * np.sin(angle - 2.0), 15.0, elbow=50.0)


def swim(take: Take) -> None:
    """Swimming strokes while standing, the trunk leaning forward: ``crawl stroke`` (alternate arms: over the top,
    pull straight down past the hip, elbow-high recovery up the side, ~0.6 cycles/s; the head turns to breathe)
    or ``breaststroke`` (both hands push forward from the chest, sweep out wide and back in, ~0.7/s)."""
    skills.stand(take)
    env = _spell(take, 0.4, 0.4, (0.85, 1.0))
    _lean(take, 18.0 * env)
    if take.mode == "crawl stroke":
        phase = timing.warped_phase(take.t, take.vary(0.6, 0.12) * take.tempo, take.rng)
        knots = (0.0, 0.2, 0.4, 0.55, 0.75, 0.9)
        for side, offset in (("left", 0.0), ("right", 0.5)):
            p = phase - offset
            flex = timing.periodic(p, knots, [170.0, 100.0, 10.0, -15.0, 40.0, 140.0])
            abd = timing.periodic(p, knots, [10.0, 8.0, 12.0, 40.0, 110.0, 40.0])
            elbow = timing.periodic(p, knots, [10.0, 25.0, 15.0, 80.0, 100.0, 30.0])
            skills.set_arm(take, side, 3.0 + env * (flex - 3.0), 6.0 + env * (abd - 6.0),
                           elbow=take.subject.arm_carry + env * (elbow - take.subject.arm_carry))
        breathe = np.maximum(np.sin(2 * np.pi * phase), 0.0) ** 2
        skills.turn_head(take, twist=take.choice((1.0, -1.0)) * 45.0 * breathe * env, flex=-10.0 * env)
        return
    phase = timing.warped_phase(take.t, take.vary(0.7, 0.12) * take.tempo, take.rng)
    knots = [0.0, 0.3, 0.55, 0.8]
    pts = np.array([[0.06, -0.1, 0.22], [0.08, 0.05, 0.55], [0.45, 0.0, 0.35], [0.2, -0.12, 0.2]]) * take.scale()
    path = timing.periodic(phase, knots, pts)
    for side in SIDES:
        skills.toward(take, side, env, path, elbow_hint=(0.9, -1.0, -0.2))
        _orient(take, side, env, 70.0)
    skills.turn_head(take, flex=-15.0 * env)


def play_instrument(take: Take) -> None:
    """Playing an instrument: ``guitar`` (the fretting hand out at the side on the neck, sliding now and then, the
    strumming hand sweeping up and down ~3/s before the belly, the head bent to it) or ``drums`` (both hands
    striking down alternately at waist height ~2/s each, the head bobbing)."""
    skills.stand(take)
    env = _spell(take, 0.5, 0.5, (0.8, 0.97))
    if take.mode == "guitar":
        fret, strum = ("left", "right") if take.rng.uniform() < 0.85 else ("right", "left")
        slide_ = take.scale() * timing.smooth_noise(take.t, take.rng, 0.04, max_hz=0.7)
        neck = _at(take, 0.34, -0.16, 0.28) + np.stack([slide_, 0.0 * slide_, 0.3 * slide_], -1)
        skills.toward(take, fret, env, neck,
                      elbow_hint=(0.4, -1.0, -0.3))
        _orient(take, fret, env, -60.0, 20.0)
        sweep = 0.06 * take.scale() * _oscillation(take, take.vary(3.0, 0.12))
        skills.toward(take, strum, env, _at(take, -0.02, -0.3, 0.2) + np.stack([0.0 * sweep, sweep, 0.0 * sweep], -1),
                      elbow_hint=(0.8, -0.6, -0.3))
        _orient(take, strum, env, 60.0)
        skills.turn_head(take, flex=20.0 * env, twist=_leftward(fret) * 15.0 * env)
        return
    rate = take.vary(2.0, 0.12) * take.tempo
    for n, side in enumerate(SIDES):
        hit_ = 0.5 + 0.5 * np.cos(2 * np.pi * (rate * take.t + 0.5 * n))
        target = _at(take, 0.16, -0.26, 0.32) + take.scale() * np.stack([0.0 * hit_, 0.1 * hit_, 0.0 * hit_], -1)
        skills.toward(take, side, env, target, elbow_hint=(0.8, -1.0, -0.3))
        _orient(take, side, env, 60.0, 25.0 * hit_)
    skills.crouch(take, 10.0 + 4.0 * np.cos(4 * np.pi * rate * take.t), 8.0)
    skills.turn_head(take, flex=(15.0 + 6.0 * np.cos(2 * np.pi * rate * take.t)) * env)


def misc_abstract_action(take: Take) -> None:
    """A nondescript movement: both arms (``whole body``: also the trunk and knees) wandering slowly and widely,
    never holding a pose."""
    skills.stand(take)
    for side in SIDES:
        skills.set_arm(take, side, 25.0 + take.wander(35.0, 0.5), 25.0 + np.abs(take.wander(25.0, 0.5)),
                       elbow=40.0 + np.abs(take.wander(35.0, 0.6)))
        take[f"{side}_elbow.pron"] = take.wander(30.0, 0.6)
    if take.mode == "whole body":
        skills.turn_trunk(take, take.wander(15.0, 0.4))
        skills.bend_trunk(take, take.wander(8.0, 0.4))
        skills.crouch(take, 12.0 + take.wander(10.0, 0.4), 5.0 + take.wander(6.0, 0.4))
    skills.turn_head(take, twist=take.wander(10.0, 0.4))


def move_misc_body_part(take: Take) -> None:
    """One limb moved on its own between random postures every ~1 s (``one arm``: shoulder, elbow and forearm;
    ``one leg``: the foot lifted, hip and knee), the rest of the body still."""
    skills.stand(take)
    side = take.choice(SIDES)
    move, hold = take.vary(0.55, 0.15) / take.tempo, take.vary(0.35, 0.3)
    count = max(1, int(np.ceil(take.duration / (move + hold))))
    keys, t = [], take.uniform(0.0, 0.2) * min(take.duration, move + hold)
    for _ in range(count):
        keys += [t, t + move]
        t += move + hold
    if take.mode == "one arm":
        pts = [[3.0, 6.0, take.subject.arm_carry, 10.0]] + [
            [take.uniform(-10, 100), take.uniform(0, 70), take.uniform(0, 120), take.uniform(-60, 80)]
            for _ in range(count)]
        v = timing.keyframes(take.t, keys, np.array([pts[0]] + [p for q in pts[1:] for p in (q, q)])[: len(keys)])
        skills.set_arm(take, side, v[:, 0], v[:, 1], elbow=v[:, 2])
        take[f"{side}_elbow.pron"] = v[:, 3]
        skills.turn_head(take, twist=_leftward(side) * 15.0)
        return
    pts = [[0.0, 0.0, 0.0]] + [[take.uniform(10, 45), take.uniform(0, 25), take.uniform(20, 80)] for _ in range(count)]
    v = timing.keyframes(take.t, keys, np.array([pts[0]] + [p for q in pts[1:] for p in (q, q)])[: len(keys)])
    take[f"{side}_hip.flex"] += v[:, 0]
    take[f"{side}_hip.abd"] += v[:, 1]
    take[f"{side}_knee.flex"] += v[:, 2]
    up = np.minimum(1.0, v[:, 2] / 15.0)
    k = SIDES.index(side)
    take.contact[:, k] = 0.5 * (1.0 - up)
    take.contact[:, 1 - k] = 1.0 - take.contact[:, k]
    for arm in SIDES:
        skills.set_arm(take, arm, 5.0, 15.0, elbow=take.subject.arm_carry)
    skills.turn_head(take, flex=20.0)


def perform(take: Take) -> None:
    """A theatrical flourish: ``bow`` (one arm sweeps out wide and in to the chest, the other out behind, a deep
    bow from the hips with one foot drawn back, up again, arms opening into a high V) or ``ta-da`` (both arms
    sweep up through the sides into a high wide V, one foot pointed forward, chin up, held)."""
    skills.stand(take)
    if take.mode == "bow":
        k = _keys(take, 0.5, 0.4, 0.6, 0.5, 0.5, 0.6, fit=0.95)
        hand = _hand(take)
        sweep = _curve(take, k, 0, 1, 0, 0, 0, 0, 0)
        chest = _curve(take, k, 0, 0, 1, 1, 1, 0, 0)
        bow_ = _curve(take, k, 0, 0, 0, 1, 1, 0, 0) * take.vary(50.0, 0.15)
        vee = _curve(take, k, 0, 0, 0, 0, 0, 1, 1)
        skills.set_arm(take, hand, 3.0 + 30.0 * sweep, 6.0 + 80.0 * sweep, elbow=take.subject.arm_carry)
        skills.toward(take, hand, chest, skills.landmark(take, "chest") + take.scale() * np.array([-0.1, 0.0, 0.0]),
                      start=skills.relaxed_wrist(take) * np.array([1.0, 1.0, 1.0]), elbow_hint=(1.0, -0.5, 0.0))
        skills.set_arm(take, other(hand), 3.0 - 25.0 * chest, 6.0 + 40.0 * chest, elbow=take.subject.arm_carry)
        for side in SIDES:
            up_arm = vee * 130.0
            if np.any(vee > 0):
                on = vee > 0
                take[f"{side}_shoulder.plane"][on] = 20.0
                take[f"{side}_shoulder.elev"][on] = np.maximum(take[f"{side}_shoulder.elev"][on], up_arm[on])
                take[f"{side}_elbow.flex"][on] = (1 - vee[on]) * take[f"{side}_elbow.flex"][on] + vee[on] * 8.0
        _lean(take, bow_)
        skills.turn_head(take, flex=0.4 * bow_ - 10.0 * vee)
        back = other(hand)
        take[f"{back}_hip.flex"] -= 12.0 * chest
        take[f"{back}_ankle.dorsi"] += 10.0 * chest
        take[f"{hand}_knee.flex"] += 10.0 * chest
        return
    k = _keys(take, 0.7, take.duration, fit=0.95)
    up = _curve(take, k, 0.0, 1.0, 1.0)
    for side in SIDES:
        skills.set_arm(take, side, 3.0 + 20.0 * up, 6.0 + 135.0 * up, elbow=take.subject.arm_carry * (1 - up) + 6.0)
        _orient(take, side, up, -30.0, -30.0)
    foot = take.choice(SIDES)
    take[f"{foot}_hip.flex"] += 20.0 * up
    take[f"{foot}_ankle.dorsi"] -= 30.0 * up
    take.contact[:, SIDES.index(foot)] = 0.5 - 0.35 * up
    take.contact[:, 1 - SIDES.index(foot)] = 0.5 + 0.35 * up
    take["spine2.flex"] -= 6.0 * up
    skills.turn_head(take, flex=-15.0 * up)


# Near group bow / bend / lean / touch ground / perform: bow is a short 30-40 degree nod of the trunk with the
# arms at the sides (NTU's) or a deep bow with the hands sliding down the thighs; bend folds the trunk past 70
# degrees with the arms dangling, or bends it sideways, and comes back; lean holds a moderate lean; touch ground
# gets the palms onto the floor (stooping or squatting); perform adds the arm sweeps.


def deep_bow(take: Take) -> None:
    """A deep bow: the trunk folds 55-70 degrees from the hips, the hands sliding down the fronts of the thighs,
    the head going down with it, held ~1 s, up again."""
    skills.stand(take)
    k = _keys(take, 0.8, 0.9, 0.8)
    env = _curve(take, k, 0, 1, 1, 0)
    _lean(take, take.vary(62.0, 0.1) * env)
    for side in SIDES:
        skills.set_arm(take, side, skills.trunk_pitch(take) - 8.0 * env, 4.0, elbow=take.subject.arm_carry)
    skills.turn_head(take, flex=15.0 * env)


def bend(take: Take) -> None:
    """Bending and coming back: ``forward`` (the trunk folds 85-115 degrees on nearly straight knees, the arms
    dangling toward the floor, ~1 s) or ``sideways`` (the trunk bends 25-30 degrees to one side, that hand sliding
    down the thigh)."""
    skills.stand(take)
    k = _keys(take, 0.9, 0.9, 0.9)
    env = _curve(take, k, 0, 1, 1, 0)
    if take.mode == "forward":
        skills.crouch(take, 8.0 * env, take.vary(100.0, 0.08) * env)
        for side in SIDES:
            skills.hang_arm(take, side, forward=5.0 * env)
        skills.turn_head(take, flex=10.0 * env)
        return
    side = take.choice(SIDES)
    skills.bend_trunk(take, _leftward(side) * take.vary(28.0, 0.12) * env)
    skills.set_arm(take, side, 3.0, 6.0 - 4.0 * env, elbow=take.subject.arm_carry)
    skills.set_arm(take, other(side), 3.0, 6.0 + 30.0 * env, elbow=take.subject.arm_carry + 30.0 * env)


def touch_ground(take: Take) -> None:
    """Touching the floor with the palms and coming back up: ``stoop`` (knees half bent, the trunk folded well
    past horizontal, both palms on the floor before the feet) or ``squat`` (a deep squat on the balls of the feet,
    the trunk forward, one palm on the floor beside the feet)."""
    skills.stand(take)
    k = _keys(take, 0.9, 0.5, 0.9)
    env = _curve(take, k, 0, 1, 1, 0)
    if take.mode == "stoop":
        skills.crouch(take, take.vary(55.0, 0.1) * env, take.vary(130.0, 0.04) * env)
        _hands_to_floor(take, env, forward=0.05, out=-0.02)
    else:
        skills.crouch(take, take.vary(120.0, 0.06) * env, take.vary(85.0, 0.06) * env, heel=15.0 * env)
        side = _hand(take, 0.3)
        _hands_to_floor(take, env, forward=0.08, out=0.1, sides=(side,))
        skills.set_arm(take, other(side), 3.0 + 50.0 * env, 6.0 + 10.0 * env, elbow=take.subject.arm_carry + 30 * env)
    for side in SIDES:
        take[f"{side}_wrist.flex"] -= 50.0 * env
    skills.turn_head(take, flex=15.0 * env)


def cartwheel(take: Take) -> None:
    """A cartwheel, as far as the joints allow: arms up, the body tips sideways over the lead leg, the lead hand
    reaching down toward the floor while the far leg kicks up high to the side, then the body comes back up
    onto the far leg a stride further sideways."""
    skills.stand(take)
    lead = "left" if take.mode == "to the left" else "right"
    far = other(lead)
    sign = _leftward(lead)
    k = _keys(take, 0.4, 0.35, 0.3, 0.45, 0.5, fit=0.9)
    arms = _curve(take, k, 0, 1, 1, 1, 0.5, 0)
    tip = _curve(take, k, 0, 0, 1, 1, 0.2, 0)
    kick = _curve(take, k, 0, 0, 0.6, 1, 0, 0)
    for side in SIDES:
        skills.set_arm(take, side, 3.0 + 15.0 * arms, 6.0 + 160.0 * arms,
                       elbow=take.subject.arm_carry * (1 - arms) + 5.0)
    skills.bend_trunk(take, sign * 30.0 * tip)
    take["pelvis.obliquity"] -= sign * 25.0 * tip
    take[f"{lead}_hip.abd"] += 25.0 * tip
    take[f"{lead}_knee.flex"] += 35.0 * tip
    take[f"{far}_hip.abd"] += 45.0 * kick
    take[f"{far}_knee.flex"] += 10.0 * kick
    take[f"{lead}_shoulder.elev"] += 0.0
    up = (take.t > k[1] + 0.1 * (k[2] - k[1])) & (take.t < k[4])
    take.contact[up, SIDES.index(far)] = 0.0
    take.contact[up, SIDES.index(lead)] = 1.0
    landing = (take.t >= k[4]) & (take.t < k[5])
    take.contact[landing, SIDES.index(far)] = 1.0
    take.contact[landing, SIDES.index(lead)] = 0.0
    take[f"{lead}_hip.abd"] += 20.0 * _curve(take, [k[3], k[4], k[5]], 0, 1, 0)
    skills.turn_head(take, bend=sign * 10.0 * tip, flex=20.0 * tip)


# --- balls and sports ---------------------------------------------------------------------------------------------
# Near group catch / play catch / throw / action with ball / dribble / play sport / sports move / golf: catch is
# one catch (hands up ready, reach to the ball, absorb to the chest, keep it); play catch repeats catch then a
# toss back every ~2.5 s; throw is HumanAct12's one throw with a step; action with ball is a two-handed pass (from
# the chest, or overhead); dribble bounces a ball at the hip (NTU's); play sport is a basketball shot (NTU's);
# sports move a tennis stroke (NTU's); golf a two-handed swing bent over the ball, or a putt.


def catch(take: Take) -> None:
    """Catching a ball: the hands come up ready, reach out to meet it (``chest height``, or ``overhead``), close and
    give with it back to the chest, and hold it there."""
    skills.stand(take)
    k = _keys(take, 0.5, 0.5, 0.25, 0.35, fit=0.85)
    ready = _curve(take, k, 0, 1, 1, 1, 1)
    meet = _curve(take, k, 0, 0, 1, 1, 0)
    high = take.mode == "overhead"
    prep = _at(take, 0.12, -0.05, 0.3)
    out = take.head_point() + _at(take, 0.1, 0.2, 0.25) if high else _at(take, 0.1, -0.02, 0.5)
    hold = _at(take, 0.09, -0.12, 0.28)
    held = _curve(take, [k[3], k[4]], 0, 1)
    for side in SIDES:
        target = prep + meet[:, None] * (out - prep) + held[:, None] * (hold - prep)
        skills.toward(take, side, ready, target, elbow_hint=(0.7, -1.0, -0.2))
        _orient(take, side, ready, -30.0, -20.0 * meet)
    skills.crouch(take, 10.0 * ready + 12.0 * _curve(take, [k[2], k[3], k[4]], 0, 1, 0), 5.0)
    skills.turn_head(take, flex=(-25.0 if high else -5.0) * meet)


def play_catch(take: Take) -> None:
    """Playing catch: repeatedly catching a ball (both hands forward, giving with it) and tossing it back
    (``underhand tosses``: a one-arm pendulum swing; ``overhand throws``: from beside the head), ~2.5 s a round."""
    skills.stand(take)
    side = _hand(take)
    period = take.vary(2.4, 0.12) / take.tempo
    phase = np.maximum(take.t - take.uniform(0.0, 0.5), 0.0) / period
    p = np.mod(phase, 1.0)
    keys = [0.0, 0.15, 0.3, 0.45, 0.6, 0.72, 0.85, 1.0]
    catch_ = timing.keyframes(p, keys, [0, 1, 1, 0.3, 0.0, 0.0, 0.0, 0.0])
    windup = timing.keyframes(p, keys, [0, 0, 0, 0.5, 1, 0, 0, 0])
    release = timing.keyframes(p, keys, [0, 0, 0, 0, 0, 1, 0.3, 0])
    held = timing.keyframes(p, keys, [0.2, 1, 1, 1, 1, 0.2, 0, 0.2])
    front, chest = _at(take, 0.1, -0.05, 0.45), _at(take, 0.09, -0.12, 0.28)
    if take.mode == "underhand tosses":
        back, fwd = _at(take, 0.18, -0.45, -0.15), _at(take, 0.1, -0.05, 0.5)
    else:
        back, fwd = take.head_point() + _at(take, 0.15, 0.0, -0.12), _at(take, 0.05, 0.1, 0.5)
    base = chest + catch_[:, None] * (front - chest)
    throwing = base + windup[:, None] * (back - base) + release[:, None] * (fwd - base)
    skills.toward(take, side, held, throwing, elbow_hint=(0.7, -1.0, -0.2))
    skills.toward(take, other(side), held * (1 - windup) * (1 - release), base, elbow_hint=(0.7, -1.0, -0.2))
    skills.turn_trunk(take, _leftward(side) * (-20.0 * windup + 12.0 * release))
    skills.crouch(take, 10.0 + 10.0 * windup, 4.0 * release)


def action_with_ball(take: Take) -> None:
    """A two-handed pass: ``chest pass`` (the ball at the chest, a step forward, both arms thrust straight out,
    wrists snapping, palms ending outward) or ``overhead pass`` (the ball taken back behind the head, the back
    arching, then thrown forward with both arms)."""
    skills.stand(take)
    k = _keys(take, 0.5, 0.4, 0.18, 0.5, 0.5)
    hold = _curve(take, k, 0, 1, 1, 1, 1, 0)
    if take.mode == "chest pass":
        chest, out = _at(take, 0.1, -0.1, 0.25), _at(take, 0.1, -0.05, 0.55)
        thrust = _curve(take, k, 0, 0, 0, 1, 1, 0)
        skills.step_out(take, take.choice(SIDES), k[1], k[3] - k[1], length=0.3 * take.scale())
        for side in SIDES:
            skills.toward(take, side, hold, chest + thrust[:, None] * (out - chest), elbow_hint=(0.8, -1.0, -0.2))
            _orient(take, side, hold, 20.0 + 60.0 * thrust, -30.0 * thrust)
        _lean(take, 10.0 * thrust)
        return
    behind, out = take.head_point() + _at(take, 0.1, 0.1, -0.12), take.head_point() + _at(take, 0.1, 0.05, 0.45)
    back = _curve(take, k, 0, 0, 1, 0, 0, 0)
    throw_ = _curve(take, k, 0, 0, 0, 1, 1, 0)
    chest = _at(take, 0.1, -0.1, 0.25)
    lifted = _curve(take, k, 0, 1, 1, 1, 0.5, 0)
    for side in SIDES:
        target = chest + lifted[:, None] * (behind - chest) + throw_[:, None] * (out - behind)
        skills.toward(take, side, hold, target, elbow_hint=(0.8, 0.2, 0.2))
    take["spine2.flex"] -= 8.0 * back
    take["spine1.flex"] += 12.0 * throw_ - 6.0 * back
    skills.crouch(take, 15.0 * back, 0.0)


def golf(take: Take) -> None:
    """A golf stroke, bent over the ball (trunk ~35 degrees forward, knees soft, feet apart) with the hands together
    below the chest: ``full swing`` (the club taken back to the right shoulder as the trunk turns away, a fast
    down-swing through the ball in ~0.3 s, follow-through up over the left shoulder, the head staying down till
    after impact) or ``putt`` (a small pendulum of arms and shoulders, the head still)."""
    skills.stand(take, heading=take.rng.normal(0.0, 10.0))
    for side in SIDES:
        take[f"{side}_hip.abd"] += 9.0
    full = take.mode == "full swing"
    k = _keys(take, 0.7, 0.9, 0.25, 0.3, 0.6, 0.6) if full else _keys(take, 0.8, 0.7, 0.5, 0.5, 0.6)
    address = _curve(take, k, *([0, 1, 1, 1, 1, 1, 0] if full else [0, 1, 1, 1, 1, 0]))
    _lean(take, 35.0 * address)
    skills.crouch(take, 18.0 * address, 0.0)
    if full:
        turn_ = _curve(take, k, 0, 0, -1, 0.2, 1, 1, 0)  # + toward the target (the golfer's left)
        hands = np.stack([_curve(take, k, 0, 0, -0.3, 0.0, 0.35, 0.3, 0),  # x: + toward the left
                          _curve(take, k, 0, -0.45, 0.05, -0.48, 0.05, 0.0, 0),
                          _curve(take, k, 0, 0.3, 0.05, 0.32, 0.0, 0.05, 0)], -1)
        skills.turn_trunk(take, 45.0 * take.amp * turn_)
        skills.turn_head(take, flex=_curve(take, k, 0, 30, 30, 30, 5, 0, 0), twist=_curve(take, k, 0, 0, 0, 0, 35, 35, 0))
    else:
        turn_ = _curve(take, k, 0, 0, -0.15, 0.15, 0, 0)
        hands = np.stack([_curve(take, k, 0, 0, -0.12, 0.12, 0.0, 0),
                          _curve(take, k, 0, -0.5, -0.48, -0.48, -0.5, 0),
                          _curve(take, k, 0, 0.25, 0.25, 0.25, 0.25, 0)], -1)
        skills.turn_trunk(take, 20.0 * turn_)
        skills.turn_head(take, flex=30.0 * address)
    hands = hands * take.scale()
    for side in SIDES:
        target = hands.copy()
        if side == "right":
            target[:, 0] *= -1.0
        target[:, 0] += 0.03 * take.scale()
        skills.toward(take, side, address, target, elbow_hint=(0.6, -1.0, -0.2), bulge=0.0)
        _orient(take, side, address, 10.0)


# --- objects -------------------------------------------------------------------------------------------------------
# Near group touch object / grasp object / place something / take-pick something up / lift something / move
# something / interact with object / clean: touch reaches one hand from rest to a table or shelf, touches briefly
# and returns empty; grasp reaches, closes and brings the object back to the chest and keeps it; place starts
# holding it at the chest and puts it down on a table or shelf, returning empty; pick up goes down to the floor
# (NTU's); lift raises a heavy box from the floor (NTU's) or an object overhead with both arms; move something
# pushes a load across the floor walking (NTU's) or slides it along a table from one side to the other, the hands
# never lifting it; interact with object works at a
# waist-high surface with both hands, one holding; clean wipes a surface in big circles.


def _reach_spot(take: Take, mode: str) -> tuple[np.ndarray, float]:
    """Where a hand reaches for an object (``table``: waist height ahead, leaning in; ``shelf``: head height
    ahead) and how far the trunk leans for it."""
    if "shelf" in mode:
        return take.head_point() + _at(take, 0.1, -0.02, 0.38), 0.0
    return _at(take, 0.14, -0.35, 0.42), take.vary(18.0, 0.2)


def touch_object(take: Take) -> None:
    """Touching something: one hand from rest to a ``table`` or ``shelf`` spot, fingertips on it briefly (a
    small rub), and back; once or twice."""
    skills.stand(take)
    side = _hand(take)
    n = 2 if take.duration > 3.5 and take.rng.uniform() < 0.5 else 1
    k = _keys(take, *([0.6, 0.5, 0.6] * n), fit=0.85)
    env = sum(_curve(take, k[3 * i: 3 * i + 4], 0, 1, 1, 0) for i in range(n))
    spot, lean_ = _reach_spot(take, take.mode)
    rub = 0.015 * take.scale() * _oscillation(take, 2.0)
    skills.toward(take, side, env, spot + np.stack([rub, 0.0 * rub, 0.0 * rub], -1), elbow_hint=(0.5, -1.0, -0.3))
    _orient(take, side, env, 70.0, -20.0)
    _lean(take, lean_ * env)
    skills.turn_head(take, flex=(20.0 if lean_ else -10.0) * env)


def grasp_object(take: Take) -> None:
    """Grasping something: one hand from rest to a ``table`` or ``shelf`` spot, closing on it (a pause, the wrist
    turning), then bringing it back to the chest and keeping it there."""
    skills.stand(take)
    side = _hand(take)
    k = _keys(take, 0.6, 0.35, 0.6, fit=0.8)
    spot, lean_ = _reach_spot(take, take.mode)
    chest = _at(take, 0.1, -0.15, 0.28)
    reach_ = _curve(take, k, 0, 1, 1, 1)
    back = _curve(take, k, 0, 0, 0, 1)
    skills.toward(take, side, reach_, spot + back[:, None] * (chest - spot), elbow_hint=(0.5, -1.0, -0.3))
    _orient(take, side, reach_, 30.0 - 50.0 * back, -15.0 * _curve(take, k, 0, 0, 1, 1))
    _lean(take, lean_ * _curve(take, k, 0, 1, 1, 0))
    skills.turn_head(take, flex=(20.0 if lean_ else -10.0) * _curve(take, k, 0, 1, 1, 0.5))


def place_something(take: Take) -> None:
    """Putting something down: it is held at the chest in both hands when the clip starts, then set down on a
    ``table`` (leaning in) or a ``shelf`` (arms up ahead), the hands open and come back to rest empty."""
    skills.stand(take)
    k = _keys(take, 0.4, 0.7, 0.3, 0.6, fit=0.85)
    spot, lean_ = _reach_spot(take, take.mode)
    chest = _at(take, 0.11, -0.15, 0.28)
    out = _curve(take, k, 0, 0, 1, 1, 1)
    free = _curve(take, k, 0, 0, 0, 0, 1)
    for side in SIDES:
        target = chest + out[:, None] * (spot - chest) + np.array([-0.03, 0.0, 0.0]) * take.scale() * out[:, None]
        skills.toward(take, side, 1.0 - free, target, elbow_hint=(0.6, -1.0, -0.3))
        _orient(take, side, 1.0 - free, 0.0, -10.0 * out)
    _lean(take, lean_ * _curve(take, k, 0, 0, 1, 1, 0))
    skills.turn_head(take, flex=(20.0 if lean_ else -10.0) * _curve(take, k, 0, 1, 1, 1, 0))


def lift_overhead(take: Take) -> None:
    """Lifting an object overhead: held at the chest in both hands, a knee dip, then pressed up on straight arms
    (onto a high shelf) and held, the head tipped back to watch it."""
    skills.stand(take)
    k = _keys(take, 0.5, 0.3, 0.7, 0.8, fit=0.9)
    hold = _curve(take, k, 0, 1, 1, 1, 1)
    up = _curve(take, k, 0, 0, 0, 1, 1)
    chest, top = _at(take, 0.13, -0.12, 0.28), take.head_point() + _at(take, 0.14, 0.38, 0.12)
    for side in SIDES:
        skills.toward(take, side, hold, chest + up[:, None] * (top - chest), elbow_hint=(0.8, -0.8, -0.2))
        _orient(take, side, hold, 0.0, -30.0 * up)
    skills.crouch(take, 25.0 * _curve(take, k, 0, 0, 1, 0, 0), 3.0)
    take["spine2.flex"] -= 6.0 * up
    skills.turn_head(take, flex=-25.0 * up)


def slide_aside(take: Take) -> None:
    """Moving something along a table: both hands on it at waist height to one side, leaning in, sliding it across
    to the other side (the trunk turning with it), then letting go."""
    skills.stand(take)
    k = _keys(take, 0.6, 1.0, 0.5, fit=0.9)
    on = _curve(take, k, 0, 1, 1, 0)
    across = _curve(take, k, 0, 0, 1, 1)
    sign = take.choice((1.0, -1.0))  # + starts on the left, ends on the right
    _lean(take, 18.0 * on)
    shift = 0.28 * take.scale() * (sign * (1 - 2 * across))  # world x of the object's centre
    for side in SIDES:
        target = np.broadcast_to(_at(take, 0.1, -0.35, 0.4), (take.num_frames, 3)).copy()
        target[:, 0] += _leftward(side) * shift
        skills.toward(take, side, on, target, elbow_hint=(0.6, -1.0, -0.3))
        _orient(take, side, on, 70.0, -30.0)
    skills.turn_trunk(take, 25.0 * sign * (1 - 2 * across) * on)
    skills.turn_head(take, flex=20.0 * on, twist=20.0 * sign * (1 - 2 * across) * on)


def interact_with_object(take: Take) -> None:
    """Working with something at a waist-high surface, the eyes on it: ``turning a part`` (one hand holds it, the
    other's forearm twists back and forth ~1.2/s) or ``tool in one hand`` (one hand strikes small blows ~2/s, the
    other steadies)."""
    skills.stand(take)
    env = _spell(take, 0.5, 0.5, (0.75, 0.95))
    worker = _hand(take)
    hold = _at(take, 0.06, -0.32, 0.33)
    skills.toward(take, other(worker), env, hold, elbow_hint=(0.6, -1.0, -0.3))
    _orient(take, other(worker), env, 40.0)
    if take.mode == "turning a part":
        twist = _oscillation(take, take.vary(1.2, 0.15))
        skills.toward(take, worker, env, _at(take, 0.04, -0.28, 0.36), elbow_hint=(0.6, -1.0, -0.3))
        take[f"{worker}_elbow.pron"] = (20.0 + 50.0 * twist) * env
    else:
        blow = np.maximum(_oscillation(take, take.vary(2.0, 0.15)), 0.0) ** 2
        target = _at(take, 0.14, -0.22, 0.36) + take.scale() * np.stack([0.0 * blow, -0.08 * blow, 0.0 * blow], -1)
        skills.toward(take, worker, env, target, elbow_hint=(0.6, -1.0, -0.3))
        _orient(take, worker, env, 10.0, 25.0 * blow)
    _lean(take, 10.0 * env)
    skills.turn_head(take, flex=25.0 * env)


def clean_something(take: Take) -> None:
    """Wiping a surface in big circles (~1/s, radius 10-15 cm) with one palm: ``wipe table`` (leaning over a table,
    the other hand resting on it) or ``wipe window`` (upright, on a wall at chest-to-face height)."""
    skills.stand(take)
    env = _spell(take, 0.5, 0.5, (0.75, 0.95))
    side = _hand(take)
    angle = 2 * np.pi * timing.warped_phase(take.t, take.vary(1.0, 0.15) * take.tempo * take.choice((1, -1)), take.rng)
    r = take.vary(0.13, 0.15) * take.scale()
    if take.mode == "wipe table":
        _lean(take, 22.0 * env)
        centre = _at(take, 0.08, -0.36, 0.42)
        path = centre + np.stack([r * np.cos(angle), 0.0 * angle, 0.7 * r * np.sin(angle)], -1)
        skills.toward(take, side, env, path, elbow_hint=(0.6, -1.0, -0.3))
        _orient(take, side, env, 80.0, -25.0)
        skills.toward(take, other(side), env, _at(take, 0.2, -0.38, 0.3), elbow_hint=(0.6, -1.0, -0.3))
        _orient(take, other(side), env, 80.0, -40.0)
        skills.turn_head(take, flex=25.0 * env)
        return
    centre = _at(take, 0.08, 0.02, 0.45)
    path = centre + np.stack([r * np.cos(angle), r * np.sin(angle), 0.0 * angle], -1)
    skills.toward(take, side, env, path, elbow_hint=(0.6, -1.0, -0.3))
    _orient(take, side, env, 20.0, -50.0)


def grab_person(take: Take) -> None:
    """Grabbing someone: ``both hands`` (reaching out at chest height to the other's shoulders, gripping and
    pulling them in with a lean back and a step back) or ``one hand`` (seizing an arm at waist height and pulling
    it to the side, the trunk turning)."""
    skills.stand(take)
    k = _keys(take, 0.45, 0.25, 0.6, 0.7, fit=0.9)
    out = _curve(take, k, 0, 1, 1, 0.4, 0)
    pull = _curve(take, k, 0, 0, 0, 1, 0)
    if take.mode == "both hands":
        grip = _at(take, 0.16, 0.03, 0.52)
        for side in SIDES:
            skills.toward(take, side, out, grip, elbow_hint=(0.6, -1.0, -0.3))
            _orient(take, side, out, 10.0, 20.0 * pull)
        take["spine1.flex"] -= 10.0 * pull
        skills.stance_steps(take, [(k[2], k[3] - k[2], take.choice(SIDES), -0.25 * take.scale())])
        skills.turn_head(take, flex=-5.0 * out)
        return
    side = _hand(take)
    grip = _at(take, 0.1, -0.22, 0.5)
    pulled = _at(take, 0.35, -0.2, 0.15)
    skills.toward(take, side, out, grip + pull[:, None] * (pulled - grip), elbow_hint=(0.6, -1.0, -0.3))
    _orient(take, side, out, 40.0, 20.0 * pull)
    skills.turn_trunk(take, -_leftward(side) * 20.0 * pull)


# --- touching one's own body ------------------------------------------------------------------------------------
# Near group touching body part / touching face / scratch / grab body part / adjust / rub: touching body part is
# a brief touch of the opposite shoulder or the knee; touching face rests a hand on the chin or cheek and keeps it
# there; scratch rubs quickly (~4/s) at the head or thigh; grab body part holds on firmly (one hand round the
# other wrist, or hugging a knee up); adjust tugs at the collar or waistband with both hands; rub is palm on palm.


def scratch(take: Take) -> None:
    """Scratching ~4/s for 1-2 s: ``head`` (fingers on the side/top of the head, the head tipping to them) or
    ``leg`` (bending a little, the hand scratching the front of the thigh)."""
    skills.stand(take)
    side = _hand(take)
    k = _keys(take, 0.5, 1.6, 0.5)
    env = _curve(take, k, 0, 1, 1, 0)
    working = _curve(take, [k[1], k[1] + 0.1, k[2] - 0.1, k[2]], 0, 1, 1, 0)
    rub = 0.02 * take.scale() * _oscillation(take, take.vary(4.0, 0.12)) * working
    if take.mode == "head":
        spot = take.head_point() + _at(take, 0.11, 0.1, 0.0)
        skills.toward(take, side, env, spot + np.stack([0.0 * rub, 0.5 * rub, rub], -1), elbow_hint=(1.0, 0.0, 0.2))
        _orient(take, side, env, -20.0, 25.0)
        skills.turn_head(take, bend=_leftward(side) * 10.0 * env, flex=5.0 * env)
        return
    _lean(take, 20.0 * env)
    for leg in SIDES:
        take[f"{leg}_knee.flex"] += 10.0 * env
    spot = _on_body(take, side, {f"{side}_knee": 0.6, f"{side}_hip": 0.4}, (0.0, 0.0, 0.09))
    skills.toward(take, side, env, spot + np.stack([0.0 * rub, rub, 0.0 * rub], -1), elbow_hint=(0.6, -1.0, -0.2))
    _orient(take, side, env, 60.0, 20.0)
    skills.turn_head(take, flex=25.0 * env)


def touching_body_part(take: Take) -> None:
    """A brief touch of one's own body, once or twice: ``shoulder`` (a hand to the opposite shoulder) or ``knee``
    (leaning down, a hand to the same-side knee)."""
    skills.stand(take)
    side = _hand(take, 0.3)
    n = 2 if take.duration > 3.5 and take.rng.uniform() < 0.4 else 1
    k = _keys(take, *([0.55, 0.5, 0.55] * n), fit=0.85)
    env = sum(_curve(take, k[3 * i: 3 * i + 4], 0, 1, 1, 0) for i in range(n))
    if take.mode == "shoulder":
        skills.toward(take, side, env, _at(take, -0.13, 0.07, 0.07), elbow_hint=(0.6, -1.0, 0.3))
        _orient(take, side, env, 20.0)
        skills.turn_head(take, twist=-_leftward(side) * 15.0 * env)
        return
    _lean(take, 35.0 * env)
    for leg in SIDES:
        take[f"{leg}_knee.flex"] += 12.0 * env
    spot = _on_body(take, side, {f"{side}_knee": 1.0}, (0.0, 0.03, 0.08))
    skills.toward(take, side, env, spot, elbow_hint=(0.6, -1.0, -0.2))
    skills.turn_head(take, flex=25.0 * env)


def touching_face(take: Take) -> None:
    """A hand resting on the face and kept there: ``chin`` (thinking: the hand under the chin, a little rubbing) or
    ``cheek`` (the palm on the cheek, the head tilted into it)."""
    skills.stand(take)
    side = _hand(take)
    env = _spell(take, 0.6, 0.6, (0.7, 0.95))
    if take.mode == "chin":
        rub = 0.01 * take.scale() * _oscillation(take, 1.2)
        skills.toward(take, side, env, skills.landmark(take, "chin") + np.stack([rub, 0.0 * rub, 0.0 * rub], -1),
                      elbow_hint=(0.3, -1.0, 0.2))
        _orient(take, side, env, -30.0, -20.0)
        skills.toward(take, other(side), env, _at(take, -0.05, -0.2, 0.2), elbow_hint=(0.6, -1.0, 0.0))
        skills.turn_head(take, flex=8.0 * env)
        return
    skills.toward(take, side, env, take.head_point() + _at(take, 0.11, -0.035, 0.106), elbow_hint=(0.6, -1.0, 0.1))
    _orient(take, side, env, -20.0, -10.0)
    skills.turn_head(take, bend=_leftward(side) * 10.0 * env)


def grab_wrist(take: Take) -> None:
    """One hand gripping the other arm's wrist before the waist and holding it (a squeeze now and then)."""
    skills.stand(take)
    held = _hand(take, 0.5)
    env = _spell(take, 0.5, 0.5, (0.7, 0.95))
    a = _at(take, 0.06, -0.25, 0.3)
    skills.toward(take, held, env, a, elbow_hint=(0.6, -1.0, -0.3))
    _orient(take, held, env, 0.0)
    squeeze = 0.01 * take.scale() * _oscillation(take, 0.8)
    b = np.array([-a[0] - 0.07 * take.scale(), a[1] + 0.02 * take.scale(), a[2] - 0.05 * take.scale()])
    skills.toward(take, other(held), env, b + np.stack([0.0 * squeeze, squeeze, 0.0 * squeeze], -1),
                  elbow_hint=(0.6, -1.0, -0.3))
    _orient(take, other(held), env, 60.0)
    skills.turn_head(take, flex=20.0 * env)


def adjust(take: Take) -> None:
    """Adjusting clothes with both hands: ``collar`` (pinching the collar and giving it 2-3 small tugs) or
    ``waistband`` (hands at the sides of the waist pulling the trousers up with a little dip)."""
    skills.stand(take)
    k = _keys(take, 0.5, 1.2, 0.5)
    env = _curve(take, k, 0, 1, 1, 0)
    tugs = (0.5 - 0.5 * np.cos(2 * np.pi * take.vary(2.0, 0.15) * (take.t - k[1]))) * _curve(
        take, [k[1], k[1] + 0.1, k[2] - 0.1, k[2]], 0, 1, 1, 0)
    if take.mode == "collar":
        spot = _at(take, 0.08, 0.06, 0.14)
        direction = np.array([0.3, -0.3, 0.7])
        skills.turn_head(take, flex=15.0 * env)
    else:
        spot = _at(take, 0.16, -0.38, 0.1)
        direction = np.array([0.0, 1.0, 0.0])
        skills.crouch(take, 10.0 * tugs, 5.0 * env)
        skills.turn_head(take, flex=20.0 * env)
    for side in SIDES:
        skills.toward(take, side, env, spot + 0.025 * take.scale() * tugs[:, None] * direction,
                      elbow_hint=(0.9, -1.0, -0.2))
        _orient(take, side, env, 10.0, 20.0 * tugs)


# --- steps and compositions -----------------------------------------------------------------------------------
# Near group step / forward movement / backwards movement / sideways movement / move back to original position /
# mix: step is one step (forward, or out to the side) kept; forward and backwards movement are several steps;
# sideways movement travels in side steps; move back to original position starts away from neutral (a foot
# forward or out, an arm out) and returns to it; mix strings different actions together.


def step(take: Take) -> None:
    """One step: ``forward`` (a step forward into a staggered stance, sometimes closed by the other foot) or ``to
    the side`` (one foot steps out to the side and the other closes beside it)."""
    skills.stand(take)
    side = take.choice(SIDES)
    dur = min(take.vary(0.6, 0.1) / take.tempo, 0.45 * take.duration)
    t0 = take.onset(2.2 * dur)
    if take.mode == "forward":
        steps = [(t0, dur, side, take.vary(0.32, 0.15) * take.scale())]
        if take.rng.uniform() < 0.5:
            steps.append((t0 + 1.2 * dur, dur, other(side), 0.0))
        skills.stance_steps(take, steps)
        return
    phase = np.clip((take.t - t0) / (2.0 * dur), 0.0, 0.999)
    skills.side_steps(take, phase, width=take.vary(16.0, 0.15), travel=1 if side == "left" else -1)


def move_back(take: Take) -> None:
    """Moving back to the starting position: the clip starts ``from a step forward`` (staggered stance, one arm
    reaching out ahead at shoulder height) or ``from a reach`` (leaning forward with one arm reaching down ahead),
    and the foot steps back in beside the other as the body and arm return to rest."""
    skills.stand(take)
    side = take.choice(SIDES)
    dur = min(take.vary(0.65, 0.1) / take.tempo, 0.6 * take.duration)
    t0 = take.onset(dur, margin=0.1)
    back = _curve(take, [t0, t0 + dur], 0.0, 1.0)
    if take.mode == "from a step forward":
        r = take.vary(0.3, 0.15) * take.scale()
        skills.stance_steps(take, [(-2.0, 0.5, side, r), (t0, dur, side, 0.0)])
        arm = _hand(take)
        skills.set_arm(take, arm, 3.0 + 70.0 * (1 - back), 6.0, elbow=take.subject.arm_carry + 10.0 * (1 - back))
        return
    # from a reach: leaning forward, one arm reaching down-forward (as after touching something low), a foot
    # forward; the trunk straightens, the arm comes back and the foot steps back in.
    r = take.vary(0.25, 0.15) * take.scale()
    skills.stance_steps(take, [(-2.0, 0.5, side, r), (t0 + 0.2 * dur, 0.8 * dur, side, 0.0)])
    _lean(take, take.vary(35.0, 0.15) * (1 - back))
    arm = _hand(take)
    skills.set_arm(take, arm, 3.0 + (45.0 + skills.trunk_pitch(take)) * (1 - back), 6.0,
                   elbow=take.subject.arm_carry)
    skills.turn_head(take, flex=15.0 * (1 - back))


def mix(take: Take) -> None:
    """A mixture of actions in one segment: ``step, turn and wave`` (a couple of steps forward, a quarter turn on
    the spot, a wave) or ``squat, stand and reach`` (a quick squat, up, one arm reaching up high)."""
    skills.stand(take)
    d = take.duration
    if take.mode == "step, turn and wave":
        s = min(take.vary(0.55, 0.1) / take.tempo, d / 6.0)
        t = 0.05 * d
        t = _step_series(take, t, 2, take.vary(0.28, 0.15), step=s, pause=0.05, first=take.choice(SIDES))
        t = _turn_steps(take, t + 0.05, take.choice((1.0, -1.0)) * take.uniform(70.0, 100.0), min(0.45, d / 8.0))
        side = _hand(take)
        up = _curve(take, [t, t + min(0.4, 0.1 * d)], 0.0, 1.0)
        wave = 0.1 * take.scale() * np.sin(2 * np.pi * 2.4 * take.t) * up
        target = take.shoulder_point() + _at(take, 0.18, 0.36, 0.14) + np.stack([wave, 0.0 * wave, 0.0 * wave], -1)
        skills.toward(take, side, up, target, elbow_hint=(1.0, -0.4, -0.2))
        return
    k = _keys(take, 0.6, 0.3, 0.6, 0.6, 0.6, fit=0.95)
    fold = _curve(take, k, 0, 1, 1, 0, 0, 0)
    skills.crouch(take, 95.0 * fold, 30.0 * fold)
    side = _hand(take)
    up = _curve(take, k, 0, 0, 0, 0, 1, 1)
    skills.set_arm(take, side, 3.0 + 60.0 * fold + 160.0 * up, 6.0, elbow=take.subject.arm_carry * (1 - up))
    skills.set_arm(take, other(side), 3.0 + 60.0 * fold, 6.0, elbow=take.subject.arm_carry)
    for leg in SIDES:
        take[f"{leg}_ankle.dorsi"] -= 15.0 * up
    skills.turn_head(take, flex=-20.0 * up)


# --- the class table ------------------------------------------------------------------------------------------------


def _own(perform: Callable[[Take], None], *modes: str) -> dict:
    """Modes that one perform function of this module tells apart itself."""
    return {mode: perform for mode in modes}


def _theirs(perform: Callable[[Take], None], *modes: str, busy: float | None = None) -> dict:
    """Modes of another class's perform function, run as they are (``busy``: sped up to fit short clips)."""
    run = perform if busy is None else _hurried(perform, busy)
    return {mode: _as(run, mode) for mode in modes}


def _dispatch(table: dict) -> Callable[[Take], None]:
    def perform(take: Take) -> None:
        table[take.mode](take)

    return perform


# One entry per category, in CATEGORIES order: {mode: perform}.
_TABLES = (
    _theirs(cmu.walk, "straight", "curving", "speed changes"),  # walk
    _own(stand, "relaxed", "weight on one leg", "shifting weight"),  # stand
    _own(hand_movements, "both hands", "one hand"),  # hand movements
    _own(turn, "to the left", "to the right"),  # turn
    _own(interact_with_object, "turning a part", "tool in one hand"),  # interact with/use object
    _own(arm_movements, "forward raises", "side raises", "alternating swings"),  # arm movements
    _own(t_pose, "held", "raised into it"),  # t pose
    _own(step, "forward", "to the side"),  # step
    _own(backwards_movement, "walking backwards", "steps back"),  # backwards movement
    _own(raising_body_part, "arm", "leg"),  # raising body part
    _own(look, "around", "up and down"),  # look
    _own(touch_object, "table", "shelf"),  # touch object
    _own(leg_movements, "side raises", "leg shake"),  # leg movements
    _own(forward_movement, "steady", "careful"),  # forward movement
    _own(circular_movement, "walk a circle", "arm circles"),  # circular movement
    {"overhead": _as(uestc.overhead_stretching, "standing"),  # stretch
     "side bend": _as(uestc.left_stretching, "both arms overhead"),
     "arms out and back": _as(ntu1p_extended.stretch_oneself, "arms out and back")},
    _theirs(humanact12.jump, "in place", "forward", busy=1.6),  # jump
    _own(touching_body_part, "shoulder", "knee"),  # touching body part
    _theirs(humanact12.sit, "with hand push", "without hand push", busy=2.6),  # sit
    _own(place_something, "table", "shelf"),  # place something
    _theirs(ntu13.pickup, "squat", "stoop", busy=2.8),  # take/pick something up
    _own(run, "straight", "curving"),  # run
    _own(bend, "forward", "sideways"),  # bend
    _theirs(humanact12.throw, "overarm", "underarm", busy=2.4),  # throw
    _own(foot_movements, "toe taps", "ankle circles"),  # foot movements
    _own(a_pose, "held", "raised into it"),  # a pose
    _theirs(ntu13.standing_up, "with hand push", "without hand push", busy=2.6),  # stand up
    _own(lowering_body_part, "arm", "leg"),  # lowering body part
    _own(sideways_movement, "to the left", "to the right"),  # sideways movement
    {"up stairs": _as(cmu.step, "high steps"), "up low steps": up_low_steps},  # move up/down incline
    _own(action_with_ball, "chest pass", "overhead pass"),  # action with ball
    _theirs(ntu13.kicking_something, "right", "left", busy=1.7),  # kick
    _own(gesture, "beckon", "thumbs up", "talking"),  # gesture
    _own(head_movements, "nod", "shake", "tilts"),  # head movements
    _own(jog, "steady", "slow", "on the spot"),  # jog
    _own(grasp_object, "table", "shelf"),  # grasp object
    _own(waist_movements, "hip circles", "hip sway"),  # waist movements
    {"from the floor": _as(ntu1p_extended.move_heavy_objects, "lift and put down"),  # lift something
     "overhead": lift_overhead},
    {"knee bends": knee_bends, "knee circles": _as(uestc.knee_circling, "clockwise")},  # knee movement
    _theirs(ntu13.hand_waving, "right", "left", "high"),  # wave
    {"push": _as(ntu1p_extended.move_heavy_objects, "push"), "slide aside": slide_aside},  # move something
    {"arms": swing_arms, "leg": _as(humanact12.warm_up, "leg swings")},  # swing body part
    _own(catch, "chest height", "overhead"),  # catch
    _theirs(cmu.dance, "step-touch", "spins"),  # dance
    _own(lean, "sideways", "forward on a table"),  # lean
    _own(greet, "handshake", "raised hand"),  # greet
    _own(poses, "arm poses", "whole body"),  # poses
    _own(touching_face, "chin", "cheek"),  # touching face
    _theirs(ntu1p_extended.tennis_bat_swing, "forehand", "backhand", "serve"),  # sports move
    {"knee-lift punches": _as(uestc.punching_and_knee_lifting, "alternating"),  # exercise/training
     "elbow to knee": _as(uestc.standing_opposite_elbow_to_knee_crunch, "alternating"),
     "high knees": _as(uestc.high_knees_running, "arms pumping")},
    _own(clean_something, "wipe table", "wipe window"),  # clean something
    {"straight punches": _as(uestc.punching, "alternating"), "boxing": _as(humanact12.boxing, "jab-cross")},  # punch
    {"arms forward": _as(_hurried(ntu13.squat_down, 3.5), "arms forward"),  # squat
     "hands on knees": _as(_hurried(ntu13.squat_down, 3.5), "hands on knees"),
     "repeated": _as(uestc.squatting, "arms forward")},
    _own(scratch, "head", "leg"),  # scratch
    _theirs(ntu1p_daily.hopping, "left foot", "right foot"),  # hop
    _theirs(ntu1p_extended.shoot_at_the_basket, "set shot", "jump shot"),  # play sport
    _own(stumble, "forward", "sideways"),  # stumble
    {"arms": _as(ntu1p_extended.cross_arms, "right over left"),  # crossing limbs
     "arms, left over right": _as(ntu1p_extended.cross_arms, "left over right"), "legs": crossing_legs},
    _own(perform, "bow", "ta-da"),  # perform
    {"kata": kata, "side kicks": _as(ntu13.side_kick, "right")},  # martial art
    _own(balance, "one leg", "beam walk"),  # balance
    _own(kneel, "one knee", "both knees"),  # kneel
    _own(shake, "shake out hands", "shimmy"),  # shake
    {"other wrist": grab_wrist, "knee": _as(uestc.knee_to_chest, "right")},  # grab body part
    _theirs(ntu1p_daily.clapping, "chest height", "face height"),  # clap
    _own(crouch, "hands on the floor", "hiding"),  # crouch
    _own(spin, "one turn", "two turns"),  # spin
    _own(upper_body_movements, "torso circles", "rocking"),  # upper body movements
    _own(knock, "knuckles", "pound"),  # knock
    _own(adjust, "collar", "waistband"),  # adjust
    _own(crawl, "steady", "slow"),  # crawl
    _theirs(uestc.standing_rotation, "arms out", "hands on chest"),  # twist
    _own(move_back, "from a step forward", "from a reach"),  # move back to original position
    {"slight": _as(ntu1p_daily.nod_head, "bow"), "deep": deep_bow},  # bow
    _own(hit, "downward strike", "backhand swipe"),  # hit
    _own(touch_ground, "stoop", "squat"),  # touch ground
    {"rolls": _as(uestc.shoulder_raising, "standing"), "pinching back": _as(uestc.pinching_back, "standing")},
    _theirs(humanact12.phone, "right ear", "left ear"),  # telephone call
    _own(grab_person, "both hands", "one hand"),  # grab person
    _own(play_instrument, "guitar", "drums"),  # play instrument
    _own(tap, "shoulder", "screen"),  # tap
    _own(spread, "arms", "legs"),  # spread
    _own(skip, "forward", "in place"),  # skip
    _own(rolling_movement, "forearm roll", "body roll"),  # rolling movement
    _theirs(uestc.rope_skipping, "both feet", "alternate feet"),  # jump rope
    _own(play_catch, "underhand tosses", "overhand throws"),  # play catch
    _theirs(humanact12.drink, "right hand", "left hand"),  # drink
    _own(evade, "duck", "dodge sideways"),  # evade
    _own(support, "hand on wall", "hands on knees"),  # support
    _theirs(ntu1p_daily.pointing, "right hand", "left hand", "pointing up"),  # point
    _own(side_to_side, "weight shift", "step-touch"),  # side to side movement
    _own(stop, "from a walk", "from a jog"),  # stop
    _own(protect, "cover head", "shield face"),  # protect
    {"circles": _as(uestc.wrist_circling, "standing"), "flexing": wrist_flexing},  # wrist movements
    _own(stances, "fighting stance", "ready stance", "horse stance"),  # stances
    _own(wait, "hands behind back", "hands clasped in front"),  # wait
    _own(shuffle, "forward", "sideways"),  # shuffle
    _theirs(uestc.forward_lunging, "alternating", "left leg", "right leg"),  # lunge
    _own(communicate, "both hands", "one hand"),  # communicate (vocalise)
    _theirs(uestc.jumping_jack, "jumping", "stepping"),  # jumping jacks
    _theirs(ntu1p_daily.rub_two_hands, "palm on palm", "washing"),  # rub
    _theirs(ntu1p_extended.bounce_ball, "right hand", "left hand"),  # dribble
    _own(swim, "crawl stroke", "breaststroke"),  # swim
    _own(sneak, "crouched", "tiptoe"),  # sneak
    _own(to_lower_a_body_part, "both arms down", "head down"),  # to lower a body part
    _own(misc_abstract_action, "arms", "whole body"),  # misc. abstract action
    _own(mix, "step, turn and wave", "squat, stand and reach"),  # mix
    _own(limp, "left leg", "right leg"),  # limp
    _own(sway, "side to side", "forward and back"),  # sway
    _own(slide, "to the left", "to the right"),  # slide
    _own(cartwheel, "to the left", "to the right"),  # cartwheel
    _own(press_something, "button", "push with both hands"),  # press something
    _own(shrug, "shoulders only", "palms up"),  # shrug
    {"box lid": _as(ntu1p_extended.open_a_box, "lid"), "bottle": _as(ntu1p_extended.open_bottle, "right hand twists")},
    _own(leap, "left leg leads", "right leg leads"),  # leap
    _own(trip, "left foot catches", "right foot catches"),  # trip
    _own(golf, "full swing", "putt"),  # golf
    _own(move_misc_body_part, "one arm", "one leg"),  # move misc. body part
    _own(get_injured, "stomach", "shoulder", "leg"),  # get injured
    _own(sudden_movement, "startle", "jerk to the side"),  # sudden movement
)

#: The 120 classes, in :data:`CATEGORIES` order, weighted by Zipf's law over the frequency rank.
CLASSES = tuple(ActionClass(name, tuple(table), _dispatch(table), weight=float((rank + 1) ** -ZIPF_EXPONENT))
                for rank, (name, table) in enumerate(zip(CATEGORIES, _TABLES, strict=True)))
