"""Per-job cost of the isolated worker pool on tiny one-config jobs, against the same jobs in process.

A script, not a test::

    python benchmarks/bench_pool_jobs.py                         # monotone-chain, 300 random 8-point cases
    python benchmarks/bench_pool_jobs.py --algorithm gift-wrap-3d --jobs 300 --workers 2

Triage sends each shrink candidate as one job of one config: this measures
what such a job costs end to end through :class:`hullstress.runner.CallPool`
(pickling, messages, the parent's handling) next to the same call, facts and
check run in this process (:func:`hullstress.runner._protocol.run_job`).

A second table runs the same jobs each in a fresh worker (``alone``), as
triage runs every candidate of a crash's shrink: what a worker's start, its
first job and its retirement cost, in wall time and in CPU time of the whole
machine (fork server, workers and this process; read from ``/proc/stat``).
"""

from __future__ import annotations

import argparse
import sys
import time

import numpy as np
from _figures import add_figures_option, recorded  # a sibling: benchmarks run as scripts


def main(argv: list[str] | None = None) -> int:
    from hullstress._registry import get_algorithm, load_builtins
    from hullstress.config import AlgorithmConfig
    from hullstress.runner import CallPool, Task
    from hullstress.runner._protocol import Job, run_job
    from hullstress.triage.shrink import candidate_case

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--algorithm", default="monotone-chain")
    parser.add_argument("--jobs", type=int, default=300)
    parser.add_argument("--points", type=int, default=8)
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--qhull", action="store_true", help="build the Qhull reference per job")
    add_figures_option(parser, "bench_pool_jobs")
    args = parser.parse_args(argv)
    with recorded(args.figures, "bench_pool_jobs", "the same jobs run in this process (the speed-up column)", argv):
        load_builtins()
        dim = get_algorithm(args.algorithm).dim
        rng = np.random.default_rng(0)
        config = AlgorithmConfig(args.algorithm)
        tasks = [Task(i, candidate_case(rng.random((args.points, dim)), dim), (config,)) for i in range(args.jobs)]

        def in_process(batch: list[Task]) -> None:
            for task in batch:
                for _ in run_job(Job(task=task, start_at=0, qhull=args.qhull, facts=None, refs=(),
                                     budget_deadline=None, qhull_options=None)):
                    pass

        in_process(tasks[:20])  # warm-up: imports and caches
        start = time.perf_counter()
        in_process(tasks)
        local = (time.perf_counter() - start) / len(tasks)
        with CallPool(args.workers) as pool:
            pool.run(tasks[:10], timeout=10, qhull=args.qhull)
            busy = _busy_seconds()
            start = time.perf_counter()
            pool.run(tasks, timeout=10, qhull=args.qhull)
            pooled = (time.perf_counter() - start) / len(tasks)
            pooled_cpu = (_busy_seconds() - busy) / len(tasks)
            busy = _busy_seconds()
            start = time.perf_counter()
            pool.run(tasks, timeout=10, qhull=args.qhull, alone=[True] * len(tasks))
            fresh = (time.perf_counter() - start) / len(tasks)
            fresh_cpu = (_busy_seconds() - busy) / len(tasks)
        print(f"| algorithm | jobs | in process ms/job | pool of {args.workers} ms/job (wall) | speed-up |")
        print("| --- | ---: | ---: | ---: | ---: |")
        print(f"| {args.algorithm} | {len(tasks)} | {local * 1e3:.2f} | {pooled * 1e3:.2f} | {local / pooled:.2f}x |")
        print()
        print(f"| pool of {args.workers} | ms/job (wall) | CPU ms/job (machine) |")
        print("| --- | ---: | ---: |")
        print(f"| a worker that ran jobs before | {pooled * 1e3:.2f} | {_ms(pooled_cpu)} |")
        print(f"| a fresh worker per job | {fresh * 1e3:.2f} | {_ms(fresh_cpu)} |")
        return 0


def _busy_seconds() -> float:
    """CPU seconds the whole machine has spent busy since boot (Linux), or NaN elsewhere."""
    try:
        with open("/proc/stat") as stat:
            ticks = [int(v) for v in stat.readline().split()[1:9]]
    except OSError:
        return float("nan")
    import os

    return (sum(ticks) - ticks[3] - ticks[4]) / os.sysconf("SC_CLK_TCK")  # all but idle and iowait


def _ms(seconds: float) -> str:
    return "n/a" if seconds != seconds else f"{seconds * 1e3:.2f}"


if __name__ == "__main__":
    sys.exit(main())
