"""``python -m hullstress run``: the main job, a sweep that writes a report folder."""

from __future__ import annotations

import argparse
import sys
from typing import Any

from ..config import EPS_CHOICES, SPHERE_CHOICES
from ..errors import UsageError
from ..options import DEFAULTS, PROFILES

__all__ = ["add_parser", "run_command", "parse_sizes"]


def parse_sizes(text: str) -> tuple[int, ...]:
    """``"20,100"`` -> ``(20, 100)``; every size a positive integer."""
    sizes = []
    for part in text.split(","):
        part = part.strip()
        try:
            value = int(part)
        except ValueError:
            raise UsageError(f"--sizes must be comma-separated positive integers, got {text!r}") from None
        if value < 1:
            raise UsageError(f"--sizes must be positive, got {value} in {text!r}")
        sizes.append(value)
    return tuple(dict.fromkeys(sizes))


def _positive(name: str, value: float | None) -> float | None:
    if value is not None and not value > 0:
        raise UsageError(f"{name} must be positive, got {value!r}")
    return value


def _memory_limit(value: float) -> float:
    if not value >= 0:
        raise UsageError(f"--memory-limit must be 0 (no limit) or a positive number of MiB, got {value!r}")
    return value


def add_parser(sub: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    p = sub.add_parser(
        "run",
        help="run a sweep (the main job) and write a report folder",
        description="Generate hard point sets, run every selected hull algorithm config on them, "
        "certify each output and write reports/<run-id>/ (results.csv, summary.md, run.json). "
        "Exit status: 0 nothing failed, 1 failures found, 2 bad arguments or input, 3 internal error, "
        "130 interrupted (the partial report is written).",
    )
    p.add_argument("--profile", choices=sorted(PROFILES), default="quick",
                   help="sweep size: quick (default, about a minute and a half) or nightly (about 30 minutes of "
                   "sweep on 2 cores)")
    p.add_argument("--algorithm", action="append", default=[], metavar="NAME",
                   help="run only this algorithm (repeatable; default: every registered one; see `list algorithms`)")
    p.add_argument("--generator", action="append", default=[], metavar="NAME",
                   help="use only this generator family (repeatable; default: every family; see `list generators`)")
    p.add_argument("--sphere", choices=SPHERE_CHOICES, default="both",
                   help="Kenwright's sphere projection before the algorithm: off, on or both (default)")
    p.add_argument("--eps", choices=EPS_CHOICES, default="both",
                   help="tolerance policy for algorithms taking eps: scaled, fixed or both (default)")
    p.add_argument("--sizes", type=str, default=None, metavar="N[,N...]",
                   help="point counts to generate (default: the profile's)")
    p.add_argument("--seed", type=int, default=0, help="base seed; same seed and arguments give the same table (default 0)")
    p.add_argument("--workers", type=int, default=None, metavar="N",
                   help="worker processes (default: all cores; 0 runs in this process without isolation)")
    p.add_argument("--timeout", type=float, default=None, metavar="SECONDS",
                   help="per-call timeout (default: the profile's)")
    p.add_argument("--time-budget", type=float, default=None, metavar="SECONDS",
                   help="stop starting new calls after this long; the report covers what ran")
    p.add_argument("--memory-limit", type=float, default=DEFAULTS.memory_limit_mb, metavar="MB",
                   help="address-space limit per worker process in MiB; a runaway allocation becomes an "
                   f"error or crash row (default {DEFAULTS.memory_limit_mb:g}; 0 for none)")
    p.add_argument("--scheduler", default=None, metavar="ADDRESS",
                   help="run on the Dask cluster at this scheduler address (e.g. tcp://host:8786) "
                   "instead of local worker processes; the table is the same as a local run's")
    p.add_argument("--plugin", action="append", default=[], metavar="MODULE_OR_FILE",
                   help="import a module or .py file that registers algorithms or generators (repeatable)")
    p.add_argument("--points-file", action="append", default=[], metavar="FILE",
                   help="add a case from a points file (.npy, .csv, .xyz, Qhull text; repeatable); "
                   "with files and no --generator only the files run")
    p.add_argument("--out", default="reports", metavar="DIR", help="where the run folder goes (default: reports)")
    p.add_argument("--no-qhull", action="store_true", help="skip the Qhull agreement check")
    p.add_argument("--no-shrink", action="store_true",
                   help="do not minimise failing cases (failure folders hold the smallest failing case as found)")
    p.add_argument("--junit", default=None, metavar="FILE",
                   help="also write JUnit XML: a test case per algorithm config x family, failures carrying the minimal case")
    p.add_argument("--baseline", default=None, metavar="RUN_OR_CORPUS",
                   help="an earlier run (folder, results.csv or .parquet) or a corpus folder: exit 1 only for "
                   "failure groups new against it; the report lists new, still-failing and fixed groups")
    p.add_argument("--save-corpus", default=None, metavar="DIR",
                   help="add the minimised new failures (one per failing algorithm x family) to this corpus folder")
    p.add_argument("--quiet", action="store_true", help="print only the report path and the exit summary line")
    p.set_defaults(handler=run_command)


def run_command(args: argparse.Namespace) -> int:
    """Parse the options into :class:`~hullstress.pipeline.RunOptions`, run the pipeline, print its summary."""
    from ..pipeline import RunOptions, run
    from ..plugins import load_plugin
    from ..progress import progress_enabled
    from ..sweep import SweepOptions

    for spec in args.plugin:
        load_plugin(spec)
    if args.workers is not None and args.workers < 0:
        raise UsageError(f"--workers must be 0 or more, got {args.workers}")
    sweep = SweepOptions(
        profile=args.profile,
        algorithms=tuple(args.algorithm),
        generators=tuple(args.generator),
        sphere=args.sphere,
        eps=args.eps,
        sizes=parse_sizes(args.sizes) if args.sizes is not None else None,
        seed=args.seed,
        points_files=tuple(args.points_file),
        workers=args.workers,
        timeout=_positive("--timeout", args.timeout),
        time_budget=_positive("--time-budget", args.time_budget),
        qhull=not args.no_qhull,
        scheduler=args.scheduler,
        memory_limit_mb=_memory_limit(args.memory_limit),
    )
    options = RunOptions(
        sweep=sweep, out=args.out, shrink=not args.no_shrink, junit=args.junit, baseline=args.baseline,
        save_corpus=args.save_corpus, plugins=tuple(args.plugin),
        arguments={k: v for k, v in vars(args).items() if k != "handler"},
    )
    echo = None if args.quiet else (lambda line: print(line, file=sys.stderr, flush=True))
    the_run = run(options, echo=echo, progress=progress_enabled(sys.stderr, quiet=args.quiet))
    _print_summary(the_run, args, quiet=args.quiet)
    return the_run.exit_status


def _print_summary(the_run: Any, args: argparse.Namespace, *, quiet: bool) -> None:
    """The terminal's last lines, like pytest's short summary: the top causes and their folders, then the totals."""
    from ..report.summary import TABLES, TOP_CAUSES

    table = the_run.table
    counts = table["status"].value_counts()
    line = ", ".join(f"{counts.get(s, 0)} {s}" for s in ("pass", "fail", "rejected", "error", "timeout", "crash"))
    triage = the_run.triage
    report = the_run.report
    folders = {r.cause.slug: r.folder for r in report.records} if report is not None else {}
    if not quiet and triage is not None and triage.causes:
        causes = triage.causes
        shown = min(TOP_CAUSES, len(causes))
        print(_rule(f"short summary: top {shown} of {len(causes)} causes"))
        for rank, cause in enumerate(causes[:shown], start=1):
            size = f"{cause.minimal_size} points" + ("" if cause.minimised else " (not shrunk)")
            print(f"CAUSE {rank}: {cause.failures} failed in {len(cause.families)} "
                  f"famil{'y' if len(cause.families) == 1 else 'ies'}, {size}: {cause.headline}")
            if cause.slug in folders:
                print(f"    {folders[cause.slug]}")
        if len(causes) > shown:
            print(f"... {len(causes) - shown} more causes in {the_run.run_dir / TABLES['causes']}")
    state = "" if the_run.complete and not the_run.interrupted else " (INCOMPLETE)"
    wall = the_run.seconds.get("sweep", 0.0)
    tail = ""
    if triage is not None and triage.groups:
        tail = f"; {len(triage.groups)} failure groups, {len(triage.causes)} causes"
    print(f"{len(table)}/{the_run.plan.n_calls} calls in {wall:.1f} s: {line}{tail}{state}")
    if the_run.comparison is not None:
        states = the_run.comparison["state"].value_counts()
        print(f"against baseline {args.baseline}: " + ", ".join(
            f"{states.get(k, 0)} {k} failure groups" for k in ("new", "still-failing", "fixed")))
    if args.save_corpus and not the_run.interrupted:
        written = sum(1 for _, w in the_run.corpus_saved if w)
        print(f"corpus: {written} new entries in {args.save_corpus} ({len(the_run.corpus_saved) - written} already there)")
    if the_run.interrupted:
        print(f"hullstress: interrupted ({'SIGTERM' if the_run.exit_status == 143 else 'SIGINT'}); "
              "the report covers what finished", file=sys.stderr)
    print(f"report: {the_run.run_dir}")


def _rule(title: str, width: int = 79) -> str:
    """``===== title =====`` across the terminal's usual width, as pytest draws its section lines."""
    text = f" {title} "
    left = max(3, (width - len(text)) // 2)
    return "=" * left + text + "=" * max(3, width - left - len(text))
