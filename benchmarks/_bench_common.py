"""Helpers the benchmark scripts share: worker-count arguments, the machine's load, a timed whole run."""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import time
from collections.abc import Sequence
from pathlib import Path

__all__ = ["add_run_options", "parse_workers", "load_average", "timed_run"]


def parse_workers(text: str) -> list[int]:
    """``"1,2"`` -> ``[1, 2]``; a one-line exit for anything else (argparse ``type=``)."""
    try:
        counts = [int(x) for x in text.split(",") if x.strip()]
    except ValueError:
        raise SystemExit(f"--workers must be comma-separated integers, got {text!r}") from None
    if not counts or min(counts) < 1:
        raise SystemExit(f"--workers must list worker counts of at least 1, got {text!r}")
    return counts


def _at_least_one(text: str) -> int:
    """``--repeat``'s type: an integer of at least 1, or a one-line exit."""
    try:
        value = int(text)
    except ValueError:
        value = 0
    if value < 1:
        raise SystemExit(f"--repeat must be an integer of at least 1, got {text!r}")
    return value


def add_run_options(parser: argparse.ArgumentParser) -> None:
    """The options every whole-run benchmark takes: what to run (as ``hullstress run``), worker counts, rounds.

    They are what :func:`timed_run` reads.
    """
    parser.add_argument("--profile", default="quick", help="sweep profile (default quick)")
    parser.add_argument("--workers", default="1,2", type=parse_workers, help="worker counts to compare (default 1,2)")
    parser.add_argument("--repeat", type=_at_least_one, default=1,
                        help="runs per worker count; the best is kept (default 1)")
    parser.add_argument("--algorithm", action="append", default=[], help="only this algorithm (repeatable)")
    parser.add_argument("--generator", action="append", default=[], help="only this generator (repeatable)")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--timeout", type=float, default=None, help="per-call timeout (default: the profile's)")


def load_average() -> str:
    """The 1, 5 and 15 minute load averages and the CPU count, for a benchmark's header."""
    try:
        return ", ".join(f"{x:.2f}" for x in os.getloadavg()) + f" (1, 5, 15 min) on {os.cpu_count()} CPUs"
    except OSError:
        return "unknown"


def timed_run(args: argparse.Namespace, workers: int, out: Path, plugins: Sequence[str] = ()) -> tuple[float, dict]:
    """One ``python -m hullstress run`` with ``workers``, timed from outside: its wall time and its run.json.

    ``args`` carries ``profile``, ``seed``, ``algorithm``, ``generator`` and ``timeout`` (the benchmarks'
    common options); a run that exits other than 0 or 1 ends the benchmark with its stderr tail.
    """
    cmd = [sys.executable, "-m", "hullstress", "run", "--profile", args.profile, "--seed", str(args.seed),
           "--workers", str(workers), "--out", str(out), "--quiet"]
    cmd += [f"--algorithm={a}" for a in args.algorithm] + [f"--generator={g}" for g in args.generator]
    cmd += [f"--plugin={p}" for p in plugins]
    if args.timeout is not None:
        cmd += ["--timeout", str(args.timeout)]
    start = time.perf_counter()
    proc = subprocess.run(cmd, capture_output=True, text=True)
    wall = time.perf_counter() - start
    if proc.returncode not in (0, 1):
        raise SystemExit(f"{' '.join(cmd)} exited {proc.returncode}: {proc.stderr[-2000:]}")
    run_dir = Path([ln for ln in proc.stdout.splitlines() if ln.startswith("report: ")][-1].split(": ", 1)[1])
    return wall, json.loads((run_dir / "run.json").read_text())
