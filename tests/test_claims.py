"""A paper's claims checked against measured rows: the verdict follows the 95% intervals."""

import pytest

from jaxmotion.evaluation.claims import Claim, check, check_all, format_claims, interval
from jaxmotion.evaluation.stats import summarize


def rows(a, b, column="FID"):
    return {"A": {column: a}, "B": {column: b}}


def test_separated_intervals_decide_and_overlapping_ones_are_inconclusive():
    low, high, around = [1.0, 1.1, 0.9, 1.0], [3.0, 3.1, 2.9, 3.0], [2.0, 0.5, 3.5, 2.0]
    assert check(Claim("A", "<", "B", "FID"), rows(low, high))["verdict"] == "holds"
    assert check(Claim("A", ">", "B", "FID"), rows(low, high))["verdict"] == "does not hold"
    assert check(Claim("B", ">", "A", "FID"), rows(low, high))["verdict"] == "holds"
    assert check(Claim("A", "<", "B", "FID"), rows(low, around))["verdict"] == "inconclusive"


def test_cells_may_be_numbers_summaries_or_repetitions_and_the_numbers_are_reported():
    values = [1.0, 2.0, 3.0]
    summary = summarize(values)
    assert interval(values) == pytest.approx((2.0, 2.0 - summary.ci95, 2.0 + summary.ci95))
    assert interval(summary.to_dict()) == interval(values)
    assert interval(5.0) == (5.0, 5.0, 5.0)  # one value: a point
    assert interval({"mean": 4.0, "ci95": None, "n": 1}) == (4.0, 4.0, 4.0)
    result = check(Claim("A", "<", "B", "FID", "Table 9"), rows(values, 10.0))
    assert result["verdict"] == "holds" and result["b"] == {"mean": 10.0, "low": 10.0, "high": 10.0}
    assert result["a"]["mean"] == 2.0 and result["source"] == "Table 9"


def test_a_missing_row_or_column_is_not_measured():
    claims = [Claim("A", "<", "C", "FID"), Claim("A", "<", "B", "Acc.")]
    assert [r["verdict"] for r in check_all(claims, rows(1.0, 2.0))] == ["not measured", "not measured"]


def test_equal_means_are_inconclusive_and_bad_claims_are_refused():
    assert check(Claim("A", "<", "B", "FID"), rows(1.0, 1.0))["verdict"] == "inconclusive"
    with pytest.raises(ValueError, match="op"):
        Claim("A", "<=", "B", "FID")
    with pytest.raises(ValueError, match="itself"):
        Claim("A", "<", "A", "FID")


def test_the_markdown_lists_every_verdict_with_both_intervals():
    text = format_claims(check_all([Claim("A", "<", "B", "FID", "§4")], rows(1.0, 2.0)))
    assert "**holds**: A < B on FID: A 1.00 [1.00, 1.00], B 2.00 [2.00, 2.00] (§4)" in text
    assert format_claims([]) == ""
