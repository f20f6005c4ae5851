"""What every experiment's smoke test runs and checks: the smoke run itself, and facts a broken generator fails.

A smoke trains for a few steps, so its scores say little about quality; what they can say is that each generating
row generates: its motions differ from sample to sample and within a class. A constant sampler (one motion, repeated)
scores exactly 0 on every diversity measure (its recogniser features are all equal) and its samples have no spread;
``test_a_constant_sampler_fails_the_smoke_checks`` shows such a sampler failing :func:`assert_generations_vary`.
The smokes share the session's cache (``tests/conftest.py``), so each smoke dataset and evaluator is made once.
"""

from pathlib import Path

import numpy as np

import jaxmotion
from jaxmotion.pipelines.load import generator_folders


def run_smoke(module, out: Path) -> dict:
    """The experiment ``module``'s smoke run into ``out``: its ``metrics.json`` content."""
    return module.main(["--profile", "smoke", "--out", str(out)])


def assert_generations_vary(rows, row: str, diversity: str, multimodality: str, share: float = 0.05) -> None:
    """Row ``row``'s generations differ across samples (``diversity`` above ``share`` of the Real row's where the
    table has one, else above 0) and within a class (``multimodality`` above 0): a constant sampler scores 0 on both.
    Its scores are numbers."""
    cells = rows[row]
    floor = share * rows["Real"][diversity]["mean"] if diversity in rows.get("Real", {}) else 0.0
    assert cells[diversity]["mean"] > floor, f"{row}: generations do not vary ({diversity} {cells[diversity]})"
    assert cells[multimodality]["mean"] > 0, f"{row}: generations of one class do not vary ({cells[multimodality]})"
    assert all(np.isfinite(cells[column]["mean"]) for column in (diversity, multimodality)), f"{row}: not a number"


def assert_real_recognised(rows, accuracy: str, classes: int) -> None:
    """The Real row's ``accuracy`` (%) is well above chance (twice ``100 / classes``): the smoke evaluator
    recognises real motions, so the table's scores measure something."""
    real = rows["Real"][accuracy]["mean"]
    assert real > 2 * 100 / classes, f"Real {accuracy} {real:.1f}% is near chance ({100 / classes:.1f}%)"


def assert_samples_vary(seed_folder: Path, samples: int = 3) -> list[str]:
    """Every generator a smoke run wrote under ``seed_folder`` (one per trained row) generates motions of one class
    that differ: the joints' spread over ``samples`` draws (of the generator's own length) is above 0 on average (a
    constant sampler's is exactly 0; a few-step ODMO's about 1e-4 m). For the tables without a diversity column
    (ActFormer's, ODMO's trajectories and modes). Returns the rows checked."""
    rows = []
    for folder in generator_folders(seed_folder):
        row = str(folder.parent.relative_to(seed_folder))
        motions = jaxmotion.load_generator(folder).generate(0, np.zeros(samples, np.int32))
        joints = np.asarray(motions.joints).reshape(samples, -1, *np.shape(motions.joints)[1:])  # [N, T, (P,) J, 3]
        assert np.isfinite(joints).all(), f"{row}: generated joints are not numbers"
        spread = joints.std(axis=0).mean()
        assert spread > 1e-6, f"{row}: samples of one class do not vary (joint spread {spread:.2e} m)"
        rows.append(row)
    return rows
