"""ActFormer's tables run end to end in their smoke profiles, laid out as the paper lays them out."""

import dataclasses
import importlib

import numpy as np
import pytest
from smoke_checks import assert_samples_vary, run_smoke

from experiments import actformer_single
from jaxmotion.models.csgn import CSGNConfig


def _columns(label):
    return [f"{label} {column}" for column in ("Acc", "FID_m", "FID_w")]


@pytest.mark.smoke
def test_single_person_table_has_the_paper_rows_and_each_baseline_where_it_reads_the_data(tmp_path):
    rows = run_smoke(actformer_single, tmp_path)["rows"]  # the smoke runs BABEL, where Action2Motion does not run
    assert list(rows) == ["Real", "Action2Motion (reported)", "CSGN", "CSGN (reported)", "ACTOR", "ACTOR (reported)",
                          "ActFormer", "ActFormer (reported)"]
    for name in ("Real", "CSGN", "ACTOR", "ActFormer"):
        assert list(rows[name]) == _columns("BABEL")
    assert list(rows["ActFormer (reported)"]) == [c for label in actformer_single.LABELS for c in _columns(label)]
    assert rows["ActFormer (reported)"]["NTU-1P FID_m"] == 12.53
    repetitions = actformer_single.ActFormerSingleConfig.smoke().tables["babel"].table.protocol.repetitions
    for name in ("Real", "CSGN", "ACTOR", "ActFormer"):
        for column, cell in rows[name].items():
            assert cell["n"] == repetitions and np.isfinite(cell["mean"]), (name, column)
    # the Real row: two draws of the same windows' features lie closer than any generator's to them
    real = rows["Real"]["BABEL FID_w"]["mean"]
    assert all(real < rows[name]["BABEL FID_w"]["mean"] for name in ("ACTOR", "ActFormer"))
    workdir = tmp_path / "actformer_single" / "smoke" / "seed-0"
    assert (workdir / "babel" / "actformer").is_dir() and (workdir / "babel" / "actor").is_dir()
    assert len(assert_samples_vary(workdir)) == 3  # CSGN, ACTOR and ActFormer


def test_profiles_choose_the_datasets_and_the_authors_recipe():
    cpu, paper = actformer_single.ActFormerSingleConfig.cpu(), actformer_single.ActFormerSingleConfig.paper()
    assert cpu.datasets == ("ntu13",) and paper.datasets == ("ntu13", "nturecon1p", "ntu1p", "babel")
    rows = {name: table.rows for name, table in paper.tables.items()}
    assert rows["babel"]["ActFormer"].sampling == "sqrt" and rows["ntu13"]["ActFormer"].sampling == "epoch"
    assert rows["nturecon1p"]["ActFormer"].generator.output == "smpl"
    assert rows["ntu1p"]["ActFormer"].generator.output == "skeleton"
    assert rows["ntu13"]["ActFormer"].generator.joints == 24 and rows["babel"]["ActFormer"].generator.joints == 25
    assert rows["ntu1p"]["ActFormer"].critic_base_channels == 32 and rows["ntu1p"]["ActFormer"].batch_size == 64
    assert not rows["ntu13"]["ACTOR"].canonical and not rows["ntu1p"]["Action2Motion"].canonical
    assert rows["ntu1p"]["Action2Motion"].model.pose_dim == 75 and rows["babel"]["ACTOR"].model.num_classes == 120
    assert list(rows["ntu1p"]) == ["Action2Motion", "CSGN", "ActFormer"]  # each baseline where it reads the data
    table = paper.tables["ntu13"].table
    assert table.protocol.accuracy == "class_mean" and table.protocol.reference == "tiles"
    assert table.evaluator.dataset == "synth-ntu13" and table.evaluator.recognizer.inputs == "limbs"
    with pytest.raises(ValueError, match="datasets"):
        dataclasses.replace(cpu, datasets=("uestc",))


# The rows each smoke trains: the full model and one row per kind of switch (each row is a GAN compile of its own,
# 10-15 s here); every row's switch is checked by test_each_ablation_row_changes_only_what_its_name_says below and
# its model path by the generator's and critic's unit tests.
SMOKE_ROWS = {"actformer_ablation_single": ("(1) Gaussian latent prior", "(4) Full model"),
              "actformer_ablation_multi": ("(7) SelfAtt. in Disc.", "(8) Fixed PE", "(10) Full model"),
              "actformer_interaction": None}


@pytest.mark.smoke
@pytest.mark.parametrize("name", list(SMOKE_ROWS))
def test_ablation_tables_measure_the_full_model_and_each_kind_of_switch_and_report_every_row(name, tmp_path,
                                                                                          monkeypatch):
    module = importlib.import_module(f"experiments.{name}")
    config_class = module.__dict__[next(k for k in module.__dict__ if k.endswith("Config"))]
    if SMOKE_ROWS[name] is not None:
        monkeypatch.setattr(config_class, "VARIANTS", {row: config_class.VARIANTS[row] for row in SMOKE_ROWS[name]})
    rows = run_smoke(module, tmp_path)["rows"]
    config = config_class.smoke()
    measured = list(config.rows())
    assert [row for row in rows if not row.endswith("(reported)")] == ["Real", *measured]
    assert [row[:-len(" (reported)")] for row in rows if row.endswith("(reported)")] == list(module.REPORTED)
    columns = list(config.COLUMNS.values())
    for row in ["Real", *measured]:
        assert list(rows[row]) == columns, row
        assert all(np.isfinite(cell["mean"]) and cell["n"] == config.table.protocol.repetitions
                   for cell in rows[row].values()), row
    if config.training.generator.persons > 1:
        assert any("FIDa" in column for column in columns)  # FID_a from the one-person recogniser
    assert len(assert_samples_vary(tmp_path / name / "smoke" / "seed-0")) == len(measured)


def test_each_ablation_row_changes_only_what_its_name_says():
    from experiments import actformer_ablation_multi, actformer_ablation_single, actformer_interaction

    for module, config in ((actformer_ablation_single, actformer_ablation_single.ActFormerAblationSingleConfig),
                           (actformer_ablation_multi, actformer_ablation_multi.ActFormerAblationMultiConfig),
                           (actformer_interaction, actformer_interaction.ActFormerInteractionConfig)):
        cfg = config.paper()
        rows = cfg.rows()
        for name, changes in cfg.VARIANTS.items():
            differ = {path for path in ("prior", "shared_z", "critic_pooling", "generator.positions",
                                                 "generator.interaction")
                      if _get(rows[name], path) != _get(cfg.training, path)}
            assert differ == set(changes), (module.__name__, name, differ)
    single = actformer_ablation_single.ActFormerAblationSingleConfig.paper()
    graph = single.rows()["(2) GraphConv. in Gen."]  # the full recipe with the graph-convolution generator
    assert list(single.rows()) == list(actformer_ablation_single.REPORTED)
    assert isinstance(graph.generator, CSGNConfig) and graph.generator.temporal == "transformer"
    assert dataclasses.replace(graph, generator=single.training.generator) == single.training
    interaction = actformer_interaction.ActFormerInteractionConfig.paper()
    assert interaction.table.person_evaluator.dataset == "synth-ntu1p" and interaction.training.generator.persons == 2


def _get(config, path):
    for part in path.split("."):
        config = getattr(config, part)
    return config


@pytest.mark.smoke
def test_multi_person_table_scores_the_pair_and_its_aggregated_persons(tmp_path):
    from experiments import actformer_multi

    rows = run_smoke(actformer_multi, tmp_path)["rows"]
    assert [row for row in rows if not row.endswith("(reported)")] == ["Real", "Action2Motion", "CSGN", "ActFormer"]
    assert list(rows["Action2Motion"]) == list(actformer_multi.NTU2P)  # the pair side by side in each frame
    combat = ["Combat 5P FIDa"]  # the smoke's one Combat set
    assert list(rows["ActFormer"]) == list(actformer_multi.NTU2P) + combat
    assert list(rows["Real"]) == list(rows["ActFormer"]) == list(rows["CSGN"])
    assert rows["CSGN (reported)"]["Combat 5P FIDa"] == 4.02
    for column in actformer_multi.NTU2P[1:] + tuple(combat):  # the real second draw lies nearer than the generators
        assert rows["Real"][column]["mean"] < min(rows[name][column]["mean"] for name in ("CSGN", "ActFormer")), column
    workdir = tmp_path / "actformer_multi" / "smoke" / "seed-0"
    assert (workdir / "combat-5p" / "actformer").is_dir()
    assert len(assert_samples_vary(workdir)) == 3 + 2  # NTU-2P's three generators, CSGN and ActFormer on Combat
    for picture in ("ntu-2p", "combat-5p"):  # Figure 5's
        assert (workdir / f"{picture}-generated.png").read_bytes()[:4] == b"\x89PNG", picture
