"""The progress bar: drawn only on a terminal, counting calls and failures."""

from __future__ import annotations

import io

import pytest

from hullstress.progress import ProgressBar, progress_enabled
from hullstress.results import ResultRow


class _Terminal(io.StringIO):
    def isatty(self) -> bool:
        return True


def _row(status: str) -> ResultRow:
    return ResultRow({"status": status})


def test_enabled_only_on_a_terminal_and_not_quiet():
    assert progress_enabled(_Terminal())
    assert not progress_enabled(_Terminal(), quiet=True)
    assert not progress_enabled(io.StringIO())


def test_disabled_bar_counts_but_writes_nothing():
    stream = io.StringIO()
    bar = ProgressBar(3, stream=stream)
    for status in ("pass", "crash", "rejected"):
        bar.update(_row(status))
    bar.close()
    assert (bar.done, bar.failed) == (3, 1)
    assert stream.getvalue() == ""


def test_fallback_counter_shows_calls_failures_and_time_left():
    stream = _Terminal()
    with ProgressBar(4, stream=stream, use_tqdm=False) as bar:
        for status in ("pass", "timeout", "fail", "rejected"):
            bar.update(_row(status))
    text = stream.getvalue()
    assert "hullstress: 1/4 calls, 0 failed" in text  # the first row draws at once
    assert text.rstrip("\n").endswith("4/4 calls, 2 failed, done in 00:00")
    assert text.endswith("\n")


def test_fallback_counter_estimates_time_left():
    bar = ProgressBar(10, stream=_Terminal(), use_tqdm=False)
    bar.done = 2
    assert bar.line(now=bar._start + 4.0).endswith("2/10 calls, 0 failed, 00:16 left")


def test_tqdm_bar_shows_calls_and_failures():
    pytest.importorskip("tqdm")
    stream = _Terminal()
    with ProgressBar(3, stream=stream) as bar:
        for status in ("pass", "error", "pass"):
            bar.update(_row(status))
    text = stream.getvalue()
    assert "3/3 calls" in text and "1 failed" in text
