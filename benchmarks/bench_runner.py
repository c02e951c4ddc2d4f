"""Measure the runner: speed-up from 1 to N workers, the harness's own overhead, and whole runs end to end.

A script, not a test::

    python benchmarks/bench_runner.py                      # quick profile, 1 vs 2 workers: sweep and end to end
    python benchmarks/bench_runner.py --workers 1,2,4 --repeat 3
    python benchmarks/bench_runner.py --algorithm monotone-chain --generator coplanar-grid
    python benchmarks/bench_runner.py --no-end-to-end      # the sweep only

**End to end** (the second table): ``python -m hullstress run`` as a user
runs it, in a fresh interpreter, with each worker count: generating the
cases, the sweep, triage (shrinking, merging into causes) and the report
(folders, pictures, summary, HTML).  Wall time of the whole command, the
phases from its ``run.json``, and the speed-up over 1 worker.  The machine's
load average is printed before and after: on a shared machine the absolute
seconds move with it, the speed-ups much less.

The sweep (cases x configs) is built once from the profile and the filters,
then executed with each worker count in turn, in the same process.  The fork
server that starts workers is warmed up first (its one-off start, reported
separately, would otherwise be charged to whichever run comes first); then
this process lowers its priority as ``python -m hullstress run`` does (its
workers keep theirs).

``--repeat`` runs rounds, in both tables: each round runs every worker count
once, in turn, because the machine's own speed drifts within minutes and
interleaving compares the counts under the same drift.  For each worker
count the best wall time is kept, and each round's speed-ups are printed
under its table, so the spread between rounds shows.

Columns:

* ``wall s``: the sweep's wall time, worker start-up included;
* ``busy s``: time inside algorithm calls, checks and case facts, summed over workers;
* ``overhead s`` / ``overhead %``: wall time not spent inside algorithms or
  checks, ``wall - busy / workers`` (messaging, result handling, worker
  restarts, idle workers at the end);
* ``per call``: that overhead divided by the number of calls;
* ``parent CPU per call``: CPU time of this (the parent) process during the
  run, per call: messaging and result handling, which competes with the
  workers for the cores (CPU time, so it holds on a loaded machine);
* ``speed-up``: the 1-worker wall time divided by this one;
* ``algorithms alone``: the calls per second the algorithms' own time allows
  on that many workers (``calls / (algorithms s / workers)``), i.e. with the
  checks and the harness free: no harness change can go beyond it.

A second table splits the last run's busy time by algorithm.
"""

from __future__ import annotations

import argparse
import os
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path
from typing import TypeVar

from hullstress.pipeline import yield_cpu_to_workers
from hullstress.plugins import load_plugin
from hullstress.results import ResultRow
from hullstress.runner import ExecutionStats, RunnerOptions, Task, execute
from hullstress.sweep import SweepOptions, build_tasks

from _bench_common import add_run_options, load_average, timed_run  # a sibling: benchmarks run as scripts
from _figures import add_figures_option, recorded  # a sibling: benchmarks run as scripts

T = TypeVar("T")


def _warm_up(tasks: list[Task]) -> float:
    start = time.perf_counter()
    execute(tasks[:1], RunnerOptions(workers=1, qhull=False), lambda row: None)
    return time.perf_counter() - start


def _one_run(tasks: list[Task], options: RunnerOptions) -> tuple[ExecutionStats, int, float, dict]:
    """One run: its stats, its row count, the parent's CPU seconds in it, and per algorithm
    ``[calls, algorithm seconds, check seconds]``."""
    per_algorithm: dict[str, list[float]] = {}

    def on_row(row: ResultRow) -> None:
        tally = per_algorithm.setdefault(str(row["algorithm"]), [0, 0.0, 0.0])
        tally[0] += 1
        tally[1] += float(row["seconds"] or 0.0)
        tally[2] += float(row["check_seconds"] or 0.0)

    cpu = time.process_time()
    stats = execute(tasks, options, on_row)
    cpu = time.process_time() - cpu
    return stats, sum(int(t[0]) for t in per_algorithm.values()), cpu, per_algorithm


def _interleaved(args: argparse.Namespace, run: Callable[[int], T], wall: Callable[[T], float]
                 ) -> tuple[dict[int, T], list[dict[int, float]]]:
    """``--repeat`` rounds, each running every worker count once, in turn: the best run per count and
    each round's wall times.  The machine's own speed drifts by several per cent within minutes, and
    interleaving puts the counts compared under the same drift."""
    best: dict[int, T] = {}
    rounds: list[dict[int, float]] = []
    for _ in range(args.repeat):
        walls: dict[int, float] = {}
        for workers in args.workers:
            got = run(workers)
            walls[workers] = wall(got)
            if workers not in best or walls[workers] < wall(best[workers]):
                best[workers] = got
        rounds.append(walls)
    return best, rounds


def _round_ratios(rounds: list[dict[int, float]], what: str, calls: int | None = None) -> None:
    """Each round's speed-ups over 1 worker (and calls per second), so the spread between rounds shows."""
    if len(rounds) < 2 or 1 not in rounds[0]:
        return
    parts = []
    for walls in rounds:
        ups = ", ".join(f"{w} workers {walls[1] / s:.2f}x" + (f" ({calls / s:.0f} calls/s)" if calls else "")
                        for w, s in walls.items() if w != 1)
        parts.append(ups)
    print(f"Each round of {what} (every worker count once, in turn): " + "; ".join(parts) + ".\n")


def _by_algorithm(per_algorithm: dict[str, list[float]], top: int = 8) -> None:
    """Where the busy time of a run goes: the algorithms with the most time (call + check), per call."""
    total = sum(t[1] + t[2] for t in per_algorithm.values()) or 1.0
    ranked = sorted(per_algorithm.items(), key=lambda kv: -(kv[1][1] + kv[1][2]))
    print(f"Busy time by algorithm (the {min(top, len(ranked))} largest of {len(ranked)}), last run above:\n")
    print("| algorithm | calls | algorithm ms per call | check ms per call | share of busy time |")
    print("| --- | ---: | ---: | ---: | ---: |")
    for name, (calls, alg, chk) in ranked[:top]:
        print(f"| {name} | {int(calls)} | {1000 * alg / calls:.2f} | {1000 * chk / calls:.2f} | "
              f"{100 * (alg + chk) / total:.1f} % |")
    print()


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    add_run_options(parser)
    parser.add_argument("--plugin", action="append", default=[], help="load a plug-in first (repeatable)")
    parser.add_argument("--no-sweep", action="store_true", help="skip the sweep-only measurement")
    parser.add_argument("--no-end-to-end", action="store_true", help="skip the end-to-end measurement")
    add_figures_option(parser, "bench_runner")
    args = parser.parse_args(argv)
    with recorded(args.figures, "bench_runner", "1 worker, interleaved round by round with the other worker counts (the speed-up columns)", argv):
        print(f"load average before: {load_average()}\n")
        # End to end first: the sweep table lowers this process's priority, which the commands would inherit.
        if not args.no_end_to_end:
            _end_to_end_table(args)
        if not args.no_sweep:
            _sweep_table(args)
        print(f"load average after: {load_average()}")
        return 0


def _end_to_end(args: argparse.Namespace, workers: int, out: Path) -> tuple[float, dict]:
    """One ``python -m hullstress run`` with ``workers``: its wall time and its run.json."""
    return timed_run(args, workers, out, plugins=args.plugin)


def _end_to_end_table(args: argparse.Namespace) -> None:
    with tempfile.TemporaryDirectory(prefix="hullstress-bench-") as tmp:
        best, rounds = _interleaved(args, lambda workers: _end_to_end(args, workers, Path(tmp) / f"w{workers}"),
                                    lambda got: got[0])
    results = [(workers, *best[workers]) for workers in args.workers]
    print(f"## End to end: `python -m hullstress run --profile {args.profile}`, seed {args.seed}\n")
    print("| workers | wall s | sweep s | triage s | report s | groups | causes | evaluations | speed-up |")
    print("|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    wall_1 = next((w for n, w, _ in results if n == 1), results[0][1])
    for workers, wall, meta in results:
        phases = meta.get("phase_seconds", {})
        triage = meta.get("triage") or {}
        print(f"| {workers} | {wall:.2f} | {phases.get('sweep', 0):.2f} | {phases.get('triage', 0):.2f} | "
              f"{phases.get('report', 0):.2f} | {triage.get('groups', '')} | {triage.get('causes', '')} | "
              f"{triage.get('evaluations', '')} | {wall_1 / wall:.2f}x |")
    print()
    _round_ratios(rounds, "end to end")


def _sweep_table(args: argparse.Namespace) -> None:
    """The sweep's tasks executed in this process with each worker count (no triage, no report)."""
    for spec in args.plugin:
        load_plugin(spec)
    sweep = SweepOptions(profile=args.profile, algorithms=tuple(args.algorithm), generators=tuple(args.generator),
                         seed=args.seed, timeout=args.timeout)
    t0 = time.perf_counter()
    tasks, _, _, _ = build_tasks(sweep)
    build_seconds = time.perf_counter() - t0
    n_calls = sum(len(t.configs) for t in tasks)
    if not tasks:
        raise SystemExit("nothing to run: no registered algorithm matches the generated cases")
    warm = _warm_up(tasks)
    # As `python -m hullstress run` does once its fork server runs: this process, which only feeds
    # the workers, yields the cores to them (they are forked from the fork server and keep theirs).
    yield_cpu_to_workers()
    base = sweep.runner_options()

    best, rounds = _interleaved(
        args,
        lambda workers: _one_run(tasks, RunnerOptions(workers=workers, timeout=base.timeout, qhull=base.qhull,
                                                      memory_limit_mb=base.memory_limit_mb)),
        lambda got: got[0].wall_seconds)
    results: list[tuple[int, ExecutionStats, int, float]] = []
    for workers in args.workers:
        stats, rows, parent_cpu, per_algorithm = best[workers]
        if rows != n_calls:
            print(f"warning: {workers} workers delivered {rows} of {n_calls} rows", file=sys.stderr)
        results.append((workers, stats, rows, parent_cpu))

    print(f"## The sweep alone: profile `{args.profile}`, seed {args.seed}\n")
    print(f"{len(tasks)} cases, {n_calls} calls; {os.cpu_count()} CPUs; cases built in {build_seconds:.2f} s; "
          f"fork server warm-up {warm:.2f} s (once per process, not in the table).\n")
    print("| workers | wall s | calls/s | algorithms s | checks s | facts s | overhead s | overhead % | per call "
          "| parent CPU per call | restarts | speed-up | algorithms alone |")
    print("|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    wall_1 = next((s.wall_seconds for w, s, _, _ in results if w == 1), results[0][1].wall_seconds)
    for workers, stats, rows, parent_cpu in results:
        per_call_ms = 1000 * stats.harness_overhead_seconds / max(1, rows)
        # The calls per second the algorithms alone allow on these workers (checks and harness free).
        ceiling = rows / (stats.algorithm_seconds / stats.workers) if stats.algorithm_seconds else float("inf")
        print(f"| {workers} | {stats.wall_seconds:.2f} | {rows / stats.wall_seconds:.0f} | "
              f"{stats.algorithm_seconds:.2f} | {stats.check_seconds:.2f} | {stats.facts_seconds:.2f} | "
              f"{stats.harness_overhead_seconds:.2f} | {100 * stats.harness_overhead_fraction:.1f} | "
              f"{per_call_ms:.2f} ms | {1000 * parent_cpu / max(1, rows):.3f} ms | {stats.worker_restarts} | "
              f"{wall_1 / stats.wall_seconds:.2f}x | {ceiling:.0f} calls/s |")
    print()
    _round_ratios(rounds, "the sweep", calls=n_calls)
    _by_algorithm(per_algorithm)


if __name__ == "__main__":
    sys.exit(main())
