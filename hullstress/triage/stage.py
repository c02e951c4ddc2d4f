"""The triage stage: failing rows -> groups -> minimal cases -> causes, deterministically and in parallel.

:func:`triage_failures` reads the results table and the cases and returns
plain records (:mod:`.records`) that the report stage writes out; it is the
only stage after the sweep that runs code under test.

How it works
------------
1. **Group** the failing rows by signature (:func:`.grouping.group_failures`),
   worst first.
2. **Shrink in chains of waves** (:func:`plan_chains`).  Groups of one
   *kind* of failure (dimension, stage, status, failed checks and severity,
   exception type: the signature without the config) form a chain of waves
   of 1, 1, 2, 4, 8 ... groups; a wave starts when the one before it in its
   chain has finished, and every chain runs at once.  Before shrinking its
   own smallest failing case, a group tries a few minimal cases found so far
   (:data:`TRIES`: for its own kind, same variant first, then for other
   kinds): the first on which its config fails with exactly its signature
   becomes its start, and it then only checks that no point can go.  The
   schedule is that of rounds in lockstep (:class:`.shrink.Shrinker`): in
   each round every running shrink asks one question, and at the end of
   the round shrinks finish and waves start.  The calls do not wait for
   rounds: each answer goes back to its shrink as it arrives and its next
   question goes at once to a pool of isolated workers
   (:meth:`hullstress.runner.CallPool.stream`), earliest round first, so no
   worker idles at the end of a round; only the ends of rounds are applied
   in order, once their questions are answered.  Shrinks that ask the same
   question share one call, and questions about one case share one job (and
   its case facts) while it waits for a worker.  A candidate that crashes
   or hangs is a row like any other (``crash``, ``timeout``), never the end
   of triage.  Hangs are shrunk last, on their own budget (each failing call
   lasts the whole timeout).
3. **Merge**: groups whose minimal cases coincide up to translation,
   power-of-two scaling, row and axis order (:mod:`.canonical`) form one
   :class:`~.records.Cause`.
4. **Verify**: every shrink ends by re-running its minimal case exactly (a
   flaky failure is marked as such); groups left unshrunk are re-run in one
   batch.  Each cause's evidence (the algorithm's output for the picture) is
   gathered here, so that the report runs nothing.

Every decision depends on the rows alone: shrinks are budgeted in
evaluations (:class:`~hullstress.options.TriageBudget`), chains depend on
the groups only, and rounds, not seconds, decide when a wave starts and what
it may try, so the same
table gives the same causes and minimal cases whatever the number of workers
and whatever the machine's load.  Only the wall-clock safety net, an
interrupt, or a call near its timeout can change that, and the first two
are written into the notes.
"""

from __future__ import annotations

import dataclasses
import heapq
import time
from collections import Counter, OrderedDict, deque
from collections.abc import Callable, Sequence

import numpy as np
import pandas as pd

from ..case import Case
from ..config import AlgorithmConfig
from ..errors import HullstressError
from ..options import DEFAULTS, TriageBudget
from ..results import ResultRow
from .canonical import canonical_key
from .inflight import Asking, InFlight
from .evidence import output_faces, storage_kind, verify_from_storage
from .grouping import FailureGroup, group_failures
from .oracle import DEFAULT_TIMEOUT
from ..records import Status
from .records import Cause, ShrinkResult, TriageRecord, TriageResult
from .shrink import Shrinker, candidate_case
from .signature import Signature, signature_of
from .waves import TRIES, Known, plan_chains, ranked, remember

__all__ = ["TriageRecord", "TriageResult", "triage_failures", "triage_one", "plan_chains", "TRIES", "Progress"]

#: Answers of earlier calls kept for reuse (about 7 KB each; a quick run makes about 6000 calls).
_ANSWERS_KEPT = 20_000

#: ``progress(done, total, detail)``: groups finished of groups to triage, and a few words.
Progress = Callable[[int, int, str], None]

_INTERRUPTED = "triage was interrupted: the case is smaller but may not be minimal"


class _Halt(Exception):
    """Triage must end now: an interrupt, or the wall-clock safety net."""

    def __init__(self, note: str, *, interrupted: bool) -> None:
        super().__init__(note)
        self.note, self.interrupted = note, interrupted


def _unshrunk(case: Case, signature: Signature, row: ResultRow | None, note: str) -> ShrinkResult:
    """The group's smallest case as its own "minimal" case, with why it was not shrunk."""
    return ShrinkResult(case=case, original=case, signature=signature, original_size=case.n_points,
                        minimal_size=case.n_points, calls=0, seconds=0.0, reproduced=False, row=row, note=note)


def _table_row(table: pd.DataFrame, index: int) -> ResultRow:
    return ResultRow({k: (None if (not isinstance(v, (list, dict)) and pd.isna(v)) else v)
                      for k, v in table.loc[index].items()})


def triage_one(result: ShrinkResult, config: AlgorithmConfig, *, group: FailureGroup | None = None,
               timeout: float | None = None, verify: bool = True) -> TriageRecord:
    """Gather one shrink result's evidence here, call by call (``shrink`` and ``fuzz`` commands).

    Parameters
    ----------
    result : ShrinkResult
        From :func:`hullstress.triage.shrink` (or an unshrunk stand-in).
    config : AlgorithmConfig
    group : FailureGroup, optional
    timeout : float, optional
        Per-call timeout for the verification run.
    verify : bool
        Re-run the case from its stored form (skipped for hangs: a full timeout each).
    """
    sig = result.signature
    kind = storage_kind(result.case.points)
    faces, note = output_faces(result.case, config, sig) if not sig.dangerous else (None, f"no output: {sig.status}")
    verified = verify_from_storage(result.case, kind, config, sig, timeout) if verify else None
    return TriageRecord(signature=sig, config=config, group=group, shrink=result, faces=faces,
                        faces_note=note, storage=kind, verified=verified)


class _Triage:
    """One run of the stage: the pool, the budget, the waves."""

    def __init__(self, pool: object, *, budget: TriageBudget, timeout: float, qhull: bool,
                 should_stop: Callable[[], bool] | None, progress: Progress | None, total: int,
                 qhull_options: str | None = None) -> None:
        self.pool = pool
        self.budget, self.qhull = budget, qhull
        self.qhull_options = qhull_options
        self.sweep_timeout = timeout
        self.timeout = min(timeout, budget.call_timeout)
        self.should_stop, self.progress = should_stop, progress
        self.start = time.perf_counter()
        self.used = 0
        self.done = 0
        self.total = total
        self.rounds = 0
        # (case, config, reference, limit) -> row, the most recently used kept: a row is about 7 KB, and the
        # nightly budget allows 150,000 evaluations.  Which answers are kept decides only which calls are made.
        self.answers: OrderedDict[tuple[str, str, bool, float], ResultRow] = OrderedDict()
        self.reused = 0  # requests answered by an identical earlier call

    # -- running candidates -------------------------------------------------

    def _check_halt(self) -> None:
        if self.should_stop is not None and self.should_stop():
            raise _Halt(_INTERRUPTED, interrupted=True)
        limit = self.budget.safety_seconds
        if time.perf_counter() - self.start > limit:
            raise _Halt(f"stopped by the wall-clock safety net ({limit:g} s): the case may not be minimal, "
                        "and may differ between runs", interrupted=False)

    def batch(self, requests: Sequence[tuple[np.ndarray, int, AlgorithmConfig, bool]], *,
              reuse: Sequence[bool] | None = None, alone: Sequence[bool] | None = None) -> list[ResultRow]:
        """Run (points, dim, config, needs qhull) requests as one batch; rows in request order.

        A request whose ``alone`` is True runs as a job of its own in a worker
        that has run nothing before it (a crash is judged so).

        A request whose ``reuse`` is True is answered by an identical earlier
        call when there was one (same points, config, reference and time limit), without
        running it again: shrinks of different groups often ask the same
        question (a minimal case tried by several groups of one config).
        The answer is the row that call would give again, so what triage
        produces does not change; only the calls it makes.  Deliberate
        re-runs (a minimal case confirmed, an unshrunk case verified) pass
        False.
        """
        from ..runner import Task

        cases: dict[str, Case] = {}
        needs_qhull: set[str] = set()
        keys = []
        for points, dim, config, needs in requests:
            case = candidate_case(points, dim)
            cases.setdefault(case.case_id, case)
            keys.append((case.case_id, config.label))
            if needs and self.qhull:
                needs_qhull.add(case.case_id)
        # A case that some request needs the Qhull reference for runs once, with it, for all of them;
        # the others skip the reference.  An earlier answer counts only if judged the same way, under the
        # same time limit (hangs are shrunk with a longer one: a call cut short before may finish then).
        full = [(cid, label, cid in needs_qhull, self.timeout) for cid, label in keys]
        found: dict[tuple[str, str, bool, float], ResultRow] = {}
        configs: dict[str, list[AlgorithmConfig]] = {}
        separate: list[tuple[str, AlgorithmConfig]] = []
        for n, ((points, dim, config, needs), key) in enumerate(zip(requests, full)):
            if (reuse is None or reuse[n]) and key in self.answers and key not in found:
                found[key] = self.answers[key]
                self.answers.move_to_end(key)
                self.reused += 1
            elif alone is not None and alone[n]:
                if (key[0], config) not in separate:
                    separate.append((key[0], config))
            elif key not in found:
                configs.setdefault(key[0], []).append(config)
        # One batch, cases with and without the reference together (a round ends with its slowest call).
        tasks = [Task(n, cases[cid], tuple(dict.fromkeys(cfgs))) for n, (cid, cfgs) in enumerate(configs.items())]
        # Largest candidates first: the early deletion steps of a 100-point case then run beside the
        # many few-point ones instead of alone at the end.  Rows are matched by task, so the order
        # changes no answer.
        tasks.sort(key=lambda t: -t.case.n_points * len(t.configs))
        own = [Task(len(tasks) + n, cases[cid], (config,)) for n, (cid, config) in enumerate(separate)]
        flags = [False] * len(tasks) + [True] * len(own)
        tasks += own
        qhull = {t.case.case_id: t.case.case_id in needs_qhull for t in tasks}
        for task, rows in zip(tasks, self.pool.run(tasks, timeout=self.timeout, qhull=qhull,
                                                      qhull_options=self.qhull_options, alone=flags)):
            for config, row in zip(task.configs, rows):
                key = (task.case.case_id, config.label, qhull[task.case.case_id], self.timeout)
                found[key] = self.answers[key] = row
        while len(self.answers) > _ANSWERS_KEPT:
            self.answers.popitem(last=False)
        return [found[k] for k in full]

    def _report(self, detail: str) -> None:
        if self.progress is not None:
            self.progress(self.done, self.total, detail)

    # -- the chains of waves, in lockstep ------------------------------------

    def run(self, groups: list[FailureGroup], cases: dict[str, Case], results: dict[int, ShrinkResult],
            rows: dict[int, ResultRow]) -> None:
        """Shrink ``groups`` (indexed by position) into ``results``; stops only by :class:`_Halt`."""
        regular = [i for i, g in enumerate(groups) if g.signature.status != Status.TIMEOUT]
        hangs = [i for i, g in enumerate(groups) if g.signature.status == Status.TIMEOUT]
        chains = [[[regular[k] for k in wave] for wave in chain] for chain in plan_chains([groups[i] for i in regular])]
        self._lockstep(chains, groups, cases, results, rows, cap_limit=self.budget.group_calls)
        if hangs:
            # A hang is a call that outlasts the sweep's timeout: shrink it with that one.
            self.timeout = self.sweep_timeout
            self._lockstep([[hangs]], groups, cases, results, rows, cap_limit=self.budget.hang_calls, learn=False)

    def _lockstep(self, chains: list[list[list[int]]], groups: list[FailureGroup], cases: dict[str, Case],
                  results: dict[int, ShrinkResult], rows: dict[int, ResultRow], *, cap_limit: int,
                  learn: bool = True) -> None:
        """Run every chain's waves, one after the other within a chain, all chains side by side.

        The schedule is that of rounds in lockstep: in round ``r`` every
        running shrink asks one question; at the end of the round the shrinks
        that got their last answer finish (in group order, each minimal case
        learned), and a chain whose wave is then complete starts its next
        wave, with the minimal cases known by then and the evaluations left
        by then.  Rounds are the clock: what starts when, with which budget
        and which cases to try, depends on the answers only.

        The calls do not wait for rounds, though: each answer goes back to
        its shrink as it arrives and the next question goes to the pool at
        once (:meth:`hullstress.runner.CallPool.stream`, earliest round
        first), so no worker idles at the end of a round.  Only the end of a
        round is kept in order: its finishes and wave starts are applied once
        every question of that round (and of the rounds before) is answered,
        exactly as in lockstep, so the result is the same whatever the
        number of workers and the order calls end in.
        """
        from ..runner import JobFeed

        known: list[Known] = []
        position = [0] * len(chains)  # the wave each chain is at
        waiting = [0] * len(chains)  # shrinks of the current wave still running, per chain
        asking: dict[int, Asking] = {}  # group -> its shrink and the question it waits on
        asked: Counter[int] = Counter()  # questions per round
        ended: dict[int, list[int]] = {}  # round -> groups whose shrink got its last answer in it
        ended_shrinks: dict[int, Asking] = {}  # their shrinks, finished at the end of that round
        restarts: dict[int, list[int]] = {}  # round -> chains whose wave is complete at its end
        ready: deque[tuple[int, ResultRow]] = deque()  # answers known without a call
        outstanding: Counter[int] = Counter()  # unanswered questions per round
        rounds_open: list[int] = []  # a heap of the rounds with unanswered questions (some may be spent)
        flight = InFlight()
        feed = JobFeed(on_take=flight.taken)
        clock = {"round": 0}  # every round up to this one is complete and applied

        def finish(i: int, shrinker: Shrinker) -> None:
            results[i] = shrinker.result()
            self.done += 1
            if learn:
                remember([i], groups, results, known)

        def start(c: int, r: int) -> None:  # the end of round r: chain c starts its next wave
            while position[c] < len(chains[c]):
                wave = chains[c][position[c]]
                position[c] += 1
                used = sum(n for k, n in asked.items() if k <= r)
                cap = min(cap_limit, max(0, self.budget.calls - used) // max(1, len(wave)))
                for i in wave:
                    shrinker = self._shrinker(i, groups, cases, rows, known, cap, cap_limit, results)
                    if shrinker is None:
                        continue
                    question = shrinker.ask()
                    if question is None:
                        finish(i, shrinker)
                        continue
                    waiting[c] += 1
                    ask(i, Asking(shrinker, c, r + 1, question))
                if waiting[c]:
                    return

        def ask(i: int, asking_now: Asking) -> None:
            asking[i] = asking_now
            asked[asking_now.round] += 1
            self.used += 1
            points, needs = asking_now.question
            case = candidate_case(points, cases[groups[i].smallest_case_id].dim)
            config = groups[i].signature.config
            qhull = bool(needs and self.qhull)
            key = (case.case_id, config.label, qhull, self.timeout)
            outstanding[asking_now.round] += 1
            if outstanding[asking_now.round] == 1:
                heapq.heappush(rounds_open, asking_now.round)
            fresh = asking_now.shrinker.rerun
            if not fresh and key in self.answers:
                self.answers.move_to_end(key)
                ready.append((i, self.answers[key]))
                return
            job = flight.add(i, case, config, qhull, fresh=fresh, alone=groups[i].signature.status == Status.CRASH)
            if job is not None:
                feed.push(job, priority=(asking_now.round, i))

        def answered(i: int, row: ResultRow) -> None:
            now = asking[i]
            outstanding[now.round] -= 1
            question = now.shrinker.answer(row)
            if question is not None:
                ask(i, Asking(now.shrinker, now.chain, now.round + 1, question))
                return
            del asking[i]
            ended.setdefault(now.round, []).append(i)
            ended_shrinks[i] = now

        def end_round() -> bool:
            """Apply the end of the next round if all its questions are answered; False when none can end."""
            r = clock["round"] + 1
            while rounds_open and outstanding[rounds_open[0]] == 0:
                heapq.heappop(rounds_open)
            frontier = rounds_open[0] if rounds_open else None
            if frontier is not None and r >= frontier:
                return False
            if frontier is None and not ended and not restarts:
                return False
            clock["round"] = r
            for i in sorted(ended.pop(r, [])):
                now = ended_shrinks.pop(i)
                finish(i, now.shrinker)
                c = now.chain
                waiting[c] -= 1
                if waiting[c] == 0:
                    restarts.setdefault(r, []).append(c)
            for c in sorted(restarts.pop(r, [])):
                start(c, r)
            self.rounds = r
            self._report(f"round {r}")
            return True

        def pump() -> None:
            while True:
                while ready:
                    answered(*ready.popleft())
                if not end_round():
                    return

        def on_row(row: ResultRow) -> None:
            self._check_halt()
            for i, key in flight.answer(row, self.timeout, feed):
                self.answers[key] = row
                ready.append((i, row))
            while len(self.answers) > _ANSWERS_KEPT:
                self.answers.popitem(last=False)
            pump()

        for c in range(len(chains)):
            start(c, 0)
        try:
            self._check_halt()
            pump()
            configs = [groups[i].signature.config for chain in chains for wave in chain for i in wave]
            self.pool.stream(feed, on_row, configs=configs, timeout=self.timeout, qhull_options=self.qhull_options)
            if asking or ended or restarts:
                raise HullstressError(f"internal: triage stopped with {len(asking)} questions unanswered")
        except (_Halt, KeyboardInterrupt) as exc:
            # The shrinks cut short keep their best exact case so far; their note says why.
            note = exc.note if isinstance(exc, _Halt) else _INTERRUPTED
            for i, now in ended_shrinks.items():
                results[i] = now.shrinker.result()
            for i, now in asking.items():
                results[i] = now.shrinker.stop(note)
            raise
        finally:
            # Questions answered by a call made for another one (earlier, or under way at the time).
            self.reused += sum(asked.values()) - flight.calls

    def _shrinker(self, i: int, groups: list[FailureGroup], cases: dict[str, Case], rows: dict[int, ResultRow],
                  known: list[Known], cap: int, cap_limit: int, results: dict[int, ShrinkResult]) -> Shrinker | None:
        """Group ``i``'s shrink, trying the known minimal cases first; None (and an unshrunk result) without budget."""
        g, case = groups[i], cases[groups[i].smallest_case_id]
        if cap < 1:
            why = ("each call of a hang lasts the whole timeout and the profile allows none"
                   if g.signature.status == Status.TIMEOUT and cap_limit == 0
                   else "the triage evaluation budget was spent on earlier groups")
            results[i] = _unshrunk(case, g.signature, rows.get(i), f"not shrunk: {why}")
            self.done += 1
            return None
        tries = [(k.points, f"the minimal case of {k.slug}") for k in ranked(known, g, case.dim)]
        return Shrinker(case, g.signature, max_calls=cap, candidates=tries, qhull=self.qhull, row=rows.get(i),
                        simplify_calls=self.budget.simplify_calls)

def triage_failures(
    table: pd.DataFrame,
    cases: Sequence[Case],
    *,
    budget: TriageBudget,
    shrink: bool = True,
    timeout: float | None = None,
    workers: int = 1,
    qhull: bool = True,
    memory_limit_mb: float | None = DEFAULTS.memory_limit_mb,
    max_records: int = DEFAULTS.max_folders,
    should_stop: Callable[[], bool] | None = None,
    progress: Progress | None = None,
    qhull_options: str | None = None,
) -> TriageResult:
    """Group the table's failures, minimise one case per group, merge groups into causes.

    Parameters
    ----------
    table : DataFrame
        The results table.
    cases : sequence of Case
        The cases whose ids appear in ``table``.
    budget : TriageBudget
        Evaluations and the safety net (the profile's).
    shrink : bool
        Shrink each group's smallest failing case (``--no-shrink`` turns it off).
    timeout : float, optional
        The sweep's per-call timeout, reused for every call triage makes.
    workers : int
        Isolated worker processes (the result does not depend on it).
    qhull : bool
        The sweep computed Qhull references (``--no-qhull`` turns them off):
        shrinking must judge the same way.
    memory_limit_mb : float or None
        Address-space limit per worker, as in the sweep.
    max_records : int
        Cap on triaged groups (worst first).
    should_stop : callable, optional
        Polled between rounds; when it returns True triage ends early (an interrupt).
    progress : callable, optional
        ``progress(done, total, detail)`` as groups finish.
    qhull_options : str, optional
        Qhull options tried first for every reference (the run's ``--qhull-options``),
        so a shrunk case is judged as the sweep judged it.

    Returns
    -------
    TriageResult
    """
    from ..runner import CallPool

    began = time.perf_counter()
    groups = group_failures(table)
    by_id = {c.case_id: c for c in cases}
    chosen = [g for g in groups[:max_records] if g.smallest_case_id in by_id]
    missing = sum(1 for g in groups[:max_records] if g.smallest_case_id not in by_id)
    rows = {i: _table_row(table, g.smallest_index) for i, g in enumerate(chosen)}
    call_timeout = timeout or DEFAULT_TIMEOUT
    results: dict[int, ShrinkResult] = {}
    halt: _Halt | None = None
    stopped = False
    with CallPool(workers, memory_limit_mb=memory_limit_mb) as pool:
        run = _Triage(pool, budget=budget, timeout=call_timeout, qhull=qhull, should_stop=should_stop,
                      progress=progress, total=len(chosen), qhull_options=qhull_options)
        if shrink and chosen:
            try:
                run.run(chosen, by_id, results, rows)
            except _Halt as exc:
                halt = exc
            except KeyboardInterrupt:  # the pipeline's signal handler, raised inside a batch
                halt = _Halt(_INTERRUPTED, interrupted=True)
        for i, g in enumerate(chosen):
            if i not in results:
                note = ("not shrunk (--no-shrink)" if not shrink
                        else "not shrunk: triage was interrupted first" if halt is not None and halt.interrupted
                        else "not shrunk: the wall-clock safety net stopped triage first")
                results[i] = _unshrunk(by_id[g.smallest_case_id], g.signature, rows[i], note)
        stopped = halt is not None and halt.interrupted
        for i, res in results.items():
            if res.row is None:  # not shrunk: its row is the sweep's
                results[i] = dataclasses.replace(res, row=rows[i])
        causes = _merge(chosen, results)
        verified: dict[int, bool | None] = {i: results[i].verified for i in results}
        if not stopped:
            try:
                verified.update(_verify(run, chosen, results))
            except (_Halt, KeyboardInterrupt):
                stopped = True
        calls, reused = run.used, run.reused
    records = _records(chosen, results, causes, verified, stopped=stopped)
    by_group = {id(r.group): r for r in records}
    cause_records = [Cause(key=key, records=tuple(by_group[id(chosen[i])] for i in members))
                     for key, members in causes]
    cause_records.sort(key=lambda c: -c.failures)  # stable: ties stay in group order
    notes = _notes(groups, chosen, results, cause_records, budget, calls, shrink, halt, missing, max_records,
                   records, reused)
    return TriageResult(groups=groups, records=records, causes=cause_records, notes=notes,
                        seconds=time.perf_counter() - began, stopped=stopped, calls=calls,
                        safety_net=halt is not None and not halt.interrupted, reused=reused)


def _merge(chosen: list[FailureGroup], results: dict[int, ShrinkResult]) -> list[tuple[str, list[int]]]:
    """Causes as (key, member group positions), in order of their first member."""
    causes: dict[str, list[int]] = {}
    for i, g in enumerate(chosen):
        res = results[i]
        key = canonical_key(np.asarray(res.case.points)) if res.reproduced else f"group:{g.slug}"
        causes.setdefault(key, []).append(i)
    return list(causes.items())


def _verify(run: _Triage, chosen: list[FailureGroup], results: dict[int, ShrinkResult]) -> dict[int, bool]:
    """Re-run the cases that were not shrunk (a shrink re-runs its own minimal case), in one batch.

    Hangs are not re-run: each would cost a whole timeout.
    """
    todo = [i for i in range(len(chosen)) if not results[i].reproduced and chosen[i].signature.status != Status.TIMEOUT]
    run._check_halt()
    rows = run.batch([(np.asarray(results[i].case.points), results[i].case.dim, chosen[i].signature.config,
                       chosen[i].signature.status == Status.FAIL) for i in todo], reuse=[False] * len(todo),
                     alone=[chosen[i].signature.status == Status.CRASH for i in todo])
    return {i: signature_of(row) == chosen[i].signature for i, row in zip(todo, rows)}


def _records(chosen: list[FailureGroup], results: dict[int, ShrinkResult], causes: list[tuple[str, list[int]]],
             verified: dict[int, bool | None], *, stopped: bool) -> list[TriageRecord]:
    """One record per group; the output faces only for each cause's representative (its folder's picture)."""
    representatives = {members[0] for _, members in causes}
    # The folder stores the representative's points; a member's coincide with them up to exact
    # transforms (same finiteness and shape), so it is stored the same way (in case.json).
    storage = {}
    for _, members in causes:
        kind = storage_kind(results[members[0]].case.points)
        storage.update({i: kind for i in members})
    records = []
    for i, g in enumerate(chosen):
        res, sig = results[i], chosen[i].signature
        if i in representatives and not sig.dangerous and not stopped:
            faces, note = output_faces(res.case, sig.config, sig)
        elif sig.dangerous:
            faces, note = None, f"no output: the call ends in {sig.status}"
        else:
            faces, note = None, "" if i in representatives else "see the cause's representative"
        records.append(TriageRecord(signature=sig, config=sig.config, group=g, shrink=res, faces=faces,
                                    faces_note=note, storage=storage[i],
                                    verified=verified.get(i)))
    return records


def _notes(groups: list[FailureGroup], chosen: list[FailureGroup], results: dict[int, ShrinkResult],
           causes: list[Cause], budget: TriageBudget, calls: int, shrink: bool, halt: _Halt | None,
           missing: int, max_records: int, records: list[TriageRecord], reused: int = 0) -> list[str]:
    notes: list[str] = []
    shrunk = sum(1 for r in results.values() if r.reproduced)
    adopted = sum(1 for r in results.values() if r.adopted)
    if shrink:
        notes.append(
            f"Triage: {len(groups)} failure groups, {len(causes)} causes (groups whose minimal cases coincide up "
            f"to translation, power-of-two scaling, row and axis order are one cause). {shrunk} of {len(chosen)} "
            f"groups minimised, {adopted} of them starting from another group's minimal case; "
            f"{calls} of {budget.calls} evaluations used ({budget.group_calls} per group at most), so the "
            "same seed gives the same causes and folders"
            + (f"; {reused} of them answered by an identical earlier call instead of a new one." if reused else "."))
    else:
        notes.append("Shrinking was turned off (--no-shrink): each group shows its smallest failing case.")
    cut = [r for r in results.values() if r.exhausted and r.reproduced]
    if shrink and cut:
        simplifying = sum(1 for r in cut if "while simplifying coordinates" in r.note)
        notes.append(f"{len(cut)} groups ran out of evaluations before their last pass: {simplifying} while "
                     f"simplifying coordinates (no single point of their case can go), {len(cut) - simplifying} "
                     "earlier (their cases are smaller but may not be minimal).")
    unshrunk = [r.note for r in results.values() if not r.reproduced and shrink]
    if unshrunk:
        reasons = pd.Series(unshrunk).value_counts()
        notes.append(f"{len(unshrunk)} groups keep their smallest failing case unshrunk: "
                     + "; ".join(f"{n} x {why}" for why, n in reasons.items()) + ".")
    if halt is not None:
        notes.append(f"Triage ended early: {halt.note}.")
    untriaged = len(groups) - len(chosen) - missing
    if untriaged > 0:
        notes.append(f"{untriaged} more failure groups have no record because of the cap of {max_records} "
                     "groups; they are listed in groups.csv.")
    if missing:
        notes.append(f"{missing} groups had no case object to shrink (their cases were not passed in).")
    unverified = [r for r in records if r.verified is False]
    if unverified:
        notes.append(f"{len(unverified)} groups did not fail the same way when their minimal case was re-run "
                     "(flaky or state-dependent); their reproduce commands may exit 0.")
    return notes
