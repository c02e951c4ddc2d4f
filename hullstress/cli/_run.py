"""``python -m hullstress run``: the main job, a sweep that writes a report folder."""

from __future__ import annotations

import argparse
import shutil
import signal
import sys
import time
from typing import Any

from ..config import EPS_CHOICES, SPHERE_CHOICES
from ..errors import UsageError
from ..profiles import PROFILES
from ..results import ResultRow, to_frame
from ..runner import DEFAULT_MEMORY_LIMIT_MB

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
                   help="sweep size: quick (default, under a minute) or nightly (about 30 minutes on 2 cores)")
    p.add_argument("--algorithm", action="append", default=[], metavar="NAME",
                   help="run only this algorithm (repeatable; default: every registered one; see `list algorithms`)")
    p.add_argument("--generator", action="append", default=[], metavar="NAME",
                   help="use only this generator family (repeatable; default: every family; see `list generators`)")
    p.add_argument("--sphere", choices=SPHERE_CHOICES, default=None,
                   help="Kenwright's sphere projection before the algorithm: off, on or both, for every algorithm "
                   "(default: both for in-house algorithms, off for plug-ins, adapters and executables)")
    p.add_argument("--eps", choices=EPS_CHOICES, default=None,
                   help="tolerance policy passed as eps to every algorithm taking eps: scaled, fixed or both "
                   "(default: both for in-house algorithms; plug-ins keep their own tolerance, no eps is passed)")
    p.add_argument("--sizes", type=str, default=None, metavar="N[,N...]",
                   help="point counts to generate (default: the profile's)")
    p.add_argument("--seed", type=int, default=0, help="base seed; same seed and arguments give the same table (default 0)")
    p.add_argument("--workers", type=int, default=None, metavar="N",
                   help="worker processes (default: all cores; 0 runs in this process without isolation)")
    p.add_argument("--timeout", type=float, default=None, metavar="SECONDS",
                   help="per-call timeout (default: the profile's)")
    p.add_argument("--time-budget", type=float, default=None, metavar="SECONDS",
                   help="stop starting new calls after this long; the report covers what ran")
    p.add_argument("--memory-limit", type=float, default=DEFAULT_MEMORY_LIMIT_MB, metavar="MB",
                   help="address-space limit per worker process in MiB; a runaway allocation becomes an "
                   f"error or crash row (default {DEFAULT_MEMORY_LIMIT_MB:g}; 0 for none)")
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


class _Terminated(Exception):
    """SIGTERM arrived: finish like Ctrl-C."""


def _raise_terminated(signum: int, frame: Any) -> None:
    raise _Terminated()


def run_command(args: argparse.Namespace) -> int:
    from ..plugins import load_plugin
    from ..progress import ProgressBar, progress_enabled
    from ..report.writer import RowStream, new_run_dir, run_metadata, write_report
    from ..report.tables import failure_counts
    from ..baseline import compare_with_baseline, load_baseline
    from ..report.finalize import finalize_run
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
        scheduler=args.scheduler,
        memory_limit_mb=_memory_limit(args.memory_limit),
    )
    baseline = load_baseline(args.baseline) if args.baseline else None  # a bad path fails before the sweep
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

    progress = ProgressBar(n_calls, enabled=progress_enabled(sys.stderr, quiet=args.quiet))

    def on_row(row: ResultRow) -> None:
        rows.append(row)
        stream(row)
        progress.update(row)

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
    except UsageError:
        # e.g. an unreachable --scheduler: nothing ran, so leave no empty run folder behind.
        stream.close(remove=True)
        if not rows:
            shutil.rmtree(run_dir, ignore_errors=True)
        raise
    finally:
        signal.signal(signal.SIGTERM, previous)
        progress.close()
    wall = time.perf_counter() - start
    arguments = {k: v for k, v in vars(args).items() if k not in ("handler",)}
    meta = run_metadata(
        run_id=run_dir.name, arguments=arguments, df=table, wall_seconds=wall,
        complete=complete, skipped=skipped,
        extra={"interrupted": interrupted, "calls_planned": n_calls,
               "budget_exhausted": bool(stats.budget_exhausted) if stats else False,
               "runner": stats.as_dict() if stats else None},
    )
    write_report(run_dir, table, meta)
    stream.close(remove=True)
    comparison = compare_with_baseline(table, baseline) if baseline is not None else None
    if comparison is not None:
        _write_baseline_section(run_dir, comparison, args.baseline)
    triage = finalize_run(
        run_dir, table, cases, meta, shrink=not (args.no_shrink or interrupted),
        timeout=options.runner_options().timeout, junit_path=args.junit, plugins=tuple(args.plugin),
    )
    if args.save_corpus and not interrupted:
        from ..corpus_save import save_minimised_failures

        new_groups = None
        if comparison is not None:
            new = comparison[comparison["state"] == "new"]
            new_groups = set(map(tuple, new[["algorithm", "sphere", "eps", "generator", "signature"]].astype(str).values))
        saved = save_minimised_failures(
            args.save_corpus, triage["records"], cases, new_groups=new_groups,
            workers=options.runner_options().workers, timeout=options.runner_options().timeout,
            found_by=f"hullstress run {run_dir.name}",
        )
        written = sum(1 for _, w in saved if w)
        print(f"corpus: {written} new entries in {args.save_corpus} ({len(saved) - written} already there)")

    failed = table["status"].isin(["fail", "error", "timeout", "crash"])
    counts = table["status"].value_counts()
    line = ", ".join(f"{counts.get(s, 0)} {s}" for s in ("pass", "fail", "rejected", "error", "timeout", "crash"))
    if not args.quiet:
        counts = failure_counts(table)
        worst = counts.groupby(["algorithm", "sphere", "eps"], observed=True)["failed"].sum()
        worst = worst[worst > 0].sort_values(ascending=False).head(8)
        if len(worst):
            print("failures by algorithm config:")
            for (alg, sph, eps), n in worst.items():
                print(f"  {alg}[sphere={sph},eps={eps}]: {n}")
        method, internal = int(counts["method_failed"].sum()), int(counts["internal_errors"].sum())
        if method or internal:
            print(f"not the algorithms': {method} failures of the sphere method or eps set-up (stage preprocess), "
                  f"{internal} internal errors (stage check)")
    state = "" if complete else " (INCOMPLETE)"
    print(f"{len(table)}/{n_calls} calls in {wall:.1f} s: {line}{state}")
    if comparison is not None:
        states = comparison["state"].value_counts()
        print(f"against baseline {args.baseline}: " + ", ".join(
            f"{states.get(k, 0)} {k} failure groups" for k in ("new", "still-failing", "fixed")))
    print(f"report: {run_dir}")
    if interrupted:
        return 130
    if comparison is not None:
        return 1 if bool((comparison["state"] == "new").any()) else 0
    return 1 if bool(failed.any()) else 0


def _write_baseline_section(run_dir: Any, comparison: Any, baseline: str) -> None:
    """``baseline.csv`` and a section of ``summary.md``: new, still-failing and fixed groups."""
    from ..report.writer import _markdown, atomic_write_text

    comparison.to_csv(run_dir / "baseline.csv", index=False)
    summary = run_dir / "summary.md"
    parts = [summary.read_text(encoding="utf-8").rstrip("\n"), "", f"## Against the baseline `{baseline}`", ""]
    for state in ("new", "still-failing", "fixed"):
        part = comparison[comparison["state"] == state].drop(columns="state")
        parts += [f"### {state} ({len(part)})", "", _markdown(part).rstrip("\n"), ""]
    atomic_write_text(summary, "\n".join(parts))
