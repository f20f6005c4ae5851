"""ODMO Table 4 and Figure 4: trajectory customisation by a requested end point.

Paper: Lu, Roy-Chowdhury et al., ACM MM 2022, §4.4, Table 4 and Figure 4; the test as the authors' code runs
it (``trajectory_customization.py``, :func:`jaxmotion.pipelines.odmo.end_point_trials`): per class, 40
times, one random real code of the class and 10 end points evenly spaced from the end root of that code's
window to the end root of another random window of the class; the 400 motions per class are generated from
the origin and compared with their targets. Rows: **ODMO**, **-L_traj** (trained without the trajectory and consistency terms), **-L_cons**
(without the consistency term); columns per dataset:

* **Acc**: the dataset's recogniser's accuracy on the customised motions (%);
* **dist_e**: the code's metric, the mean squared distance between the target and the final root (m²;
  mean over classes);
* **end error** (cm): the mean Euclidean distance; **hit rate** (%): the share of motions ending within 10% of the target's distance from the
  start (the code's logged "error rate", which counts successes).

Two diagnostics of where the end error comes from (not in the paper): **path end error** (cm), the
trajectory generator's own error (its path's last point against the target; the motion generator then has
to follow that path), and **end response**, how far the final root moves per metre the target moves along
a trial's 10 end points (:func:`jaxmotion.pipelines.odmo.end_response`; 1 follows, 0 ignores the target).

Each repetition (10 in the paper, seeds 0..9) draws new codes and end points from the same trained models.

    python -m experiments.odmo_trajectory                   # cpu profile on the embedded data
    python -m experiments.odmo_trajectory --profile paper

Figure 4 (``figures/`` in the run folder): top views of one code sent to 10 end points, and of 4 codes of
the class sent to one end point, for the first class of each dataset.

Differences: the embedded stand-ins (24 joints; CMU MoCap's 20 in the paper) and their recognisers. The cpu
profile runs HumanAct12 and MoCap (UESTC: ``--set 'datasets=["mocap","humanact12","uestc"]'``).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping

import jax
import jax.numpy as jnp
import numpy as np

from jaxmotion import experiment
from jaxmotion.config import FrozenMap, check_at_least
from jaxmotion.evaluation.claims import Claim
from jaxmotion.evaluation.protocol import check_evaluator
from jaxmotion.evaluation.recognizers import RecognizerTraining, trained_recognizer
from jaxmotion.recipes.evaluators import evaluator_spec
from jaxmotion.data.datasets import paper_dataset
from jaxmotion.evaluation.tables import TableData, interleave_reported, real_sets, side_by_side, slug
from jaxmotion.metrics.classification import accuracy, confusion_matrix
from jaxmotion.pipelines.odmo import ODMOGenerator, customize_end, end_point_trials
from jaxmotion.recipes.odmo import ODMORecipe, odmo_table_recipe
from jaxmotion.recipes.tables import fit_generator, table_key
from jaxmotion.viz import save_trajectories

LABELS = ("MoCap", "HumanAct12", "UESTC")
EVALUATORS = {"MoCap": "synth-cmu/gru", "HumanAct12": "synth-humanact12/gru", "UESTC": "synth-uestc/gru"}
ROWS = ("-L_traj", "-L_cons", "ODMO")
# Table 4, means: Acc (%), dist_e on MoCap, HumanAct12, UESTC
REPORTED = {
    "-L_traj": {"MoCap": (89.23, 0.71), "HumanAct12": (96.02, 0.04), "UESTC": (92.84, 0.03)},
    "-L_cons": {"MoCap": (88.04, 0.35), "HumanAct12": (94.21, 0.02), "UESTC": (94.02, 0.02)},
    "ODMO": {"MoCap": (91.56, 0.06), "HumanAct12": (96.95, 0.00), "UESTC": (93.42, 0.01)},
}
# §4.4: "the ODMO model (with both trajectory loss and consistency loss) has the most powerful customization
# ability"
CLAIMS = tuple(Claim("ODMO", "<", other, f"{label} dist_e", "Table 4: both terms are needed to reach the end")
               for label in LABELS for other in ("-L_traj", "-L_cons"))


@dataclasses.dataclass(frozen=True)
class TrajectoryTable:
    """One dataset of Table 4: data, evaluator, the full recipe (the ablations follow from it), the test's size."""

    label: str
    data: TableData
    evaluator: RecognizerTraining
    odmo: ODMORecipe
    trials: int = 40
    points: int = 10
    repetitions: int = 10

    def __post_init__(self):
        check_at_least(self, 1, "trials", "points", "repetitions")


def ablations(odmo: ODMORecipe) -> dict[str, ODMORecipe]:
    """Table 4's rows from the full recipe."""
    def without(**change):
        return dataclasses.replace(odmo, training=dataclasses.replace(
            odmo.training, losses=dataclasses.replace(odmo.training.losses, **change)))

    return {"-L_traj": without(trajectory_loss=False), "-L_cons": without(consistency=False), "ODMO": odmo}


@dataclasses.dataclass(frozen=True)
class OdmoTrajectoryConfig(experiment.ProfileConfig):
    datasets: tuple[str, ...]  # which of Table 4's datasets run (keys of ``tables``: mocap, humanact12, uestc)
    tables: Mapping[str, TrajectoryTable]

    @classmethod
    def for_profile(cls, profile: str) -> OdmoTrajectoryConfig:
        tables = {}
        for label in LABELS:
            smoke = profile == "smoke"
            tables[table_key(label)] = TrajectoryTable(
                label, TableData(paper_dataset(label).stand_in, count=80 if smoke else None, test_split=False),
                evaluator_spec(EVALUATORS[label], profile), odmo_table_recipe(label, profile),
                trials=2 if smoke else 40, points=3 if smoke else 10,
                repetitions={"smoke": 2, "cpu": 5, "paper": 10}[profile])
        chosen = {"cpu": ("MoCap", "HumanAct12"), "smoke": ("HumanAct12",)}.get(profile, LABELS)
        return cls(datasets=tuple(table_key(label) for label in chosen), tables=FrozenMap(tables))


def _figures(odmo: ODMOGenerator, folder, label: str, key: jax.Array) -> None:
    folder.mkdir(parents=True, exist_ok=True)
    bank = odmo.bank
    rows = bank.of_class(0)
    pick = np.asarray(jax.random.randint(key, (6,), 0, len(rows)))
    a, b = bank.ends[rows[pick[0]]], bank.ends[rows[pick[1]]]
    ends = np.linspace(a, b, 10).astype(np.float32)
    one_code = customize_end(odmo, bank.codes[rows[pick[2]]], 0, ends)
    many = customize_end(odmo, bank.codes[rows[pick[2:6]]], 0, np.repeat(ends[5:6], 4, axis=0))
    save_trajectories(folder / f"{slug(label)}-end-points.png",
                      {"one code, 10 end points": (one_code["joints"][:, :, 0], ends),
                       "4 codes, one end point": (many["joints"][:, :, 0], many["ends"])},
                      title=f"{label}: root paths (top view) and requested end points")


def run_table(table: TrajectoryTable, ctx: experiment.RunContext) -> dict[str, dict]:
    """Table 4's rows on one dataset, ``{row: {column: values over repetitions}}``."""
    data = real_sets(table.data, ctx.data_root)["train"]
    recognizer, _ = trained_recognizer(table.evaluator, data_root=ctx.data_root)  # before any row trains
    check_evaluator(recognizer, {"train": data})  # an evaluator of other classes would score every row near 0
    rows = {}
    key = ctx.key(f"train {table.label}")
    for name, recipe in ablations(table.odmo).items():
        odmo = fit_generator(recipe, data, key, ctx.workdir / slug(table.label) / slug(name), mesh=ctx.mesh,
                             writers=ctx.writers)
        cells = {"Acc": [], "dist_e": [], "end error (cm)": [], "hit rate (%)": [], "path end error (cm)": [],
                 "end response": []}
        for r in range(table.repetitions):
            result = end_point_trials(odmo, jax.random.fold_in(ctx.key(f"trials {table.label}"), r),
                                      trials=table.trials, points=table.points)
            motions = result["motions"]
            logits, _ = recognizer(motions)
            confusion = confusion_matrix(jnp.asarray(motions["actions"]), jnp.argmax(logits, -1), recognizer.num_classes)
            cells["Acc"].append(100 * float(accuracy(confusion)))
            cells["dist_e"].append(result["dist_e"])
            cells["end error (cm)"].append(100 * result["end_error"])
            cells["hit rate (%)"].append(100 * result["hit_rate"])
            cells["path end error (cm)"].append(100 * result["path_end_error"])
            cells["end response"].append(result["end_response"])
        rows[name] = cells
        if name == "ODMO":
            _figures(odmo, ctx.workdir / "figures", table.label, ctx.key(f"figures {table.label}"))
    return rows


def run(config: OdmoTrajectoryConfig, ctx: experiment.RunContext):
    measured = side_by_side({config.tables[name].label: run_table(config.tables[name], ctx) for name in config.datasets})
    reported = {row: {f"{label} {column}": value for label, values in by_label.items()
                      for column, value in zip(("Acc", "dist_e"), values, strict=True)}
                for row, by_label in REPORTED.items()}
    return interleave_reported(measured, reported, ROWS)


def main(argv=None):
    return experiment.main("odmo_trajectory", OdmoTrajectoryConfig, run, argv, description=__doc__, claims=CLAIMS)


if __name__ == "__main__":
    main()
