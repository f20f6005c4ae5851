"""Open a trained generator of any method from a run folder: :func:`load_generator`."""

from __future__ import annotations

from pathlib import Path
from types import MappingProxyType

from jaxmotion.pipelines.a2m import A2MGenerator
from jaxmotion.pipelines.actformer import ActFormerGenerator
from jaxmotion.pipelines.actor import ActorGenerator
from jaxmotion.pipelines.artefacts import RECORD, ArtefactError, Generator, read_artefact
from jaxmotion.pipelines.marionette import CONTEXT_MODELS, ContextGenerator
from jaxmotion.pipelines.odmo import ODMOGenerator

#: The generator class of each method's artefacts.
GENERATORS = MappingProxyType({**{cls.method: cls for cls in (ActorGenerator, A2MGenerator, ODMOGenerator,
                                                               ActFormerGenerator)},
                               **{model.method: ContextGenerator for model in CONTEXT_MODELS.values()}})


def generator_folders(path: str | Path) -> list[Path]:
    """Every generator folder at or below ``path`` (a generator folder, a row folder, a seed folder), sorted."""
    path = Path(path)
    if (path / RECORD).is_file():
        return [path]
    return sorted(record.parent for record in path.rglob(RECORD))


def load_generator(path: str | Path, row: str | None = None) -> Generator:
    """The trained generator in ``path``: a generator folder, the row folder holding one, or a seed folder of an
    experiment. A folder holding several (a table's rows) needs ``row``: the row's folder relative to ``path``
    (``"actor"``, ``"ntu-13/actformer"``), or any unique suffix of it. Needs no training data, optimiser state or
    experiment module::

        generator = jaxmotion.load_generator("results/actor_uestc/cpu/seed-0")
        motions = generator.generate(0, actions=[3, 3, 8], durations=[40, 80, 120])   # a MotionDataset
    """
    path = Path(path)
    if not path.exists():
        raise FileNotFoundError(f"path: {path} does not exist")
    folders = generator_folders(path)
    if not folders:
        raise ArtefactError(f"{path}: no trained generator in it ({RECORD} below it); a run writes one per row "
                            f"when that row's training finishes")
    names = {str(folder.parent.relative_to(path)) if folder != path else ".": folder for folder in folders}
    if row is not None:
        matches = [name for name in names if name == row or name.endswith("/" + row)]
        if len(matches) != 1:
            raise ArtefactError(f"row: {row!r} matches {len(matches)} of the generators in {path}: "
                                f"{', '.join(sorted(names))}")
        folders = [names[matches[0]]]
    elif len(folders) > 1:
        raise ArtefactError(f"{path} holds {len(folders)} generators; name one with row=: "
                            f"{', '.join(sorted(names))}")
    artefact = read_artefact(folders[0])
    if artefact.method not in GENERATORS:
        raise ArtefactError(f"{folders[0]}: method {artefact.method!r}; this jaxmotion loads "
                            f"{', '.join(GENERATORS)}")
    return GENERATORS[artefact.method].load(artefact)
