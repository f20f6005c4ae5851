"""The embedded procedural motion dataset: action-labelled human motion on the SMPL-24 tree.

No motion-capture data can be downloaded here, so every experiment trains and evaluates by default on
motions generated from how people move (published anthropometry and biomechanics): joint-angle curves
per action phase with minimum-jerk timing, coordinated limbs, clinical joint limits, feet planted while
they bear weight, ballistic flight. Variants stand in for the paper datasets, with their class names:

>>> from jaxmotion.data import synthetic
>>> data = synthetic.load("synth-humanact12")          # generated once, then read from the cache
>>> data.class_names[data.actions[0]], data.mode_names[data.actions[0]][data.modes[0]]

Every sequence has local axis-angle ``rotations [T, 24, 3]`` (float32), root ``translation [T, 3]``,
``joints = forward_kinematics(rotations, translation, subject_offsets(...))`` (within 1e-5), an action,
a ground-truth style ``mode`` and a ``subject`` whose bones are scaled within +-10% of the template.

Frame rate: 20 fps for the HumanAct12 / UESTC / NTU stand-ins (ACTOR and A2M train on 60-frame crops of
2-4 s actions, i.e. ~20 fps; HumanAct12's own rate is not published), 12 fps for the CMU stand-in
(A2M's downsampled CMU set).

Foot sliding: during single support the weight-bearing foot is pinned by construction (float rounding
only); in walking double support the feet's disagreement is split by their weight shares. Measured on
walk and run of ``synth-humanact12`` (seed 0), the toe joint's horizontal speed while within 2 cm of the
floor is below ``FOOT_SKATE_TOLERANCE`` m/s on average (see ``tests/test_synthetic.py``).

Determinism: sequence i of a split uses ``SeedSequence([seed, crc32(variant), crc32(split), i])`` and
subject s uses its own stream, so arrays do not depend on generation order: same (variant, split, seed),
same bytes. ``GENERATOR_VERSION`` is part of the cache file name; bump it when the output changes.
"""

from __future__ import annotations

import sys
from pathlib import Path
from types import MappingProxyType
from typing import Any

import numpy as np

from jaxmotion.cache import cache_root
from jaxmotion.files import file_lock
from jaxmotion.data.formats.ntu120 import NUM_SUBJECTS as NTU_NUM_SUBJECTS
from jaxmotion.data.formats.ntu120 import XSUB_TRAIN_SUBJECTS as NTU_XSUB_TRAIN_SUBJECTS
from jaxmotion.data.formats.uestc import NUM_SUBJECTS as UESTC_NUM_SUBJECTS
from jaxmotion.data.formats.uestc import TRAIN_SUBJECTS as UESTC_TRAIN_SUBJECTS
from jaxmotion.data.motion import MotionDataset, SourceMismatchError, concatenate
from jaxmotion.data.synthetic import (babel120, cmu, combat, humanact12, mag, ntu1p_daily, ntu1p_extended, ntu2p,
                                      ntu13, uestc)
from jaxmotion.data.synthetic.engine import Split, Variant, generate_split, subject
from jaxmotion.data.synthetic.noise import EstimateNoise, KinectNoise
from jaxmotion.geometry.markers import GTA22_ON_SMPL24, NTU25_ON_SMPL24

__all__ = ["FOOT_SKATE_TOLERANCE", "GENERATOR_VERSION", "VARIANTS", "cache_path", "cache_source", "generate", "load",
           "subject_offsets"]

GENERATOR_VERSION = 3  # 3: CMU Step/Climb go up (per-foot support height); in-place flights land where they stood
#: Mean toe-joint horizontal speed (m/s) allowed on floor-contact frames of walking and running.
FOOT_SKATE_TOLERANCE = 0.08

#: NTU RGB+D 120's cross-subject split of its 106 performers (FACTS 1.3).
_NTU_XSUB = {"train": tuple(sorted(NTU_XSUB_TRAIN_SUBJECTS)),
             "test": tuple(s for s in range(1, NTU_NUM_SUBJECTS + 1) if s not in NTU_XSUB_TRAIN_SUBJECTS)}

VARIANTS: MappingProxyType[str, Variant] = MappingProxyType({
    "synth-humanact12": Variant(
        name="synth-humanact12", classes=humanact12.CLASSES, fps=20.0, lengths=(40, 150),
        splits=MappingProxyType({"train": Split(num_sequences=1200, subjects=tuple(range(12)))}),
    ),
    # NTU-13: 3 902 clips in the real set, used for both training and testing (FACTS 1.1), so "train" is
    # the whole set; 40 performers as in NTU RGB+D.
    "synth-ntu13": Variant(
        name="synth-ntu13", classes=ntu13.CLASSES, fps=20.0, lengths=(40, 150),
        splits=MappingProxyType({"train": Split(num_sequences=3900, subjects=tuple(range(40)))}),
    ),
    # CMU mocap as A2M/ODMO use it: 970 clips of 7 classes at 12 fps, all "train" (FACTS 1.2); 100-frame
    # clips (~8.3 s), class shares locomotion-heavy (est.), ~20 performers. The real set stores 20 joints;
    # the stand-in keeps the SMPL-24 rotations and joints of every other variant.
    "synth-cmu": Variant(
        name="synth-cmu", classes=cmu.CLASSES, fps=12.0, lengths=(100, 100),
        splits=MappingProxyType({"train": Split(num_sequences=970, subjects=tuple(range(20)))}),
    ),
    # UESTC as ACTOR uses it (FACTS 1.1): 40 exercises, 118 subjects split by ACTOR's 51 training subjects,
    # 10 650 / 13 350 clips; VIBE-estimated, hence the monocular-estimate noise (noise.py).
    "synth-uestc": Variant(
        name="synth-uestc", classes=uestc.CLASSES, fps=20.0, lengths=(40, 150), noise=EstimateNoise(),
        splits=MappingProxyType({
            "train": Split(num_sequences=10650, subjects=tuple(sorted(UESTC_TRAIN_SUBJECTS))),
            "test": Split(num_sequences=13350, subjects=tuple(
                s for s in range(1, UESTC_NUM_SUBJECTS + 1) if s not in UESTC_TRAIN_SUBJECTS)),
        }),
    ),
    # NTU-1P as ActFormer prepares it (FACTS 1.3): NTU-120's 94 one-person classes (A001-A049, A061-A105) under
    # their names, 30 fps Kinect v2 skeletons (NTU-25 markers with Kinect-like capture, ActFormer's gap filling
    # and smoothing), cross-subject split, 2-5 s clips; 60 clips per class and split (the real set: ~600).
    "synth-ntu1p": Variant(
        name="synth-ntu1p", classes=ntu1p_daily.CLASSES + ntu1p_extended.CLASSES, fps=30.0, lengths=(60, 150),
        markers=NTU25_ON_SMPL24, joint_noise=KinectNoise(),
        splits=MappingProxyType({split: Split(num_sequences=94 * 60, subjects=subjects)
                                 for split, subjects in _NTU_XSUB.items()}),
    ),
    # NTURecon-1P (ActFormer): the same takes as synth-ntu1p (its random streams) stored as SMPL rotations with
    # the monocular-estimate noise of synth-uestc, as SMPL is fitted to NTU's videos there.
    "synth-ntu1p-smpl": Variant(
        name="synth-ntu1p-smpl", classes=ntu1p_daily.CLASSES + ntu1p_extended.CLASSES, fps=30.0, lengths=(60, 150),
        noise=EstimateNoise(), stream="synth-ntu1p",
        splits=MappingProxyType({split: Split(num_sequences=94 * 60, subjects=subjects)
                                 for split, subjects in _NTU_XSUB.items()}),
    ),
    # BABEL-120 as ActFormer uses it: AMASS segments of BABEL's 120 most frequent categories, SMPL at 30 fps, 1-8 s,
    # long-tailed class shares (babel120.ZIPF_EXPONENT: "walk" 120 times the rarest); train/val as BABEL's.
    # AMASS performers are not split by subject in BABEL; disjoint subject sets keep val held out here.
    "synth-babel120": Variant(
        name="synth-babel120", classes=babel120.CLASSES, fps=30.0, lengths=(30, 240),
        splits=MappingProxyType({"train": Split(num_sequences=12000, subjects=tuple(range(60))),
                                 "val": Split(num_sequences=3000, subjects=tuple(range(60, 80)))}),
    ),
    # NTU-2P as ActFormer prepares it (FACTS 1.3): the 26 mutual actions, 30 fps Kinect v2 skeletons (NTU-25,
    # with Kinect-like capture, gap filling and smoothing), cross-subject split; each clip also stored with its
    # persons swapped (ActFormer's -flip copies). 50 scenes per class and split (the real set: ~470), 2-5 s.
    "synth-ntu2p": Variant(
        name="synth-ntu2p", classes=ntu2p.CLASSES, fps=30.0, lengths=(60, 150), persons=2, swapped_copies=True,
        markers=NTU25_ON_SMPL24, joint_noise=KinectNoise(),
        splits=MappingProxyType({split: Split(num_sequences=1300, subjects=subjects)
                                 for split, subjects in _NTU_XSUB.items()}),
    ),
    # GTA Combat (ActFormer): one class, 2-5 fighters on GTA-22, game-engine clean. The real sets hold about
    # 2.3 / 1.9 / 1.5 / 1.2 thousand sequences; these keep the proportions at a fifth. One split, as
    # ActFormer trains on the whole file (FACTS 1.3); 60 performers; 30 fps assumed (GTA's rate is unpublished).
    **{f"synth-combat-{p}p": Variant(
        name=f"synth-combat-{p}p", classes=combat.CLASSES, fps=30.0, lengths=(60, 150), persons=p,
        markers=GTA22_ON_SMPL24,
        splits=MappingProxyType({"train": Split(num_sequences=n, subjects=tuple(range(60)))}),
    ) for p, n in ((2, 460), (3, 380), (4, 300), (5, 240))},
    # BABEL-MAG (Neural Marionette): BABEL-MAG's 31 tags as actions of continuous multi-action takes, the paper's
    # counts, 20% (at most 100) of each tag in test (mag module). Sequences are takes with segment tables; a
    # split's num_sequences counts its actions and lengths bound an action's frames (1-4 s at 30 fps).
    "synth-mag": Variant(
        name="synth-mag", classes=mag.CLASSES, fps=mag.FPS, lengths=(30, 120), takes=mag.plan_takes,
        splits=MappingProxyType({split: Split(num_sequences=mag.split_actions(split), subjects=tuple(range(40)))
                                 for split in ("train", "test")}),
    ),
})


def _variant(name: str) -> Variant:
    if name not in VARIANTS:
        raise ValueError(f"unknown synthetic variant {name!r}; valid names: {sorted(VARIANTS)}")
    return VARIANTS[name]


def _splits(variant: Variant, split: str) -> tuple[str, ...]:
    if split == "all":
        return tuple(variant.splits)
    if split not in variant.splits:
        raise ValueError(f"{variant.name} has splits {sorted(variant.splits)} (and 'all'), not {split!r}")
    return (split,)


def generate(name: str, split: str = "train", *, seed: int = 0, count: int | None = None,
             progress: bool = True) -> MotionDataset:
    """Generate a split in memory (``"all"`` = every split, concatenated).

    ``count`` keeps only the first ``count`` sequences of each split; prefixes are class- and
    mode-balanced, so small counts give small, representative datasets (tests, smoke runs). ``progress``:
    a progress line with an ETA on stderr once generation has run for ``JAXMOTION_PROGRESS_AFTER`` seconds
    (:func:`jaxmotion.progress.phase`).
    """
    variant = _variant(name)
    parts = [generate_split(variant, s, seed, count, progress=progress) for s in _splits(variant, split)]
    return parts[0] if len(parts) == 1 else concatenate(parts, split="all")


def cache_path(name: str, split: str = "train", *, seed: int = 0, cache_dir: str | Path | None = None,
               count: int | None = None) -> Path:
    """Where :func:`load` keeps a generated split (``count``: its first ``count`` sequences)."""
    part = "" if count is None else f"-n{count}"
    return cache_root(cache_dir) / f"{name}-{split}-seed{seed}{part}-v{GENERATOR_VERSION}.npz"


def cache_source(name: str, split: str = "train", *, seed: int = 0, count: int | None = None) -> dict[str, Any]:
    """What a cached split is generated from, recorded in its file and checked when it is read."""
    return {"variant": name, "split": split, "seed": seed, "generator_version": GENERATOR_VERSION, "count": count}


def load(name: str, split: str = "train", *, seed: int = 0, cache_dir: str | Path | None = None,
         count: int | None = None) -> MotionDataset:
    """A split (``count``: its first ``count`` sequences, as :func:`generate`'s; the smoke runs' small sets),
    generated on first use and cached as ``.npz`` (see :func:`cache_path`).

    The file records what it was generated from (variant, split, seed, generator version, count), checked
    on every load; a file that holds something else or cannot be read is generated again, with a message
    naming it. Processes that want the same split at once generate it once: the others wait, then read it.
    """
    _splits(_variant(name), split)
    path = cache_path(name, split, seed=seed, cache_dir=cache_dir, count=count)
    source = cache_source(name, split, seed=seed, count=count)
    with file_lock(path, what="dataset cache", wait=True):
        if path.exists():
            try:
                return MotionDataset.load(path, source=source)
            except SourceMismatchError as error:
                reason = str(error)
            except Exception as error:  # numpy, zipfile and json raise many types for a damaged file
                reason = f"{path} cannot be read ({type(error).__name__}: {error})"
            print(f"[data] generating {name}/{split} again: {reason}", file=sys.stderr)
        data = generate(name, split, seed=seed, count=count)
        print(f"[data] cached {name}/{split} in {path}", file=sys.stderr)
        data.save(path, source=source)
        return data


def subject_offsets(name: str, subject_id: int, *, seed: int = 0) -> np.ndarray:
    """``[J, 3]`` float32 rest offsets of a subject's body: the skeleton its ``joints`` were posed with."""
    return subject(_variant(name), subject_id, seed).offsets
