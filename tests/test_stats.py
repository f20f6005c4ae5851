"""Mean ± 95% confidence intervals and result tables."""

import math
import statistics

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from jaxmotion.evaluation import Summary, format_table, summarize, t_critical_95


def test_t_critical_matches_scipy():
    scipy_stats = pytest.importorskip("scipy.stats")
    for df in [1, 2, 3, 9, 19, 30, 31, 50, 200, 10_000]:
        assert t_critical_95(df) == pytest.approx(scipy_stats.t.ppf(0.975, df), abs=2e-4)


def test_summary_of_known_values():
    s = summarize([1.0, 2.0, 3.0])  # mean 2, s = 1, t(0.975, 2) = 4.3027
    assert s.mean == 2.0 and s.n == 3
    assert s.ci95 == pytest.approx(4.3027 / math.sqrt(3), rel=1e-4)


@given(st.integers(0, 2**31 - 1), st.integers(2, 40), st.floats(-100, 100), st.floats(0.01, 100))
def test_interval_is_affine_equivariant(seed, n, shift, scale):
    x = np.random.default_rng(seed).normal(size=n)
    a, b = summarize(x), summarize(scale * x + shift)
    assert b.mean == pytest.approx(scale * a.mean + shift, abs=1e-9 * (1 + abs(shift)))
    assert b.ci95 == pytest.approx(scale * a.ci95, rel=1e-9)


def test_single_value_has_no_interval_and_serialises_without_nan():
    s = summarize([4.0])
    assert math.isnan(s.ci95) and s.format() == "4.000"
    assert s.to_dict() == {"mean": 4.0, "ci95": None, "n": 1}
    assert math.isnan(Summary.from_dict(s.to_dict()).ci95)


def test_summarize_rejects_empty_and_2d():
    with pytest.raises(ValueError, match=r"\[N\]"):
        summarize([])
    with pytest.raises(ValueError, match=r"\[N\]"):
        summarize(np.zeros((2, 2)))


def test_table_layout():
    table = format_table({"Real": {"FID": 0.5, "Acc": Summary(99.0, 0.1, 20)}, "Ours": {"FID": 1.25}}, digits=2)
    assert table.splitlines() == [
        "| | FID | Acc |",
        "| --- | --- | --- |",
        "| Real | 0.50 | 99.00 ± 0.10 |",
        "| Ours | 1.25 | – |",
    ]


def test_paper_interval_conventions_reproduce_their_formulas():
    values = [1.0, 2.0, 4.0, 7.0]
    x = np.asarray(values)
    assert summarize(values, "actor").ci95 == pytest.approx(1.96 * x.var())
    # ODMO: statistics.NormalDist.from_samples(x).stdev * z / sqrt(n - 1)
    odmo = statistics.NormalDist.from_samples(values).stdev * statistics.NormalDist().inv_cdf(0.975) / 3 ** 0.5
    assert summarize(values, "odmo").ci95 == pytest.approx(odmo, rel=1e-12)
    assert summarize(values, "odmo").mean == summarize(values).mean == pytest.approx(3.5)
    with pytest.raises(ValueError, match="convention"):
        summarize(values, "scipy")
