"""BABEL-MAG's 31 tags (Neural Marionette, supplement Table 1): names, ids, kinds and the paper's counts.

Kinds: ``root`` (intention tags that move the root), ``in place`` (intention tags that do not), ``state`` (body
states) and ``body part`` (body-part movements). An intention action carries its one tag; a non-intention action a
body state and zero or more body parts (the paper's counts sum to 8,924 tags over 7,643 actions). Shared by the
embedded stand-in (:mod:`jaxmotion.data.synthetic.mag`) and the loader of BABEL's files
(:mod:`jaxmotion.data.formats.babel_mag`).
"""

from __future__ import annotations

import dataclasses
from typing import Literal

import numpy as np

Kind = Literal["root", "in place", "state", "body part"]


@dataclasses.dataclass(frozen=True)
class Tag:
    """One tag: its name, kind and the paper's number of segments carrying it."""

    name: str
    kind: Kind
    count: int

    @property
    def intention(self) -> bool:
        return self.kind in ("root", "in place")


TAGS = tuple(Tag(*row) for row in (
    ("Walk", "root", 1370), ("Walk Backward", "root", 160), ("Walk Sideway", "root", 105),
    ("Walk Upward/Downward", "root", 272), ("Step", "root", 536), ("Run", "root", 198), ("Jump", "root", 168),
    ("Turn", "in place", 1063), ("Sit Down", "in place", 86), ("Stand Up", "in place", 123),
    ("Using Object", "in place", 227), ("Take Something Up", "in place", 375),
    ("Place Something Down", "in place", 261), ("Move Something", "in place", 102), ("Throw", "in place", 143),
    ("Touch Something", "in place", 301), ("Kick", "in place", 91), ("Punch", "in place", 69),
    ("Wave Hand", "in place", 29), ("Stretch", "in place", 410), ("Crossing Limbs", "in place", 33),
    ("Touch Body Part", "in place", 200), ("Using Object and Sit", "in place", 39),
    ("Step and Touch Body Part", "in place", 54), ("Stand", "state", 754), ("Bend", "state", 149),
    ("Sit", "state", 325), ("Head Movement", "body part", 199), ("Arm Movement", "body part", 859),
    ("Waist Movement", "body part", 30), ("Leg Movement", "body part", 193),
))
TAG_NAMES = tuple(t.name for t in TAGS)
KINDS = {t.name: t.kind for t in TAGS}


def root_tag_mask(class_names: tuple[str, ...]) -> np.ndarray:
    """``[C]`` bool: which of ``class_names`` move the root (the "root" kind); a name that is not a BABEL-MAG tag
    is an error."""
    unknown = [name for name in class_names if name not in KINDS]
    if unknown:
        raise ValueError(f"class_names: expected BABEL-MAG's tags; {unknown[0]!r} is not one")
    return np.array([KINDS[name] == "root" for name in class_names])
