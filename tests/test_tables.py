"""Method-agnostic tables: rows are recipes trained from one key in their own folders, scored together."""

import jax
import numpy as np
import pytest

from jaxmotion.evaluation.tables import ACTOR_COLUMNS, interleave_reported, paper_columns, slug
from jaxmotion.recipes.tables import FIT_RECORD, fit_rows, table_dataset


class Recorder:
    """A recipe that records what it was trained with; its generator samples a constant and records its saves."""

    def __init__(self, calls, value):
        self.calls, self.value = calls, value

    def __repr__(self):  # what a fit record holds of a recipe
        return f"Recorder({self.value})"

    def fit(self, data, key, workdir=None, **options):
        resumed = workdir is not None and (workdir / "checkpoints").is_dir()
        self.calls.append((data, key, workdir, options, resumed))
        if workdir is not None:
            (workdir / "checkpoints").mkdir(parents=True, exist_ok=True)
            (workdir / "metrics.jsonl").write_text(f'{{"step": {self.value}}}\n')
        return self.value

    def generator(self, params, facts):
        return Constant(params, facts, self.calls)


class Constant:
    def __init__(self, params, facts, calls):
        self.params, self.facts, self.calls = params, facts, calls

    def sampler(self):
        return lambda key, actions, durations: {"params": self.params, "skeleton": self.facts.skeleton}

    def save(self, folder):
        self.calls.append(("saved", folder))
        folder.mkdir(parents=True, exist_ok=True)


class Data:
    skeleton, class_names, fps = "SMPL-24", ("a", "b"), 20

    def __init__(self, content="DATA"):
        self.content = content

    def digest(self):
        return self.content


def test_every_row_trains_from_the_same_key_in_its_own_folder(tmp_path):
    calls, key = [], jax.random.key(0)
    generators = fit_rows({"w/o µ/Σ tokens": Recorder(calls, 1), "GRU": Recorder(calls, 2)}, Data(), key, tmp_path,
                          mesh="MESH")
    fits = [c for c in calls if c[0] != "saved"]
    assert all(c[1] is key for c in fits)
    assert [c[2] for c in fits] == [tmp_path / "w-o-tokens", tmp_path / "gru"]
    assert all(c[3] == {"mesh": "MESH"} for c in fits)
    # each row's generator is written beside its checkpoints
    saved = [c[1] for c in calls if c[0] == "saved"]
    assert saved == [tmp_path / "w-o-tokens" / "generator", tmp_path / "gru" / "generator"]
    assert generators["GRU"].sampler()(None, None, None) == {"params": 2, "skeleton": "SMPL-24"}
    with pytest.raises(ValueError, match="distinct folder names"):
        fit_rows({"a b": Recorder([], 0), "a-b": Recorder([], 0)}, Data(), key, tmp_path)


def test_a_row_resumes_the_finished_fit_another_table_made_with_the_same_recipe_data_and_key(tmp_path, capsys):
    key = jax.random.key(0)
    table_1 = tmp_path / "single" / "cpu" / "seed-0"
    fit_rows({"MARIONET": Recorder([], 1), "MANN": Recorder([], 2)}, Data(), key, table_1)
    assert (table_1 / "marionet" / FIT_RECORD).is_file()
    calls = []
    fit_rows({"MARIONET": Recorder(calls, 1), "MANN": Recorder(calls, 3)}, Data(), key, tmp_path / "multi",
             lenders=[tmp_path / "nowhere", table_1])
    resumed = {c[2].name: c[4] for c in calls if c[0] != "saved"}
    assert resumed == {"marionet": True, "mann": False}  # MANN's recipe differs: trained anew
    assert f"the same fit finished in {table_1 / 'marionet'}" in capsys.readouterr().err
    assert (tmp_path / "multi" / "marionet" / "metrics.jsonl").read_text() == '{"step": 1}\n'  # its log as well
    for name, args in (("other-key", (Data(), jax.random.key(1))), ("other-data", (Data("OTHER"), key))):
        calls = []
        fit_rows({"MARIONET": Recorder(calls, 1)}, *args, tmp_path / name, lenders=[table_1])
        assert [c[4] for c in calls if c[0] != "saved"] == [False], name
    (table_1 / "marionet" / "generator").rmdir()  # a fit not finished (no generator yet) is not lent
    calls = []
    fit_rows({"MARIONET": Recorder(calls, 1)}, Data(), key, tmp_path / "early", lenders=[table_1])
    assert [c[4] for c in calls if c[0] != "saved"] == [False]


def test_paper_columns_rename_in_the_paper_order_with_accuracy_in_percent():
    rows = {"X": {"diversity": [1.0], "accuracy": [0.5, 0.7], "FID_train": [2.0], "FID_test": [3.0], "other": [9]}}
    out = paper_columns(rows)
    assert list(out["X"]) == ["FID_tr", "FID_test", "Acc. (%)", "Div."]
    np.testing.assert_allclose(out["X"]["Acc. (%)"], [50.0, 70.0])
    assert "other" not in out["X"] and set(ACTOR_COLUMNS) >= {"FID_train", "accuracy"}


def test_reported_rows_follow_their_measured_row():
    table = interleave_reported({"Real": {"a": 1}, "GRU": {"a": 2}}, {"GRU": {"a": 3}, "CondGRU": {"a": 4}},
                                ["Real", "CondGRU", "GRU"])
    assert list(table) == ["Real", "CondGRU (reported)", "GRU", "GRU (reported)"]


def test_table_datasets_use_the_stand_in_and_its_evaluator_in_each_profile():
    smoke, cpu = table_dataset("NTU-13", "smoke"), table_dataset("NTU-13", "cpu")
    assert smoke.data.name == "synth-ntu13" and smoke.data.count == 80 and not smoke.data.test_split
    assert cpu.data.count is None and cpu.evaluator.name == "synth-ntu13/gru"
    assert table_dataset("UESTC", "paper").protocol.repetitions == 20
    with pytest.raises(ValueError, match="label"):
        table_dataset("NTU-120", "cpu")
    assert slug("(c) w/o bias token") == "c-w-o-bias-token"
    assert slug("NEURAL MARIONETTE*") == "neural-marionette-star" != slug("NEURAL MARIONETTE")
