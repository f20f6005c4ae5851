"""Multi-action takes: one performer doing several actions in a row, joined into one continuous take.

A variant of multi-action takes (``Variant.takes``) plans each take as a lead-in (the frames before the first
action, so that it too has real context) and its actions, each with its perform function, style mode, tags and
length. Every piece is performed into a take of its own length by the same performer, from the take's one
generator; the pieces are then joined:

* **Heading and support height carry over.** Each piece starts facing where the previous one ended (its whole
  heading curve shifted), and on the level it ended on (stairs leave the performer higher).
* **Every angle is joined by inertialisation** (Bollo, GDC 2018): the next piece's first frames are offset by the
  difference between where the previous piece was going (its last pose plus its last velocity) and where the next
  one starts, in value and in velocity; the offset decays to zero with a quintic of zero velocity and acceleration
  at its end, over :data:`BLEND_SECONDS` (at most half the piece). Pose and velocity are continuous across every
  boundary, and the transition happens inside the next action's first frames, as in captured takes.
* **Secondary motion and joint limits** (:func:`take.finish`) run once over the joined take, so breathing does not
  restart at a boundary.

The joined take is then posed, grounded and stored by the engine like any other sequence: the root path comes
from the feet over the whole take, so it is continuous too.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable

import numpy as np

from jaxmotion.data.synthetic.body import Subject
from jaxmotion.data.synthetic.take import Take, finish

#: Seconds over which the difference between two joined pieces decays.
BLEND_SECONDS = 0.4


@dataclasses.dataclass(frozen=True)
class PlannedAction:
    """One piece of a take: how to perform it and what it is.

    Attributes:
      perform: writes the piece into a take (a class's perform function, or a composition of several).
      mode: the style mode's name the perform function reads.
      frames: its length.
      tags: the tag indices it carries (first = its main tag); empty for a lead-in, which is no action.
      mode_index: the mode's index within the main tag's modes (-1 for a lead-in).
    """

    perform: Callable[[Take], None]
    mode: str
    frames: int
    tags: tuple[int, ...] = ()
    mode_index: int = -1


@dataclasses.dataclass(frozen=True)
class TakePlan:
    """A lead-in followed by the actions of one take."""

    lead_in: PlannedAction
    actions: tuple[PlannedAction, ...]

    @property
    def pieces(self) -> tuple[PlannedAction, ...]:
        return (self.lead_in, *self.actions)

    @property
    def num_frames(self) -> int:
        return sum(p.frames for p in self.pieces)


@dataclasses.dataclass(frozen=True)
class Joined:
    """A joined take before posing: the engine's inputs, per frame."""

    angles: np.ndarray  # [T, J, 3] degrees, finished (within the joint limits)
    contact: np.ndarray  # [T, 2]
    ground: np.ndarray  # [T, 2]
    flight_speed: np.ndarray  # [T]
    flight_carry: np.ndarray  # [T]


def perform_plan(plan: TakePlan, fps: float, rng: np.random.Generator, subject: Subject) -> Joined:
    """Perform every piece of ``plan`` and join them (module docstring)."""
    pieces = []
    for piece in plan.pieces:
        take = Take(piece.frames, fps, rng, subject, piece.mode)
        piece.perform(take)
        pieces.append(take)
    angles = pieces[0].angles.copy()
    contact, ground = [pieces[0].contact], [pieces[0].ground]
    for previous, take in zip(pieces[:-1], pieces[1:]):
        nxt = take.angles.copy()
        nxt[:, 0, 0] += angles[-1, 0, 0] - nxt[0, 0, 0]  # pelvis heading: continue from where it ended
        angles = np.concatenate([angles, inertialized(angles[-2:], nxt, round(BLEND_SECONDS * fps))])
        contact.append(take.contact)
        ground.append(take.ground + ground[-1][-1].mean() - take.ground[0].mean())
    whole = Take(len(angles), fps, rng, subject, "")
    whole.angles = angles
    lengths = [t.num_frames for t in pieces]
    per_frame = (lambda values: np.repeat(np.asarray(values, float), lengths))
    return Joined(finish(whole), np.concatenate(contact), np.concatenate(ground),
                  per_frame([t.flight_speed for t in pieces]), per_frame([t.flight_carry for t in pieces]))


def inertialized(before: np.ndarray, after: np.ndarray, blend: int) -> np.ndarray:
    """``after [T, ...]`` with the offset that continues ``before [2, ...]`` (the previous piece's last two frames)
    added to its first frames and decayed to zero over ``blend`` frames (at most half of ``after``): value and
    velocity continuous at the join (module docstring)."""
    velocity = before[-1] - before[-2]
    start = before[-1] + velocity  # where the previous piece was going
    offset = start - after[0]
    rate = velocity - (after[1] - after[0]) if len(after) > 1 else np.zeros_like(offset)
    span = max(min(blend, len(after) // 2), 1)
    frames = np.arange(len(after), dtype=float).reshape(-1, *([1] * offset.ndim))
    return after + _quintic(frames, float(span), offset, rate)


def _quintic(t: np.ndarray, span: float, x0: np.ndarray, v0: np.ndarray) -> np.ndarray:
    """The decay ``x(t)`` with ``x(0) = x0``, ``x'(0) = v0``, ``x''(0) = 0`` and ``x = x' = x'' = 0`` at ``span`` (and
    after it)."""
    a = -(6.0 * v0 * span + 12.0 * x0) / (2.0 * span ** 5)
    b = (16.0 * v0 * span + 30.0 * x0) / (2.0 * span ** 4)
    c = -(12.0 * v0 * span + 20.0 * x0) / (2.0 * span ** 3)
    tc = np.minimum(t, span)
    return np.where(t < span, ((((a * tc + b) * tc + c) * tc) * tc + v0) * tc + x0, 0.0)
