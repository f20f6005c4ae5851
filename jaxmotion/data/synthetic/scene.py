"""Several persons acting together: scenes of P takes in one world, with contacts resolved on the posed bodies.

A scene class ``perform(scene)`` composes each person's :class:`~take.Take` from the skills (as one-person
classes do), puts the persons where they start (:meth:`Scene.place`) and declares what can only be decided
on the posed bodies:

* **reaches**: a hand (its wrist) goes to a world point that depends on the posed bodies (the partner's
  chest, a meeting point between two persons' shoulders) as an envelope goes 0 -> 1;
* **strikes**: at a given time a joint of one person (a kicking foot, a charging shoulder) must be at a
  point of another; the receiver is moved (horizontally, as a whole) so that it is.

:func:`pose_scenes` poses a batch of scenes: every person's clean angles (:func:`take.finish`) are posed
about the origin and grounded (:mod:`grounding`), the persons are moved to their places and the strikes
aligned; then each reach is solved by two-bone inverse kinematics in the reaching person's thorax frame
(:func:`skills.reach`), blended into the arm's own motion by the envelope, and corrected once by the
residual measured on the re-posed body (the collar's secondary motion moves the shoulder a little). Arms
never move the feet, so the root paths found by the grounding stay valid.

Persons do not walk through each other by construction of the classes: their places and steps keep
bodies apart except where the class makes them touch (tested in ``tests/test_synthetic_scenes.py``).

Axes: P persons, T frames, J = 24 SMPL joints.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Sequence

import jax
import jax.numpy as jnp
import numpy as np

from jaxmotion.data.synthetic import anatomy, grounding, skills
from jaxmotion.data.synthetic.body import Subject
from jaxmotion.data.synthetic.take import SIDES, Take, finish
from jaxmotion.geometry.kinematics import forward_kinematics_transforms
from jaxmotion.geometry.skeletons import SMPL24

_SPINE3 = SMPL24.index("spine3")
_ANKLES = (SMPL24.index("left_ankle"), SMPL24.index("right_ankle"))
_TOES = (SMPL24.index("left_foot"), SMPL24.index("right_foot"))
_ARM_CHANNELS = ("shoulder.plane", "shoulder.elev", "shoulder.rot", "elbow.flex")
_BLEND = 0.25  # envelope value from which a reach fully owns the arm (below it, blended with the arm's own motion)


class World:
    """The posed bodies of one scene, for reach and strike targets: world joints ``[P, T, 24, 3]`` and global
    joint rotations ``[P, T, 24, 3, 3]``; sizes of the persons (relative to the 1.70 m template)."""

    def __init__(self, joints: np.ndarray, rotations: np.ndarray, scales: Sequence[float]):
        self.joints, self.rotations, self.scales = joints, rotations, tuple(scales)

    def joint(self, person: int, name: str) -> np.ndarray:
        """``[T, 3]`` a joint's world position."""
        return self.joints[person, :, SMPL24.index(name)]

    def point(self, person: int, name: str, offset) -> np.ndarray:
        """``[T, 3]`` a point fixed in a joint's frame: ``offset`` metres (template size; scaled with the
        person) along the joint's axes (x the person's left, y up, z forward at rest)."""
        j = SMPL24.index(name)
        return self.joints[person, :, j] + self.rotations[person, :, j] @ (self.scales[person] * np.asarray(offset, float))

    def between(self, a: np.ndarray, b: np.ndarray, share: float = 0.5) -> np.ndarray:
        """``[T, 3]`` the point ``share`` of the way from ``a`` to ``b``."""
        return a + share * (b - a)


@dataclasses.dataclass
class Reach:
    """``person``'s ``side`` wrist to ``target(world) [T, 3]`` as ``envelope [T]`` goes 0 -> 1."""

    person: int
    side: str
    envelope: np.ndarray
    target: Callable[[World], np.ndarray]
    elbow_hint: tuple[float, float, float] = (0.4, -1.0, -0.3)


@dataclasses.dataclass
class Strike:
    """At ``time`` (s), ``striker(world) [T, 3]`` must be ``gap`` metres short of ``target(world) [T, 3]`` on
    ``receiver``: the receiver is moved horizontally, along the line from the striker's point, to make it so."""

    receiver: int
    time: float
    striker: Callable[[World], np.ndarray]
    target: Callable[[World], np.ndarray]
    gap: float = 0.0


class Scene:
    """P persons' takes over the same frames, where each starts, and the contacts to resolve.

    Attributes:
      takes: one :class:`Take` per person (their own subjects, tempo and amplitude; one shared generator).
      places: ``[P, 3]`` where each person's root starts on the floor (x, 0, z), world metres.
      reaches, strikes: what :func:`pose_scenes` resolves on the posed bodies.
      mode: the style mode's name, shared by the persons.
    """

    def __init__(self, num_frames: int, fps: float, rng: np.random.Generator, subjects: Sequence[Subject], mode: str):
        self.takes = tuple(Take(num_frames, fps, rng, s, mode) for s in subjects)
        self.places = np.zeros((len(subjects), 3))
        self.reaches: list[Reach] = []
        self.strikes: list[Strike] = []
        self.mode = mode
        self.rng = rng

    @property
    def persons(self) -> int:
        return len(self.takes)

    @property
    def t(self) -> np.ndarray:
        return self.takes[0].t

    @property
    def duration(self) -> float:
        return self.takes[0].duration

    def place(self, person: int, x: float, z: float) -> None:
        """Start ``person``'s root at (x, z) on the floor (it faces where its take's heading says)."""
        self.places[person] = (x, 0.0, z)

    def reach(self, person: int, side: str, envelope: np.ndarray, target: Callable[[World], np.ndarray], *,
              elbow_hint=(0.4, -1.0, -0.3)) -> None:
        self.reaches.append(Reach(person, side, np.asarray(envelope, float), target, tuple(elbow_hint)))

    def strike(self, receiver: int, time: float, striker: Callable[[World], np.ndarray],
               target: Callable[[World], np.ndarray], *, gap: float = 0.0) -> None:
        self.strikes.append(Strike(receiver, time, striker, target, gap))


@dataclasses.dataclass(frozen=True)
class SceneClass:
    """A class of scenes: its name, its style modes and the function that performs a scene.

    ``touches``: the body parts the class brings into contact, as pairs ``((person, joints), (person,
    joints))`` of SMPL joint names (a part is the chain through its joints): what the tests check comes
    within reach at some frame; empty for classes without contact, whose persons must then stay apart.
    """

    name: str
    modes: tuple[str, ...]
    perform: Callable[[Scene], None]
    weight: float = 1.0
    touches: tuple[tuple[tuple[int, tuple[str, ...]], tuple[int, tuple[str, ...]]], ...] = ()


# --- posing ------------------------------------------------------------------------------------------------

@jax.jit
def _pose(rotmats, offsets):
    """``[F, J, 3, 3]``, ``[F, J, 3]`` -> (joints about the origin, global rotations)."""
    rotations, joints = forward_kinematics_transforms(rotmats, jnp.zeros(rotmats.shape[:1] + (3,)), offsets,
                                                      SMPL24.parents)
    return joints, rotations


def _pose_all(angles: list[np.ndarray], offsets: list[np.ndarray], chunk: int) -> tuple[np.ndarray, np.ndarray]:
    """Every person's angles ``[T, J, 3]`` (degrees) posed about the origin, in one padded pass: -> joints
    ``[F, J, 3]`` and global rotations ``[F, J, 3, 3]`` for the concatenated frames."""
    frames = sum(len(a) for a in angles)
    if frames > chunk:
        raise ValueError(f"scene batch of {frames} frames exceeds the chunk of {chunk}")
    padded = np.zeros((chunk, SMPL24.num_joints, 3), np.float32)
    padded[:frames] = np.concatenate(angles)
    body = np.zeros((chunk, SMPL24.num_joints, 3), np.float32)
    body[:frames] = np.concatenate([np.broadcast_to(o, a.shape) for a, o in zip(angles, offsets)])
    joints, rotations = _pose(anatomy.angles_to_rotmats_f32(padded), body)
    return np.asarray(joints)[:frames], np.asarray(rotations)[:frames]


def _roots(take: Take, joints: np.ndarray, rotations: np.ndarray) -> np.ndarray:
    """``[T, 3]`` the grounded root path of a take posed about the origin."""
    soles = np.stack([
        grounding.sole_points(joints[:, a], rotations[:, a], joints[:, toe], take.subject.offsets[toe],
                              take.subject.height / 1.70)
        for a, toe in zip(_ANKLES, _TOES)], axis=1)
    heading = np.radians(take.angles[:, 0, 0])
    return grounding.root_translation(soles, take.contact, take.ground, heading, take.fps, take.flight_speed,
                                      take.flight_carry)


def _local(world_points: np.ndarray, world: World, person: int, side: str) -> np.ndarray:
    """World points ``[T, 3]`` -> the person's thorax frame, side-normalised (x away from the midline)."""
    p3, r3 = world.joints[person, :, _SPINE3], world.rotations[person, :, _SPINE3]
    local = np.einsum("tji,tj->ti", r3, world_points - p3)
    if side == "right":
        local[:, 0] *= -1.0
    return local


def _wrap(degrees: np.ndarray) -> np.ndarray:
    return (degrees + 180.0) % 360.0 - 180.0


def _apply_reach(take: Take, reach: Reach, target_local: np.ndarray, now_local: np.ndarray) -> None:
    """Solve one reach into ``take.angles`` (already finished): IK toward ``target_local`` from where the wrist
    is ``now_local`` (both ``[T, 3]``), blended into the arm's own channels by the envelope."""
    env = np.clip(reach.envelope, 0.0, 1.0)
    names = [f"{reach.side}_{c}" for c in _ARM_CHANNELS]
    before = {n: take[n].copy() for n in names}
    skills.reach(take, reach.side, now_local + env[:, None] * (target_local - now_local),
                 elbow_hint=reach.elbow_hint)
    weight = np.clip(env / _BLEND, 0.0, 1.0)
    for n in names:
        delta = _wrap(take[n] - before[n]) if n.endswith("plane") else take[n] - before[n]
        take[n] = before[n] + weight * delta


def pose_scenes(scenes: Sequence[Scene], chunk: int) -> list[tuple[np.ndarray, np.ndarray]]:
    """Resolve and pose scenes (module docstring): per scene ``(angles [P, T, J, 3] degrees within the joint
    limits, translation [P, T, 3] world root paths)``. All their frames must fit in ``chunk``.

    Reach targets must not depend on anybody's arms (they are read off the bodies posed before any reach)."""
    takes = [t for s in scenes for t in s.takes]
    for take in takes:
        take.angles = finish(take)
    offsets = [t.subject.offsets for t in takes]
    joints, rotations = _pose_all([t.angles for t in takes], offsets, chunk)
    starts = np.cumsum([0] + [t.num_frames for t in takes])
    roots = [_roots(t, joints[a:b], rotations[a:b]) for t, a, b in zip(takes, starts[:-1], starts[1:])]

    def worlds(joints, rotations):
        out, k = [], 0
        for s in scenes:
            part = range(k, k + s.persons)
            placed = np.stack([joints[starts[i]:starts[i + 1]] + (roots[i] + s.places[i - k])[:, None] for i in part])
            out.append(World(placed, np.stack([rotations[starts[i]:starts[i + 1]] for i in part]),
                             [takes[i].scale() for i in part]))
            k += s.persons
        return out

    world = worlds(joints, rotations)
    for s, w in zip(scenes, world):
        for strike in s.strikes:
            frame = int(np.clip(round(strike.time * s.takes[0].fps), 0, s.takes[0].num_frames - 1))
            hit, aim = strike.striker(w)[frame], strike.target(w)[frame]
            away = (aim - hit) * np.array([1.0, 0.0, 1.0])
            distance = np.linalg.norm(away)
            shift = -away + (strike.gap * away / distance if distance > 1e-9 else 0.0)
            s.places[strike.receiver] += shift
            w.joints[strike.receiver] += shift
    # Each reach: from the arm's own path (read once, before any reach) to a target fixed on the bodies; solved,
    # then solved again from the same start with the target corrected by the residual of the first solution.
    plans = []
    for s, w in zip(scenes, world):
        for r in s.reaches:
            wrist = SMPL24.index(f"{r.side}_wrist")
            plans.append((s, r, wrist, _local(r.target(w), w, r.person, r.side),
                          _local(w.joints[r.person, :, wrist], w, r.person, r.side)))
    base = {id(t): t.angles.copy() for s in scenes if s.reaches for t in s.takes}
    correction = [np.zeros(3)] * len(plans)
    for round_ in range(2):
        for s in scenes:
            for t in s.takes if s.reaches else ():
                t.angles = base[id(t)].copy()
        for k, (s, r, wrist, target, start) in enumerate(plans):
            _apply_reach(s.takes[r.person], r, target + correction[k], start)
        for s in scenes:
            for t in s.takes if s.reaches else ():
                t.angles = anatomy.clip_to_limits(t.angles)
        if round_ == 1 or not plans:
            break
        reached = worlds(*_pose_all([t.angles for t in takes], offsets, chunk))
        by_scene = {id(s): w for s, w in zip(scenes, reached)}
        for k, (s, r, wrist, target, start) in enumerate(plans):
            w = by_scene[id(s)]
            miss = target - _local(w.joints[r.person, :, wrist], w, r.person, r.side)
            correction[k] = np.where((r.envelope >= 0.99)[:, None], miss, 0.0)
    out, k = [], 0
    for s in scenes:
        out.append((np.stack([t.angles for t in s.takes]),
                    np.stack([roots[k + p] + s.places[p] for p in range(s.persons)])))
        k += s.persons
    return out


def facing(scene: Scene, person: int, other: int) -> float:
    """Heading (degrees, 0 = +Z, + = to the left about +Y) from ``person``'s place toward ``other``'s."""
    d = scene.places[other] - scene.places[person]
    return float(np.degrees(np.arctan2(d[0], d[2])))


__all__ = ["Reach", "Scene", "SceneClass", "Strike", "World", "facing", "pose_scenes", "SIDES"]
