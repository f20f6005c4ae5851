"""One entry point for the embedded stand-in datasets and the real ones."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from jaxmotion.data import formats, synthetic
from jaxmotion.data.motion import MotionDataset

EMBEDDED_PREFIX = "synth-"

#: The paper datasets' sizes, as the papers give them: ``(classes, training clips)``. Their
#: embedded stand-ins have the same; trainers size the paper profiles (epochs -> steps) from them.
PAPER_SIZES = {"NTU-13": (13, 3900), "UESTC": (40, 10_650), "HumanAct12": (12, 1200), "MoCap": (7, 970)}


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
    sequences of the split (embedded data: generated directly, class- and mode-balanced, not cached; for
    smoke runs).
    """
    if count is not None and count < 1:
        raise ValueError(f"count: expected a positive number of sequences or None, got {count}")
    check_dataset_name(name)
    if name in synthetic.VARIANTS:
        if data_root is not None:
            raise ValueError(f"{name} is generated, not read: drop data_root, or load the real "
                             f"{name.removeprefix(EMBEDDED_PREFIX)!r} from it")
        if count is not None:
            return synthetic.generate(name, split, seed=seed, count=count)
        return synthetic.load(name, split, seed=seed)
    if data_root is None:
        stand_in = EMBEDDED_PREFIX + name
        hint = f"; its embedded stand-in is {stand_in!r}" if stand_in in synthetic.VARIANTS else ""
        raise ValueError(f"the real dataset {name!r} needs data_root (the folder with its files){hint}")
    data = formats.REAL_LOADERS[name](data_root, split)
    return data if count is None else data.subset(np.arange(min(count, len(data))))
