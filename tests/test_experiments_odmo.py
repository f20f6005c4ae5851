"""ODMO's tables run end to end in their smoke profiles, laid out as the paper lays them out."""

import dataclasses

import numpy as np
import pytest
from smoke_checks import assert_real_recognised, assert_samples_vary, run_smoke
from smoke_checks import assert_generations_vary as _assert_generations_vary

from experiments import odmo_benchmark
from jaxmotion.data.datasets import paper_dataset
from jaxmotion.recipes.odmo import benchmark_variants

HUMANACT12 = ["HumanAct12 Acc", "HumanAct12 FID_tr", "HumanAct12 Diversity", "HumanAct12 MModality",
              "HumanAct12 n-APD"]


def assert_generations_vary(rows, row, prefix):
    """ODMO's tables: diversity across samples, n-APD within a class. Four steps leave ODMO's decoder near its mean
    motion (diversity about a hundredth of the Real row's, yet above a constant sampler's 0)."""
    _assert_generations_vary(rows, row, f"{prefix}Diversity", f"{prefix}n-APD", share=1e-3)


@pytest.mark.smoke
def test_benchmark_table_has_the_paper_rows_and_trains_odmo_conv_with_odmo(tmp_path):
    rows = run_smoke(odmo_benchmark, tmp_path)["rows"]
    measured = ["Real", "A2M-xyz", "ACTOR", "ODMO", "ODMO_conv", "-r_e", "-L_es"]
    order = []
    for name in odmo_benchmark.ROWS:
        if name in measured:
            order.append(name)
        order.append(f"{name} (reported)")
    assert list(rows) == order
    for name in measured:  # the smoke runs HumanAct12; the paper profile both datasets
        assert list(rows[name]) == HUMANACT12
    assert rows["ODMO (reported)"]["UESTC FID_test"] == 0.17 and rows["ACTOR (reported)"]["HumanAct12 n-APD"] == 74.30
    for name in measured[1:]:
        assert_generations_vary(rows, name, "HumanAct12 ")
    assert_real_recognised(rows, "HumanAct12 Acc", paper_dataset("HumanAct12").num_classes)
    # ODMO_conv samples the model ODMO trained: no folder of its own
    workdir = tmp_path / "odmo_benchmark" / "smoke" / "seed-0" / "humanact12"
    trained = sorted(p.name for p in workdir.iterdir() if (p / "checkpoints").is_dir())
    assert trained == ["a2m-xyz", "actor", "l-es", "odmo", "r-e"]


def test_ablation_rows_change_one_thing_each():
    config = odmo_benchmark.OdmoBenchmarkConfig.smoke()
    odmo = config.tables["humanact12"].rows["ODMO"]
    rows = benchmark_variants(odmo)
    assert dict(config.tables["humanact12"].rows) == {**rows, "A2M-xyz": config.tables["humanact12"].rows["A2M-xyz"],
                                                      "ACTOR": config.tables["humanact12"].rows["ACTOR"]}
    assert rows["ODMO_conv"].fit_key == odmo.fit_key and rows["ODMO_conv"].sampling == "conventional"
    assert rows["-r_e"].training.model.use_end is False and rows["-r_e"].training.losses == odmo.training.losses
    assert rows["-L_es"].training.losses.contrastive is False and rows["-L_es"].training.model == odmo.training.model
    with pytest.raises(ValueError, match="datasets"):
        dataclasses.replace(config, datasets=("ntu13",))
    assert odmo_benchmark.OdmoBenchmarkConfig.paper().datasets == ("humanact12", "uestc")


@pytest.mark.smoke
def test_mocap_table_has_the_paper_rows_on_100_frame_windows(tmp_path):
    from experiments import odmo_mocap

    rows = run_smoke(odmo_mocap, tmp_path)["rows"]
    assert [name for name in rows if not name.endswith("(reported)")] == [
        "Real", "A2M-xyz", "ACTOR", "ODMO", "ODMO_conv", "-r_e", "-L_es"]
    assert odmo_mocap.OdmoMocapConfig.smoke().mocap.protocol.duration == 100
    for name in ("A2M-xyz", "ACTOR", "ODMO", "ODMO_conv", "-r_e", "-L_es"):
        assert_generations_vary(rows, name, "MoCap ")
    assert_real_recognised(rows, "MoCap Acc", paper_dataset("MoCap").num_classes)


@pytest.mark.smoke
def test_modes_table_scores_both_latent_spaces_against_the_true_modes(tmp_path):
    from experiments import odmo_modes

    rows = run_smoke(odmo_modes, tmp_path)["rows"]
    assert [name for name in rows if not name.endswith("(reported)")] == list(odmo_modes.ROWS)
    for label in ("HumanAct12",):  # the smoke's dataset
        assert rows["True modes"][f"{label} ARI"]["mean"] == 1.0
        assert rows["Real motions"][f"{label} mode-homogeneity"]["mean"] == pytest.approx(0.0, abs=1e-3)
        for name in ("Modes_ODMO", "Modes_ACTOR"):  # discovered modes split the classes: APD drops
            assert rows[name][f"{label} mode-homogeneity"]["mean"] > 0
            assert rows[name][f"{label} ARI"]["mean"] < 1.0  # a few steps of training do not find the true modes
    figures = tmp_path / "odmo_modes" / "smoke" / "seed-0" / "figures"
    assert (figures / "humanact12-codes.png").is_file() and list(figures.glob("humanact12-mode-*.png"))
    assert len(assert_samples_vary(tmp_path / "odmo_modes" / "smoke" / "seed-0")) == 2  # ODMO and ACTOR


@pytest.mark.smoke
def test_trajectory_table_measures_the_end_point_error_of_every_row(tmp_path):
    from experiments import odmo_trajectory

    rows = run_smoke(odmo_trajectory, tmp_path)["rows"]
    assert [name for name in rows if not name.endswith("(reported)")] == list(odmo_trajectory.ROWS)
    for name in odmo_trajectory.ROWS:
        for label in ("HumanAct12",):  # the smoke's dataset
            cells = rows[name]
            # dist_e is the mean squared error; the end error its root's mean: mean(√e) ≤ √mean(e)
            error_m = cells[f"{label} end error (cm)"]["mean"] / 100
            assert 0 < error_m <= np.sqrt(cells[f"{label} dist_e"]["mean"]) + 1e-6
    workdir = tmp_path / "odmo_trajectory" / "smoke" / "seed-0"
    assert (workdir / "figures" / "humanact12-end-points.png").is_file()
    assert len(assert_samples_vary(workdir)) == len(odmo_trajectory.ROWS)


@pytest.mark.smoke
def test_sigma_sweep_trains_one_model_per_value_with_the_code_reading(tmp_path):
    from experiments import odmo_sigma

    result = run_smoke(odmo_sigma, tmp_path)
    rows = result["rows"]
    assert [name for name in rows if not name.endswith("(reported)")] == ["σ²=6.25", "σ²=0.05", "Real"]
    # its config names the evaluators of all three datasets; metrics.json names the one the run used, whatever
    # else the (session's) cache holds
    assert [e["name"] for e in result["run"]["evaluators"]] == ["synth-uestc/gru"]
    assert 0 < result["run"]["evaluators"][0]["held_out_accuracy"] <= 1
    # the smoke runs UESTC (the paper profile all three), scored on the train and the test split
    assert list(rows["σ²=0.05"]) == [f"UESTC {c}" for c in ("Acc", "FID_tr", "FID_test", "Diversity", "MModality")]
    for name in ("σ²=6.25", "σ²=0.05"):
        _assert_generations_vary(rows, name, "UESTC Diversity", "UESTC MModality", share=1e-3)
    assert odmo_sigma.OdmoSigmaConfig.paper().datasets == ("humanact12", "mocap", "uestc")
    sweep = odmo_sigma.sweep(odmo_sigma.OdmoSigmaConfig.smoke().tables["humanact12"].odmo, (6.25, 0.05), "std")
    assert [r.training.losses.prior_std for r in sweep.values()] == [6.25, 0.05]
    assert (odmo_sigma.sweep(sweep["σ²=0.05"], (0.25,), "variance")["σ²=0.25"].training.losses.prior_std
            == pytest.approx(0.5))


def test_trajectory_table_refuses_an_evaluator_of_other_classes(tmp_path, monkeypatch):
    # It scores accuracy itself (not through the protocol): an evaluator of UESTC's 40 classes on HumanAct12's 12
    # would put every row near 0 % without a word.
    from types import SimpleNamespace

    from experiments import odmo_trajectory

    def uestc_recognizer(spec, data_root=None):
        assert spec.dataset == "synth-uestc"
        return SimpleNamespace(num_classes=40), None

    monkeypatch.setattr(odmo_trajectory, "trained_recognizer", uestc_recognizer)
    argv = ["--profile", "smoke", "--out", str(tmp_path), "--set", "tables.humanact12.evaluator.dataset=synth-uestc"]
    message = "evaluator: it recognises 40 classes, but the real set 'train'"
    # The command line prints the check's message alone, and the traceback on request.
    with pytest.raises(SystemExit, match=rf"^odmo_trajectory: seed 0: ValueError: .*{message}.*\n\(--traceback "):
        odmo_trajectory.main(argv)
    with pytest.raises(ValueError, match=message):
        odmo_trajectory.main([*argv, "--traceback"])
