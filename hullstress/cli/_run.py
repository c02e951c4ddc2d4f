"""``python -m hullstress run``: the main job, a sweep that writes a report folder."""

from __future__ import annotations

import argparse
import math
import sys
from collections.abc import Sequence
from typing import Any

from ..config import EPS_CHOICES, SPHERE_CHOICES
from ..errors import UsageError
from ..options import DEFAULTS, PROFILES
from . import EXIT_NO_WORK, EXIT_STATUS_HELP
from ._common import PROCESS, add_registration_options, count, mebibytes, registration_args, seconds
from ..records import Stage, Status

__all__ = ["add_parser", "run_command", "parse_sizes", "run_options", "print_summary"]


def parse_sizes(text: str) -> tuple[int, ...]:
    """``"20,100"`` -> ``(20, 100)``; every size a positive integer (``1e4`` is read as 10000).

    Examples
    --------
    >>> parse_sizes("24, 1e3")
    (24, 1000)
    """
    sizes = []
    for part in text.split(","):
        part = part.strip()
        try:
            value = int(part)
        except ValueError:
            try:
                as_float = float(part)
            except ValueError:
                raise UsageError(f"--sizes must be comma-separated positive integers, got {text!r}") from None
            if not (math.isfinite(as_float) and as_float.is_integer()):
                raise UsageError(f"--sizes must be comma-separated positive integers, got {part!r} in {text!r}")
            value = int(as_float)
        if value < 1:
            raise UsageError(f"--sizes must be positive, got {value} in {text!r}")
        sizes.append(value)
    return tuple(dict.fromkeys(sizes))


def _transforms(names: list[str]) -> tuple[str, ...]:
    from generators import TRANSFORMS

    from ..suggest import did_you_mean

    for name in names:
        if name not in TRANSFORMS:
            raise UsageError(f"--transform must be one of {', '.join(sorted(TRANSFORMS))}, got {name!r}"
                             f"{did_you_mean(name, TRANSFORMS)}")
    return tuple(dict.fromkeys(names))


def add_parser(sub: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    p = sub.add_parser(
        "run",
        help="run a sweep (the main job) and write a report folder",
        description="Generate hard point sets, run every selected hull algorithm config on them, "
        "certify each output and write reports/<run-id>/ (results.csv, summary.md, run.json). "
        "Algorithms are the built-ins, plug-ins (--plugin) and programs in any language (--exec). "
        + EXIT_STATUS_HELP,
    )
    p.add_argument("--profile", choices=sorted(PROFILES), default="quick",
                   help="sweep size: quick (default, about a minute and a half) or nightly (about 30 minutes of "
                   "sweep on 2 cores)")
    p.add_argument("--algorithm", action="append", default=[], metavar="NAME",
                   help="run only this algorithm (repeatable; default: every registered one; see `list algorithms`)")
    p.add_argument("--generator", action="append", default=[], metavar="NAME[:KEY=VALUE,...]",
                   help="use only this generator family, every variant; with parameters (e.g. "
                   "near-coplanar:surface=plane,delta=1e-12) exactly that one (repeatable; default: every "
                   "family; see `list generators` for each family's parameters); rbox:'ARGS' runs Qhull's rbox with ARGS "
                   "(e.g. rbox:'100 D3 s'), seeded from --seed")
    p.add_argument("--transform", action="append", default=[], metavar="NAME",
                   help="also run a metamorphic copy of every case that must have the same hull "
                   "(permute-rows, reverse-rows, scale-pow2, permute-axes, reflect, ...; repeatable); the "
                   "report lists cases whose verdict the transform changed")
    p.add_argument("--sphere", choices=SPHERE_CHOICES, default=None,
                   help="Kenwright's sphere projection before the algorithm: off, on or both, for every algorithm "
                   "(default: both for in-house algorithms, off for plug-ins, adapters and executables)")
    p.add_argument("--eps", choices=EPS_CHOICES, default=None,
                   help="tolerance policy passed as eps to every algorithm taking eps: scaled, fixed or both "
                   "(default: both for in-house algorithms; plug-ins keep their own tolerance, no eps is passed)")
    p.add_argument("--sizes", type=str, default=None, metavar="N[,N...]",
                   help="point counts to generate (default: the profile's)")
    p.add_argument("--seed", type=int, default=0,
                   help="base seed; same seed and arguments give the same table (default 0)")
    p.add_argument("--workers", type=count(minimum=0), default=None, metavar="N",
                   help="worker processes (default: all cores; 0 runs in this process without isolation: a crash of "
                   "the code under test ends the run, and `report RUN_FOLDER` then makes the report of its rows)")
    p.add_argument("--timeout", type=seconds(), default=None, metavar="SECONDS",
                   help="per-call timeout (default: the profile's)")
    p.add_argument("--time-budget", type=seconds(), default=None, metavar="SECONDS",
                   help="stop starting new calls after this long (each family's smallest case always runs); "
                   "the report covers what ran and says what it did not reach (exit status 5 when not one call ran)")
    p.add_argument("--memory-limit", type=mebibytes, default=DEFAULTS.memory_limit_mb, metavar="MB",
                   help="what the code under test and its check may allocate per worker process, in MiB, beyond "
                   "the worker's own libraries (RLIMIT_AS); a runaway allocation becomes an error row naming the "
                   "limit (or a crash row), and sizes whose cases would not fit are refused before anything "
                   f"is generated (default {DEFAULTS.memory_limit_mb:g}; at least {DEFAULTS.min_memory_limit_mb:g}; "
                   "0 for none)")
    p.add_argument("--scheduler", default=None, metavar="ADDRESS",
                   help="run on the Dask cluster at this scheduler address (e.g. tcp://host:8786) "
                   "instead of local worker processes; the table is the same as a local run's")
    add_registration_options(p)
    p.add_argument("--points-file", action="append", default=[], metavar="FILE",
                   help="add a case from a points file (.npy, .csv, .xyz, Qhull/rbox text; '-' reads stdin, "
                   "e.g. rbox 100 D3 | ... --points-file -; repeatable); with files and no --generator "
                   "only the files run")
    p.add_argument("--out", default="reports", metavar="DIR", help="where the run folder goes (default: reports)")
    p.add_argument("--no-qhull", action="store_true", help="skip the Qhull agreement check")
    p.add_argument("--qhull-options", default=None, metavar="OPTIONS",
                   help="Qhull options for the reference hull the agreement check compares with (e.g. 'Qbb Qc "
                   "Qz Q12'); tried first, then the usual fallbacks; the qhull_options column records which "
                   "produced each reference")
    last = p.add_mutually_exclusive_group()
    last.add_argument("--last-failed", "--lf", action="store_true",
                      help="run only the (case, config) calls that failed in the latest run in --out "
                      "(everything when it has none)")
    last.add_argument("--failed-first", "--ff", action="store_true",
                      help="run the cases that failed in the latest run in --out first, then the rest")
    p.add_argument("--no-shrink", action="store_true",
                   help="do not minimise failing cases (failure folders hold the smallest failing case as found)")
    p.add_argument("--junit", default=None, metavar="FILE",
                   help="also write JUnit XML: a test case per algorithm config x family, failures carrying the minimal case")
    p.add_argument("--baseline", default=None, metavar="RUN_OR_CORPUS",
                   help="an earlier run (folder, results.csv or .parquet) or a corpus folder: exit 1 only for "
                   "failure groups new against it; the terminal and the report list new, still-failing, fixed and "
                   "not-reached groups.  The folder --save-corpus writes may not exist yet (the first night)")
    p.add_argument("--save-corpus", default=None, metavar="DIR",
                   help="add one entry (its minimal case) per failure group this corpus folder does not hold yet; "
                   "created when missing")
    p.add_argument("--quiet", action="store_true", help="print only the report path and the exit summary line")
    p.set_defaults(handler=run_command)


def run_command(args: argparse.Namespace) -> int:
    """Parse the options into :class:`~hullstress.pipeline.RunOptions`, run the pipeline, print its summary."""
    if args.workers != 0:
        # First of all: the workers' fork server imports NumPy, SciPy and hullstress (about 0.6 s)
        # while this process imports pandas and builds the cases (see hullstress.forkserver).
        from ..forkserver import start_method

        start_method()
    from ..pipeline import run
    from ..progress import progress_enabled

    options = run_options(args)
    echo = None if args.quiet else (lambda line: print(line, file=sys.stderr, flush=True))
    the_run = run(options, echo=echo, progress=progress_enabled(sys.stderr, quiet=args.quiet),
                  warn=lambda line: print(line, file=sys.stderr, flush=True))
    print_summary(the_run, args, quiet=args.quiet)
    return the_run.exit_status


def run_options(args: argparse.Namespace) -> Any:
    """The :class:`~hullstress.pipeline.RunOptions` of ``run``'s parsed arguments (also those a run.json recorded)."""
    from ..pipeline import RunOptions
    from ..sweep import SweepOptions

    sweep = SweepOptions(
        profile=args.profile,
        algorithms=tuple(args.algorithm),
        generators=tuple(args.generator),
        transforms=_transforms(args.transform),
        sphere=args.sphere,
        eps=args.eps,
        sizes=parse_sizes(args.sizes) if args.sizes is not None else None,
        seed=args.seed,
        points_files=tuple(args.points_file),
        workers=args.workers,
        timeout=args.timeout,
        time_budget=args.time_budget,
        qhull=not args.no_qhull,
        qhull_options=args.qhull_options,
        scheduler=args.scheduler,
        memory_limit_mb=args.memory_limit,
    )
    options = RunOptions(
        sweep=sweep, out=args.out, shrink=not args.no_shrink, junit=args.junit, baseline=args.baseline,
        save_corpus=args.save_corpus, plugins=tuple(args.plugin), registration=registration_args(args),
        last_failed="only" if args.last_failed else "first" if args.failed_first else None,
        arguments={k: v for k, v in vars(args).items() if k != "handler"},
        yield_cpu=PROCESS.owned,
    )
    return options


def print_summary(the_run: Any, args: argparse.Namespace, *, quiet: bool) -> None:
    """The terminal's last lines, like pytest's short summary: the top causes and their folders, then the totals.

    Results go to stdout; what needs the user's attention (notes, hints, an
    interrupt, a refused write, no work done) to stderr.
    """
    from ..report.failures import reproduce_command
    from ..report.summary import TABLES, TOP_CAUSES
    from ..report.tables import failure_counts

    for note in the_run.plan.notes:
        print(f"note: {note}", file=sys.stderr)
    table = the_run.table
    counts = table["status"].value_counts()
    line = ", ".join(f"{counts.get(s, 0)} {s}" for s in Status)
    triage = the_run.triage
    report = the_run.report
    folders = {r.cause.slug: r.folder for r in report.records} if report is not None else {}
    if not quiet and triage is not None and triage.causes:
        for title, tag, causes in cause_sections(triage.causes):
            shown = min(TOP_CAUSES, len(causes))
            print(_rule(title.format(shown=shown, total=len(causes))))
            for rank, cause in enumerate(causes[:shown], start=1):
                print(_cause_line(tag, rank, cause))
                if cause.slug in folders:
                    print(f"    {folders[cause.slug]}")
                    print(f"    reproduce: {reproduce_command(folders[cause.slug])}")
            if len(causes) > shown:
                print(f"... {len(causes) - shown} more causes in {the_run.run_dir / TABLES['causes']}")
    if not quiet and len(table):
        by_config = failure_counts(table)
        method, internal = int(by_config["method_failed"].sum()), int(by_config["internal_errors"].sum())
        if method or internal:
            print(f"not the algorithms': {method} failures of the sphere method or eps set-up (stage preprocess), "
                  f"{internal} internal errors (stage check)")
    state = "" if the_run.complete and not the_run.interrupted else " (INCOMPLETE)"
    wall = the_run.seconds.get("sweep", 0.0)
    tail = ""
    if triage is not None and triage.groups:
        tail = f"; {len(triage.groups)} failure groups, {len(triage.causes)} causes"
    print(f"{len(table)}/{the_run.plan.n_calls} calls in {wall:.1f} s: {line}{tail}{state}")
    if the_run.baseline_note:
        print(f"note: {the_run.baseline_note}", file=sys.stderr)
    if the_run.comparison is not None:
        _print_comparison(the_run.comparison, args.baseline)
    if args.save_corpus and not the_run.interrupted and not the_run.environment_errors:
        written = [sig for _, w, sig in the_run.corpus_saved if w]
        held = len(triage.groups) - len(the_run.corpus_saved) if triage is not None else 0
        print(f"corpus: {len(written)} new entries in {args.save_corpus} (one per failure group it did not hold; "
              f"{max(held, 0)} groups already held)")
    for hint in the_run.report.hints if the_run.report is not None else ():
        print(f"hint: {hint}", file=sys.stderr)
    print(f"report: {the_run.run_dir}")
    status = the_run.exit_status
    if the_run.crash:
        print(f"the sweep was cut short ({the_run.ended}): {the_run.crash}", file=sys.stderr)
    untriaged = the_run.n_failed if triage is None or not triage.groups else 0
    if the_run.interrupted:
        from ..report.failures import report_run_command

        print(f"hullstress: interrupted ({'SIGTERM' if status == 143 else 'SIGINT'}); "
              "the report covers what finished"
              + (f"; {untriaged} failed calls were not triaged: run `{report_run_command(the_run.run_dir)}` "
                 "to triage them" if untriaged else ""), file=sys.stderr)
    elif the_run.environment_errors:
        more = len(the_run.environment_errors) - 1
        print(f"hullstress: error: {the_run.environment_errors[0]}"
              + (f" (and {more} more writes refused)" if more > 0 else "")
              + f"; what was written stays in {the_run.run_dir}", file=sys.stderr)
    elif status == EXIT_NO_WORK:
        print(f"hullstress: no work done: not one of {the_run.plan.n_calls} planned calls ran"
              + (f" within --time-budget {args.time_budget:g} s" if args.time_budget else ""), file=sys.stderr)


def _print_comparison(comparison: Any, baseline: str) -> None:
    """The counts per state, then every new, fixed and not-reached group by name (what a nightly log is read for)."""
    from ..corpus.baseline import STATES

    states = comparison["state"].value_counts()
    print(f"against baseline {baseline}: " + ", ".join(f"{int(states.get(k, 0))} {k}" for k in STATES)
          + " failure groups")
    for state in ("new", "fixed", "not-reached"):
        for label in comparison.loc[comparison["state"] == state, "label"]:
            print(f"  {state}: {label}")


#: The terminal's sections of causes, by the stage that failed: the algorithms' own first.
CAUSE_SECTIONS = (
    (Stage.ALGORITHM, "short summary: top {shown} of {total} causes in the algorithms", "CAUSE"),
    (Stage.PREPROCESS, "the sphere method: top {shown} of {total} causes (stage preprocess)", "METHOD"),
    (Stage.CHECK, "hullstress itself: top {shown} of {total} errors (stage check)", "INTERNAL"),
)


def cause_sections(causes: Sequence[Any]) -> list[tuple[str, str, list[Any]]]:
    """Triage's causes split by stage, in :data:`CAUSE_SECTIONS` order, each worst first; empty sections left out."""
    out = []
    for stage, title, tag in CAUSE_SECTIONS:
        mine = [c for c in causes if str(c.signature.stage) == stage.value]
        if mine:
            out.append((title, tag, mine))
    return out


def _cause_line(tag: str, rank: int, cause: Any) -> str:
    size = (f"{cause.minimal_size} point{'' if cause.minimal_size == 1 else 's'}"
            + ("" if cause.minimised else " (not shrunk)"))
    return (f"{tag} {rank}: {cause.failures} failed in {len(cause.families)} "
            f"famil{'y' if len(cause.families) == 1 else 'ies'}, {size}: {cause.headline}")


def _rule(title: str, width: int = 79) -> str:
    """``===== title =====`` across the terminal's usual width, as pytest draws its section lines."""
    text = f" {title} "
    left = max(3, (width - len(text)) // 2)
    return "=" * left + text + "=" * max(3, width - left - len(text))
