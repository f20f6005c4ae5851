"""ACTOR's use-case experiments (Table 4, Figures 4 and 6) run end to end in their smoke profile."""

import dataclasses
import json

import jax
import numpy as np
import pytest
from smoke_checks import assert_samples_vary, run_smoke
from smooth_motions import smooth_dataset

from experiments import actor_augmentation, actor_durations, actor_recognition
from jaxmotion.evaluation.tables import slug
from jaxmotion.pipelines.actor import real_plus_generated
from jaxmotion.train import Checkpointer


@pytest.mark.smoke
def test_recognition_smoke_has_a_row_per_training_set_the_jitter_rows_and_the_reported_ones(tmp_path):
    result = run_smoke(actor_recognition, tmp_path)
    rows = result["rows"]
    sets = ["Real_orig", "Real_denoised", "Real_interpolated", "Generated", "Real_orig + Generated"]
    jitter = ["jitter (mm/frame²)", "jitter, noisy (mm/frame²)"]
    assert list(rows) == [*sets, *jitter, *(f"{name} (reported)" for name in sets)]
    assert all(list(cells) == ["Real_orig test", "Real_denoised test"] for cells in rows.values())
    assert rows[jitter[1]]["Real_orig test"] > rows[jitter[0]]["Real_orig test"] > 0  # the noise adds jitter
    folder = tmp_path / "actor_recognition" / "smoke" / "seed-0"
    assert sorted(p.name for p in (folder / "recognizers").iterdir()) == sorted(map(slug, sets))
    assert json.loads((folder / "metrics.json").read_text()) == result
    assert assert_samples_vary(folder) == ["actor"]  # the generator of the Generated rows
    # each accuracy is a share of the test windows
    windows = actor_recognition.ActorRecognitionConfig.smoke().recognizer.test_count
    shares = np.array([rows[name][column] * windows / 100 for name in sets for column in rows[name]])
    np.testing.assert_allclose(shares, shares.round(), atol=1e-3)


@pytest.mark.smoke
def test_durations_smoke_scores_both_models_at_every_duration_and_plots_them(tmp_path):
    result = run_smoke(actor_durations, tmp_path)
    config = actor_durations.ActorDurationsConfig.smoke()
    rows = result["rows"]
    assert list(rows) == ["Fixed-size", "Variable-size", "Real"]
    columns = [f"{metric} @{d}" for d in config.durations for metric in ("Acc. (%)", "FID_tr")]
    assert all(list(cells) == columns for cells in rows.values())
    assert rows["Fixed-size"][columns[0]]["n"] == config.table.protocol.repetitions
    folder = tmp_path / "actor_durations" / "smoke" / "seed-0"
    assert (folder / "durations.png").read_bytes()[:4] == b"\x89PNG"
    # the fine-tune went on from the fixed run's last step
    with Checkpointer(folder / "variable-size" / "checkpoints") as ckpt:
        assert ckpt.latest_step() == config.training.loop.steps + config.finetune_steps
    log = (folder / "variable-size" / "metrics.jsonl").read_text().splitlines()
    assert all(json.loads(line)["step"] > config.training.loop.steps for line in log)
    assert assert_samples_vary(folder) == ["fixed-size", "variable-size"]


@pytest.mark.smoke
def test_augmentation_smoke_has_both_rows_at_every_fraction_and_plots_them(tmp_path):
    result = run_smoke(actor_augmentation, tmp_path)
    fractions = actor_augmentation.ActorAugmentationConfig.smoke().fractions
    assert list(result["rows"]) == ["Real", "Real + generated"]
    assert all(list(cells) == [f"{100 * f:g}%" for f in fractions] for cells in result["rows"].values())
    assert (tmp_path / "actor_augmentation" / "smoke" / "seed-0" / "augmentation.png").read_bytes()[:4] == b"\x89PNG"
    assert len(assert_samples_vary(tmp_path / "actor_augmentation" / "smoke" / "seed-0")) == len(fractions)


def test_fractions_keep_every_class_and_nest():
    data = smooth_dataset(count=10)  # two classes of five clips
    key = jax.random.key(0)
    half, all_ = (actor_augmentation.fraction_of(data, f, key) for f in (0.5, 1.0))
    np.testing.assert_array_equal(np.bincount(half.actions), [3, 3])  # ceil(0.5 · 5)
    assert set(half.names) <= set(all_.names) and len(all_) == len(data)


def test_real_plus_generated_repeats_the_real_set_to_the_generated_size():
    real, generated = smooth_dataset(count=2), smooth_dataset(count=6)
    mixed = real_plus_generated(real, generated)
    assert len(mixed) == 3 * len(real) + len(generated)


@pytest.mark.parametrize("module, cls, field, value", [
    (actor_durations, "ActorDurationsConfig", "durations", ()),
    (actor_durations, "ActorDurationsConfig", "finetune_steps", 0),
    (actor_durations, "ActorDurationsConfig", "min_length", 120),
    (actor_augmentation, "ActorAugmentationConfig", "fractions", (0.0, 1.0)),
    (actor_recognition, "ActorRecognitionConfig", "noise_sigma", -1.0),
])
def test_configs_name_the_field_they_refuse(module, cls, field, value):
    with pytest.raises(ValueError, match=field):
        dataclasses.replace(getattr(module, cls).smoke(), **{field: value})
