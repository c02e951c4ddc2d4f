"""Measure the runner: speed-up from 1 to N workers, and the harness's own overhead.

A script, not a test::

    python benchmarks/bench_runner.py                      # quick profile, 1 vs 2 workers
    python benchmarks/bench_runner.py --workers 1,2,4 --repeat 3
    python benchmarks/bench_runner.py --algorithm monotone-chain --generator coplanar-grid

The sweep (cases x configs) is built once from the profile and the filters,
then executed with each worker count in turn, in the same process.  The fork
server that starts workers is warmed up first (its one-off start, reported
separately, would otherwise be charged to whichever run comes first).  For
each worker count the best wall time of ``--repeat`` runs is kept.

Columns:

* ``wall s``: the sweep's wall time, worker start-up included;
* ``busy s``: time inside algorithm calls, checks and case facts, summed over workers;
* ``overhead s`` / ``overhead %``: wall time not spent inside algorithms or
  checks, ``wall - busy / workers`` (messaging, result handling, worker
  restarts, idle workers at the end);
* ``per call``: that overhead divided by the number of calls;
* ``speed-up``: the 1-worker wall time divided by this one.
"""

from __future__ import annotations

import argparse
import os
import sys
import time

from hullstress.plugins import load_plugin
from hullstress.runner import ExecutionStats, RunnerOptions, Task, execute
from hullstress.sweep import SweepOptions, build_tasks


def _parse_workers(text: str) -> list[int]:
    try:
        counts = [int(x) for x in text.split(",") if x.strip()]
    except ValueError:
        raise SystemExit(f"--workers must be comma-separated integers, got {text!r}") from None
    if not counts or min(counts) < 1:
        raise SystemExit(f"--workers must list worker counts of at least 1, got {text!r}")
    return counts


def _warm_up(tasks: list[Task]) -> float:
    start = time.perf_counter()
    execute(tasks[:1], RunnerOptions(workers=1, qhull=False), lambda row: None)
    return time.perf_counter() - start


def _best_run(tasks: list[Task], options: RunnerOptions, repeat: int) -> tuple[ExecutionStats, int]:
    best: ExecutionStats | None = None
    rows = 0
    for _ in range(repeat):
        count = [0]

        def on_row(row: object) -> None:
            count[0] += 1

        stats = execute(tasks, options, on_row)
        if best is None or stats.wall_seconds < best.wall_seconds:
            best, rows = stats, count[0]
    assert best is not None
    return best, rows


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--profile", default="quick", help="sweep profile (default quick)")
    parser.add_argument("--workers", default="1,2", type=_parse_workers, help="worker counts to compare (default 1,2)")
    parser.add_argument("--repeat", type=int, default=1, help="runs per worker count; the best is kept (default 1)")
    parser.add_argument("--algorithm", action="append", default=[], help="only this algorithm (repeatable)")
    parser.add_argument("--generator", action="append", default=[], help="only this generator (repeatable)")
    parser.add_argument("--plugin", action="append", default=[], help="load a plug-in first (repeatable)")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--timeout", type=float, default=None, help="per-call timeout (default: the profile's)")
    args = parser.parse_args(argv)

    for spec in args.plugin:
        load_plugin(spec)
    sweep = SweepOptions(profile=args.profile, algorithms=tuple(args.algorithm), generators=tuple(args.generator),
                         seed=args.seed, timeout=args.timeout)
    t0 = time.perf_counter()
    tasks, _, _, _ = build_tasks(sweep)
    build_seconds = time.perf_counter() - t0
    n_calls = sum(len(t.configs) for t in tasks)
    if not tasks:
        print("nothing to run: no registered algorithm matches the generated cases", file=sys.stderr)
        return 2
    warm = _warm_up(tasks)
    base = sweep.runner_options()

    results: list[tuple[int, ExecutionStats, int]] = []
    for workers in args.workers:
        options = RunnerOptions(workers=workers, timeout=base.timeout, qhull=base.qhull,
                                memory_limit_mb=base.memory_limit_mb)
        stats, rows = _best_run(tasks, options, args.repeat)
        if rows != n_calls:
            print(f"warning: {workers} workers delivered {rows} of {n_calls} rows", file=sys.stderr)
        results.append((workers, stats, rows))

    print(f"## Runner benchmark: profile `{args.profile}`, seed {args.seed}\n")
    print(f"{len(tasks)} cases, {n_calls} calls; {os.cpu_count()} CPUs; cases built in {build_seconds:.2f} s; "
          f"fork server warm-up {warm:.2f} s (once per process, not in the table).\n")
    print("| workers | wall s | busy s | overhead s | overhead % | per call | restarts | speed-up |")
    print("|---:|---:|---:|---:|---:|---:|---:|---:|")
    wall_1 = next((s.wall_seconds for w, s, _ in results if w == 1), results[0][1].wall_seconds)
    for workers, stats, rows in results:
        busy = stats.algorithm_seconds + stats.check_seconds + stats.facts_seconds
        per_call_ms = 1000 * stats.harness_overhead_seconds / max(1, rows)
        print(f"| {workers} | {stats.wall_seconds:.2f} | {busy:.2f} | {stats.harness_overhead_seconds:.2f} | "
              f"{100 * stats.harness_overhead_fraction:.1f} | {per_call_ms:.2f} ms | {stats.worker_restarts} | "
              f"{wall_1 / stats.wall_seconds:.2f}x |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
