"""Progress lines: silent for short phases, rate-limited, ETA without the first unit's compilation."""

import io
import re

import numpy as np
import pytest

from jaxmotion.data.pipeline import map_in_chunks
from jaxmotion.progress import ENV_AFTER, ENV_EVERY, Progress, duration, phase


class Clock:
    """Seconds that pass only when a test says so."""

    def __init__(self):
        self.now = 0.0

    def __call__(self):
        return self.now


def _run(bar: Progress, clock: Clock, unit_seconds) -> list[str]:
    for seconds in unit_seconds:
        clock.now += seconds
        bar.advance(note="work")
    bar.close()
    return bar.stream.getvalue().splitlines()


def _phase(total, clock, after="10", every="5", **options):
    return phase("[test]", total, unit="item", environ={ENV_AFTER: after, ENV_EVERY: every}, stream=io.StringIO(),
                 clock=clock, primary=True, **options)


def test_eta_leaves_out_the_first_unit_which_includes_compilation():
    clock = Clock()
    lines = _run(_phase(10, clock, after="0", every="0"), clock, [30.0, 2.0, 2.0])  # compile, then 2 s a unit
    assert lines[0] == "[test] item 1/10  10% | work | 30s | ETA ?"  # no speed before a second unit
    # 2 units in the 4 s after the first: 0.5 unit/s, 7 units left
    assert lines[2] == "[test] item 3/10  30% | work | 0.5 item/s | 34s | ETA 14s"


def test_a_phase_shorter_than_the_threshold_prints_nothing():
    clock = Clock()
    assert _run(_phase(5, clock), clock, [1.9] * 5) == []


def test_lines_come_after_the_threshold_then_every_few_seconds_and_at_the_end():
    clock = Clock()
    lines = _run(_phase(20, clock), clock, [2.0] * 20)  # units end at 2, 4, ..., 40 s
    shown = [int(re.match(r"\[test\] item (\d+)/20", line).group(1)) for line in lines]
    assert shown == [5, 8, 11, 14, 17, 20]  # 10 s, then >= 5 s apart (16, 22, 28, 34), and the last unit
    assert lines[-1].endswith("| 40s | ETA 0s")


def test_a_phase_ending_early_shows_where_it_ended():
    clock = Clock()
    bar = _phase(9, clock, after="0", every="100")
    lines = _run(bar, clock, [1.0] * 4)
    assert [line.split(" | ")[0] for line in lines] == ["[test] item 1/9  11%", "[test] item 4/9  44%"]


def test_nothing_is_printed_by_a_process_other_than_the_primary():
    clock = Clock()
    bar = phase("[test]", 3, environ={ENV_AFTER: "0"}, stream=io.StringIO(), clock=clock, primary=False)
    assert _run(bar, clock, [20.0] * 3) == []


def test_fractional_units_per_chunk_add_up_to_one_per_pass():
    clock = Clock()
    bar = _phase(2, clock, after="0", every="0")
    tick = bar.per_chunk("pass")
    for i in range(3):
        clock.now += 1.0
        tick(i + 1, 3)
    assert bar.done == pytest.approx(1.0)
    assert bar.stream.getvalue().splitlines()[-1].startswith("[test] item 1/2  50% | pass | ")


def test_map_in_chunks_reports_each_chunk_once_it_is_done():
    calls = []
    out = map_in_chunks(lambda i, part: part * 2, np.arange(7), 3, on_chunk=lambda i, n: calls.append((i, n)))
    np.testing.assert_array_equal(out, 2 * np.arange(7))
    assert calls == [(1, 3), (2, 3), (3, 3)]


@pytest.mark.parametrize("text", ["-1", "soon", "nan"])
def test_a_threshold_that_is_not_seconds_is_refused(text):
    with pytest.raises(ValueError, match=ENV_AFTER):
        phase("[test]", 1, environ={ENV_AFTER: text})


def test_thresholds_default_to_ten_and_five_seconds():
    bar = phase("[test]", 1, environ={})
    assert (bar.after_s, bar.every_s) == (10.0, 5.0)


def test_durations_are_short():
    assert [duration(s) for s in (None, 0.4, 42, 80, 3600 + 5 * 60)] == ["?", "0s", "42s", "1m20s", "1h05m"]
