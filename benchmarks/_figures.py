"""Write a benchmark's printed tables to ``docs/figures/<bench>.md``, which the documentation includes.

Nobody types a figure by hand: each benchmark script prints its Markdown tables
as before, and :func:`recorded` copies everything it prints on stdout into the
figure file, under a header that says when, on which machine and with which
command the figures were measured, and what each ratio is measured against.
The performance page of the documentation includes the file with the MkDocs
snippets syntax (``--8<-- "figures/bench_runner.md"``), so re-running the
benchmark is the only way its figures change.
"""

from __future__ import annotations

import argparse
import io
import os
import platform
import shlex
import sys
import time
from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from pathlib import Path

__all__ = ["FIGURES_DIR", "add_figures_option", "recorded", "machine"]

#: Where the documentation looks for figure files (``mkdocs.yml``: snippets' ``base_path``).
FIGURES_DIR = Path(__file__).resolve().parent.parent / "docs" / "figures"


def add_figures_option(parser: argparse.ArgumentParser, bench: str) -> None:
    """Add ``--figures FILE`` (default ``docs/figures/<bench>.md``; ``none`` writes no file)."""
    parser.add_argument(
        "--figures", default=str(FIGURES_DIR / f"{bench}.md"), metavar="FILE",
        help=f"also write the printed tables to FILE for the docs (default docs/figures/{bench}.md; 'none': do not)",
    )


def machine() -> str:
    """One line naming the machine: OS, architecture, CPU model and count, Python, the load average."""
    model = platform.processor() or platform.machine()
    try:
        with open("/proc/cpuinfo", encoding="utf-8") as handle:
            names = [ln.split(":", 1)[1].strip() for ln in handle if ln.startswith("model name")]
        if names:
            model = names[0]
    except OSError:
        pass
    try:
        load = ", ".join(f"{x:.2f}" for x in os.getloadavg())
    except OSError:
        load = "unknown"
    return (f"{platform.system()} {platform.machine()}, {os.cpu_count()} CPUs ({model}), "
            f"Python {platform.python_version()}; load average at the start {load} (1, 5, 15 min)")


class _Tee(io.TextIOBase):
    """A text stream that writes to the terminal and keeps a copy."""

    def __init__(self, terminal: io.TextIOBase) -> None:
        self.terminal = terminal
        self.copy = io.StringIO()

    def write(self, text: str) -> int:
        self.terminal.write(text)
        return self.copy.write(text)

    def flush(self) -> None:
        self.terminal.flush()


def _demote_headings(text: str) -> str:
    # A benchmark prints "## ..." as a document of its own; included in a page, its tables sit
    # under the page's own section, so its headings go two levels down.
    return "\n".join("##" + ln if ln.startswith("#") else ln for ln in text.splitlines())


@contextmanager
def recorded(figures: str, bench: str, reference: str, argv: Sequence[str] | None = None) -> Iterator[None]:
    """Copy what the block prints on stdout into the figure file ``figures`` (unless it is ``none``).

    Parameters
    ----------
    figures : str
        The ``--figures`` value: a path, or ``none``.
    bench : str
        The script's name, e.g. ``bench_runner``, for the header's command line.
    reference : str
        What every ratio of the tables is measured against, in the same run.
    argv : sequence of str, optional
        The script's arguments (default ``sys.argv[1:]``), repeated in the header.

    The file is written only when the block ends without an exception, so a
    failed or interrupted benchmark never replaces good figures with half a table.
    """
    args = list(sys.argv[1:] if argv is None else argv)
    shown = [a for i, a in enumerate(args) if a != "--figures" and (i == 0 or args[i - 1] != "--figures")
             and not a.startswith("--figures=")]
    started = time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime())
    where = machine()
    tee = _Tee(sys.stdout)  # type: ignore[arg-type]
    saved, sys.stdout = sys.stdout, tee
    try:
        yield
    finally:
        sys.stdout = saved
    if figures.lower() == "none":
        return
    command = shlex.join(["python", f"benchmarks/{bench}.py", *shown])
    header = (
        f"<!-- Written by benchmarks/{bench}.py: do not edit by hand, re-run the command below. -->\n"
        f"Measured {started} on {where}.  \n"
        f"Command: `{command}`.  \n"
        f"Reference, measured in the same run: {reference}.\n\n"
    )
    path = Path(figures)
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(header + _demote_headings(tee.copy.getvalue()).strip() + "\n", encoding="utf-8")
    print(f"figures written to {path}", file=sys.stderr)
