"""``python -m hullstress report RUN_FOLDER``: triage the rows of a run folder and write its report.

The way out of a run that ended before its report: a run without isolation
(``--workers 0``) killed by the code under test, a run killed by SIGKILL or
by the machine, a run interrupted (Ctrl-C) before triage.  It reads the rows
(``results.csv``, else ``results.partial.csv``, streamed row by row during the
sweep), rebuilds the run's cases from the arguments ``run.json`` recorded
(cases depend only on them), groups and shrinks the failures and writes the
report into the same folder, as ``run`` would have.  ``run.json`` then says
how the sweep ended (``crashed``, ``interrupted``, ``running`` for a process
that vanished without a trace) and which calls it did not reach.

Exit status: 0 no failed call, 1 failures, 2 not a run folder (or its files
cannot be read, or its cases cannot be rebuilt), 4 the folder cannot be
written, 5 the folder holds no rows, 130/143 interrupted.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path
from typing import Any

from ..errors import UsageError
from . import EXIT_NO_WORK
from ._common import count

__all__ = ["add_parser", "report_command", "read_run_folder", "RunFolder"]

#: The rows of a run folder, the final table first.
ROW_FILES = ("results.csv", "results.partial.csv")


def add_parser(sub: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    p = sub.add_parser(
        "report",
        help="triage a run folder's rows (a crashed or interrupted run's too) and write its report",
        description="Read the rows of a run folder (results.csv, else results.partial.csv of a run that died), "
        "rebuild its cases from run.json, triage the failures and write the report into the folder. "
        "Exit status: 0 nothing failed, 1 failures, 2 not a run folder, 4 the folder cannot be written, "
        "5 no rows, 130/143 interrupted.",
    )
    p.add_argument("folder", metavar="RUN_FOLDER", help="a run folder (reports/<run-id>/, it holds run.json)")
    p.add_argument("--no-shrink", action="store_true", help="do not minimise failing cases")
    p.add_argument("--workers", type=count(minimum=1), default=None, metavar="N",
                   help="worker processes for triage (default: the run's, at least 1: triage runs isolated)")
    p.add_argument("--quiet", action="store_true", help="print only the report path and the exit summary line")
    p.set_defaults(handler=report_command)


class RunFolder:
    """What ``report`` reads from a run folder: ``run.json``, the rows and ``crash.log``."""

    def __init__(self, folder: Path, meta: dict[str, Any], rows_file: Path, crash: str | None) -> None:
        self.folder = folder
        self.meta = meta
        self.rows_file = rows_file
        self.crash = crash

    @property
    def arguments(self) -> dict[str, Any]:
        return dict(self.meta.get("arguments") or {})

    @property
    def ended(self) -> str:
        """How the sweep ended: run.json's state, ``crashed`` for a run that died with a crash log."""
        state = str(self.meta.get("state") or "complete")
        from ..pipeline import RUNNING

        if state == RUNNING and self.crash:
            return "crashed"
        return state


def read_run_folder(text: str) -> RunFolder:
    """Check ``text`` names a run folder and read it.

    Raises
    ------
    UsageError
        One line naming the folder: missing, not a folder, no ``run.json``,
        no rows file, or a ``run.json`` that ``run`` did not write.
    """
    from ..runner import CRASH_LOG

    folder = Path(text)
    if not folder.exists():
        raise UsageError(f"{text!r}: no such folder")
    if not folder.is_dir():
        raise UsageError(f"{text!r} is not a run folder: it is a file (a run folder is <out>/<run-id>/, "
                         "made by `hullstress run`)")
    meta_path = folder / "run.json"
    if not meta_path.is_file():
        raise UsageError(f"{text!r} is not a run folder: it has no run.json (a run folder is <out>/<run-id>/, "
                         "made by `hullstress run`)")
    try:
        meta = json.loads(meta_path.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, ValueError) as exc:
        raise UsageError(f"{str(meta_path)!r}: cannot read run.json: {exc}") from None
    arguments = meta.get("arguments") if isinstance(meta, dict) else None
    if not isinstance(arguments, dict) or "profile" not in arguments or "out" not in arguments:
        raise UsageError(f"{text!r}: its run.json records no arguments of `hullstress run` "
                         "(only a run's folder can be reported again)")
    rows_file = next((folder / name for name in ROW_FILES if (folder / name).is_file()), None)
    if rows_file is None:
        raise UsageError(f"{text!r} is not a run folder with rows: it has neither {' nor '.join(ROW_FILES)}")
    crash_path = folder / CRASH_LOG
    crash = None
    if crash_path.is_file():
        crash = _crash_summary(crash_path.read_text(encoding="utf-8", errors="replace"))
    return RunFolder(folder, meta, rows_file, crash)


def _crash_summary(text: str) -> str | None:
    """faulthandler's first line and the innermost frame: ``Fatal Python error: ...; File "x.py", line 3 in f``."""
    lines = [line.strip() for line in text.splitlines() if line.strip()]
    if not lines:
        return None
    frames = [line for line in lines if line.startswith("File ")]
    return lines[0] + (f"; innermost: {frames[0]}" if frames else "")


def _recorded_arguments(found: RunFolder) -> argparse.Namespace:
    """``run``'s arguments as the run folder recorded them, over ``run``'s defaults."""
    from . import build_parser

    defaults = build_parser().parse_args(["run"])
    recorded = {k: v for k, v in found.arguments.items() if hasattr(defaults, k) and k != "handler"}
    args = argparse.Namespace(**{**vars(defaults), **recorded})
    # Plug-in files given relative to the folder the run started in.
    cwd = found.meta.get("cwd")
    if cwd:
        args.plugin = [str(Path(cwd) / p) if (p.endswith(".py") and not Path(p).is_absolute()) else p
                       for p in args.plugin]
        args.points_file = [p if (p == "-" or Path(p).is_absolute()) else str(Path(cwd) / p)
                            for p in args.points_file]
    if "-" in args.points_file:
        raise UsageError(f"{str(found.folder)!r}: the run read points from stdin (--points-file -); "
                         "its cases cannot be rebuilt")
    return args


def report_command(args: argparse.Namespace) -> int:
    """Read the folder, rebuild the plan, triage and report; print the run's summary."""
    from ..pipeline import plan, report_rows
    from ..progress import progress_enabled
    from ..results import read_frame
    from . import _registrations
    from ._run import print_summary, run_options

    found = read_run_folder(args.folder)
    recorded = _recorded_arguments(found)
    try:
        table = read_frame(found.rows_file)
    except (OSError, ValueError, ImportError) as exc:
        raise UsageError(f"{str(found.rows_file)!r}: not a results table: {exc}") from None
    if args.workers is not None:
        recorded.workers = args.workers
    elif recorded.workers == 0:
        recorded.workers = None  # triage shrinks in isolated workers: the run's 0 was the sweep's
    recorded.no_shrink = bool(recorded.no_shrink or args.no_shrink)
    recorded.baseline = recorded.save_corpus = recorded.junit = None  # a report does not compare nor save
    recorded.last_failed = recorded.failed_first = False
    recorded.out = str(found.folder.parent)
    recorded.quiet = args.quiet
    with _registrations(recorded):
        options = run_options(recorded)
        the_plan = plan(options.sweep)
        known = {c.case_id for c in the_plan.cases}
        missing = sorted(set(table["case_id"]) - known) if len(table) else []
        if missing:
            raise UsageError(f"{str(found.folder)!r}: {len(missing)} cases of its rows cannot be rebuilt from its "
                             f"run.json (first: {missing[0]}); was it written by another version of hullstress?")
        # The plan keeps every planned call: those without a row are "not reached" in run.json.
        echo = None if args.quiet else (lambda line: print(line, file=sys.stderr, flush=True))
        if echo is not None:
            echo(f"hullstress report: {len(table)} rows from {found.rows_file}; the sweep ended {found.ended}"
                 + (f" ({found.crash})" if found.crash else ""))
        timings = found.meta.get("timings") or {}
        the_run = report_rows(
            found.folder, options, table, the_plan, ended=found.ended,
            complete=bool(found.meta.get("complete")) and found.ended == "complete",
            crash=found.crash, sweep_seconds=float(timings.get("wall_seconds") or 0.0),
            echo=echo, progress=progress_enabled(sys.stderr, quiet=args.quiet))
        print_summary(the_run, recorded, quiet=args.quiet)
    if not len(the_run.table) and the_run.signal is None and not the_run.environment_errors:
        return EXIT_NO_WORK
    return the_run.exit_status

