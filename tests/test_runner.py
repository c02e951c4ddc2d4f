"""The runner: isolation statuses, worker replacement, determinism across backends, budgets, interruption.

The misbehaving algorithms are plug-ins written to a temporary file and
loaded with ``load_plugin``, exactly as ``--plugin`` does, so the worker
processes must find them the way they would in a real run.
"""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import textwrap
import time
from collections import deque
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from hullstress import AlgorithmConfig, Case
from hullstress._registry import ALGORITHMS, GENERATORS
from hullstress.errors import UsageError
from hullstress.plugins import load_plugin
from hullstress.results import ROW_COLUMNS, STATUSES, TIMING_COLUMNS, to_frame
from hullstress.runner import CallPool, ExecutionStats, PendingJob, RunnerOptions, Task, execute, run_one
from hullstress.runner._pool import PoolSettings
from hullstress.runner._protocol import algorithm_refs
from hullstress.sweep import sort_table

from _processes import alive, forked_from_a_fork_server_of

P = "runner-test-"

PLUGIN = textwrap.dedent(
    '''
    """Misbehaving 2D algorithms for the runner tests (one per way of breaking)."""
    import ctypes
    import os
    import time

    import numpy as np
    from scipy.spatial import ConvexHull, QhullError

    from hullstress import register_algorithm, register_generator

    P = "runner-test-"


    @register_algorithm(P + "ok", dim=2)
    def ok(points):
        """Qhull's vertices: counter-clockwise, correct on general position."""
        try:
            return ConvexHull(points).vertices
        except QhullError:
            # Qhull's own message carries a per-run "run-id": keep reasons reproducible.
            raise ValueError("Qhull declined a flat input") from None


    @register_algorithm(P + "hang", dim=2)
    def hang(points):
        """Never returns."""
        while True:
            pass


    @register_algorithm(P + "segfault", dim=2)
    def segfault(points):
        """Dereferences a null pointer."""
        return ctypes.string_at(0)


    @register_algorithm(P + "exit", dim=2)
    def exit3(points):
        """Ends its process without unwinding."""
        os._exit(3)


    @register_algorithm(P + "raise", dim=2)
    def raises(points):
        """Declines every input."""
        raise RuntimeError("declined on purpose")


    @register_algorithm(P + "alloc", dim=2)
    def alloc(points):
        """Allocates (and touches) 32 MiB more forever."""
        hoard = []
        while True:
            hoard.append(np.ones(2**22))


    @register_algorithm(P + "none", dim=2)
    def none(points):
        """Returns nothing."""
        return None


    @register_algorithm(P + "floats", dim=2)
    def floats(points):
        """Returns floats instead of indices."""
        return np.array([0.0, 1.5, 2.0])


    @register_algorithm(P + "out-of-range", dim=2)
    def out_of_range(points):
        """Returns an index past the last point."""
        return [0, 1, len(points) + 7]


    @register_algorithm(P + "pid", dim=2)
    def pid(points):
        """Reports which process ran it."""
        raise RuntimeError(f"pid {os.getpid()}")


    CALLS = []


    @register_algorithm(P + "count", dim=2)
    def count(points):
        """Reports how many calls of it its process has run, this one included."""
        CALLS.append(1)
        raise RuntimeError(f"call {len(CALLS)}")


    @register_algorithm(P + "slow", dim=2)
    def slow(points):
        """Correct, after a pause; leaves its pid where RUNNER_TEST_PID_DIR says."""
        where = os.environ.get("RUNNER_TEST_PID_DIR")
        if where:
            open(os.path.join(where, str(os.getpid())), "w").close()
        time.sleep(0.25)
        return ConvexHull(points).vertices


    @register_generator(P + "cloud", dims=(2,), variants=({"spread": 1.0}, {"spread": 1000.0}))
    def cloud(rng, n, *, dim, spread=1.0):
        """Uniform points in a square."""
        return rng.random((n, dim)) * spread
    '''
)

# Imported in worker processes only, it makes the next check after a
# "runner-test-slow-check" call sleep: the checker's own limit must catch it.
SLOW_CHECKER_PLUGIN = textwrap.dedent(
    '''
    """Makes the exact checker hang once, inside worker processes only."""
    import multiprocessing
    import time

    from scipy.spatial import ConvexHull

    import hullstress.checker
    from hullstress import register_algorithm

    _armed = []


    @register_algorithm("runner-test-slow-check", dim=2)
    def slow_check(points):
        """Correct, but its check will hang."""
        _armed.append(True)
        return ConvexHull(points).vertices


    if multiprocessing.parent_process() is not None:
        _real_check = hullstress.checker.check

        def _check(*args, **kwargs):
            if _armed:
                _armed.clear()
                time.sleep(60)
            return _real_check(*args, **kwargs)

        hullstress.checker.check = _check
    '''
)

BAD_STATUS = {
    "hang": "timeout",
    "segfault": "crash",
    "exit": "crash",
    "raise": "error",
    "none": "fail",
    "floats": "fail",
    "out-of-range": "fail",
}


@pytest.fixture(scope="module")
def plugin(tmp_path_factory):
    path = tmp_path_factory.mktemp("runner_plugin") / "runner_misbehaving.py"
    path.write_text(PLUGIN)
    load_plugin(str(path))
    yield path
    # Leave the registries as other test modules expect them.
    for name in [n for n in ALGORITHMS.names() if n.startswith(P)]:
        ALGORITHMS.remove(name)
    GENERATORS.remove(P + "cloud")


@pytest.fixture(scope="module")
def warm(plugin):
    """Start the fork server once, so that timing-sensitive tests do not pay for it."""
    execute(_tasks(_cases(1), ["ok"]), RunnerOptions(workers=1, qhull=False), lambda row: None)


def _cases(n_cases: int, *, n_points: int = 12, seed: int = 7) -> list[Case]:
    rng = np.random.default_rng(seed)
    return [Case.from_points(rng.random((n_points, 2)), family="test-random", seed=i) for i in range(n_cases)]


def _collinear() -> Case:
    t = np.linspace(0.0, 1.0, 6)
    return Case.from_points(np.column_stack([t, 2 * t]), family="test-collinear", seed=0)


def _tasks(cases: list[Case], names: list[str]) -> list[Task]:
    configs = tuple(AlgorithmConfig(P + n) for n in names)
    return [Task(i, c, configs) for i, c in enumerate(cases)]


def _run(tasks: list[Task], **options) -> tuple[pd.DataFrame, object]:
    rows = []
    stats = execute(tasks, RunnerOptions(**options), rows.append)
    table = sort_table(to_frame(rows), sorted(t.case.case_id for t in tasks))
    return table, stats


def _without_timing(df: pd.DataFrame) -> pd.DataFrame:
    return df.drop(columns=list(TIMING_COLUMNS))


# -- isolation -----------------------------------------------------------------


def test_each_misbehaviour_is_recorded_and_the_sweep_completes(plugin):
    # The well-behaved config comes last in every task, after three worker deaths.
    names = ["hang", "segfault", "exit", "raise", "none", "floats", "out-of-range", "ok"]
    tasks = _tasks(_cases(2), names)
    table, stats = _run(tasks, workers=2, timeout=2.0, qhull=False)

    assert len(table) == len(tasks) * len(names)
    assert not table.duplicated(["case_id", "config"]).any()
    by = {(alg[len(P):], cid): row for alg, cid, row in zip(table["algorithm"], table["case_id"], table.itertuples())}
    for case in (t.case for t in tasks):
        got = {name: by[name, case.case_id] for name in names}
        for name, status in BAD_STATUS.items():
            assert got[name].status == status, (name, got[name].reason)
        assert got["hang"].reason == "exceeded 2.0 s"
        assert got["segfault"].reason == "killed by signal 11 (SIGSEGV)"
        assert got["exit"].reason == "exited with code 3"
        assert got["raise"].reason == "RuntimeError: declined on purpose"
        assert got["none"].reason.startswith("output contract: ") and "None" in got["none"].reason
        assert "integer" in got["floats"].reason
        assert "out of range" in got["out-of-range"].reason
        assert got["ok"].status == "pass"
    # hang, segfault and exit each cost a worker, per case.
    assert stats.worker_restarts >= 3 * len(tasks)
    assert stats.calls_started == stats.calls_done == len(table)
    assert stats.backend == "local" and stats.workers == 2


@pytest.mark.parametrize("bad", ["segfault", "hang"])
def test_a_death_mid_task_costs_only_the_call_that_caused_it(plugin, bad):
    # Rows travel with the next call's start in one message: the rows before the
    # death must be kept (not re-run), the death must name its own call, and the
    # rest of the task must run once, in a fresh worker.
    names = ["ok", "raise", bad, "pid"]
    table, stats = _run(_tasks(_cases(1), names), workers=1, timeout=1.0, qhull=False)
    status = dict(zip((a[len(P):] for a in table["algorithm"]), table["status"]))
    assert status == {"ok": "pass", "raise": "error", bad: BAD_STATUS[bad], "pid": "error"}
    assert stats.calls_started == stats.calls_done == len(names)  # nothing ran twice
    assert stats.worker_restarts == 1


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="RLIMIT_AS is enforced on Linux")
def test_a_runaway_allocation_hits_the_worker_memory_limit(plugin):
    # Touching memory is slow on a shared machine (about 0.5 GB/s): a 1 GiB
    # address space fills within a few seconds, far below the timeout.
    tasks = _tasks(_cases(1), ["alloc", "ok"])
    table, stats = _run(tasks, workers=1, timeout=60.0, memory_limit_mb=1024, qhull=False)
    alloc, ok = (table.set_index("algorithm").loc[P + name] for name in ("alloc", "ok"))
    assert (alloc["status"], alloc["reason"].split(":")[0]) in {
        ("error", "MemoryError"), ("crash", "killed by signal 9 (SIGKILL)"), ("crash", "killed by signal 6 (SIGABRT)")
    }, alloc["reason"]
    assert alloc["seconds"] < 30.0
    assert ok["status"] == "pass"


def test_a_hung_checker_is_an_internal_error_and_the_task_goes_on(plugin, tmp_path):
    path = tmp_path / "runner_slow_checker.py"
    path.write_text(SLOW_CHECKER_PLUGIN)
    load_plugin(str(path))
    try:
        case = _cases(1)[0]
        configs = (AlgorithmConfig("runner-test-slow-check"), AlgorithmConfig(P + "ok"))
        table, stats = _run([Task(0, case, configs)], workers=1, timeout=5.0, check_timeout=1.0, qhull=False)
    finally:
        ALGORITHMS.remove("runner-test-slow-check")
    rows = table.set_index("algorithm")
    assert rows.loc["runner-test-slow-check", "status"] == "error"
    assert rows.loc["runner-test-slow-check", "reason"] == "internal: checker exceeded 1 s"
    assert rows.loc[P + "ok", "status"] == "pass"
    assert stats.worker_restarts == 1


def test_a_killed_worker_is_replaced_and_later_tasks_run(plugin):
    tasks = _tasks(_cases(5), ["segfault", "pid", "ok"])
    table, stats = _run(tasks, workers=1, timeout=5.0, qhull=False)
    statuses = table.groupby("algorithm")["status"].agg(set).to_dict()
    assert statuses == {P + "segfault": {"crash"}, P + "pid": {"error"}, P + "ok": {"pass"}}
    pids = {r.split()[-1] for r in table.loc[table["algorithm"] == P + "pid", "reason"]}
    assert len(pids) == len(tasks)  # every task after a death ran in a fresh process
    assert stats.worker_restarts == len(tasks)


def test_no_task_is_lost_when_workers_die_between_prefetches(plugin):
    # Every task kills its worker at once, while the parent is sending the
    # next task to that worker: the dying worker's task must still get its rows.
    tasks = _tasks(_cases(30, n_points=6), ["exit", "pid"])
    for _ in range(3):  # a race: give it several chances to show
        table, stats = _run(tasks, workers=2, timeout=5.0, qhull=False)
        assert len(table) == 2 * len(tasks)
        assert set(table.loc[table["algorithm"] == P + "exit", "status"]) == {"crash"}
        assert stats.worker_restarts == len(tasks)


def test_serial_backend_has_no_isolation_but_the_same_rows(plugin):
    # A hang in Python code is interrupted in-process too (SIGALRM), with the same row.
    names = ["raise", "none", "floats", "out-of-range", "hang", "ok"]
    tasks = _tasks(_cases(2) + [_collinear()], names)
    serial, s0 = _run(tasks, workers=0, timeout=0.5, qhull=False)
    isolated, s1 = _run(tasks, workers=1, timeout=0.5, qhull=False)
    assert set(serial.loc[serial["algorithm"] == P + "hang", "reason"]) == {"exceeded 0.5 s"}
    pd.testing.assert_frame_equal(_without_timing(serial), _without_timing(isolated))
    assert s0.backend == "serial" and s1.backend == "local"
    # An exception on a degenerate (collinear) case is acceptable behaviour.
    collinear = serial[serial["case_id"] == _collinear().case_id]
    assert collinear.set_index("algorithm").loc[P + "raise", "status"] == "rejected"


def test_table_does_not_depend_on_worker_count(plugin):
    names = ["segfault", "raise", "none", "ok", "exit"]
    builtin = ["monotone-chain"] if "monotone-chain" in ALGORITHMS else []
    cases = _cases(6, n_points=15, seed=11) + [_collinear()]
    configs = tuple([AlgorithmConfig(P + n) for n in names] + [AlgorithmConfig(b) for b in builtin])
    tasks = [Task(i, c, configs) for i, c in enumerate(cases)]
    one, _ = _run(tasks, workers=1, timeout=5.0)
    two, _ = _run(list(reversed(tasks)), workers=2, timeout=5.0)
    assert list(one.columns) == list(ROW_COLUMNS)
    pd.testing.assert_frame_equal(_without_timing(one), _without_timing(two))
    assert set(one["status"]) <= set(STATUSES) and "crash" in set(one["status"])


def test_time_budget_stops_new_calls_and_keeps_whole_rows(plugin, warm):
    tasks = _tasks(_cases(20), ["slow", "ok"])  # about 2.5 s of work on 2 workers
    start = time.perf_counter()
    table, stats = _run(tasks, workers=2, timeout=5.0, time_budget=1.0, qhull=False)
    wall = time.perf_counter() - start
    assert stats.budget_exhausted
    assert 0 < len(table) < 2 * len(tasks)
    assert set(table["status"]) == {"pass"}
    # Calls under way finish (each within 0.25 s); none starts after the budget.
    assert stats.calls_started == len(table)
    assert wall < 1.0 + 1.0


def test_harness_overhead_is_measured(plugin):
    tasks = _tasks(_cases(6), ["slow"])
    _, stats = _run(tasks, workers=2, timeout=5.0, qhull=False)
    assert stats.algorithm_seconds >= 6 * 0.25
    assert 0.0 <= stats.harness_overhead_seconds < stats.wall_seconds
    assert stats.harness_overhead_fraction == pytest.approx(stats.harness_overhead_seconds / stats.wall_seconds)
    record = stats.as_dict()
    assert {"harness_overhead_seconds", "harness_overhead_fraction", "worker_restarts", "backend"} <= set(record)
    json.dumps(record)


# -- run_one (the shrinker's oracle) ---------------------------------------------


def test_run_one_reuses_its_worker_until_it_dies(plugin):
    case = _cases(1)[0]
    pid = lambda: run_one(case, AlgorithmConfig(P + "pid"), timeout=5.0, qhull=False)["reason"]  # noqa: E731
    first, second = pid(), pid()
    assert first == second and first.startswith("RuntimeError: pid ")
    crash = run_one(case, AlgorithmConfig(P + "segfault"), timeout=5.0, qhull=False)
    assert (crash.status, crash["reason"]) == ("crash", "killed by signal 11 (SIGSEGV)")
    assert pid() != first
    hang = run_one(case, AlgorithmConfig(P + "hang"), timeout=0.5, qhull=False)
    assert (hang.status, hang["reason"]) == ("timeout", "exceeded 0.5 s")
    start = time.perf_counter()
    for _ in range(10):
        assert run_one(case, AlgorithmConfig(P + "ok"), timeout=5.0, qhull=False).status == "pass"
    assert (time.perf_counter() - start) / 10 < 0.25  # a round trip, not a new process per call


# -- CallPool (parallel triage) -----------------------------------------------------


def test_call_pool_returns_rows_in_task_order_and_survives_crashes_and_hangs(plugin):
    cases = _cases(3)
    tasks = [Task(0, cases[0], (AlgorithmConfig(P + "ok"), AlgorithmConfig(P + "segfault"))),
             Task(1, cases[1], (AlgorithmConfig(P + "hang"),)),
             Task(2, cases[2], (AlgorithmConfig(P + "raise"), AlgorithmConfig(P + "ok"))),
             Task(3, cases[0], (AlgorithmConfig(P + "pid"),))]  # the same case again: merged into one job
    with CallPool(2, memory_limit_mb=None) as pool:
        assert pool.workers == 2
        rows = pool.run(tasks, timeout=1.0, qhull=False)
        assert [[r.status for r in task_rows] for task_rows in rows] == [
            ["pass", "crash"], ["timeout"], ["error", "pass"], ["error"]]
        assert [[r["config"] for r in task_rows] for task_rows in rows] == [
            [c.label for c in t.configs] for t in tasks]
        assert rows[0][1]["reason"] == "killed by signal 11 (SIGSEGV)"
        # The pool goes on after deaths, with the same results for the same calls.
        again = pool.run(tasks[2:3], timeout=1.0, qhull=False)
        assert [r.status for r in again[0]] == ["error", "pass"]
        assert pool.stats.worker_restarts >= 2
        assert pool.run([], timeout=1.0) == []


def test_call_pool_judges_with_the_reference_only_the_cases_the_mapping_names(plugin):
    # One batch can mix cases judged with and without the Qhull reference (triage asks both in a
    # round): the reference is computed for the cases mapped to True and for no other.
    cases = _cases(3)
    config = AlgorithmConfig("monotone-chain", eps="scaled")
    tasks = [Task(i, c, (config,)) for i, c in enumerate(cases)]
    with CallPool(2, memory_limit_mb=None) as pool:
        rows = pool.run(tasks, timeout=5.0, qhull={cases[0].case_id: True, cases[1].case_id: False})
    agreement = [r[0]["qhull_agreement"] for r in rows]
    assert [r[0].status for r in rows] == ["pass"] * 3
    assert agreement[0] == "agree" and agreement[1] in (None, "") and agreement[2] in (None, "")


@pytest.mark.parametrize("workers", [1, 2])
def test_a_task_run_alone_gets_a_worker_that_has_run_nothing_before(plugin, workers):
    # Whether native code dies can depend on what its process ran before: triage judges a
    # crash in a fresh worker, and the same case's other tasks do not join that job.
    cases = _cases(4)
    count = AlgorithmConfig(P + "count")
    tasks = [Task(0, cases[0], (count,)), Task(1, cases[0], (count,)), Task(2, cases[1], (count,)),
             Task(3, cases[2], (count,)), Task(4, cases[3], (count,)), Task(5, cases[3], (count,))]
    alone = [False, True, False, True, False, True]
    with CallPool(workers, memory_limit_mb=None) as pool:
        for _ in range(2):  # the second time every worker has run something already
            rows = pool.run(tasks, timeout=5.0, qhull=False, alone=alone)
            reasons = [r[0]["reason"] for r in rows]
            assert all(reasons[n].endswith("call 1") for n in (1, 3, 5)), reasons
            if workers == 1:  # one worker runs the other tasks one after another
                assert not all(reasons[n].endswith("call 1") for n in (0, 2, 4)), reasons
        assert pool.stats.worker_restarts == 0  # a worker retired for a fresh one is not a death


def test_call_pool_uses_every_worker(plugin):
    cases = _cases(12)
    with CallPool(2, memory_limit_mb=None) as pool:
        rows = pool.run([Task(i, c, (AlgorithmConfig(P + "pid"),)) for i, c in enumerate(cases)],
                        timeout=5.0, qhull=False)
    assert len({r[0]["reason"] for r in rows}) == 2


@pytest.mark.parametrize("workers", [1, 2])
def test_on_idle_is_called_once_when_a_worker_runs_out_of_work_at_the_tail(plugin, workers):
    # One slow call (0.25 s) first, then quick ones: with 2 workers one of them runs out of work
    # while the slow call still runs, and the caller hears of it then, once.  With 1 worker no
    # core ever frees before the end.
    cases = _cases(7)
    tasks = [Task(0, cases[0], (AlgorithmConfig(P + "slow"),))]
    tasks += [Task(i, c, (AlgorithmConfig(P + "ok"),)) for i, c in enumerate(cases[1:], start=1)]
    rows: list = []
    heard: list[int] = []
    execute(tasks, RunnerOptions(workers=workers, timeout=5.0, qhull=False), rows.append,
            on_idle=lambda: heard.append(len(rows)))
    assert len(rows) == len(tasks)
    if workers == 1:
        assert heard == []
    else:
        assert len(heard) == 1
        assert heard[0] < len(tasks)  # the slow call had not ended


class _RecordingPipe:
    """A worker's pipe end that only records what the parent sends (no worker behind it)."""

    def __init__(self) -> None:
        self.sent: list[bytes] = []

    def send_bytes(self, payload: bytes) -> None:
        self.sent.append(payload)


@pytest.mark.parametrize("n_points, prefetch, expected", [
    (6, 2, 2),  # the sweep's default: one running, one waiting
    (6, 8, 8),  # streamed one-call jobs (triage): eight
    (600, 8, 4),  # about 10 KB each: the jobs waiting in a pipe stay within PREFETCH_MAX_BYTES together
    (2100, 8, 1),  # over 32 KiB: sent only to an idle worker
])
def test_jobs_queued_per_worker_follow_the_prefetch_depth_and_the_byte_cap(n_points, prefetch, expected):
    from hullstress.runner._pool import PREFETCH_MAX_BYTES, WorkerPool

    pool = WorkerPool(1)
    slot = pool._slots[0]
    slot.proc, slot.conn = object(), _RecordingPipe()  # taken for a live worker: nothing is started
    config = AlgorithmConfig("monotone-chain")
    queue = deque(PendingJob(Task(i, c, (config,))) for i, c in enumerate(_cases(10, n_points=n_points)))
    settings = PoolSettings(timeout=1.0, check_timeout=1.0, prefetch=prefetch)
    pool._fill(queue, settings, ExecutionStats())
    assert len(slot.conn.sent) == len(slot.jobs) == expected
    assert len(queue) == 10 - expected
    assert sum(map(len, slot.conn.sent[1:])) <= PREFETCH_MAX_BYTES


def test_streamed_jobs_are_prefetched_deeper_than_the_sweeps():
    from hullstress.runner._pool import PREFETCH_DEPTH, STREAM_PREFETCH

    assert PoolSettings(timeout=1.0, check_timeout=1.0).prefetch == PREFETCH_DEPTH == 2
    assert STREAM_PREFETCH > PREFETCH_DEPTH


# -- bad options -------------------------------------------------------------------


@pytest.mark.parametrize(
    "kwargs, message",
    [
        ({"workers": -1}, "workers must be 0 or more, got -1"),
        ({"timeout": 0}, "timeout must be positive, got 0"),
        ({"time_budget": -5}, "time_budget must be positive, got -5"),
        ({"memory_limit_mb": -1}, "memory_limit_mb must be 0 (no limit) or positive, got -1"),
        ({"check_timeout": 0.0}, "check_timeout must be positive, got 0.0"),
    ],
)
def test_bad_runner_options(kwargs, message):
    with pytest.raises(UsageError) as info:
        RunnerOptions(**kwargs)
    assert str(info.value) == message


def test_an_algorithm_workers_cannot_import_is_refused_up_front():
    from hullstress import register_algorithm

    def make():
        @register_algorithm("runner-test-local-closure", dim=2)
        def closure(points):
            return [0, 1, 2]

    make()
    try:
        tasks = [Task(0, _cases(1)[0], (AlgorithmConfig("runner-test-local-closure"),))]
        with pytest.raises(UsageError, match="runner-test-local-closure.*--workers 0"):
            execute(tasks, RunnerOptions(workers=1, qhull=False), lambda row: None)
        rows = []
        execute(tasks, RunnerOptions(workers=0, qhull=False), rows.append)
        assert len(rows) == 1
    finally:
        ALGORITHMS.remove("runner-test-local-closure")


# -- the CLI: interruption and a killed run --------------------------------------


def _start_cli(plugin: Path, out: Path, *extra: str, env: dict | None = None) -> subprocess.Popen:
    args = [sys.executable, "-m", "hullstress", "run", "--plugin", str(plugin), "--generator", P + "cloud",
            "--algorithm", P + "slow", "--sizes", ",".join(map(str, range(8, 20))), "--sphere", "off",
            "--workers", "2", "--no-qhull",
            "--out", str(out), *extra]
    return subprocess.Popen(args, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            env={**os.environ, **(env or {})}, cwd=out.parent)


def _wait_for_rows(out: Path, n: int, proc: subprocess.Popen, limit: float = 60.0) -> Path:
    deadline = time.monotonic() + limit
    while time.monotonic() < deadline:
        partial = list(out.glob("*/results.partial.csv"))
        if partial and len(partial[0].read_text().splitlines()) > n:
            return partial[0]
        assert proc.poll() is None, proc.communicate()
        time.sleep(0.05)
    raise AssertionError(f"fewer than {n} rows after {limit} s")


@pytest.mark.parametrize("signum", [signal.SIGINT, signal.SIGTERM], ids=["SIGINT", "SIGTERM"])
def test_interrupted_run_writes_an_incomplete_report_and_exits_130_or_143(plugin, tmp_path, signum):
    out = tmp_path / "out"
    proc = _start_cli(plugin, out)
    _wait_for_rows(out, 2, proc)
    proc.send_signal(signum)
    stdout, stderr = proc.communicate(timeout=60)
    assert proc.returncode == {signal.SIGINT: 130, signal.SIGTERM: 143}[signum], stderr
    run_dir = next(out.iterdir())
    meta = json.loads((run_dir / "run.json").read_text())
    assert meta["complete"] is False and meta["interrupted"] is True
    table = pd.read_csv(run_dir / "results.csv")
    planned = 2 * 12  # variants x sizes
    assert 2 <= len(table) < planned == meta["calls_planned"]
    assert set(table["status"]) == {"pass"}
    assert "(INCOMPLETE)" in stdout


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="workers die with their parent via PR_SET_PDEATHSIG")
def test_a_killed_run_leaves_a_readable_partial_table_and_no_workers(plugin, tmp_path):
    out = tmp_path / "out"
    pids = tmp_path / "pids"
    pids.mkdir()
    proc = _start_cli(plugin, out, env={"RUNNER_TEST_PID_DIR": str(pids)})
    partial = _wait_for_rows(out, 3, proc)
    proc.kill()
    proc.communicate(timeout=30)
    table = pd.read_csv(partial)
    assert list(table.columns) == list(ROW_COLUMNS) and len(table) >= 3
    assert set(table["status"]) == {"pass"}
    workers = [int(p.name) for p in pids.iterdir()]
    assert workers
    deadline = time.monotonic() + 10
    while time.monotonic() < deadline and any(alive(p) for p in workers):
        time.sleep(0.1)
    assert not any(alive(p) for p in workers)
    # Nor the fork server, nor the report's helpers forked from it (its picture drawers run from the
    # start): every child of the fork server keeps it alive, so each must leave by itself.
    if sys.platform.startswith("linux"):
        deadline = time.monotonic() + 10
        while time.monotonic() < deadline and forked_from_a_fork_server_of(tmp_path):
            time.sleep(0.1)
        assert not forked_from_a_fork_server_of(tmp_path)


# -- call output ----------------------------------------------------------------


def test_call_output_is_captured_per_call_even_after_a_call_closed_stdout():
    from hullstress.runner._protocol import captured_output

    with captured_output() as first:
        print("first call")
        sys.stdout.close()  # the code under test closes the stream it was given
    with captured_output() as second:
        print("second call")
        os.write(2, b"QH7088 from C, run-id 42\n")
    with captured_output() as quiet:
        pass
    assert first == ["first call"]
    # Python's buffered text and C's direct write may interleave either way.
    assert sorted(second[0].splitlines()) == ["QH7088 from C, run-id <n>", "second call"]
    assert quiet == [""]
    print("the terminal's own stream still works")


# -- workers started in the background ----------------------------------------------


def test_a_worker_started_in_the_background_is_taken_in_or_stopped_with_the_pool(plugin):
    # A replacement worker starts in a thread (the fork server's fork no longer stops the loop);
    # the pool takes it in when it is up, and closing the pool stops one still starting.
    from hullstress.runner._pool import WorkerPool

    pool = WorkerPool(1, memory_limit_bytes=None)
    slot = pool._slots[0]
    pool._begin_start(slot)
    pool._adopt_started(wait=True)
    assert slot.alive and slot.starting is None and slot.proc.is_alive()
    pool._kill(slot)
    pool._begin_start(slot)
    starting = slot.starting
    starting.thread.join()
    second = starting.result[0].pid
    pool.close()  # a started worker not yet taken in: stopped all the same
    assert slot.starting is None and slot.proc is None and pool._wake is None
    with pytest.raises(ProcessLookupError):
        os.kill(second, 0)
    # A pool used again after close works as before.
    rows = []
    pool.run([PendingJob(Task(0, _cases(1)[0], (AlgorithmConfig(P + "ok"),)))],
             PoolSettings(timeout=5.0, check_timeout=5.0, qhull=False, refs=algorithm_refs(
                 [Task(0, _cases(1)[0], (AlgorithmConfig(P + "ok"),))])), rows.append, ExecutionStats())
    assert [r.status for r in rows] == ["pass"]
    pool.close()


def test_a_worker_that_cannot_start_fails_the_run_in_the_callers_thread(plugin, monkeypatch):
    from hullstress.runner import _pool

    def refuse(self, index):
        raise OSError(24, "Too many open files")

    monkeypatch.setattr(_pool.WorkerPool, "_new_worker", refuse)
    with pytest.raises(OSError, match="Too many open files"):
        with CallPool(1, memory_limit_mb=None) as pool:
            pool.run([Task(0, _cases(1)[0], (AlgorithmConfig(P + "ok"),))], timeout=5.0, qhull=False)
