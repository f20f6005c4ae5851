"""GTA Combat's one class, "combat", for 2-5 persons: each fights one randomly chosen other.

The persons start on a ring, each facing the opponent it picked at random among its two nearest (two may pick
each other, or a third person).
Over the clip every fighter bounces in a guard (knees bent, fists at the chin, MOTION_FACTS 3.5 and 4 for
boxing) and, in turns, steps in and strikes its opponent: a jab or cross, a hook, a front kick, or (brawling)
a wide overhand swing. The opponent blocks (forearms up), dodges (leans away and steps back), or is hit:
it recoils 0.1-0.3 s after contact and staggers back, or (brawling, more often) goes down to a knee, a hand
on the floor, and gets up (MOTION_FACTS 5). A strike within reach lands on the opponent (its hand is solved
onto the opponent's head or chest on the posed bodies, :mod:`scene`); out of reach it is a feint and nobody
reacts. Mode names are the styles: ``boxing`` (fists only, few knockdowns) and ``brawling``.
"""

from __future__ import annotations

import numpy as np

from jaxmotion.data.synthetic import skills, timing
from jaxmotion.data.synthetic.scene import Scene, SceneClass, World
from jaxmotion.data.synthetic.take import SIDES, Take, other

_REACH = {"jab": 0.55, "hook": 0.5, "swing": 0.55, "kick": 0.85}  # root-to-root distance a strike lands from (m)


def _guard(take: Take, bounce_hz: float) -> None:
    """The fighting stance: knees soft with a small bounce, trunk a little forward, fists by the chin."""
    bounce = 0.5 + 0.5 * np.sin(2 * np.pi * bounce_hz * take.t + take.uniform(0, 2 * np.pi))
    skills.crouch(take, 18.0 + 10.0 * bounce, 8.0)
    guard = skills.landmark(take, "chin") + take.scale() * np.array([0.0, -0.05, 0.06])
    for side in SIDES:
        skills.reach(take, side, guard, elbow_hint=(0.3, -1.0, 0.0))


def _knockdown(take: Take, time: float, duration: float) -> None:
    """Down to a crouch, trunk pitched, one hand to the floor, then back up into the guard."""
    keys = time + duration * np.array([0.0, 0.25, 0.65, 1.0])
    down = timing.keyframes(take.t, keys, [0.0, 1.0, 1.0, 0.0])
    skills.crouch(take, 105.0 * down, 55.0 * down, heel=15.0 * down)
    side = take.choice(SIDES)
    skills.set_arm(take, side, take[f"{side}_shoulder.elev"] * (1 - down) + 60.0 * down, 20.0 * down,
                   elbow=15.0 + 20.0 * (1 - down))


def combat(scene: Scene) -> None:
    persons = scene.persons
    rng = scene.rng
    brawling = scene.mode == "brawling"
    radius = 0.55 + 0.15 * (persons - 2)  # 1.1 m between two; neighbours ~1.2 m apart on a ring of five
    start = rng.uniform(0.0, 2.0 * np.pi)
    for p in range(persons):
        angle = start + 2.0 * np.pi * p / persons + rng.normal(0.0, 0.15)
        r = radius * rng.uniform(0.9, 1.15)
        scene.place(p, r * np.sin(angle), r * np.cos(angle))
    # each picks one of its two nearest others at random (with five on a ring, someone across it is out of reach)
    def nearest(p):
        d = np.linalg.norm((scene.places - scene.places[p])[:, [0, 2]], axis=-1)
        return [int(q) for q in np.argsort(d)[1:3]]
    foes = [int(rng.choice(nearest(p))) for p in range(persons)]
    for p, take in enumerate(scene.takes):
        d = scene.places[foes[p]] - scene.places[p]
        take["pelvis.heading"] += np.degrees(np.arctan2(d[0], d[2])) + rng.normal(0.0, 3.0)
        _guard(take, take.vary(1.6, 0.15))
    # turns: fighters strike in a shuffled order, one attack starting every ~0.5-0.9 s
    busy = np.zeros(persons)  # until when each person is busy attacking (s)
    guarded = np.zeros(persons)  # until when each person is busy defending or reacting (s)
    t = rng.uniform(0.2, 0.6)
    strikes = {p: [] for p in range(persons)}
    while t < scene.duration - 1.0:
        free = [p for p in range(persons) if busy[p] <= t and guarded[p] <= t]
        if free:
            p = int(rng.choice(free))
            foe = foes[p]
            kinds = ["jab", "hook"] + (["kick", "swing"] if brawling else [])
            kind = str(rng.choice(kinds))
            take = scene.takes[p]
            gap = float(np.linalg.norm((scene.places[foe] - scene.places[p])[[0, 2]]))
            step = min(max(2.0 * (gap - _REACH[kind]), 0.0), 1.0)  # a step of L carries the pelvis L / 2
            lead = take.choice(SIDES)
            skills.stance_steps(take, [(t, 0.3, lead, step), (t + 0.9, 0.35, lead, 0.0)], lift=0.5)
            hit_time = t + 0.45
            lands = gap - step / 2.0 <= _REACH[kind] + 0.05
            side = take.choice(SIDES)
            if kind == "kick":
                skills.kick(take, side, hit_time - 0.5, height=take.uniform(0.6, 0.9), duration=0.9)
            else:
                strikes[p].append((kind, side, t + 0.15, hit_time, foe))
            busy[p] = t + 1.3
            if lands and guarded[foe] <= hit_time - 0.3:
                _defend(scene.takes[foe], hit_time, rng, brawling, scene.duration)
                guarded[foe] = hit_time + (2.4 if brawling else 1.0)
        t += rng.uniform(0.5, 0.9)
    for p, moves in strikes.items():
        for side in SIDES:
            mine = [m for m in moves if m[1] == side]
            if mine:
                _strike_arm(scene, p, side, mine)


def _defend(take: Take, hit: float, rng: np.random.Generator, brawling: bool, clip: float) -> None:
    """The opponent's answer to a strike landing at ``hit``: block, dodge or take it."""
    roll = rng.uniform()
    if roll < 0.3:  # block: forearms up in front of the face
        up = timing.keyframes(take.t, [hit - 0.25, hit - 0.05, hit + 0.3, hit + 0.6], [0, 1, 1, 0])
        for side in SIDES:
            take[f"{side}_shoulder.elev"] += 35.0 * up
            take[f"{side}_elbow.flex"] += 20.0 * up
    elif roll < 0.55:  # dodge: lean away and step back
        away = timing.keyframes(take.t, [hit - 0.25, hit, hit + 0.5], [0, 1, 0])
        take["spine2.flex"] -= 15.0 * away
        take["spine1.bend"] += take.choice((-12.0, 12.0)) * away
        side = take.choice(SIDES)
        skills.stance_steps(take, [(hit - 0.2, 0.3, side, -0.3 * take.scale()), (hit + 0.3, 0.35, other(side), 0.0)],
                            lift=0.5)
    else:  # hit: recoil, then stagger back or go down and get up
        skills.recoil(take, hit, strength=take.uniform(0.8, 1.3), where=take.choice(("head", "chest", "stomach")))
        down = rng.uniform() < (0.5 if brawling else 0.1) and hit + 2.2 < clip
        if down:
            _knockdown(take, hit + 0.15, take.vary(2.0, 0.1))
        else:
            side = take.choice(SIDES)
            back = take.vary(0.35, 0.15) * take.scale()
            skills.stance_steps(take, [(hit + 0.15, 0.35, side, -back), (hit + 0.55, 0.35, other(side), 0.0)],
                                lift=0.6)


def _strike_arm(scene: Scene, person: int, side: str, moves) -> None:
    """One arm's strikes as one reach: out from the guard to the opponent's head or chest at each hit time,
    back after it (a jab straight, a hook round from the side, a swing from above)."""
    take = scene.takes[person]
    env = np.zeros(take.num_frames)
    spans = []
    for kind, _, go, hit, foe in moves:
        bump = timing.keyframes(take.t, [go, hit, hit + 0.1, hit + 0.45], [0, 1, 1, 0])
        env = np.maximum(env, bump)
        spans.append((go, hit + 0.45, kind, foe))
    sign = 1.0 if side == "left" else -1.0

    def target(w: World):
        out = np.zeros((take.num_frames, 3))
        for go, end, kind, foe in spans:
            now = (take.t >= go) & (take.t <= end)
            aim = w.point(foe, "head", (0.0, -0.02, 0.0)) if kind != "hook" else w.point(foe, "spine3", (0.0, 0.1, 0.0))
            shoulder = w.joint(person, f"{side}_shoulder")
            d = aim - shoulder
            d /= np.linalg.norm(d, axis=-1, keepdims=True)
            lateral = np.cross(np.array([0.0, 1.0, 0.0]), d) * sign  # outward, for the hook's arc
            arc = np.clip((take.t - go) / max(end - go, 1e-3), 0.0, 1.0)[:, None]
            if kind == "hook":
                aim = aim + 0.2 * np.sin(np.pi * arc) * lateral
            elif kind == "swing":
                aim = aim + 0.25 * np.sin(np.pi * arc) * np.array([0.0, 1.0, 0.0])
            out[now] = aim[now] - 0.06 * d[now]  # the wrist just short, so the fist lands
        return out

    scene.reach(person, side, env, target, elbow_hint=(0.6, -0.8, -0.2))
    skills.turn_trunk(take, (15.0 if side == "right" else -15.0) * env)


CLASSES = (SceneClass("combat", ("boxing", "brawling"), combat),)
