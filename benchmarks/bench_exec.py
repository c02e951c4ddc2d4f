"""What hullstress costs around an ``--exec`` program, in spawn and in persistent mode.

For each driver (the kit's C and Node.js examples, and the shipped libqhull_r and
quickhull3d drivers when built), in one run:

* **direct**: the program's own time per run, started by a shell loop on one
  24-point file (``while ...; do PROGRAM < points.txt > /dev/null; done``);
* **spawn**: the time per call of the same program in spawn mode, judged, as a
  worker does it (:func:`hullstress.evaluate.evaluate` on 24-point cases: case
  facts, start, feed, read, parse, judge), and its overhead over **direct**:
  hullstress's own cost per call; also hullstress's own CPU time per call
  (this process's, the program's excluded), which a loaded machine does not inflate;
* **persistent**: the time per judged call in this process, the CPU time per
  judged call of this process and of the program together (what a call costs
  an idle core: its inverse is the calls per second one idle core sustains,
  whatever the load when measuring), calls per second
  of the isolated runner with 2 workers on 24-point cases (starts included),
  and over the whole quick profile
  (``python -m hullstress run --exec ... --workers 2``: its calls divided by
  its sweep's wall time, worker and program starts included).

A second table compares, for the first driver, starting the program from a
process the size of a worker (NumPy, SciPy and hullstress loaded) the way
hullstress did before (``subprocess`` with a ``preexec_fn``, which forks the
whole process) and the way it does now (``posix_spawn``), feeding and reading
included, judging excluded.  A third table times ``qconvex Qt i`` through the
Python wrapper that ``pip install cmeel-qhull`` puts on PATH and as the real
binary that hullstress runs in its place.

Every figure is measured in the same run; wall-clock figures are the best of
several rounds, and on a loaded machine all of them are still depressed (the
table's header gives the load).  Writes
``docs/figures/bench_exec.md`` (included by docs/performance.md).

Usage: ``python benchmarks/bench_exec.py [--calls K] [--out FILE]``
(builds ``make -C drivers example`` first; ``make -C drivers qhull`` and
``npm install --prefix drivers/js`` add the library drivers).
"""

from __future__ import annotations

import argparse
import json
import os
import shlex
import shutil
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _bench_common import load_average  # noqa: E402

REPO = Path(__file__).resolve().parent.parent
DRIVERS = REPO / "drivers"
FIGURES = REPO / "docs" / "figures" / "bench_exec.md"
#: Points per case, as the issue's goal states it.
POINTS = 24


@dataclass
class Driver:
    label: str
    command: list[str]
    dim: int
    output: str
    direct_runs: int


def _drivers() -> list[Driver]:
    subprocess.run(["make", "-C", str(DRIVERS), "example"], check=True, capture_output=True)
    found = [Driver("C, kit example (2D monotone chain)", [str(DRIVERS / "build" / "monotone_chain")], 2, "Fx", 400)]
    node = shutil.which("node")
    if node:
        found.append(Driver("Node.js, kit example (2D monotone chain)",
                            [node, str(DRIVERS / "examples" / "monotone_chain.mjs")], 2, "Fx", 60))
    if subprocess.run(["make", "-C", str(DRIVERS), "qhull"], capture_output=True).returncode == 0:
        found.append(Driver("C, libqhull_r driver (3D)", [str(DRIVERS / "build" / "qhull_r_driver")], 3, "i", 400))
    if node and (DRIVERS / "js" / "node_modules" / "quickhull3d").is_dir():
        found.append(Driver("Node.js, quickhull3d driver (3D)", [node, str(DRIVERS / "js" / "quickhull3d_driver.mjs")],
                            3, "i", 60))
    return found


ROUNDS = 5


def _direct(driver: Driver, points_file: Path) -> float:
    """Seconds per run of the program started by a shell loop on the points file (best of :data:`ROUNDS`)."""
    runs = max(1, driver.direct_runs // ROUNDS)
    loop = (f"i=0; while [ $i -lt {runs} ]; do {shlex.join(driver.command)} "
            f"< {shlex.quote(str(points_file))} > /dev/null; i=$((i+1)); done")
    best = float("inf")
    for _ in range(ROUNDS):
        start = time.perf_counter()
        subprocess.run(["sh", "-c", loop], check=True)
        best = min(best, (time.perf_counter() - start) / runs)
    return best


def _cases(dim: int, count: int, seed: int) -> list:
    from hullstress import Case

    rng = np.random.default_rng(seed)
    return [Case.from_points(rng.random((POINTS, dim))) for _ in range(count)]


def _session_cpu() -> float:
    """CPU seconds used so far by the persistent programs this process runs (Linux ``/proc``; 0 elsewhere)."""
    from hullstress.adapters import exec_session

    total = 0.0
    for session in exec_session._sessions.values():
        try:
            fields = Path(f"/proc/{session.program.pid}/stat").read_text().rsplit(")", 1)[1].split()
        except OSError:
            continue
        total += (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")  # utime, stime
    return total


def _in_process(name: str, dim: int, calls: int) -> tuple[float, float, float]:
    """Per judged call: wall seconds (best of :data:`ROUNDS`), this process's CPU seconds, and the
    persistent program's CPU seconds (0 in spawn mode), each the best round."""
    import resource

    from hullstress import AlgorithmConfig
    from hullstress.evaluate import evaluate

    config = AlgorithmConfig(name)
    cases = _cases(dim, calls, 1)
    evaluate(cases[0], config, qhull=False)  # a persistent program starts here, not in the rounds
    best, cpu, program_cpu = float("inf"), float("inf"), float("inf")
    for _ in range(ROUNDS):
        before, program_before = resource.getrusage(resource.RUSAGE_SELF), _session_cpu()
        start = time.perf_counter()
        for case in cases:
            row = evaluate(case, config, qhull=False)
            if row["status"] != "pass":
                raise SystemExit(f"{name}: a call did not pass: {row['status']} {row['reason']}")
        best = min(best, (time.perf_counter() - start) / calls)
        after = resource.getrusage(resource.RUSAGE_SELF)
        cpu = min(cpu, (after.ru_utime + after.ru_stime - before.ru_utime - before.ru_stime) / calls)
        program_cpu = min(program_cpu, (_session_cpu() - program_before) / calls)
    return best, cpu, program_cpu


def _start_costs(driver: Driver) -> list[str]:
    """Rows: wall and this process's CPU per start of the program, subprocess + preexec_fn vs posix_spawn."""
    import ctypes
    import resource
    import signal

    import hullstress.runner._preload  # noqa: F401  (a worker's imports: the size a fork copies)
    from hullstress.adapters.exec_process import Program
    from hullstress.qhull_format import format_points

    data = format_points(np.random.default_rng(0).random((POINTS, driver.dim))).encode()
    libc = ctypes.CDLL(None)

    def die_with_parent() -> None:  # what the previous code ran between fork and exec
        libc.prctl(1, int(signal.SIGKILL), 0, 0, 0)

    def before() -> None:
        subprocess.run(driver.command, input=data, capture_output=True, start_new_session=True,
                       preexec_fn=die_with_parent, check=True)

    def now() -> None:
        program = Program(driver.command)
        program.exchange(data, close_stdin=True)
        program.wait()
        program.kill()

    rows = []
    runs = max(5, driver.direct_runs // ROUNDS)
    for label, start in (("subprocess + preexec_fn (before)", before), ("posix_spawn (now)", now)):
        wall, cpu = float("inf"), float("inf")
        for _ in range(ROUNDS):
            t0, r0 = time.perf_counter(), resource.getrusage(resource.RUSAGE_SELF)
            for _ in range(runs):
                start()
            r1 = resource.getrusage(resource.RUSAGE_SELF)
            wall = min(wall, (time.perf_counter() - t0) / runs)
            cpu = min(cpu, (r1.ru_utime + r1.ru_stime - r0.ru_utime - r0.ru_stime) / runs)
        rows.append(f"| {driver.label} | {label} | {wall * 1e3:.2f} ms | {cpu * 1e3:.2f} ms |")
    return rows


def _wrapper_costs() -> list[str]:
    """Rows: ``qconvex Qt i`` on 100 points through cmeel-qhull's Python wrapper on PATH and as the real binary.

    Empty when ``qconvex`` is not installed or is not a wrapper.
    """
    from hullstress.adapters.executable import locate_program
    from hullstress.qhull_format import format_points

    wrapper, real = shutil.which("qconvex"), locate_program("qconvex")
    if wrapper is None or real is None or Path(wrapper).resolve() == Path(real).resolve():
        return []
    data = format_points(np.random.default_rng(0).random((100, 3))).encode()
    rows = []
    for label, program in (("the wrapper on PATH", wrapper), ("the real binary (what hullstress runs)", real)):
        best = float("inf")
        for _ in range(ROUNDS):
            start = time.perf_counter()
            subprocess.run([program, "Qt", "i"], input=data, capture_output=True, check=True)
            best = min(best, time.perf_counter() - start)
        rows.append(f"| `qconvex Qt i`, 100 points | {label}: `{program}` | {best * 1e3:.1f} ms |")
    return rows


def _sweep_seconds(name: str, dim: int, calls: int, workers: int) -> float:
    """Wall seconds of the isolated runner doing ``calls`` calls of ``name`` on distinct 24-point cases."""
    from hullstress import AlgorithmConfig
    from hullstress.runner import RunnerOptions, Task, execute

    config = (AlgorithmConfig(name),)
    tasks = [Task(i, case, config) for i, case in enumerate(_cases(dim, calls, calls))]
    rows: list = []
    start = time.perf_counter()
    execute(tasks, RunnerOptions(workers=workers, qhull=False), rows.append)
    wall = time.perf_counter() - start
    bad = [r for r in rows if r["status"] != "pass"]
    if bad:
        raise SystemExit(f"{name}: {len(bad)} of {len(rows)} calls did not pass: {bad[0]['reason']}")
    return wall


def _runner_rate(name: str, dim: int, calls: int, workers: int) -> float:
    """Calls per second of the isolated runner over ``calls`` 24-point cases, worker and program starts included.

    A lower bound of the steady state (a difference of two runs would exclude the starts,
    but on a loaded machine the difference is noise).
    """
    return calls / _sweep_seconds(name, dim, calls, workers)


def _quick_profile(driver: Driver) -> tuple[int, float]:
    """Calls and sweep wall seconds of the quick profile in persistent mode, 2 workers."""
    with tempfile.TemporaryDirectory() as out:
        spec = f"bench[dim={driver.dim},output={driver.output},mode=persistent]={shlex.join(driver.command)}"
        proc = subprocess.run([sys.executable, "-m", "hullstress", "run", "--exec", spec, "--algorithm", "bench",
                               "--workers", "2", "--no-shrink", "--quiet", "--out", out],
                              capture_output=True, text=True, cwd=REPO)
        if proc.returncode not in (0, 1):
            raise SystemExit(f"quick profile of {driver.label}: exit {proc.returncode}: {proc.stderr[-500:]}")
        meta = json.loads(next(Path(out).glob("*/run.json")).read_text())
        return int(meta["calls"]), float(meta["runner"]["wall_seconds"])


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--calls", type=int, default=200,
                        help="calls per round in this process; the runner runs 10 times as many "
                        "(default 200)")
    parser.add_argument("--out", type=Path, default=FIGURES, help=f"the Markdown table (default {FIGURES})")
    args = parser.parse_args(argv)
    from hullstress._registry import ALGORITHMS, register_executable
    from hullstress.qhull_format import format_points

    load_before = load_average()
    lines = ["| driver | direct run | spawn mode, per judged call | hullstress's overhead per call (spawn) "
             "| hullstress's CPU per call (spawn) | persistent, per judged call | persistent, CPU per judged call "
             "(hullstress + program; calls/s per idle core) | persistent, runner, 24 points, "
             "2 workers, starts included | persistent, quick profile, 2 workers |",
             "|---|---|---|---|---|---|---|---|---|"]
    starts: list[str] = []
    with tempfile.TemporaryDirectory() as tmp:
        for k, driver in enumerate(_drivers()):
            points_file = Path(tmp) / f"points{driver.dim}.txt"
            points_file.write_text(format_points(np.random.default_rng(0).random((POINTS, driver.dim))))
            spawn_name, persistent_name = f"bench-spawn-{k}", f"bench-persistent-{k}"
            register_executable(spawn_name, driver.command, dim=driver.dim, output=driver.output)
            register_executable(persistent_name, driver.command, dim=driver.dim, output=driver.output,
                                mode="persistent")
            direct = _direct(driver, points_file)
            spawn, spawn_cpu, _ = _in_process(spawn_name, driver.dim, max(10, args.calls * driver.direct_runs // 400))
            alone, alone_cpu, program_cpu = _in_process(persistent_name, driver.dim, args.calls)
            persistent = _runner_rate(persistent_name, driver.dim, args.calls * 10, workers=2)
            calls, wall = _quick_profile(driver)
            ALGORITHMS.remove(spawn_name)
            ALGORITHMS.remove(persistent_name)
            row = (f"| {driver.label} | {direct * 1e3:.2f} ms | {spawn * 1e3:.2f} ms | "
                   f"{(spawn - direct) * 1e3:+.2f} ms | {spawn_cpu * 1e3:.2f} ms | "
                   f"{alone * 1e3:.3f} ms ({1 / alone:,.0f} calls/s) | "
                   f"{(alone_cpu + program_cpu) * 1e3:.3f} ms ({1 / (alone_cpu + program_cpu):,.0f} calls/s) | "
                   f"{persistent:,.0f} calls/s | "
                   f"{calls / wall:,.0f} calls/s ({calls} calls in {wall:.2f} s) |")
            print(row, flush=True)
            lines.append(row)
            if k == 0:
                starts = _start_costs(driver)
                print(*starts, sep="\n", flush=True)
    text = "\n".join([
        # The header every figure file starts with (benchmarks/_figures.py): the docs test checks it.
        "<!-- Written by benchmarks/bench_exec.py: do not edit by hand, re-run the command below. -->",
        f"Measured by `python benchmarks/bench_exec.py` on {time.strftime('%Y-%m-%d %H:%M %Z')}; "
        f"load average {load_before} before, {load_average()} after.  Per-call figures are on {POINTS}-point "
        "cases, judged as a worker judges them, best of 5 rounds; \"overhead\" is spawn mode minus the direct "
        "run of the same program in the same run; the runner's figure is 10 x --calls calls of 24 points "
        "divided by the wall time of the whole execution, worker and program starts included.", "", *lines, "",
        "Starting the program from a worker-sized process (feeding and reading included, judging excluded):", "",
        "| driver | how | wall per start | this process's CPU per start |", "|---|---|---|---|", *starts, ""])
    wrapper = _wrapper_costs()
    if wrapper:
        print(*wrapper, sep="\n")
        text += "\n".join(["", "Qhull's `qconvex` from `pip install cmeel-qhull` (best of 5 runs each):", "",
                           "| program | run | wall per run |", "|---|---|---|", *wrapper, ""])
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(text)
    print(f"wrote {args.out}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
