"""A one-line progress report: step, percentage, the latest metrics, speed and ETA."""

from __future__ import annotations

import datetime
import sys
import time
from collections.abc import Mapping
from typing import TextIO


class Progress:
    """Prints ``step 200/1000 [####------] 20% | loss 0.1234 | 35.1 step/s | ETA 0:00:23``.

    On a terminal the line is redrawn in place; in a log file each update is a line of its own. ``unit``
    names what is counted (``"step"``; ``"sequence"`` for dataset generation), ``label`` starts the line.
    """

    def __init__(self, total: int, start: int = 0, *, stream: TextIO | None = None, width: int = 20,
                 unit: str = "step", label: str = ""):
        self.total, self.start, self.width, self.unit = total, start, width, unit
        self.label = f"{label} " if label else ""
        self.stream = sys.stderr if stream is None else stream
        self._t0 = time.perf_counter()
        self._tty = bool(getattr(self.stream, "isatty", lambda: False)())

    def update(self, step: int, metrics: Mapping[str, float]) -> None:
        done = step - self.start
        elapsed = time.perf_counter() - self._t0
        rate = done / elapsed if elapsed > 0 and done > 0 else 0.0
        eta = datetime.timedelta(seconds=round((self.total - step) / rate)) if rate else "?"
        filled = int(self.width * step / max(self.total, 1))
        bar = "#" * filled + "-" * (self.width - filled)
        shown = "".join(f" | {k} {v:.4g}" for k, v in metrics.items())
        line = (f"{self.label}{self.unit} {step}/{self.total} [{bar}] {100 * step / max(self.total, 1):3.0f}%{shown} | "
                f"{rate:.1f} {self.unit}/s | ETA {eta}")
        self.stream.write(("\r" + line) if self._tty else line + "\n")
        self.stream.flush()

    def message(self, text: str) -> None:
        """A line of its own (e.g. an evaluation's results) that the progress line does not overwrite."""
        self.stream.write(("\r\033[K" + text + "\n") if self._tty else text + "\n")
        self.stream.flush()

    def close(self) -> None:
        if self._tty:
            self.stream.write("\n")
            self.stream.flush()
