"""ODMO's tables run end to end in their smoke profiles, laid out as the paper lays them out."""

import numpy as np
import pytest

from experiments import odmo_benchmark

HUMANACT12 = ["HumanAct12 Acc", "HumanAct12 FID_tr", "HumanAct12 Diversity", "HumanAct12 MModality",
              "HumanAct12 n-APD"]
UESTC = ["UESTC Acc", "UESTC FID_tr", "UESTC FID_test", "UESTC Diversity", "UESTC MModality", "UESTC n-APD"]


@pytest.fixture(scope="module")
def cache(tmp_path_factory):
    """One cache for the module: each smoke evaluator is trained once."""
    return tmp_path_factory.mktemp("cache")


def _smoke(module, tmp_path, monkeypatch, cache):
    monkeypatch.setenv("JAXMOTION_CACHE", str(cache))
    return module.main(["--profile", "smoke", "--out", str(tmp_path)])["rows"]


def assert_generations_vary(rows, row, prefix):
    """What a constant sampler cannot pass, even untrained: its motions differ (diversity above zero) and
    spread within each class (n-APD above zero)."""
    cells = rows[row]
    assert cells[f"{prefix}Diversity"]["mean"] > 0, f"{row}: generations do not vary"
    assert cells[f"{prefix}n-APD"]["mean"] > 0, f"{row}: generations of one class do not vary"
    assert np.isfinite(cells[f"{prefix}FID_tr"]["mean"])


@pytest.mark.slow
def test_benchmark_table_has_the_paper_rows_and_trains_odmo_conv_with_odmo(tmp_path, monkeypatch, cache):
    rows = _smoke(odmo_benchmark, tmp_path, monkeypatch, cache)
    measured = ["Real", "A2M-xyz", "ACTOR", "ODMO", "ODMO_conv", "-r_e", "-L_es"]
    order = []
    for name in odmo_benchmark.ROWS:
        if name in measured:
            order.append(name)
        order.append(f"{name} (reported)")
    assert list(rows) == order
    for name in measured:
        assert list(rows[name]) == HUMANACT12 + UESTC
    assert rows["ODMO (reported)"]["UESTC FID_test"] == 0.17 and rows["ACTOR (reported)"]["HumanAct12 n-APD"] == 74.30
    for name in measured[1:]:
        assert_generations_vary(rows, name, "HumanAct12 ")
    # ODMO_conv samples the model ODMO trained: no folder of its own
    workdir = tmp_path / "odmo_benchmark" / "smoke" / "seed-0" / "humanact12"
    trained = sorted(p.name for p in workdir.iterdir() if (p / "checkpoints").is_dir())
    assert trained == ["a2m-xyz", "actor", "l-es", "odmo", "r-e"]


def test_ablation_rows_change_one_thing_each():
    odmo = odmo_benchmark.OdmoBenchmarkConfig.smoke().humanact12_odmo
    rows = odmo_benchmark.ablations(odmo)
    assert rows["ODMO_conv"].training == odmo.training and rows["ODMO_conv"].sampling == "conventional"
    assert rows["-r_e"].model.use_end is False and rows["-r_e"].losses == odmo.losses
    assert rows["-L_es"].losses.contrastive is False and rows["-L_es"].model == odmo.model
    with pytest.raises(ValueError, match="datasets"):
        odmo_benchmark.OdmoBenchmarkConfig.for_profile("smoke").__class__(
            **{**odmo_benchmark.OdmoBenchmarkConfig.smoke().__dict__, "datasets": ("NTU-13",)})
