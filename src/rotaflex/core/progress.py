"""Progress of a long run: a bar on a terminal, one line per update in a log.

One helper for every verb: a solver creates a :class:`Progress` and calls :meth:`Progress.update`
as often as it likes; the helper decides what to show. On a terminal it draws a tqdm bar; when
stderr is not a terminal (a log file, CI, a pipe) it writes one plain line per update, at most
every ``interval`` seconds and at every 10 % step, with the elapsed time and an estimate of the
time left. Inside ``rotaflex reproduce`` the lines go through :func:`rotaflex.core.report.step`,
so they carry the stage prefix (``[2/4 gear]``).
"""

from __future__ import annotations

import sys
import time
from typing import Any, TextIO


def _clock(seconds: float) -> str:
    """``"42 s"``, ``"3 min 20 s"``."""
    seconds = max(0.0, seconds)
    if seconds < 90:
        return f"{seconds:.0f} s"
    return f"{int(seconds // 60)} min {int(seconds % 60):02d} s"


class Progress:
    """Progress over ``total`` units of work.

    Parameters
    ----------
    total : float
        Amount of work (steps, cases, simulated seconds...); may be changed by :meth:`update`.
    desc : str
        What is running, e.g. ``"gear"`` or ``"simulating"``.
    unit : str
        Unit of ``total`` shown in the lines (``"step"``, ``"case"``, ``"s"``).
    enabled : bool
        False: show nothing (``--quiet``, or a library call without progress).
    tty : bool, optional
        Draw a bar (True) or write lines (False); default: whether ``stream`` is a terminal.
    interval : float
        Smallest time between two lines when not on a terminal [s].
    stream : file, optional
        Where lines and the bar go (default ``sys.stderr``).
    """

    def __init__(
        self,
        total: float,
        desc: str,
        unit: str = "",
        *,
        enabled: bool = True,
        tty: bool | None = None,
        interval: float = 5.0,
        stream: TextIO | None = None,
    ):
        self.total, self.desc, self.unit = float(total), desc, unit
        self.enabled = enabled
        self.stream = stream or sys.stderr
        self.tty = self.stream.isatty() if tty is None else tty
        self.interval = interval
        self.done = 0.0
        self.lines: list[str] = []  # every line written (for callers and tests)
        self._t0 = time.perf_counter()
        self._last_line = self._t0  # the first line after a tenth of the work or `interval`
        self._written = -1.0  # ``done`` at the last line written
        self._last_decile = 0
        self._bar: Any = None
        if enabled and self.tty:
            from tqdm import tqdm

            self._bar = tqdm(total=self.total, desc=desc, unit=unit or "it", leave=False, file=self.stream)

    def update(self, done: float, total: float | None = None) -> None:
        """Set the work done so far (absolute, not an increment); ``total`` may be revised."""
        if total is not None:
            self.total = float(total)
        self.done = float(done)
        if not self.enabled:
            return
        if self._bar is not None:
            self._bar.total = self.total
            self._bar.n = min(self.done, self.total)
            self._bar.refresh()
            return
        frac = self.done / self.total if self.total > 0 else 0.0
        decile = int(10 * min(frac, 1.0))
        now = time.perf_counter()
        if decile > self._last_decile or now - self._last_line >= self.interval:
            self._last_decile = max(decile, self._last_decile)
            self._write(self.line(now))

    def line(self, now: float | None = None) -> str:
        """The one-line state: ``"gear: 40 % (400/1000 step), 12 s elapsed, about 18 s left"``."""
        elapsed = (now or time.perf_counter()) - self._t0
        frac = min(self.done / self.total, 1.0) if self.total > 0 else 0.0
        unit = f" {self.unit}" if self.unit else ""
        text = f"{self.desc}: {100 * frac:.0f} % ({self.done:g}/{self.total:g}{unit}), {_clock(elapsed)} elapsed"
        if 0.02 <= frac < 1.0:
            text += f", about {_clock(elapsed * (1 - frac) / frac)} left"
        return text

    def _write(self, text: str) -> None:
        from rotaflex.core.report import reporter_active, step

        self._last_line = time.perf_counter()
        self._written = self.done
        self.lines.append(text)
        if reporter_active():
            step(text)
        else:
            print(text, file=self.stream, flush=True)

    def close(self) -> None:
        """End the bar; in a log, write the final line if the last update was not written."""
        if self._bar is not None:
            self._bar.close()
            self._bar = None
        elif self.enabled and self.done > 0 and self.done != self._written:
            self._write(self.line())

    def __enter__(self) -> Progress:
        return self

    def __exit__(self, *exc) -> None:
        self.close()
