"""Tests for the triage stage: waves, lockstep shrinking on a worker pool, causes, determinism, budgets.

Throw-away plug-in algorithms fail on a planted configuration of four points
hidden in random clouds: one drops a hull vertex, one raises, one crashes its
process, and one of them hangs on small inputs, so shrinking meets crashes
and hangs on the way.
"""

from __future__ import annotations

import textwrap

import numpy as np
import pytest

from hullstress.case import Case
from hullstress.config import AlgorithmConfig
from hullstress.options import TriageBudget
from hullstress.plugins import load_plugin
from hullstress.results import to_frame
from hullstress.triage import Signature, canonical_key, run_config, signature_of
from hullstress.triage.stage import plan_chains, triage_failures

PLANTED = np.array([[0.3, 0.1], [2.7, 0.45], [2.2, 3.3], [0.1, 2.9]])

PLUGIN = textwrap.dedent(
    '''
    """Planted failures for tests/test_triage_stage.py."""
    import ctypes
    import time

    import numpy as np
    from scipy.spatial import ConvexHull

    from hullstress import register_algorithm

    PLANTED = np.array(%r)


    def _planted(points):
        return all(bool(np.all(points == row, axis=1).any()) for row in PLANTED)


    def _hull(points):
        return [int(i) for i in ConvexHull(points).vertices]


    @register_algorithm("test-stage-drop", dim=2)
    def drop(points, *, eps=None):
        """Drops a vertex when the planted points are present (the same with either eps)."""
        hull = _hull(points)
        return hull[1:] if _planted(points) else hull


    @register_algorithm("test-stage-raise", dim=2)
    def raiser(points):
        """Raises when the planted points are present; hangs on fewer than 5 points that lack them."""
        if _planted(points):
            raise KeyError("planted")
        if len(points) < 5:
            while True:
                time.sleep(0.01)
        return _hull(points)


    @register_algorithm("test-stage-crash", dim=2)
    def crash(points):
        """Dereferences a null pointer when the planted points are present."""
        if _planted(points):
            ctypes.string_at(0)
        return _hull(points)
    '''
    % (PLANTED.tolist(),)
)

CONFIGS = (AlgorithmConfig("test-stage-drop", "off", "scaled"), AlgorithmConfig("test-stage-drop", "off", "fixed"),
           AlgorithmConfig("test-stage-raise"), AlgorithmConfig("test-stage-crash"))


def _load(tmp_path_factory, name: str, text: str) -> None:
    """Write plug-in ``text`` to a fresh folder as ``name`` and load it (workers import it by path)."""
    path = tmp_path_factory.mktemp(name.replace("_", "-")) / f"{name}.py"
    path.write_text(text)
    load_plugin(str(path))


@pytest.fixture(scope="module")
def sweep(tmp_path_factory):
    _load(tmp_path_factory, "stage_plugins", PLUGIN)
    rng = np.random.default_rng(11)
    cases = []
    for k, n in enumerate((16, 20, 24)):
        pts = np.vstack([rng.uniform(-10, 10, size=(n - 4, 2)), PLANTED])[rng.permutation(n)]
        cases.append(Case(points=pts, dim=2, family=f"test-planted-{k % 2}", seed=k, size=n))
    rows = [run_config(c, config, timeout=2.0) for c in cases for config in CONFIGS]
    return to_frame(rows), cases


BUDGET = TriageBudget(calls=3000, group_calls=200, hang_calls=0, pictures=0, safety_seconds=900.0)


def _triage(sweep, workers, budget=BUDGET):
    table, cases = sweep
    return triage_failures(table, cases, budget=budget, timeout=1.0, workers=workers)


def _summary(result):
    return [(c.key, [(r.signature, r.shrink.case.points.tobytes(), r.shrink.calls, r.shrink.steps, r.verified)
                     for r in c.records]) for c in result.causes]


def test_planted_failures_shrink_to_the_planted_points_and_twins_merge(sweep):
    result = _triage(sweep, 2)
    assert len(result.groups) == 4 and len(result.records) == 4
    statuses = {r.signature.config.label: r.signature for r in result.records}
    assert statuses["test-stage-crash[sphere=off,eps=n/a]"].error == "SIGSEGV"
    assert statuses["test-stage-raise[sphere=off,eps=n/a]"].frame.endswith(" in raiser")
    for rec in result.records:
        rows = {tuple(p) for p in rec.case.points.tolist()}
        assert rows == {tuple(p) for p in PLANTED.tolist()}, (rec.signature.label, rec.shrink.steps)
        assert rec.shrink.reproduced and rec.verified is True
    # Every group shrank to the same four points (up to exact transforms): one cause, listing every
    # config, although each fails there in its own way.
    assert len({canonical_key(r.case.points) for r in result.records}) == 1
    assert len(result.causes) == 1 and len(result.causes[0].records) == 4
    assert set(result.causes[0].configs) == {c.label for c in CONFIGS}
    assert dict(result.causes[0].families) == {"test-planted-0": 8, "test-planted-1": 4}
    # The second eps variant of the dropper started from the first's minimal case, and paid less.
    drop = [r for r in result.records if r.signature.algorithm == "test-stage-drop"]
    assert not drop[0].shrink.adopted and drop[1].shrink.adopted
    assert drop[1].shrink.calls < drop[0].shrink.calls
    assert result.stopped is False and result.safety_net is False


def test_triage_does_not_depend_on_the_number_of_workers(sweep):
    assert _summary(_triage(sweep, 1)) == _summary(_triage(sweep, 2))


def test_a_spent_budget_leaves_groups_unshrunk_and_says_so(sweep):
    result = _triage(sweep, 2, TriageBudget(calls=0, group_calls=10, hang_calls=0, pictures=0, safety_seconds=9.0))
    assert all(not r.shrink.reproduced and "evaluation budget" in r.shrink.note for r in result.records)
    assert len(result.causes) == 4  # groups that were not minimised never merge
    tiny = _triage(sweep, 2, TriageBudget(calls=1000, group_calls=3, hang_calls=0, pictures=0, safety_seconds=900.0))
    assert all(r.shrink.calls <= 3 for r in tiny.records)
    assert any("ran out of evaluations" in n for n in tiny.notes)


def test_an_interrupt_keeps_the_best_cases_so_far(sweep):
    polls = []

    def stop_after_a_few_rounds() -> bool:
        polls.append(1)
        return len(polls) > 3

    table, cases = sweep
    result = triage_failures(table, cases, budget=BUDGET, timeout=1.0, workers=2, should_stop=stop_after_a_few_rounds)
    assert result.stopped and len(result.records) == 4
    assert any("interrupted" in r.shrink.note for r in result.records)
    for rec in result.records:
        if rec.shrink.reproduced:  # whatever it kept still fails that way
            assert signature_of(run_config(rec.case, rec.config, timeout=2.0)) == rec.signature


HISTORY_PLUGIN = textwrap.dedent(
    '''
    """A crash that depends on what the process ran before, for tests/test_triage_stage.py."""
    import os

    from scipy.spatial import ConvexHull

    from hullstress import register_algorithm

    WARM = []


    @register_algorithm("test-history-crash", dim=2)
    def crash_when_cold(points):
        """Dies on 3 points or more in a process that has not run test-history-warm (like native
        code reading memory it never set, whose contents earlier calls decide)."""
        if not WARM and len(points) >= 3:
            os.abort()
        return [int(i) for i in ConvexHull(points).vertices]


    @register_algorithm("test-history-warm", dim=2)
    def warm(points):
        """Drops a vertex (a failure for triage to shrink) and leaves its process warm."""
        WARM.append(1)
        return [int(i) for i in ConvexHull(points).vertices][1:]
    '''
)


@pytest.fixture(scope="module")
def history_sweep(tmp_path_factory):
    _load(tmp_path_factory, "history_plugins", HISTORY_PLUGIN)
    rng = np.random.default_rng(5)
    cases = [Case(points=rng.uniform(-10, 10, size=(n, 2)), dim=2, family="test-history", seed=n, size=n)
             for n in (12, 16)]
    configs = (AlgorithmConfig("test-history-crash"), AlgorithmConfig("test-history-warm"))
    # The crashes first: each kills its worker, so the next call starts cold too.
    table = to_frame([run_config(c, config, timeout=5.0) for config in configs for c in cases])
    assert list(table["status"]) == ["crash", "crash", "fail", "fail"]
    return table, cases


@pytest.mark.parametrize("workers", [1, 2])
def test_a_crash_is_judged_in_a_fresh_worker_whatever_ran_there_before(history_sweep, workers):
    table, cases = history_sweep
    result = triage_failures(table, cases, budget=BUDGET, timeout=5.0, workers=workers)
    crashes = [r for c in result.causes for r in c.records if r.signature.status == "crash"]
    assert crashes
    for record in crashes:  # reproduced, shrunk to the 3 points it needs and verified, whatever ran before
        assert record.shrink.reproduced and len(record.shrink.case.points) == 3, record.shrink.note
        assert record.verified


def test_chains_hold_back_groups_of_a_kind_seen_before():
    from types import SimpleNamespace

    error = Signature("a", "off", "n/a", status="error", error="KeyError")
    fail = Signature("b", "off", "n/a", checks="containment", severity="gross")
    groups = [SimpleNamespace(dim=2, signature=error) for _ in range(7)] + [SimpleNamespace(dim=2, signature=fail)]
    groups.append(SimpleNamespace(dim=3, signature=error))
    chains = plan_chains(groups)
    assert chains == [[[0], [1], [2, 3], [4, 5, 6]], [[7]], [[8]]]
    assert sorted(i for chain in chains for wave in chain for i in wave) == list(range(len(groups)))


class _CountingPool:
    """A stand-in for the call pool: every config passes; counts the (case, config, reference) calls it runs."""

    def __init__(self) -> None:
        self.calls: list[tuple[str, str, bool]] = []

    def run(self, tasks, *, timeout, qhull, qhull_options=None, alone=None):
        from hullstress.results import ResultRow

        out = []
        for task in tasks:
            # The real pool takes one flag for all tasks or one per case id (a missing case: none).
            need = qhull.get(task.case.case_id, False) if isinstance(qhull, dict) else qhull
            self.calls += [(task.case.case_id, c.label, need) for c in task.configs]
            out.append([ResultRow({"case_id": task.case.case_id, "config": c.label, "status": "pass",
                                   "qhull": need}) for c in task.configs])
        return out


def test_a_repeated_question_is_answered_by_the_earlier_call_but_a_rerun_runs_again():
    from hullstress.triage.stage import _Triage

    pool = _CountingPool()
    run = _Triage(pool, budget=TriageBudget(calls=100, group_calls=10, hang_calls=0, pictures=0,
                                            safety_seconds=60.0), timeout=5.0, qhull=True, should_stop=None,
                  progress=None, total=1)
    square = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
    a, b = AlgorithmConfig("monotone-chain", eps="scaled"), AlgorithmConfig("monotone-chain", eps="fixed")
    first = run.batch([(square, 2, a, False), (square, 2, b, True)])
    assert len(pool.calls) == 2 and run.reused == 0
    # Judged with the reference once a request of the batch needs it, for every config of the case.
    assert [r["qhull"] for r in first] == [True, True]
    again = run.batch([(square, 2, a, True), (square, 2, b, True)])
    assert len(pool.calls) == 2 and run.reused == 2 and all(x is y for x, y in zip(again, first))
    # Judged another way (no reference): a new call; a deliberate re-run: a new call too.
    run.batch([(square, 2, a, False)])
    run.batch([(square, 2, b, True)], reuse=[False])
    assert len(pool.calls) == 4 and run.reused == 2
    assert pool.calls[2][2] is False and pool.calls[3][1] == b.label
    # Under another time limit (hangs are shrunk with the sweep's): a new call.
    run.timeout = 10.0
    run.batch([(square, 2, a, False)])
    assert len(pool.calls) == 5 and run.reused == 2


def test_the_answers_kept_for_reuse_are_bounded_and_the_least_recently_used_go_first(monkeypatch):
    from hullstress.triage import stage
    from hullstress.triage.stage import _Triage

    monkeypatch.setattr(stage, "_ANSWERS_KEPT", 2)
    pool = _CountingPool()
    run = _Triage(pool, budget=TriageBudget(calls=100, group_calls=10, hang_calls=0, pictures=0,
                                            safety_seconds=60.0), timeout=5.0, qhull=True, should_stop=None,
                  progress=None, total=1)
    config = AlgorithmConfig("monotone-chain", eps="scaled")
    square = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
    first, second, third = (square + k for k in range(3))
    run.batch([(first, 2, config, False)])
    run.batch([(second, 2, config, False)])
    run.batch([(first, 2, config, False)])  # reused: now the most recently used
    run.batch([(third, 2, config, False)])  # evicts `second`, the least recently used
    assert len(run.answers) == 2 and len(pool.calls) == 3 and run.reused == 1
    run.batch([(first, 2, config, False)])
    assert len(pool.calls) == 3 and run.reused == 2  # still kept
    run.batch([(second, 2, config, False)])
    assert len(pool.calls) == 4  # asked again: a new call, the same answer a re-run gives


# -- streaming: the same result whatever order the calls end in ---------------------------------------


class _ShufflingPool:
    """A stand-in for the call pool that ends queued calls in a seeded random order, in this process.

    It takes every job the feed holds, then ends one of them at random (its rows go back at
    once), so answers arrive in an order no real pool would keep: the triage's result must not
    depend on it.
    """

    def __init__(self, seed: int) -> None:
        import random

        self.rng = random.Random(seed)
        self.jobs = 0

    def stream(self, feed, on_row, *, configs, timeout, check_timeout=None, qhull_options=None):
        from hullstress.evaluate import evaluate

        taken = []
        while feed or taken:
            while feed:
                taken.append(feed.popleft())
            job = taken.pop(self.rng.randrange(len(taken)))
            self.jobs += 1
            for config in job.task.configs:
                on_row(evaluate(job.task.case, config, qhull=bool(job.qhull)))

    def run(self, tasks, *, timeout, qhull=True, qhull_options=None, alone=None):
        from hullstress.evaluate import evaluate

        return [[evaluate(t.case, c, qhull=qhull.get(t.case.case_id, False) if isinstance(qhull, dict) else qhull)
                 for c in t.configs] for t in tasks]


def test_the_shrinks_and_causes_do_not_depend_on_the_order_calls_end_in():
    from hullstress.sweep import SweepOptions, run_sweep
    from hullstress.triage.grouping import group_failures
    from hullstress.triage.stage import _Triage

    sweep = run_sweep(SweepOptions(generators=("coplanar-grid", "kettner-classroom"), sizes=(8, 24),
                                   algorithms=("jarvis-march", "gift-wrap-3d", "monotone-chain"), workers=0))
    groups = group_failures(sweep.table)
    assert len(groups) >= 5
    by_id = {c.case_id: c for c in sweep.cases}
    budget = TriageBudget(calls=400, group_calls=12, hang_calls=0, pictures=0, safety_seconds=600.0,
                          simplify_calls=4)
    outcomes = []
    for seed in (0, 1, 2):
        pool = _ShufflingPool(seed)
        run = _Triage(pool, budget=budget, timeout=5.0, qhull=True, should_stop=None, progress=None,
                      total=len(groups))
        results: dict = {}
        run.run(groups, by_id, results, {})
        outcomes.append(({i: (r.case.points.tobytes(), r.calls, r.steps, r.note, r.adopted)
                          for i, r in results.items()}, run.used, run.reused, pool.jobs))
    assert len(outcomes[0][0]) == len(groups)
    assert outcomes[0][0] == outcomes[1][0] == outcomes[2][0]  # every shrink, step for step
    assert outcomes[0][1] == outcomes[1][1] == outcomes[2][1]  # the evaluations
    assert outcomes[0][2] == outcomes[1][2] == outcomes[2][2]  # and those answered by another's call
    assert any(r.adopted for r in results.values())  # a wave started from a case found before


def test_questions_in_flight_share_calls_merge_queued_jobs_and_reruns_get_their_own():
    from hullstress.runner import JobFeed
    from hullstress.triage.inflight import InFlight

    flight = InFlight()
    feed = JobFeed(on_take=flight.taken)
    square = Case.from_points([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]], family="shrink")
    a, b = AlgorithmConfig("monotone-chain", eps="scaled"), AlgorithmConfig("monotone-chain", eps="fixed")
    job = flight.add(1, square, a, False)
    feed.push(job, priority=(1, 1))
    assert flight.add(2, square, a, False) is None  # the same question: the same call
    assert flight.add(3, square, b, False) is None  # the same case, judged the same way: one job, facts once
    assert [c.label for c in job.task.configs] == [a.label, b.label] and flight.calls == 2
    assert flight.add(4, square, a, True) is None  # under way the other way: it waits for that call
    assert flight.add(5, square, a, False, fresh=True) is None  # a deliberate re-run waits too
    assert feed.popleft() is job and not feed
    jarvis = AlgorithmConfig("jarvis-march", eps="scaled")
    later = flight.add(6, square, jarvis, False)  # the first job is taken: a new one
    assert later is not None and later is not job
    row = {"case_id": square.case_id, "config": a.label}
    answered = flight.answer(row, 5.0, feed)
    assert answered == [(1, (square.case_id, a.label, False, 5.0)), (2, (square.case_id, a.label, False, 5.0))]
    # The two that waited are asked in turn, each a call of its own: one (case, config) under way at a time.
    waited = feed.popleft()
    assert not feed and (waited.qhull, [c.label for c in waited.task.configs]) == (True, [a.label])
    assert flight.answer(row, 5.0, feed) == [(4, (square.case_id, a.label, True, 5.0))]
    # The re-run joins the job still queued for that case (a new call all the same).
    assert not feed and [c.label for c in later.task.configs] == [jarvis.label, a.label]
    assert flight.answer(row, 5.0, feed) == [(5, (square.case_id, a.label, False, 5.0))]
    assert flight.calls == 5
