"""ODMO put to use: the code bank, mode discovery on codes with known modes, mode-preserving and conventional
sampling, nearest-code end points, generation from codes, mode interpolation and end-point customisation."""

import dataclasses

import jax
import numpy as np
import pytest

from jaxmotion.data.datasets import load_dataset
from jaxmotion.models.odmo import ODMOConfig, init_odmo
from jaxmotion.pipelines import odmo as pipe
from jaxmotion.geometry.skeletons import SMPL24
from jaxmotion.pipelines.artefacts import DataFacts
from jaxmotion.pipelines.odmo import CodeBankConfig

CONFIG = ODMOConfig(num_joints=24, num_classes=3, num_frames=12, code_dim=4, encoder_hidden=8, encoder_width=16,
                    trajectory_hidden=8, trajectory_layers=1, motion_hidden=8, motion_layers=1)
BANK = CodeBankConfig(passes=1, draws=300)


def _bank(seed=0, per_mode=(40, 25, 5), classes=3, spread=0.05):
    """Codes of ``classes`` classes, each with modes of ``per_mode`` codes around far-apart centres; a mode's
    end points sit near a mode-specific place, so the nearest code's end tells the mode."""
    rng = np.random.default_rng(seed)
    codes, ends, actions, modes = [], [], [], []
    for c in range(classes):
        for m, n in enumerate(per_mode):
            centre = np.zeros(4)
            centre[m % 4] = 3.0 * (m + 1)
            centre += 20.0 * c
            codes.append(centre + spread * rng.standard_normal((n, 4)))
            ends.append(np.array([c, m, 0.0]) + 0.01 * rng.standard_normal((n, 3)))
            actions += [c] * n
            modes += [m] * n
    return pipe.CodeBank(np.concatenate(codes).astype(np.float32), np.concatenate(ends).astype(np.float32),
                         np.array(actions, np.int32), np.arange(len(actions), dtype=np.int32), np.array(modes, np.int32))


def _trained(bank):
    params, stats = init_odmo(jax.random.key(0), CONFIG)
    facts = DataFacts(SMPL24, ("a", "b", "c"), 20.0)
    return pipe.ODMOGenerator(CONFIG, params, stats, bank, pipe.fit_mixtures(bank, 3), facts)


def test_mode_counts_follow_the_codes_rounding_and_drop_small_modes():
    np.testing.assert_array_equal(pipe.mode_counts(np.array([40, 25, 5]), 100), [62, 38, 0])
    np.testing.assert_array_equal(pipe.mode_counts(np.array([30, 30, 30]), 10), [4, 3, 3])
    np.testing.assert_array_equal(pipe.mode_counts(np.array([11, 10, 3]), 7), [7, 0, 0])
    np.testing.assert_array_equal(pipe.mode_counts(np.array([4, 2, 0]), 6), [4, 2, 0])  # nothing above 10: keep all


def test_class_modes_find_well_separated_modes_and_sampling_preserves_their_shares():
    bank = _bank()
    modes = pipe.class_modes(bank, 3, n_init=2)
    assert modes.k.tolist() == [3, 3, 3]
    labels = pipe.bank_labels(bank, modes)
    for c in range(3):  # each discovered mode is one true mode
        rows = bank.of_class(c)
        pairs = set(zip(labels[rows].tolist(), bank.modes[rows].tolist()))
        assert len(pairs) == 3
    actions = np.repeat(np.arange(3), 100)
    codes, components = pipe.sample_codes(jax.random.key(1), actions, modes)
    for c in range(3):
        sizes = np.bincount(labels[bank.of_class(c)], minlength=3)
        counts = np.bincount(components[actions == c], minlength=modes.gmm.weights.shape[1])[:3]
        np.testing.assert_array_equal(counts, pipe.mode_counts(sizes, 100))
        assert counts[np.argmin(sizes)] == 0  # the 5-code mode gets no samples
    # codes land near their component's centre: the nearest real end point is the mode's
    ends = pipe.nearest_ends(bank, codes, actions)
    means = np.asarray(modes.gmm.means)
    np.testing.assert_allclose(codes, means[actions, components], atol=0.5)
    assert np.all(np.round(ends[:, 0]) == actions)
    again, _ = pipe.sample_codes(jax.random.key(1), actions, modes)
    np.testing.assert_array_equal(codes, again)


def test_a_class_too_small_for_the_silhouette_rule_gets_one_mode():
    bank = _bank(per_mode=(3, 3, 2), classes=2)
    modes = pipe.class_modes(bank, 2, n_init=1)
    assert modes.k.tolist() == [1, 1]
    rows = bank.of_class(1)
    np.testing.assert_allclose(np.asarray(modes.gmm.means[1, 0]), bank.codes[rows].mean(0), rtol=1e-5, atol=1e-5)
    codes, components = pipe.sample_codes(jax.random.key(0), np.array([1] * 5), modes)
    assert np.all(components == 0) and np.isfinite(codes).all()


def test_conventional_sampling_maps_each_class_to_its_majority_component():
    bank = _bank(per_mode=(40, 30, 20), spread=0.3)
    conventional = pipe.conventional_mixture(bank, 3)
    assert sorted(conventional.mapping.tolist()) == [0, 1, 2]  # three far-apart classes, three components
    codes, components = pipe.sample_codes(jax.random.key(2), np.repeat(np.arange(3), 50), conventional)
    assert all(len(set(components[i * 50:(i + 1) * 50].tolist())) == 1 for i in range(3))
    for c in range(3):  # a class's codes stay in its region of the code space
        centre = bank.codes[bank.of_class(c)].mean(0)
        assert np.abs(codes[c * 50:(c + 1) * 50].mean(0) - centre).max() < 2.0


def test_generation_from_codes_returns_the_motion_record_and_steers_by_the_end():
    trained = _trained(_bank())
    out = pipe.customize_end(trained, trained.bank.codes[0], 0, np.array([[0, 0, 0], [1.0, 0, 2.0]]))
    assert out["joints"].shape == (2, 12, 24, 3) and out["lengths"].tolist() == [12, 12]
    np.testing.assert_array_equal(out["translation"], out["joints"][:, :, 0])
    assert not np.allclose(out["trajectory"][0], out["trajectory"][1])  # same code, other end: another path
    np.testing.assert_array_equal(out["codes"][0], out["codes"][1])
    chunked = pipe.generate_from_codes(trained.params, CONFIG, out["codes"], out["actions"], out["ends"], chunk=1)
    np.testing.assert_allclose(chunked["joints"], out["joints"], atol=1e-5)
    with pytest.raises(ValueError, match=r"codes: expected \[N, 4\]"):
        pipe.generate_from_codes(trained.params, CONFIG, np.zeros((2, 3)), np.zeros(2, int), np.zeros((2, 3)))


def test_interpolation_runs_from_one_mode_mean_to_the_other():
    trained = _trained(_bank())
    modes = pipe.class_modes(trained.bank, 3, n_init=2)
    strip = pipe.interpolate_modes(trained, 1, 0, 2, 5, modes)
    means = np.asarray(modes.gmm.means[1])
    np.testing.assert_allclose(strip["codes"][0], means[0], rtol=1e-6)
    np.testing.assert_allclose(strip["codes"][-1], means[2], rtol=1e-5)
    np.testing.assert_allclose(strip["codes"][2], (means[0] + means[2]) / 2, rtol=1e-5, atol=1e-6)
    with pytest.raises(ValueError, match="class 1 has 3 modes"):
        pipe.interpolate_modes(trained, 1, 0, 3, 5, modes)


def test_end_point_trials_measure_the_distance_to_the_requested_end():
    trained = _trained(_bank())
    result = pipe.end_point_trials(trained, jax.random.key(0), trials=2, points=4)
    assert result["motions"]["joints"].shape == (3 * 2 * 4, 12, 24, 3)
    final = result["motions"]["joints"][:, -1, 0]
    squared = np.square(final - result["motions"]["ends"]).sum(-1)
    np.testing.assert_allclose(result["squared_error"], squared, rtol=1e-5)
    np.testing.assert_allclose(result["dist_e"], squared.reshape(3, 8).mean(1).mean(), rtol=1e-5)
    np.testing.assert_allclose(result["end_error"], np.sqrt(squared).reshape(3, 8).mean(1).mean(), rtol=1e-5)
    # a hit: the end within 10% of the requested end's distance from the origin; per class, then averaged
    hits = squared < 0.1**2 * np.square(result["motions"]["ends"]).sum(-1)
    assert result["hit_rate"] == pytest.approx(hits.reshape(3, 8).mean(1).mean())
    path = np.linalg.norm(result["motions"]["trajectory"][:, -1] - result["motions"]["ends"], axis=-1)
    np.testing.assert_allclose(result["path_end_error"], path.reshape(3, 8).mean(1).mean(), rtol=1e-5)
    assert result["end_response"] == pytest.approx(
        pipe.end_response(final.reshape(6, 4, 3), result["motions"]["ends"].reshape(6, 4, 3)))
    ends = result["motions"]["ends"].reshape(3, 2, 4, 3)
    np.testing.assert_allclose(ends[:, :, 1] - ends[:, :, 0], ends[:, :, 3] - ends[:, :, 2], atol=1e-6)  # evenly spaced
    # as the authors' test, each trial's first end point is its source window's own end
    codes = result["motions"]["codes"].reshape(3, 2, 4, -1)[:, :, 0]
    for code, first in zip(codes.reshape(-1, codes.shape[-1]), ends[:, :, 0].reshape(-1, 3)):
        row = int(np.flatnonzero(np.all(trained.bank.codes == code, axis=1))[0])
        np.testing.assert_allclose(first, trained.bank.ends[row], atol=1e-6)


def test_end_response_is_one_when_motions_follow_their_ends_and_zero_when_they_ignore_them():
    ends = np.stack([np.linspace([0.0, 0.0, 1.0], [2.0, 0.0, 3.0], 5), np.linspace([1.0, 0.0, 0.0], [0.0, 0.0, -2.0], 5)])
    assert pipe.end_response(ends + np.array([0.3, 0.0, -0.2]), ends) == pytest.approx(1.0)  # offset, follows
    assert pipe.end_response(np.broadcast_to(ends[:, :1], ends.shape) + 0.1, ends) == pytest.approx(0.0)
    assert pipe.end_response(ends[:, :1] + 0.5 * (ends - ends[:, :1]), ends) == pytest.approx(0.5)
    with pytest.raises(ValueError, match="ends: every sweep"):
        pipe.end_response(ends, np.zeros_like(ends))


def test_code_bank_holds_unique_codes_in_class_order_with_their_windows_ends():
    data = load_dataset("synth-humanact12", count=24).subset(np.arange(24))
    config = dataclasses.replace(CONFIG, num_classes=12)
    params, stats = init_odmo(jax.random.key(1), config)
    bank = pipe.code_bank(params, stats, config, data, jax.random.key(2), bank=BANK)
    assert len(np.unique(bank.codes, axis=0)) == len(bank.codes)
    assert np.all(np.diff(bank.actions) >= 0) and set(bank.actions.tolist()) == set(range(12))
    np.testing.assert_array_equal(bank.actions, data.actions[bank.clips])
    np.testing.assert_array_equal(bank.modes, data.modes[bank.clips])
    again = pipe.code_bank(params, stats, config, data, jax.random.key(2), bank=BANK)
    np.testing.assert_array_equal(bank.codes, again.codes)


def test_end_point_trials_refuse_a_class_without_bank_codes():
    import dataclasses

    trained = _trained(_bank())
    bank = trained.bank
    keep = bank.actions != 1
    empty = pipe.CodeBank(bank.codes[keep], bank.ends[keep], bank.actions[keep], bank.clips[keep], bank.modes[keep])
    with pytest.raises(ValueError, match="class 1 has no code in its bank"):  # it was a bare IndexError
        pipe.end_point_trials(dataclasses.replace(trained, bank=empty), jax.random.key(0), trials=2, points=4)


@pytest.mark.parametrize("change, message", [
    ({"actions": np.array([0, 1, 3, 1])}, r"score_modes: actions: expected class ids in \[0, 3\).*got \[3\]"),
    ({"actions": np.array([0, 1, 2])}, r"score_modes: actions: expected \[4\] integer class ids"),
    ({"true_modes": np.array([0, 1, -2, 0])}, r"score_modes: true_modes: expected \[4\] integer modes \(-1: unknown\)"),
    ({"joints": np.zeros((3, 5, 24, 3))}, r"score_modes: expected codes \[N, Z\] and joints \[N, T, J, 3\] of the same N"),
])
def test_mode_scores_refuse_labels_they_cannot_mean(change, message):
    """Checked before anything is fitted: a class id past the classes would be miscounted, not reported."""
    from jaxmotion.pipelines.odmo import score_modes

    inputs = {"codes": np.zeros((4, 2), np.float32), "actions": np.array([0, 1, 2, 1]),
              "true_modes": np.array([0, 1, -1, 0]), "joints": np.zeros((4, 5, 24, 3), np.float32), **change}
    with pytest.raises(ValueError, match=message):
        score_modes(inputs["codes"], inputs["actions"], inputs["true_modes"], inputs["joints"], 3)
