"""``python -m hullstress run``: the main job, a sweep that writes a report folder."""

from __future__ import annotations

import argparse
import os
import signal
import sys
import time
from typing import Any

from ..config import EPS_CHOICES, SPHERE_CHOICES
from ..errors import UsageError
from ..profiles import PROFILES
from ..results import ResultRow, to_frame

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
                   help="sweep size: quick (default, under a minute) or nightly (about 30 minutes on 2 cores)")
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
    p.add_argument("--plugin", action="append", default=[], metavar="MODULE_OR_FILE",
                   help="import a module or .py file that registers algorithms or generators (repeatable)")
    p.add_argument("--points-file", action="append", default=[], metavar="FILE",
                   help="add a case from a points file (.npy, .csv, .xyz, Qhull text; repeatable); "
                   "with files and no --generator only the files run")
    p.add_argument("--out", default="reports", metavar="DIR", help="where the run folder goes (default: reports)")
    p.add_argument("--no-qhull", action="store_true", help="skip the Qhull agreement check")
    p.add_argument("--quiet", action="store_true", help="print only the report path and the exit summary line")
    p.set_defaults(handler=run_command)


class _Terminated(Exception):
    """SIGTERM arrived: finish like Ctrl-C."""


def _raise_terminated(signum: int, frame: Any) -> None:
    raise _Terminated()


def run_command(args: argparse.Namespace) -> int:
    from ..plugins import load_plugin
    from ..report.writer import RowStream, new_run_dir, run_metadata, write_report
    from ..report.tables import failure_counts
    from ..sweep import SweepOptions, build_tasks, run_sweep, sort_table

    for spec in args.plugin:
        load_plugin(spec)
    if args.workers is not None and args.workers < 0:
        raise UsageError(f"--workers must be 0 or more, got {args.workers}")
    options = SweepOptions(
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
    )
    tasks, cases, _, skipped = build_tasks(options)
    if not tasks:
        raise UsageError("nothing to run: no case matches the selected algorithms' dimensions")
    run_id = f"{time.strftime('%Y%m%d-%H%M%S')}-{args.profile}-seed{args.seed}"
    run_dir = new_run_dir(args.out, run_id)
    n_calls = sum(len(t.configs) for t in tasks)
    if not args.quiet:
        print(f"hullstress: {len(tasks)} cases x configs = {n_calls} calls -> {run_dir}", file=sys.stderr)

    stream = RowStream(run_dir)
    rows: list[ResultRow] = []

    def on_row(row: ResultRow) -> None:
        rows.append(row)
        stream(row)

    previous = signal.signal(signal.SIGTERM, _raise_terminated)
    start = time.perf_counter()
    complete = True
    interrupted = False
    stats = None
    try:
        result = run_sweep(options, on_row=on_row, tasks=tasks)
        table, stats = result.table, result.stats
        complete = not stats.budget_exhausted
    except (KeyboardInterrupt, _Terminated):
        interrupted, complete = True, False
        table = sort_table(to_frame(rows), [c.case_id for c in cases])
    finally:
        signal.signal(signal.SIGTERM, previous)
    wall = time.perf_counter() - start
    arguments = {k: v for k, v in vars(args).items() if k not in ("handler",)}
    meta = run_metadata(
        run_id=run_dir.name, arguments=arguments, df=table, wall_seconds=wall,
        complete=complete, skipped=skipped,
        extra={"interrupted": interrupted, "calls_planned": n_calls,
               "budget_exhausted": bool(stats.budget_exhausted) if stats else False},
    )
    write_report(run_dir, table, meta)
    stream.close(remove=True)

    failed = table["status"].isin(["fail", "error", "timeout", "crash"])
    counts = table["status"].value_counts()
    line = ", ".join(f"{counts.get(s, 0)} {s}" for s in ("pass", "fail", "rejected", "error", "timeout", "crash"))
    if not args.quiet:
        worst = failure_counts(table).groupby(["algorithm", "sphere", "eps"], observed=True)["failed"].sum()
        worst = worst.sort_values(ascending=False).head(8)
        if len(worst):
            print("failures by algorithm config:")
            for (alg, sph, eps), n in worst.items():
                print(f"  {alg}[sphere={sph},eps={eps}]: {n}")
    state = "" if complete else " (INCOMPLETE)"
    print(f"{len(table)}/{n_calls} calls in {wall:.1f} s: {line}{state}")
    print(f"report: {run_dir}")
    if interrupted:
        return 130
    return 1 if bool(failed.any()) else 0
