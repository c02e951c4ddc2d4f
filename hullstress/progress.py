"""A progress bar on stderr for interactive sweeps: calls done of planned, failures so far, time left.

It shows only when the stream is a terminal and the run is not ``--quiet``;
redirected or piped output (CI logs, ``2> file``) stays clean.  tqdm draws the
bar when installed (the optional extra ``progress``); otherwise a one-line
counter is redrawn in place.
"""

from __future__ import annotations

import sys
import time
from typing import Any, TextIO

from .results import ResultRow
from .records import FAILED_STATUSES

__all__ = ["ProgressBar", "PhaseProgress", "progress_enabled"]

#: Seconds between redraws of the fallback counter.
_REDRAW_SECONDS = 0.5


def progress_enabled(stream: TextIO | None = None, *, quiet: bool = False) -> bool:
    """True when a progress bar belongs on ``stream`` (default stderr): a terminal and not quiet.

    Examples
    --------
    >>> import io
    >>> progress_enabled(io.StringIO())
    False
    """
    if quiet:
        return False
    stream = sys.stderr if stream is None else stream
    try:
        return bool(stream.isatty())
    except (AttributeError, ValueError):  # closed or not a real stream
        return False


def _format_seconds(seconds: float) -> str:
    seconds = max(0, int(round(seconds)))
    h, rest = divmod(seconds, 3600)
    m, s = divmod(rest, 60)
    return f"{h}:{m:02d}:{s:02d}" if h else f"{m:02d}:{s:02d}"


class ProgressBar:
    """Counts rows as they arrive and draws progress on a terminal.

    Parameters
    ----------
    total : int
        Calls planned.
    stream : text stream, optional
        Where to draw (default stderr).
    enabled : bool, optional
        Force on or off; default :func:`progress_enabled` of ``stream``.
    use_tqdm : bool
        Use tqdm when importable (set False to get the plain counter).

    Examples
    --------
    Disabled bars count but draw nothing:

    >>> import io
    >>> from hullstress.progress import ProgressBar
    >>> bar = ProgressBar(3, stream=io.StringIO())
    >>> bar.enabled
    False
    """

    def __init__(self, total: int, *, stream: TextIO | None = None, enabled: bool | None = None,
                 use_tqdm: bool = True) -> None:
        self.total = int(total)
        self.stream = sys.stderr if stream is None else stream
        self.enabled = progress_enabled(self.stream) if enabled is None else bool(enabled)
        self.done = 0
        self.failed = 0
        self._start = time.monotonic()
        self._last_draw = 0.0
        self._bar: Any = None
        if self.enabled and use_tqdm:
            self._bar = _make_tqdm(self.total, self.stream)

    def update(self, row: ResultRow) -> None:
        """Count one finished call."""
        self.done += 1
        failed = row.get("status") in FAILED_STATUSES
        self.failed += failed
        if not self.enabled:
            return
        if self._bar is not None:
            if failed:
                self._bar.set_postfix_str(f"{self.failed} failed", refresh=False)
            self._bar.update(1)
            return
        now = time.monotonic()
        if now - self._last_draw >= _REDRAW_SECONDS or self.done == self.total:
            self._last_draw = now
            self.stream.write("\r" + self.line(now))
            self.stream.flush()

    __call__ = update

    def line(self, now: float | None = None) -> str:
        """The fallback counter's text: ``120/4000 calls, 3 failed, 00:45 left``."""
        now = time.monotonic() if now is None else now
        elapsed = now - self._start
        if self.done and self.total > self.done:
            left = _format_seconds(elapsed / self.done * (self.total - self.done)) + " left"
        elif self.done >= self.total:
            left = f"done in {_format_seconds(elapsed)}"
        else:
            left = "time left unknown"
        return f"hullstress: {self.done}/{self.total} calls, {self.failed} failed, {left}"

    def close(self) -> None:
        """Finish the bar's line so later output starts on a fresh one."""
        if not self.enabled:
            return
        if self._bar is not None:
            self._bar.close()
            self._bar = None
        else:
            self.stream.write("\r" + self.line() + "\n")
            self.stream.flush()
        self.enabled = False

    def __enter__(self) -> "ProgressBar":
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


def _make_tqdm(total: int, stream: TextIO) -> Any:
    try:
        from tqdm import tqdm
    except ImportError:
        return None

    class _Quiet(tqdm):  # type: ignore[misc,valid-type]
        # No monitor thread: the runner starts worker processes, and a helper
        # thread in the parent is one more thing to reason about.
        monitor_interval = 0

    return _Quiet(
        total=total, file=stream, unit="call", dynamic_ncols=True, smoothing=0.05, mininterval=0.2,
        desc="hullstress", postfix="0 failed",
        # tqdm puts ", " before the postfix: "hullstress: 120/4000 calls, 3 failed |###   | 00:45 left"
        bar_format="{desc}: {n_fmt}/{total_fmt} calls{postfix} |{bar}| {remaining} left",
    )


class PhaseProgress:
    """Progress of a phase after the sweep (triage, report) on stderr: ``done/total`` units and a detail.

    On a terminal the line is redrawn in place (at most every half second);
    elsewhere (CI logs, a redirected stderr) one line is written at each
    quarter, so a log shows that the phase moves without filling up.

    Parameters
    ----------
    phase : str
        ``triage``, ``report``.
    unit : str
        What is counted (``groups``, ``folders``).
    stream : text stream, optional
        Default stderr.
    live : bool, optional
        Redraw in place; default :func:`progress_enabled` of ``stream``.
    enabled : bool
        False draws nothing (``--quiet``).

    Examples
    --------
    >>> import io
    >>> out = io.StringIO()
    >>> p = PhaseProgress("triage", "groups", stream=out, live=False)
    >>> for k in range(1, 5):
    ...     p(k, 4, "wave 1 of 1")
    >>> p.close()
    >>> print(out.getvalue().strip())
    hullstress triage: 1/4 groups (wave 1 of 1)
    hullstress triage: 2/4 groups (wave 1 of 1)
    hullstress triage: 3/4 groups (wave 1 of 1)
    hullstress triage: 4/4 groups (wave 1 of 1)
    """

    def __init__(self, phase: str, unit: str, *, stream: TextIO | None = None, live: bool | None = None,
                 enabled: bool = True) -> None:
        self.phase, self.unit = phase, unit
        self.stream = sys.stderr if stream is None else stream
        self.live = progress_enabled(self.stream) if live is None else bool(live)
        self.enabled = enabled
        self._last_draw = 0.0
        self._last_quarter = -1
        self._drawn = False

    def line(self, done: int, total: int, detail: str = "") -> str:
        return f"hullstress {self.phase}: {done}/{total} {self.unit}" + (f" ({detail})" if detail else "")

    def __call__(self, done: int, total: int, detail: str = "") -> None:
        if not self.enabled or total <= 0:
            return
        if self.live:
            now = time.monotonic()
            if now - self._last_draw >= _REDRAW_SECONDS or done >= total:
                self._last_draw = now
                self.stream.write("\r\x1b[2K" + self.line(done, total, detail))
                self.stream.flush()
                self._drawn = True
            return
        quarter = 4 * done // total
        if quarter > self._last_quarter:
            self._last_quarter = quarter
            self.stream.write(self.line(done, total, detail) + "\n")
            self.stream.flush()

    def close(self) -> None:
        """End a redrawn line so later output starts on a fresh one."""
        if self.enabled and self.live and self._drawn:
            self.stream.write("\n")
            self.stream.flush()
        self._drawn = False
