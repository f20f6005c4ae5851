"""Progress lines on stderr: the training loop's bar, and every long phase's "N units, advance as each completes".

A phase (:func:`phase`) is silent while it is short: it prints its first line once it has run for
``JAXMOTION_PROGRESS_AFTER`` seconds (default 10; ``0``: from the first unit; ``inf``: never), then at most
every ``JAXMOTION_PROGRESS_EVERY`` seconds (default 5), and once at its end, e.g.
``[eval] pass 5/14  36% | rep 2/5 ACTOR generating | 0.12 pass/s | 42s | ETA 1m20s``.
Units may be fractions: a pass over chunks advances ``1 / chunks`` per chunk (:meth:`Progress.per_chunk`).

Speed and ETA are measured from the end of the first unit, whose time includes compilation. Only the
primary process prints (process 0, as ``jaxmotion.train.mesh.is_primary``; asked of JAX only when a line
is due, so short phases never touch it). Progress reads a clock and nothing else: it never changes a number.
"""

from __future__ import annotations

import math
import os
import sys
import time
from collections.abc import Callable, Mapping
from typing import Self, TextIO

ENV_AFTER = "JAXMOTION_PROGRESS_AFTER"
ENV_EVERY = "JAXMOTION_PROGRESS_EVERY"
DEFAULT_AFTER_S = 10.0
DEFAULT_EVERY_S = 5.0


class Progress:
    """Prints ``step 200/1000 [####------] 20% | loss 0.1234 | 35.1 step/s | 6s | ETA 23s``.

    ``total`` units from ``start``; ``unit`` names what is counted (``"step"``; ``"sequence"`` for dataset
    generation), ``label`` starts the line. A line is printed by :meth:`update` once ``after_s`` seconds
    have passed since construction, then when ``every_s`` seconds have passed since the last line, and at
    the last unit; the defaults (0, 0) print every update, as the training loop wants (it updates once per
    logging interval). ``primary``: whether this process prints (``None``: process 0). ``clock``: seconds,
    injectable for tests. On a terminal the line is redrawn in place; in a log file each one is a line.
    """

    def __init__(self, total: float, start: float = 0, *, stream: TextIO | None = None, width: int = 20,
                 unit: str = "step", label: str = "", after_s: float = 0.0, every_s: float = 0.0,
                 primary: bool | None = None, clock: Callable[[], float] = time.perf_counter):
        self.total, self.start, self.done, self.width, self.unit = total, start, start, width, unit
        self.label = f"{label} " if label else ""
        self.after_s, self.every_s, self.clock = after_s, every_s, clock
        self.stream = sys.stderr if stream is None else stream
        self._primary = primary
        self._t0 = clock()
        self._first: tuple[float, float] | None = None  # (time, done) when the first unit ended
        self._printed: tuple[float, float] | None = None  # (time, done) of the last line
        self._tty = bool(getattr(self.stream, "isatty", lambda: False)())

    def update(self, done: float, metrics: Mapping[str, float] | None = None, note: str = "") -> None:
        """``done`` units are complete (``metrics`` and ``note`` go into the line, if one is due)."""
        now = self.clock()
        self.done = done
        if self._first is None and done >= self.start + 1 - 1e-9:  # fractional units may sum to 0.999...
            self._first = (now, done)
        since = None if self._printed is None else now - self._printed[0]
        due = now - self._t0 >= self.after_s and (since is None or since >= self.every_s or done >= self.total)
        if due and self._is_primary():
            self._write(self._line(now, metrics or {}, note))
            self._printed = (now, done)

    def advance(self, units: float = 1, note: str = "") -> None:
        """``units`` more units are complete."""
        self.update(self.done + units, note=note)

    def per_chunk(self, note: str) -> Callable[[int, int], None]:
        """An ``on_chunk(i, chunks)`` callback (:func:`jaxmotion.data.pipeline.map_in_chunks`) that advances one
        unit over a pass's chunks; a call making several passes with it advances one unit per pass."""
        return lambda i, chunks: self.advance(1 / chunks, note)

    def message(self, text: str) -> None:
        """A line of its own (e.g. an evaluation's results) that the progress line does not overwrite."""
        self.stream.write(("\r\033[K" + text + "\n") if self._tty else text + "\n")
        self.stream.flush()

    def close(self) -> None:
        """End the phase: a phase that has shown a line shows where it ended (if that line was earlier)."""
        if self._printed is not None and self._printed[1] != self.done:
            self._write(self._line(self.clock(), {}, ""))
        if self._tty and self._printed is not None:
            self.stream.write("\n")
            self.stream.flush()

    def __enter__(self) -> Self:
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def _is_primary(self) -> bool:
        if self._primary is None:
            import jax  # lazily: this module sits below jaxmotion.train.mesh, and short phases never ask

            self._primary = jax.process_index() == 0
        return self._primary

    def _line(self, now: float, metrics: Mapping[str, float], note: str) -> str:
        fraction = self.done / self.total if self.total > 0 else 1.0
        filled = int(self.width * min(fraction, 1.0))
        bar = f" [{'#' * filled}{'-' * (self.width - filled)}]" if self.width else ""
        rate = None
        if self._first is not None and self.done > self._first[1] and now > self._first[0]:
            rate = (self.done - self._first[1]) / (now - self._first[0])
        eta = 0.0 if self.done >= self.total else None if rate is None else (self.total - self.done) / rate
        shown = (f" | {note}" if note else "") + "".join(f" | {k} {v:.4g}" for k, v in metrics.items())
        if rate is not None:  # unknown until a unit after the first has ended
            shown += f" | {rate:.1f} {self.unit}/s" if rate >= 1 else f" | {rate:.2g} {self.unit}/s"
        return (f"{self.label}{self.unit} {math.floor(self.done + 1e-9)}/{self.total}{bar} {100 * fraction:3.0f}%"
                f"{shown} | {duration(now - self._t0)} | ETA {duration(eta)}")

    def _write(self, line: str) -> None:
        self.stream.write(("\r\033[K" + line) if self._tty else line + "\n")
        self.stream.flush()


def phase(label: str, total: float, *, unit: str = "unit", environ: Mapping[str, str] | None = None,
          **options) -> Progress:
    """A long phase's :class:`Progress` (``with phase("[export]", n, unit="motion") as bar: ... bar.advance()``),
    silent for ``JAXMOTION_PROGRESS_AFTER`` seconds, then a line at most every ``JAXMOTION_PROGRESS_EVERY``
    seconds and one at the end (module docstring). ``options`` go to :class:`Progress` (``stream``, ``clock``,
    ``primary``)."""
    env = os.environ if environ is None else environ
    return Progress(total, unit=unit, label=label, width=0, after_s=_seconds(env, ENV_AFTER, DEFAULT_AFTER_S),
                    every_s=_seconds(env, ENV_EVERY, DEFAULT_EVERY_S), **options)


def _seconds(env: Mapping[str, str], name: str, default: float) -> float:
    text = env.get(name, "").strip()
    if not text:
        return default
    try:
        value = float(text)
    except ValueError:
        value = -1.0
    if not value >= 0:  # also refuses nan
        raise ValueError(f"{name}: expected seconds >= 0 (or 'inf': never), got {text!r}")
    return value


def duration(seconds: float | None) -> str:
    """``42s``, ``1m20s``, ``2h05m``; ``?`` when unknown."""
    if seconds is None or not math.isfinite(seconds):
        return "?"
    s = round(seconds)
    if s < 60:
        return f"{s}s"
    if s < 3600:
        return f"{s // 60}m{s % 60:02d}s"
    return f"{s // 3600}h{s % 3600 // 60:02d}m"
