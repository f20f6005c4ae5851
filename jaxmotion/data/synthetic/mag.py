"""synth-mag: BABEL-MAG's 31 tags (Neural Marionette) as actions of continuous multi-action takes.

**Tags** (:mod:`jaxmotion.data.mag_tags`, the paper's supplement, Table 1): 7 intention tags that move the root, 17
intention tags in place, 3 body states and 4 body-part movements, in the paper's order and ids. An intention action carries its one tag; a
non-intention action carries a body state and zero or more body parts (multi-hot), as BABEL-MAG's tagging
protocol has it (its per-tag counts sum to 8,924 over 7,643 actions: every body-part tag rides on a body state).
Leg and waist movements come with standing only (they need the stance); head and arm movements with any state.

**Counts** are the paper's, at scale 1 (:data:`SCALE`): each tag's actions and occurrences as Table 1 lists them.
The test split holds ``min(round(20 %), 100)`` of each tag (the paper's "20% to 100 samples"), the train split the
rest; the two are planned as separate takes, so no test action shares a take with a train action.

**Takes.** Each split is assembled into takes of 3-8 actions (fewer where a pool runs dry) by drawing each next
action from the plausible followers of the current one (:data:`FOLLOWERS`, weights times the actions left of
each tag): a few pairs dominate (turn and walk both ways, stand and walk), most are rare, implausible ones never
occur (nothing but sitting or standing up follows "Sit Down"; "Stand Up" only follows a seated state). A take
starts with a lead-in of 8-30 frames (standing, or seated before a seated action), so every action has real
context frames; the actions are joined continuously by :mod:`chain`. Root-motion tags move the root (walks
straight and curving, backwards, sideways, up and down steps, runs, jumps); in-place tags keep it near a spot.

**Motion.** Every tag reuses the perform function of the BABEL-120 stand-in for its category
(:data:`REUSED`; its modes are the tag's style modes); three are compositions: "Sit" (standing sway on a seated
body), "Using Object and Sit" (using an object, seated) and "Step and Touch Body Part" (a step, the upper body
touching). A body state with body parts is performed as the body part that needs the stance (leg, waist) or the
state, with the other parts' joints taken from their own performance. Durations per tag are drawn from
:data:`SECONDS` (the paper's examples run 1.1-3.0 s; most here 1-4 s); 30 fps; 40 performers.
"""

from __future__ import annotations

import zlib
from collections.abc import Callable

import numpy as np

from jaxmotion.data.mag_tags import KINDS, TAG_NAMES, TAGS
from jaxmotion.data.synthetic import babel120, skills
from jaxmotion.data.synthetic.chain import PlannedAction, TakePlan
from jaxmotion.data.synthetic.engine import ActionClass
from jaxmotion.data.synthetic.take import Take
from jaxmotion.geometry.skeletons import SMPL24

#: The paper's action counts are used as they are.
SCALE = 1.0
FPS = 30.0
#: Actions per take (inclusive); the last takes of a split may be shorter.
ACTIONS_PER_TAKE = (3, 8)
#: Lead-in frames before a take's first action (its context; Neural Marionette reads 6).
LEAD_IN_FRAMES = (8, 30)
_PLAN_STREAM = 2_000_003  # keeps the planner's generator apart from the takes'


#: Seconds an action led by each tag lasts (drawn uniformly; the paper's examples run 1.1-3.0 s).
SECONDS = {
    "Walk": (1.5, 4.0), "Walk Backward": (1.5, 3.0), "Walk Sideway": (1.5, 3.0), "Walk Upward/Downward": (2.0, 4.0),
    "Step": (1.0, 2.5), "Run": (1.5, 3.5), "Jump": (1.2, 2.5), "Turn": (1.0, 2.5), "Sit Down": (2.0, 3.5),
    "Stand Up": (2.0, 3.5), "Using Object": (2.0, 4.0), "Take Something Up": (2.0, 3.5),
    "Place Something Down": (2.0, 3.5), "Move Something": (2.0, 4.0), "Throw": (1.5, 3.0),
    "Touch Something": (1.5, 3.0), "Kick": (1.2, 2.5), "Punch": (1.2, 3.0), "Wave Hand": (1.5, 3.0),
    "Stretch": (2.0, 4.0), "Crossing Limbs": (1.5, 3.0), "Touch Body Part": (1.5, 3.0),
    "Using Object and Sit": (2.0, 4.0), "Step and Touch Body Part": (2.0, 3.5), "Stand": (1.0, 3.0),
    "Bend": (1.5, 3.5), "Sit": (1.5, 3.5),
}
_ID = {name: i for i, name in enumerate(TAG_NAMES)}

#: The BABEL-120 stand-in's category each tag is performed as.
REUSED = {
    "Walk": "walk", "Walk Backward": "backwards movement", "Walk Sideway": "sideways movement",
    "Walk Upward/Downward": "move up/down incline", "Step": "step", "Run": "run", "Jump": "jump", "Turn": "turn",
    "Sit Down": "sit", "Stand Up": "stand up", "Using Object": "interact with/use object",
    "Take Something Up": "take/pick something up", "Place Something Down": "place something",
    "Move Something": "move something", "Throw": "throw", "Touch Something": "touch object", "Kick": "kick",
    "Punch": "punch", "Wave Hand": "wave", "Stretch": "stretch", "Crossing Limbs": "crossing limbs",
    "Touch Body Part": "touching body part", "Stand": "stand", "Bend": "bend", "Head Movement": "head movements",
    "Arm Movement": "arm movements", "Waist Movement": "waist movements", "Leg Movement": "leg movements",
}
_BABEL = {c.name: c for c in babel120.CLASSES}

#: Tags whose action starts seated (a take beginning with one gets a seated lead-in); which actions end seated is
#: in FOLLOWERS, which lets only seated actions follow them.
STARTS_SEATED = frozenset({"Stand Up", "Sit", "Using Object and Sit"})

#: Plausible next actions (by their first tag) and their weights; any other order does not occur.
FOLLOWERS: dict[str, dict[str, float]] = {
    "Walk": {"Turn": 10, "Stand": 6, "Step": 2, "Walk Upward/Downward": 2, "Take Something Up": 2,
             "Place Something Down": 2, "Touch Something": 2, "Run": 1, "Walk Backward": 1, "Walk Sideway": 1,
             "Using Object": 1, "Move Something": 1, "Sit Down": 1, "Jump": 0.5, "Stretch": 0.5},
    "Walk Backward": {"Walk": 3, "Turn": 3, "Stand": 3, "Step": 1},
    "Walk Sideway": {"Walk": 3, "Stand": 3, "Step": 2, "Turn": 1},
    "Walk Upward/Downward": {"Walk": 5, "Turn": 3, "Stand": 2, "Step": 1},
    "Step": {"Stand": 4, "Turn": 4, "Walk": 3, "Step": 1, "Touch Something": 2, "Take Something Up": 1,
             "Place Something Down": 1, "Kick": 1, "Step and Touch Body Part": 1},
    "Run": {"Walk": 3, "Stand": 3, "Turn": 2, "Jump": 1},
    "Jump": {"Stand": 3, "Walk": 2, "Jump": 2, "Step": 1, "Run": 1},
    "Turn": {"Walk": 10, "Stand": 5, "Step": 3, "Run": 1, "Walk Backward": 1, "Walk Sideway": 1,
             "Take Something Up": 1, "Place Something Down": 1, "Touch Something": 1, "Using Object": 1,
             "Sit Down": 1},
    "Sit Down": {"Sit": 6, "Using Object and Sit": 2, "Stand Up": 2},
    "Stand Up": {"Walk": 4, "Stand": 4, "Turn": 2, "Step": 1, "Stretch": 1},
    "Using Object": {"Stand": 3, "Place Something Down": 2, "Turn": 2, "Walk": 2, "Touch Something": 1},
    "Take Something Up": {"Place Something Down": 4, "Walk": 3, "Turn": 3, "Throw": 2, "Stand": 2,
                          "Using Object": 2, "Move Something": 1},
    "Place Something Down": {"Stand": 3, "Walk": 3, "Turn": 3, "Take Something Up": 2, "Touch Something": 1},
    "Move Something": {"Place Something Down": 2, "Walk": 2, "Stand": 2, "Turn": 1},
    "Throw": {"Stand": 3, "Walk": 2, "Take Something Up": 1, "Turn": 1},
    "Touch Something": {"Stand": 3, "Walk": 2, "Turn": 2, "Take Something Up": 2, "Using Object": 1},
    "Kick": {"Stand": 3, "Step": 2, "Kick": 1, "Punch": 1, "Walk": 1},
    "Punch": {"Stand": 3, "Kick": 2, "Punch": 1, "Step": 1},
    "Wave Hand": {"Stand": 3, "Walk": 2, "Turn": 1},
    "Stretch": {"Stand": 4, "Bend": 2, "Stretch": 1, "Walk": 1, "Crossing Limbs": 1, "Touch Body Part": 1},
    "Crossing Limbs": {"Stand": 3, "Stretch": 1, "Walk": 1},
    "Touch Body Part": {"Stand": 3, "Walk": 1, "Stretch": 1, "Turn": 1},
    "Using Object and Sit": {"Sit": 3, "Stand Up": 3},
    "Step and Touch Body Part": {"Stand": 2, "Step": 2, "Walk": 1},
    "Stand": {"Walk": 6, "Turn": 5, "Step": 3, "Stand": 2, "Stretch": 2, "Take Something Up": 2,
              "Touch Something": 2, "Using Object": 2, "Bend": 2, "Touch Body Part": 2, "Wave Hand": 1,
              "Sit Down": 1, "Throw": 1, "Kick": 1, "Punch": 1, "Crossing Limbs": 1, "Place Something Down": 1,
              "Run": 1, "Jump": 1, "Walk Backward": 1, "Walk Sideway": 1, "Move Something": 1,
              "Step and Touch Body Part": 1},
    "Bend": {"Stand": 4, "Take Something Up": 2, "Place Something Down": 2, "Stretch": 1, "Touch Something": 1},
    "Sit": {"Stand Up": 4, "Sit": 2, "Using Object and Sit": 1},
}

# Joints a body part moves (overlaid from its own performance) and the upper body a touch takes.
_HEAD = tuple(SMPL24.index(j) for j in ("neck", "head"))
_ARMS = tuple(SMPL24.index(f"{side}_{j}") for side in ("left", "right")
              for j in ("collar", "shoulder", "elbow", "wrist", "hand"))
_UPPER = (*(SMPL24.index(j) for j in ("spine1", "spine2", "spine3")), *_HEAD, *_ARMS)
_OVERLAID = {"Head Movement": _HEAD, "Arm Movement": _ARMS}
#: Body parts that need the stance: performed as the action's lead (standing only, at most one of them).
_STANCE_PARTS = ("Waist Movement", "Leg Movement")


def _reused(tag: str) -> ActionClass:
    return _BABEL[REUSED[tag]]


def _overlay(take: Take, perform: Callable[[Take], None], mode: str, joints: tuple[int, ...]) -> None:
    """``joints``' angles of ``take`` replaced by those of ``perform`` in ``mode`` over the same frames."""
    other = Take(take.num_frames, take.fps, take.rng, take.subject, mode)
    perform(other)
    take.angles[:, list(joints)] = other.angles[:, list(joints)]


def _sit_still(take: Take) -> None:
    """Sitting: standing sway and arm carriage on a seated body."""
    skills.stand(take)
    skills.seated(take)


def _use_object_seated(take: Take) -> None:
    """Using an object (the BABEL-120 stand-in's, in the take's mode) while seated."""
    _reused("Using Object").perform(take)
    skills.seated(take)


def _step_and_touch(take: Take) -> None:
    """A step (forward or to the side), the upper body touching a body part (the take's mode: shoulder or knee)."""
    touch = take.mode
    take.mode = take.choice(_reused("Step").modes)
    try:
        _reused("Step").perform(take)
    finally:
        take.mode = touch
    _overlay(take, _reused("Touch Body Part").perform, touch, _UPPER)


#: Each tag that leads an action: its style modes and the perform function the mode is read by.
_MODES: dict[str, tuple[str, ...]] = {
    **{tag: _reused(tag).modes for tag in REUSED},
    "Sit": ("still",),
    "Using Object and Sit": _reused("Using Object").modes,
    "Step and Touch Body Part": _reused("Touch Body Part").modes,
}

_COMPOSED = {"Sit": _sit_still, "Using Object and Sit": _use_object_seated,
             "Step and Touch Body Part": _step_and_touch}
#: The tags as the dataset's classes: each with its style modes and the perform function of an action it leads.
CLASSES = tuple(ActionClass(tag.name, _MODES[tag.name],
                            _COMPOSED[tag.name] if tag.name in _COMPOSED else _reused(tag.name).perform)
                for tag in TAGS)


def split_counts(split: str) -> dict[str, int]:
    """Actions (and body-part occurrences) of each tag in ``split``: ``min(round(20 %), 100)`` for test, the rest for
    train, at :data:`SCALE`."""
    counts = {}
    for tag in TAGS:
        total = round(SCALE * tag.count)
        test = min(round(0.2 * total), 100)
        counts[tag.name] = test if split == "test" else total - test
    return counts


def split_actions(split: str) -> int:
    """The actions of ``split``: its intention and state tags (body parts ride on state actions)."""
    return sum(n for tag, n in split_counts(split).items() if KINDS[tag] != "body part")


def _draw(rng: np.random.Generator, weights: dict[str, float]) -> str:
    names = sorted(weights)
    p = np.array([weights[n] for n in names], float)
    return names[int(rng.choice(len(names), p=p / p.sum()))]


def _sequences(counts: dict[str, int], rng: np.random.Generator) -> list[list[str]]:
    """Each take's actions by their first tag: every action of ``counts`` (intention and state tags) once."""
    left = {tag: n for tag, n in counts.items() if KINDS[tag] != "body part" and n > 0}
    takes = []
    while left:
        size = int(rng.integers(ACTIONS_PER_TAKE[0], ACTIONS_PER_TAKE[1] + 1))
        take = [_draw(rng, {tag: float(n) for tag, n in left.items()})]
        while True:
            left[take[-1]] -= 1
            if not left[take[-1]]:
                del left[take[-1]]
            options = {tag: w * left[tag] for tag, w in FOLLOWERS[take[-1]].items() if tag in left}
            if len(take) == size or not options:
                break
            take.append(_draw(rng, options))
        takes.append(take)
    return takes


def _body_parts(takes: list[list[str]], counts: dict[str, int], rng: np.random.Generator) -> dict[tuple, list[str]]:
    """Body-part tags given to the state actions: leg and waist movements to standing ones (each at most one of
    the two), head and arm movements to any; ``(take, position) -> parts``."""
    states = [(i, k) for i, take in enumerate(takes) for k, tag in enumerate(take) if KINDS[tag] == "state"]
    standing = [slot for slot in states if takes[slot[0]][slot[1]] == "Stand"]
    parts: dict[tuple, list[str]] = {}
    used_for_stance: set[tuple] = set()
    for part, pool in (*((p, standing) for p in _STANCE_PARTS), ("Arm Movement", states), ("Head Movement", states)):
        eligible = [s for s in pool if s not in used_for_stance] if part in _STANCE_PARTS else pool
        chosen = rng.choice(len(eligible), size=min(counts[part], len(eligible)), replace=False)
        for c in sorted(chosen.tolist()):
            slot = eligible[c]
            parts.setdefault(slot, []).append(part)
            if part in _STANCE_PARTS:
                used_for_stance.add(slot)
    return parts


def _action(tags: tuple[str, ...], rng: np.random.Generator) -> tuple[Callable[[Take], None], str, int]:
    """The perform function of an action with ``tags`` (first: its intention or state tag), its mode's name and the
    mode's index among the first tag's modes (-1 where another tag's performance leads)."""
    first, parts = tags[0], tags[1:]
    stance = [p for p in parts if p in _STANCE_PARTS]
    lead = stance[0] if stance else first
    modes = _MODES[lead]
    index = int(rng.integers(len(modes)))
    base = CLASSES[_ID[lead]].perform
    overlays = [(p, _MODES[p][int(rng.integers(len(_MODES[p])))]) for p in parts if p in _OVERLAID]
    if not overlays:
        perform = base
    else:
        def perform(take: Take, base=base, overlays=tuple(overlays)) -> None:
            base(take)
            for part, mode in overlays:
                _overlay(take, CLASSES[_ID[part]].perform, mode, _OVERLAID[part])
    return perform, modes[index], index if lead == first else -1


def plan_takes(split: str, seed: int) -> tuple[TakePlan, ...]:
    """Every take of ``split``: its lead-in and its actions (module docstring), deterministic in ``seed``."""
    rng = np.random.default_rng(np.random.SeedSequence([seed, zlib.crc32(b"synth-mag"), zlib.crc32(split.encode()),
                                                        _PLAN_STREAM]))
    counts = split_counts(split)
    takes = _sequences(counts, rng)
    parts = _body_parts(takes, counts, rng)
    plans = []
    for i, take in enumerate(takes):
        actions = []
        for k, tag in enumerate(take):
            tags = (tag, *sorted(parts.get((i, k), ()), key=_ID.get))
            perform, mode, index = _action(tags, rng)
            low, high = SECONDS[tag]
            frames = int(round(rng.uniform(low, high) * FPS))
            actions.append(PlannedAction(perform, mode, frames, tuple(_ID[t] for t in tags), index))
        seated = take[0] in STARTS_SEATED
        lead = PlannedAction(_sit_still if seated else _reused("Stand").perform, "still" if seated else "relaxed",
                             int(rng.integers(LEAD_IN_FRAMES[0], LEAD_IN_FRAMES[1] + 1)))
        plans.append(TakePlan(lead, tuple(actions)))
    return tuple(plans)
