"""ACTOR's Tables 1-3 run end to end in their smoke profiles, laid out as the paper lays them out."""

import pytest
from smoke_checks import assert_generations_vary, assert_real_recognised, run_smoke

from experiments import actor_architecture, actor_losses, actor_sota
from jaxmotion.data.datasets import paper_dataset
from jaxmotion.evaluation.tables import reported_row, side_by_side

UESTC = ["UESTC FID_tr", "UESTC FID_test", "UESTC Acc. (%)", "UESTC Div.", "UESTC Multimod."]
NTU13 = ["NTU-13 FID_tr", "NTU-13 Acc. (%)", "NTU-13 Div.", "NTU-13 Multimod."]
HUMANACT12 = ["HumanAct12 FID_tr", "HumanAct12 Acc. (%)", "HumanAct12 Div.", "HumanAct12 Multimod."]


def assert_real_rows_recognised(rows, labels):
    for label in labels:
        assert_real_recognised(rows, f"{label} Acc. (%)", paper_dataset(label).num_classes)


@pytest.mark.smoke
def test_losses_table_has_the_paper_rows_and_no_numbers_for_the_vertex_losses(tmp_path):
    rows = run_smoke(actor_losses, tmp_path)["rows"]
    not_run = ["L_V (needs an SMPL model: not run)", "L_R + L_V (needs an SMPL model: not run)"]
    assert list(rows) == ["Real", "Real (reported)", "L_J", "L_J (reported)", "L_R", "L_R (reported)",
                          not_run[0], "L_V (reported)", not_run[1], "L_R + L_V (reported)",
                          "L_R + L_J (stand-in for L_R + L_V)"]
    for name in ("Real", "L_J", "L_R", "L_R + L_J (stand-in for L_R + L_V)"):
        assert list(rows[name]) == UESTC + NTU13
        assert rows[name]["UESTC FID_test"]["n"] == actor_losses.ActorLossesConfig.smoke().tables["uestc"].table.protocol.repetitions
    for name in ("L_J", "L_R", "L_R + L_J (stand-in for L_R + L_V)"):
        for prefix in ("UESTC ", "NTU-13 "):
            assert_generations_vary(rows, name, f"{prefix}Div.", f"{prefix}Multimod.")
    assert all(rows[name] == {} for name in not_run)
    assert_real_rows_recognised(rows, ("UESTC", "NTU-13"))
    # the paper prints "3M*" / "4M*", not numbers, for the coordinate losses' UESTC FIDs
    assert "UESTC FID_tr" not in rows["L_V (reported)"] and rows["L_V (reported)"]["NTU-13 FID_tr"] == 0.25


@pytest.mark.smoke
def test_architecture_table_has_one_row_per_architecture(tmp_path):
    rows = run_smoke(actor_architecture, tmp_path)["rows"]
    names = ["Real", *actor_architecture.ARCHITECTURES]
    assert list(rows) == [row for name in names for row in (name, f"{name} (reported)")]
    assert all(list(rows[name]) == UESTC + NTU13 for name in names)
    assert rows["Transformer (reported)"]["UESTC FID_test"] == 23.43
    for name in actor_architecture.ARCHITECTURES:
        assert_generations_vary(rows, name, "UESTC Div.", "UESTC Multimod.")
    assert_real_rows_recognised(rows, ("UESTC", "NTU-13"))
    # each row trained in its own folder, per dataset
    workdir = tmp_path / "actor_architecture" / "smoke" / "seed-0"
    for dataset in ("uestc", "ntu-13"):
        trained = [p for p in (workdir / dataset).iterdir() if (p / "checkpoints").is_dir()]
        assert len(trained) == len(actor_architecture.ARCHITECTURES)


@pytest.mark.smoke
def test_sota_table_scores_action2motion_and_actor_beside_the_reported_baselines(tmp_path):
    rows = run_smoke(actor_sota, tmp_path)["rows"]
    assert list(rows) == ["Real", "Real [21] (reported)", "Real* (reported)", "CondGRU (reported)",
                          "Two-stage GAN (reported)", "Act-MoCoGAN (reported)", "Action2Motion",
                          "Action2Motion (reported)", "ACTOR", "ACTOR (reported)"]
    assert all(list(cells) == NTU13 + HUMANACT12 for cells in rows.values())
    assert rows["ACTOR (reported)"]["HumanAct12 FID_tr"] == 0.12
    for name in ("Action2Motion", "ACTOR"):
        assert_generations_vary(rows, name, "HumanAct12 Div.", "HumanAct12 Multimod.")
    assert_real_rows_recognised(rows, ("NTU-13", "HumanAct12"))


def test_loss_rows_never_read_the_translation_and_need_a_body_model_for_the_vertices():
    training = actor_losses.ActorLossesConfig.smoke().tables["ntu13"].training
    without, with_body = actor_losses.loss_variants(training, False), actor_losses.loss_variants(training, True)
    assert list(without) == ["L_J", "L_R", "L_R + L_J (stand-in for L_R + L_V)"]
    assert list(with_body) == ["L_J", "L_R", "L_V", "L_R + L_V", "L_R + L_J (stand-in for L_R + L_V)"]
    # L_P (motion) and L_D (translation) are the only terms on the translation row
    assert all(t.losses.motion == 0 and t.losses.translation == 0 for t in with_body.values())
    assert all(t.losses.kl == training.losses.kl for t in with_body.values())
    assert actor_losses.row_name("L_R + L_V", False) == "L_R + L_V (needs an SMPL model: not run)"
    assert actor_losses.row_name("L_R + L_V", True) == "L_R + L_V" and actor_losses.row_name("L_R", False) == "L_R"


def test_reported_rows_lay_out_the_paper_columns_per_dataset():
    row = reported_row({"UESTC": (None, 2.0, 3.0, 4.0, 5.0), "NTU-13": (0.1, 96.0, 7.0, 2.0)})
    assert list(row) == UESTC[1:] + NTU13 and row["UESTC FID_test"] == 2.0
    with pytest.raises(ValueError, match=r"numbers\['NTU-13'\]: expected 4 values"):
        reported_row({"NTU-13": (0.1, 0.2, 96.0, 7.0, 2.0)})
    assert side_by_side({"A": {"x": {"m": 1}}, "B": {"x": {"m": 2}, "y": {"m": 3}}}) == {
        "x": {"A m": 1, "B m": 2}, "y": {"B m": 3}}
