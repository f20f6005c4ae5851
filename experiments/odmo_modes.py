"""ODMO Table 3 and Figure 3: the modes discovered in the latent space, their homogeneity, and (a column no
paper could compute) their agreement with the true style modes.

Paper: Lu, Roy-Chowdhury et al., ACM MM 2022, §4.3.1, Table 3 and Figure 3. ODMO and ACTOR are trained on
each dataset; in each repetition, class-balanced real windows are encoded by both (ODMO's code means µ,
ACTOR's posterior means), each class's codes are clustered by ODMO's adaptive GMM (the silhouette rule,
:func:`jaxmotion.mixtures.discover_modes_batched`) and the discovered modes are scored
(:func:`jaxmotion.pipelines.odmo.score_modes`):

* **mode-homogeneity** (%): the paper's; the relative drop of the APD of each class's windows when split
  into the discovered modes (higher: purer modes);
* **ARI**: the adjusted Rand index of the discovered modes against the embedded data's ground-truth style
  modes (every synth-humanact12 class has 2-3: left/right hand, slow/fast/turning, ...), mean over classes;
  1 is a perfect recovery, 0 chance.

Rows: **Real motions** (each class one mode: 0 by definition, the paper's first row), **Modes_ACTOR**,
**Modes_ODMO**, and **True modes** (the ground-truth modes themselves: the homogeneity a perfect discovery
reaches; ARI 1), each with the paper's numbers beside (reported rows).

    python -m experiments.odmo_modes                   # cpu profile on the embedded data
    python -m experiments.odmo_modes --profile paper

Figure 3 (``figures/`` in the run folder): for one class per dataset (HumanAct12: warm_up), a 2-D PCA
projection of its ODMO codes coloured by discovered mode (the paper uses t-SNE, which is not in the
project's dependencies), a time-lapse strip of one real window per mode, and a strip of motions decoded
from codes interpolated between the two largest modes' means.

Differences: the embedded data and its recognisers (not used here) stand in for the real sets; the windows
of a repetition are 250 (HumanAct12) / 200 (UESTC) per class, drawn as ODMO's protocol draws real sets (the
paper does not say which codes Table 3 clusters). Profiles as ``odmo_benchmark``'s (the cpu profile runs
HumanAct12 only).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping

import jax
import jax.numpy as jnp
import numpy as np

from jaxmotion import experiment
from jaxmotion.config import FrozenMap, check_at_least
from jaxmotion.data.motion import Motion
from jaxmotion.data.pipeline import BatchSpec, class_windows, map_in_chunks
from jaxmotion.viz.motion import filmstrip
from jaxmotion.evaluation.claims import Claim
from jaxmotion.evaluation.tables import TableData, interleave_reported, real_sets, side_by_side, slug
from jaxmotion.pipelines.actor import posterior
from jaxmotion.pipelines.odmo import encode_windows, interpolate_modes, score_modes
from jaxmotion.metrics.apd import mode_homogeneity
from jaxmotion.train.actor import ActorTraining
from jaxmotion.recipes.actor import table_training
from jaxmotion.recipes.odmo import ODMORecipe, odmo_table_recipe
from jaxmotion.recipes.tables import fit_generator, table_key
from jaxmotion.viz import save_scatter

LABELS = ("HumanAct12", "UESTC")
DATASETS = {"HumanAct12": "synth-humanact12", "UESTC": "synth-uestc"}
ROWS = ("Real motions", "Modes_ACTOR", "Modes_ODMO", "True modes")
# Table 3: mode-homogeneity (%) on HumanAct12 and UESTC, means
REPORTED = {"Real motions": (0.00, 0.00), "Modes_ACTOR": (0.14, 0.05), "Modes_ODMO": (15.22, 8.74)}
CLAIMS = tuple(Claim("Modes_ODMO", ">", "Modes_ACTOR", f"{label} mode-homogeneity",
                     "Table 3: ODMO's latent space is more meaningful than ACTOR's") for label in LABELS)


@dataclasses.dataclass(frozen=True)
class ModesTable:
    """One dataset of Table 3: its data, the two models, the windows per class and the repetitions."""

    label: str
    data: TableData
    odmo: ODMORecipe
    actor: ActorTraining
    per_class: int
    repetitions: int
    figure_class: int = 0

    def __post_init__(self):
        check_at_least(self, 1, "per_class", "repetitions")
        check_at_least(self, 0, "figure_class")


@dataclasses.dataclass(frozen=True)
class OdmoModesConfig(experiment.ProfileConfig):
    datasets: tuple[str, ...]  # which of Table 3's datasets run (keys of ``tables``: humanact12, uestc)
    tables: Mapping[str, ModesTable]

    @classmethod
    def for_profile(cls, profile: str) -> OdmoModesConfig:
        tables = {}
        for label in LABELS:
            smoke = profile == "smoke"
            tables[table_key(label)] = ModesTable(
                label, TableData(DATASETS[label], count=80 if smoke else None, test_split=False),
                odmo_table_recipe(label, profile), table_training(label, profile),
                per_class=12 if smoke else {"HumanAct12": 250, "UESTC": 200}[label],
                repetitions={"smoke": 2, "cpu": 5, "paper": 10}[profile])
        chosen = LABELS if profile == "paper" else ("HumanAct12",)
        return cls(datasets=tuple(table_key(label) for label in chosen), tables=FrozenMap(tables))


def actor_means(params, training: ActorTraining, windows: dict, chunk: int = 512) -> np.ndarray:
    """ACTOR's posterior means of windows (rotations, translation, mask, actions) -> ``[N, d]``."""
    rows = {k: windows[k] for k in ("rotations", "translation", "actions", "mask")}
    return map_in_chunks(lambda _, r: posterior(params, r["rotations"], r["translation"], r["actions"], r["mask"],
                                                config=training.model)[0], rows, chunk)


def _figures(table: ModesTable, odmo, windows: dict, codes: np.ndarray, scored: dict, skeleton, folder) -> None:
    folder.mkdir(parents=True, exist_ok=True)
    c = table.figure_class
    rows = np.flatnonzero(windows["actions"] == c)
    x = codes[rows] - codes[rows].mean(0)
    _, _, vt = np.linalg.svd(x, full_matrices=False)
    labels = scored["labels"][rows]
    save_scatter(folder / f"{slug(table.label)}-codes.png", x @ vt[:2].T, labels,
                 title=f"{table.label}, class {c}: ODMO codes (PCA) by discovered mode")
    for mode in np.unique(labels):
        first = rows[labels == mode][0]
        motion = Motion(windows["joints"][first], windows["translation"][first], None, action=c, mode=int(mode),
                        subject=-1, name=f"mode-{mode}")
        filmstrip(motion, skeleton, str(folder / f"{slug(table.label)}-mode-{mode}.png"), title=f"mode {mode}")
    sizes = np.bincount(labels)
    if len(sizes) >= 2:
        a, b = np.argsort(sizes)[::-1][:2]
        strip = interpolate_modes(odmo, c, int(a), int(b), 5)
        for i, w in enumerate(strip["weights"]):
            motion = Motion(strip["joints"][i], strip["translation"][i], None, action=c, mode=-1, subject=-1,
                            name=f"interpolation-{i}")
            filmstrip(motion, skeleton, str(folder / f"{slug(table.label)}-interpolation-{i}.png"),
                      title=f"mode {a} → {b}: weight {w:.2f}")


def run_table(table: ModesTable, ctx: experiment.RunContext) -> dict[str, dict]:
    """Table 3's rows on one dataset, ``{row: {column: values over repetitions}}``."""
    data = real_sets(table.data, ctx.data_root)["train"]
    workdir = ctx.workdir / slug(table.label)
    key = ctx.key(f"train {table.label}")
    odmo = fit_generator(table.odmo, data, key, workdir / "odmo", mesh=ctx.mesh, writers=ctx.writers)
    actor_params = fit_generator(table.actor, data, key, workdir / "actor", mesh=ctx.mesh,
                                 writers=ctx.writers).params
    spec = BatchSpec(batch_size=1, window=odmo.model.num_frames, canonical=table.odmo.training.canonical)
    cells = {row: {"mode-homogeneity": [], "ARI": []} for row in ROWS}
    for r in range(table.repetitions):
        k_windows, k_modes = jax.random.split(jax.random.fold_in(ctx.key(f"modes {table.label}"), r))
        windows = class_windows(data, k_windows, spec, table.per_class)
        codes = encode_windows(odmo.params, odmo.buffers, odmo.model, windows["joints"])
        scores = {"Modes_ODMO": score_modes(codes, windows["actions"], windows["modes"], windows["joints"],
                                            data.num_classes, key=k_modes),
                  "Modes_ACTOR": score_modes(actor_means(actor_params, table.actor, windows), windows["actions"],
                                             windows["modes"], windows["joints"], data.num_classes, key=k_modes)}
        for name, scored in scores.items():
            cells[name]["mode-homogeneity"].append(scored["mode_homogeneity"])
            cells[name]["ARI"].append(float(np.nanmean(scored["ari"])))
        one_mode = np.zeros_like(windows["modes"])
        truth = windows["modes"]
        for name, modes in (("Real motions", one_mode), ("True modes", truth)):
            cells[name]["mode-homogeneity"].append(float(mode_homogeneity(
                jnp.asarray(windows["joints"]), jnp.asarray(windows["actions"]), jnp.asarray(modes), data.num_classes,
                int(truth.max()) + 1)))
            cells[name]["ARI"].append(0.0 if name == "Real motions" else 1.0)
        if r == 0:
            _figures(table, odmo, windows, codes, scores["Modes_ODMO"], data.skeleton, ctx.workdir / "figures")
    return cells


def run(config: OdmoModesConfig, ctx: experiment.RunContext):
    measured = side_by_side({config.tables[name].label: run_table(config.tables[name], ctx) for name in config.datasets})
    reported = {row: {f"{label} mode-homogeneity": value for label, value in zip(LABELS, values, strict=True)}
                for row, values in REPORTED.items()}
    return interleave_reported(measured, reported, ROWS)


def main(argv=None):
    return experiment.main("odmo_modes", OdmoModesConfig, run, argv, description=__doc__, claims=CLAIMS)


if __name__ == "__main__":
    main()
