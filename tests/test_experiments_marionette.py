"""Neural Marionette's tables run end to end in their smoke profiles, laid out as the paper lays them out; every
trained row is a generator that loads and acts in one call; the multi-action table chains the rows Table 1 trained."""

import dataclasses
import json

import matplotlib.pyplot as plt
import numpy as np
import pytest
from smoke_checks import assert_generations_vary, run_smoke

import jaxmotion
from experiments import marionet_ablation, marionet_multi, marionet_next_tag, marionet_revision, marionet_single
from jaxmotion.config import FrozenMap
from jaxmotion.recipes.marionette import ContextFreeRecipe, ContextRecipe
from jaxmotion.evaluation.tables import slug


def _assert_scored(rows, row, columns):
    assert list(rows[row]) == list(columns), row
    assert all(np.isfinite(rows[row][c]["mean"]) for c in columns), row


@pytest.mark.smoke
def test_single_action_table_scores_marionet_its_baselines_and_actor(tmp_path):
    rows = run_smoke(marionet_single, tmp_path)["rows"]
    measured = ("MARIONET", "MANN", "A2M", "ACTOR")
    assert list(rows) == [r for name in marionet_single.ROWS for r in (name, f"{name} (reported)")]
    for name in measured:
        _assert_scored(rows, name, marionet_single.COLUMNS)
        assert_generations_vary(rows, name, "Div", "Multi-mod", share=1e-3)
    assert list(rows["Real"]) == ["Acc", "Div", "Multi-mod"]  # no FID, no ΔTraj: the paper's "/"
    assert rows["Real"]["Acc"]["mean"] > 2 / 31  # the smoke evaluator recognises real actions: a fraction
    assert rows["MARIONET (reported)"] == dict(zip(marionet_single.COLUMNS, (1.115, 0.874, 9.904, 2.068, 0.129)))
    assert "ΔTraj" not in rows["A2M (reported)"]
    seed = tmp_path / "marionet_single" / "smoke" / "seed-0"
    walk = jaxmotion.load_generator(seed, row="marionet").action(0, "Walk", 20)  # one call from a tag to an action
    assert walk.lengths.tolist() == [20] and np.isfinite(walk.joints).all()
    for row, method in (("mann", "mann"), ("a2m", "a2m-context"), ("actor", "actor")):  # (they generated the table)
        assert jaxmotion.load_generator(seed, row=row).method == method
    for name in ("figure5.png", "figure6.png"):  # Figs. 5 and 6: a strip per action, drawn
        picture = plt.imread(seed / name)
        assert picture.shape[0] > 100 and picture[..., :3].std() > 0.01, name
    _multi_action_table_chains_the_rows_table_1_trained(tmp_path, seed)


def _multi_action_table_chains_the_rows_table_1_trained(tmp_path, single):
    """Table 3 trains its rows as Table 1 does (same recipes, data and key): run in the same --out, it resumes Table 1's
    finished rows as they are (and saves this smoke three trainings)."""
    multi = tmp_path / "marionet_multi" / "smoke" / "seed-0"
    rows = run_smoke(marionet_multi, tmp_path)["rows"]
    assert list(rows) == [r for name in marionet_multi.ROWS for r in (name, f"{name} (reported)")]
    columns = [f"{c} ({s})" for s in "OS" for c in ("Acc", "FID", "Δpose", "Δvel", "Motion QR", "PJ",
                                                    "AUJ", "Trans. FID")]
    for name in marionet_multi.ROWS:
        _assert_scored(rows, name, columns)
        assert rows[name]["Δpose (O)"]["mean"] > 0 and rows[name]["PJ (S)"]["mean"] > 0
        # resumed at its last step, nothing trained: its log is Table 1's, copied with the checkpoints
        log = (single / slug(name) / "metrics.jsonl").read_text()
        assert log and (multi / slug(name) / "metrics.jsonl").read_text() == log
        assert (multi / slug(name) / "checkpoints").is_dir()
    assert rows["MARIONET (reported)"]["Acc (S)"] == 0.862 and "PJ (O)" not in rows["MARIONET (reported)"]
    curves = json.loads((multi / "curves.json").read_text())
    assert set(curves) == {"Acc", "FID", "Action QR", "Motion QR"}
    assert all(len(values) == 4 for values in curves["Acc"].values()) and len(curves["Acc"]) == 6  # 3 rows x 2 sets
    picture = plt.imread(multi / "figure8.png")
    assert picture.shape[1] > 3 * picture.shape[0] and picture[..., :3].std() > 0.01


def test_single_action_rows_are_the_papers_methods():
    config = marionet_single.MarionetSingleConfig.smoke()
    assert list(config.rows) == ["MARIONET", "MANN", "A2M", "ACTOR"]
    assert isinstance(config.rows["ACTOR"], ContextFreeRecipe)
    assert all(isinstance(config.rows[r], ContextRecipe) for r in ("MARIONET", "MANN", "A2M"))
    assert config.table.protocol.joint_error is False
    paper = marionet_single.MarionetSingleConfig.paper()
    assert paper.rows["MARIONET"].training.model.width == 256 and paper.rows["MARIONET"].training.batch_size == 30
    assert paper.table.protocol.count is None


def test_ablation_rows_switch_off_what_their_names_say():
    rows = marionet_ablation.MarionetAblationConfig.cpu().rows
    full = rows["MARIONET"].training
    for name, switches in marionet_ablation.VARIANTS.items():
        training = rows[name].training
        expected = dataclasses.replace(full, model=dataclasses.replace(
            full.model, **{k: v for k, v in switches.items() if k != "scheduled_sampling"}),
            scheduled_sampling=switches.get("scheduled_sampling", True))
        assert training == expected, name
    assert rows["w/o TU and w/o TI"].training.model.time_unrolling is False
    # tag injection acts on the unrolling's queries only: without unrolling the two rows are one fit
    assert rows["w/o TU"].fit_key == rows["w/o TU and w/o TI"].fit_key != rows["w/o TI"].fit_key
    assert rows["w/o Schedule Sampling"].training.scheduled_sampling is False


@pytest.mark.smoke
def test_ablation_table_measures_the_joint_error_with_z_at_mu(tmp_path, monkeypatch):
    # The full row (its program compiled by the Table 1 smoke) and the one without scheduled sampling, the trainer's
    # other code path: each other row is a MARIONET compile of its own (about 20 s here); what their switches do is
    # tested above and in tests/test_marionet.py
    smoke = marionet_ablation.MarionetAblationConfig.smoke()
    measured = ("MARIONET", "w/o Schedule Sampling")
    monkeypatch.setattr(marionet_ablation.MarionetAblationConfig, "smoke", classmethod(
        lambda cls: dataclasses.replace(smoke, rows=FrozenMap({name: smoke.rows[name] for name in measured}))))
    rows = run_smoke(marionet_ablation, tmp_path)["rows"]
    assert list(rows) == ["MARIONET", "MARIONET (reported)", "w/o Schedule Sampling",
                          *(f"{name} (reported)" for name in marionet_ablation.VARIANTS if name != "MARIONET"), "Real"]
    for name in measured:
        _assert_scored(rows, name, marionet_ablation.COLUMNS)
    assert rows["MARIONET"]["ΔJPE"]["n"] == 1 and rows["MARIONET"]["ΔJPE"]["mean"] > 0  # Z = mu: one value, in cm
    # Two steps of an untrained model never pass the gate, so the full row trains by teacher forcing alone too: the
    # same parameters, and with Z = mu the same actions
    assert rows["w/o Schedule Sampling"]["ΔJPE"] == rows["MARIONET"]["ΔJPE"]
    assert rows["w/o TU (reported)"]["ΔJPE"] == 9.42


@pytest.mark.smoke
def test_revision_table_chains_one_marionet_four_ways_and_reports_both_readings(tmp_path):
    rows = run_smoke(marionet_revision, tmp_path)["rows"]
    variants = list(marionet_revision.VARIANTS)
    assert list(rows) == [r for name in variants for r in (name, f"{name} (reported)")] + [
        "NEURAL MARIONETTE (reported, text)"]
    columns = ["Acc", "FID", "Δpose", "Δvel", "Motion QR", "PJ", "AUJ", "Trans. FID"]
    for name in variants:
        revising = marionet_revision.VARIANTS[name].shadow_start == "revision"
        _assert_scored(rows, name, columns + ["Revised"] * revising)
    # the smoke's classifier, a few steps trained, rejects most actions: Action Revision regenerates some
    assert rows["NEURAL MARIONETTE"]["Revised"]["mean"] > 0
    assert rows["NEURAL MARIONETTE (reported)"]["Acc"] == 0.896
    assert rows["NEURAL MARIONETTE (reported, text)"] == {"Acc": 0.853, "Δpose": 2.65, "Δvel": 0.401}
    seed = tmp_path / "marionet_revision" / "smoke" / "seed-0"
    trained = [row for row in ("marionet", "marionet+ss", "neural-marionette-star", "neural-marionette")
               if (seed / row / "metrics.jsonl").exists()]
    assert len(trained) == 1  # one training for the four rows
    assert plt.imread(seed / "figure10.png")[..., :3].std() > 0.01


@pytest.mark.smoke
def test_next_tag_table_scores_single_and_multi_action_accuracy(tmp_path):
    rows = run_smoke(marionet_next_tag, tmp_path)["rows"]
    assert list(rows) == ["W/ next tag", "W/ next tag (reported)", "W/O next tag", "W/O next tag (reported)"]
    for name in marionet_next_tag.ROWS:
        _assert_scored(rows, name, marionet_next_tag.COLUMNS)
    assert rows["W/O next tag (reported)"] == dict(zip(marionet_next_tag.COLUMNS, (0.875, 0.770, 0.823)))
    config = marionet_next_tag.MarionetNextTagConfig.cpu()
    assert config.rows["W/O next tag"].recipe.training.model.next_tag is False
    assert config.rows["W/ next tag"].recipe == marionet_single.MarionetSingleConfig.cpu().rows["MARIONET"]
