"""One entry point for the embedded stand-in datasets and the real ones, and the one registry of the paper
datasets they stand in for (:data:`PAPER_DATASETS`)."""

from __future__ import annotations

import dataclasses
from pathlib import Path
from types import MappingProxyType

import numpy as np

from jaxmotion.data import formats, synthetic
from jaxmotion.data.motion import MotionDataset

EMBEDDED_PREFIX = "synth-"



@dataclasses.dataclass(frozen=True)
class PaperDataset:
    """A dataset of the papers' tables: its name in the papers (``label``), its embedded stand-in, whether its
    tables score against a test split too (``FID_test``) and, where the papers give it, the number of training
    clips (the paper profiles turn epochs into steps with it)."""

    label: str
    stand_in: str
    test_split: bool = False
    clips: int | None = None

    @property
    def num_classes(self) -> int:
        return len(synthetic.VARIANTS[self.stand_in].classes)


#: The paper datasets by their papers' names -> their stand-ins (ACTOR's and ODMO's, then ActFormer's).
PAPER_DATASETS: MappingProxyType[str, PaperDataset] = MappingProxyType({d.label: d for d in (
    PaperDataset("NTU-13", "synth-ntu13", clips=3900),
    PaperDataset("UESTC", "synth-uestc", test_split=True, clips=10_650),
    PaperDataset("HumanAct12", "synth-humanact12", clips=1200),
    PaperDataset("MoCap", "synth-cmu", clips=970),
    PaperDataset("NTURecon-1P", "synth-ntu1p-smpl"),
    PaperDataset("NTU-1P", "synth-ntu1p"),
    PaperDataset("BABEL", "synth-babel120"),
    PaperDataset("NTU-2P", "synth-ntu2p"),
    *(PaperDataset(f"Combat {p}P", f"synth-combat-{p}p") for p in range(2, 6)),
)})


def paper_dataset(label: str) -> PaperDataset:
    """The paper dataset ``label``, or a ``ValueError`` listing the labels."""
    if label not in PAPER_DATASETS:
        raise ValueError(f"label: expected one of {', '.join(PAPER_DATASETS)}, got {label!r}")
    return PAPER_DATASETS[label]


def dataset_names() -> dict[str, tuple[str, ...]]:
    """Loadable names: ``embedded`` (generated here) and ``real`` (read from ``data_root``)."""
    return {"embedded": tuple(sorted(synthetic.VARIANTS)), "real": tuple(sorted(formats.REAL_LOADERS))}


def check_dataset_name(name: str, where: str = "dataset") -> str:
    """``name`` if it is a loadable dataset, else a ``ValueError`` from ``where`` listing the names."""
    names = dataset_names()
    if name not in names["embedded"] and name not in names["real"]:
        raise ValueError(f"{where}: unknown dataset {name!r}; embedded: {', '.join(names['embedded'])}; "
                         f"real (with data_root): {', '.join(names['real'])}")
    return name


def load_dataset(name: str, split: str = "train", *, seed: int = 0, data_root: str | Path | None = None,
                 count: int | None = None) -> MotionDataset:
    """Load a dataset split as a packed ``MotionDataset`` (index it, iterate it, batch it).

    ``synth-*`` names are the embedded procedural datasets, generated from ``seed`` on first use and
    cached. Other names are the real datasets, read from ``data_root`` in their original formats (as the
    authors' loaders read them); the seed does not apply to them. ``count``: only the first ``count``
    sequences of the split (embedded data: generated class- and mode-balanced and cached on their own; for
    smoke runs).
    """
    if count is not None and count < 1:
        raise ValueError(f"count: expected a positive number of sequences or None, got {count}")
    check_dataset_name(name)
    if name in synthetic.VARIANTS:
        if data_root is not None:
            raise ValueError(f"{name} is generated, not read: drop data_root, or load the real "
                             f"{name.removeprefix(EMBEDDED_PREFIX)!r} from it")
        return synthetic.load(name, split, seed=seed, count=count)
    if data_root is None:
        stand_in = EMBEDDED_PREFIX + name
        hint = f"; its embedded stand-in is {stand_in!r}" if stand_in in synthetic.VARIANTS else ""
        raise ValueError(f"the real dataset {name!r} needs data_root (the folder with its files){hint}")
    data = formats.REAL_LOADERS[name](data_root, split)
    return data if count is None else data.subset(np.arange(min(count, len(data))))
