"""The search loop: evaluate seeds, then generations of mutated candidates, on the sweep's isolated workers.

It is an execute stage of :func:`hullstress.pipeline.run` (an
:class:`~hullstress.pipeline.Executor`): the generate stage's cases are the
seeds, the candidates it makes are new cases (family ``search``, with their
lineage in ``params``), and every row goes through the same triage, report
and corpus stages as a sweep's.

1. **Seeds.** The first ``seeds`` cases of the plan, in the sweep's
   schedule (round robin over families, smallest first), are evaluated and
   all kept (those with finite points of the right shape become parents).
2. **Generations** of ``generation`` candidates: each takes a parent from
   the kept inputs and applies one to three mutation operators
   (:mod:`.mutate`; ``merge`` draws a second parent), trims it to
   ``max_points`` rows and is skipped when its points were evaluated
   before.  Every candidate runs on every config of its dimension; its rows
   decide whether it is kept (:mod:`.guidance`).
3. It stops after ``evaluations`` inputs (seeds included), or earlier when
   the wall-clock ``time_budget`` runs out (checked between batches; then
   ``budget_exhausted``).

Determinism: every random draw comes from ``default_rng([seed, stream,
generation])``, the batch size does not depend on the number of workers, the
pool returns rows in task order and guidance reads no timing, so a seed and
an evaluation budget give the same cases, rows and decisions on any machine
and with any ``--workers`` (calls that time out are the exception, as in a
sweep).
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from ..case import Case
from ..config import AlgorithmConfig
from ..errors import UsageError
from ..results import ResultRow
from ..runner import CallPool, ExecutionStats, RunnerOptions, Task, execute
from ..sweep import SweepOptions
from .guidance import Guidance, Verdict, finite_points
from .mutate import MUTATIONS, mutations_for

__all__ = ["SearchOptions", "Search", "SEARCH_FAMILY"]

#: The family of every case the search makes (``params`` holds its lineage).
SEARCH_FAMILY = "search"
#: Separates the search's random stream from any other use of the seed.
_STREAM = 0x5EA4C4
#: Attempts at a new candidate before a generation settles for fewer.
_ATTEMPTS = 8


@dataclass(frozen=True)
class SearchOptions:
    """How long and how wide a search runs (``python -m hullstress search --help``).

    Attributes
    ----------
    evaluations : int
        Inputs to evaluate, seeds included; each runs on every config of its dimension.
    seeds : int or None
        How many of the plan's cases seed the search (default: a quarter of
        ``evaluations``, at least one).
    generation : int
        Candidates per generation (a fixed number, so results never depend on the workers).
    max_points : int
        Candidates with more rows are trimmed to this many (a random subset).
    population : int
        Parents kept at most; beyond it the oldest kept only for a score are forgotten.
    time_budget : float or None
        Wall-clock seconds after which no new batch starts.

    Examples
    --------
    >>> SearchOptions(evaluations=0)
    Traceback (most recent call last):
    ...
    hullstress.errors.UsageError: --evaluations must be at least 1, got 0
    """

    evaluations: int = 400
    seeds: int | None = None
    generation: int = 16
    max_points: int = 200
    population: int = 256
    time_budget: float | None = None

    def __post_init__(self) -> None:
        for name, low in (("evaluations", 1), ("generation", 1), ("max_points", 4), ("population", 1)):
            value = getattr(self, name)
            if not isinstance(value, int) or value < low:
                raise UsageError(f"--{name.replace('_', '-')} must be at least {low}, got {value!r}")
        if self.seeds is not None and (not isinstance(self.seeds, int) or self.seeds < 1):
            raise UsageError(f"--seeds must be at least 1, got {self.seeds!r}")
        if self.time_budget is not None and not self.time_budget > 0:
            raise UsageError(f"--time-budget must be positive, got {self.time_budget!r}")

    @property
    def n_seeds(self) -> int:
        return self.seeds if self.seeds is not None else max(1, self.evaluations // 4)


@dataclass
class _Kept:
    case: Case
    root: str
    signatures: bool


@dataclass
class Search:
    """The search as an execute stage: ``Search(options, sweep)(plan, on_row)`` (see the module docstring).

    Attributes
    ----------
    guidance : Guidance
        What it has seen (signatures, best scores, differential splits), after a run.
    log : list of (str, str, tuple of str)
        ``(case_id, lineage, reasons)`` of every input kept, in order.
    evaluated : int
        Inputs evaluated.
    """

    options: SearchOptions
    sweep: SweepOptions
    echo: Callable[[str], None] | None = None
    guidance: Guidance = field(default_factory=Guidance)
    log: list[tuple[str, str, tuple[str, ...]]] = field(default_factory=list)
    evaluated: int = 0

    def planned_calls(self, plan: object) -> int:
        tasks = getattr(plan, "tasks")
        widest = max((len(t.configs) for t in tasks), default=0)
        return self.options.evaluations * widest

    def __call__(self, plan: object, on_row: Callable[[ResultRow], None]) -> ExecutionStats:
        options, runner = self.options, self.sweep.runner_options()
        if runner.scheduler is not None:
            raise UsageError("search runs on local worker processes; --scheduler is not supported")
        seeds = list(plan.tasks)[: options.n_seeds]  # type: ignore[attr-defined]
        configs = _configs_by_dim(plan.tasks)  # type: ignore[attr-defined]
        plan.tasks.clear()  # type: ignore[attr-defined]
        plan.cases.clear()  # type: ignore[attr-defined]
        started = time.perf_counter()
        deadline = None if options.time_budget is None else time.monotonic() + options.time_budget
        stats = ExecutionStats(backend="serial" if runner.workers == 0 else "local", workers=max(1, runner.workers))
        population: list[_Kept] = []
        seen = set()
        pool = CallPool(runner.workers, memory_limit_mb=runner.memory_limit_mb) if runner.workers else None
        try:
            for start in range(0, len(seeds), options.generation):
                if self._out_of_time(deadline, stats):
                    break
                batch = seeds[start:start + options.generation]
                for task in batch:
                    seen.add(task.case.content_hash)
                self._evaluate(batch, runner, pool, plan, on_row, stats, population, roots=None)
            generation = 0
            while self.evaluated < options.evaluations and population:
                if self._out_of_time(deadline, stats):
                    break
                wanted = min(options.generation, options.evaluations - self.evaluated)
                batch, roots = self._candidates(generation, wanted, population, configs, seen)
                generation += 1
                if not batch:
                    continue
                self._evaluate(batch, runner, pool, plan, on_row, stats, population, roots=roots)
        finally:
            if pool is not None:
                stats.worker_restarts += pool.stats.worker_restarts
                stats.facts_seconds += pool.stats.facts_seconds
                pool.close()
        stats.notes.append(self.summary())
        return stats.finish(time.perf_counter() - started)

    def summary(self) -> str:
        """One line: inputs, signatures, what the kept inputs were kept for."""
        why = {"signature": 0, "score": 0, "differential": 0}
        for _, _, reasons in self.log:
            for kind in why:
                why[kind] += any(r.startswith(kind) for r in reasons)
        return (f"search: {self.evaluated} inputs evaluated, {len(self.guidance.signatures)} failure signatures; "
                f"kept {len(self.log)} inputs: {why['signature']} for a new signature, {why['score']} for a "
                f"raised degeneracy score, {why['differential']} for a new differential split")

    # -- internals -------------------------------------------------------------------------------

    def _out_of_time(self, deadline: float | None, stats: ExecutionStats) -> bool:
        if deadline is not None and time.monotonic() >= deadline:
            stats.budget_exhausted = True
            return True
        return False

    def _evaluate(self, batch: list[Task], runner: RunnerOptions, pool: CallPool | None, plan: object,
                  on_row: Callable[[ResultRow], None], stats: ExecutionStats, population: list[_Kept],
                  roots: list[str] | None) -> None:
        batch = batch[: self.options.evaluations - self.evaluated]
        if pool is not None:
            rows_per_task = pool.run(batch, timeout=runner.timeout, qhull=runner.qhull,
                                     check_timeout=runner.check_timeout, qhull_options=runner.qhull_options)
        else:
            rows_per_task = _serial(batch, runner)
        for k, (task, rows) in enumerate(zip(batch, rows_per_task)):
            indexed = Task(index=len(plan.tasks), case=task.case, configs=task.configs)  # type: ignore[attr-defined]
            plan.tasks.append(indexed)  # type: ignore[attr-defined]
            plan.cases.append(task.case)  # type: ignore[attr-defined]
            for row in rows:
                stats.calls_started += 1
                stats.calls_done += 1
                stats.algorithm_seconds += float(row.get("seconds") or 0.0)
                stats.check_seconds += float(row.get("check_seconds") or 0.0)
                on_row(row)
            self.evaluated += 1
            verdict = self.guidance.judge(task.case, rows)
            root = task.case.family if roots is None else roots[k]
            self._keep(task.case, root, verdict, seed=roots is None, population=population)

    def _keep(self, case: Case, root: str, verdict: Verdict, *, seed: bool, population: list[_Kept]) -> None:
        if not (seed or verdict.kept):
            return
        lineage = case.family if case.family != SEARCH_FAMILY else f"{root}: {case.params.get('mutations')}"
        self.log.append((case.case_id, lineage, verdict.reasons))
        if self.echo is not None and verdict.new_signatures and not seed:
            for sig in verdict.new_signatures:
                self.echo(f"search: input {self.evaluated} ({lineage}, {case.n_points} points): new {sig.label}")
        if finite_points(case):
            population.append(_Kept(case, root, bool(verdict.new_signatures) or seed))
            if len(population) > self.options.population:
                oldest = next((i for i, k in enumerate(population) if not k.signatures), 0)
                del population[oldest]

    def _candidates(self, generation: int, wanted: int, population: list[_Kept],
                    configs: dict[int, tuple[AlgorithmConfig, ...]], seen: set) -> tuple[list[Task], list[str]]:
        rng = np.random.default_rng([self.sweep.seed, _STREAM, generation])
        tasks: list[Task] = []
        roots: list[str] = []
        for _ in range(wanted):
            for _attempt in range(_ATTEMPTS):
                made = self._mutant(rng, population, generation)
                if made is None:
                    continue
                case, root = made
                if case.content_hash in seen or case.dim not in configs:
                    continue
                seen.add(case.content_hash)
                tasks.append(Task(index=len(tasks), case=case, configs=configs[case.dim]))
                roots.append(root)
                break
        return tasks, roots

    def _mutant(self, rng: np.random.Generator, population: list[_Kept], generation: int) -> tuple[Case, str] | None:
        parent = population[int(rng.integers(len(population)))]
        dim = parent.case.dim
        names = mutations_for(dim)
        points = np.asarray(parent.case.points)
        applied: list[str] = []
        for _ in range(int(rng.integers(1, 4))):
            name = names[int(rng.integers(len(names)))]
            other = None
            if name == "merge":
                mates = [k for k in population if k.case.dim == dim and k is not parent]
                if not mates:
                    continue
                other = np.asarray(mates[int(rng.integers(len(mates)))].case.points)
            moved = MUTATIONS[name](points, rng, other=other)
            if moved is None:
                continue
            points = moved
            applied.append(name)
        if not applied:
            return None
        if len(points) > self.options.max_points:
            points = points[np.sort(rng.choice(len(points), size=self.options.max_points, replace=False))]
            applied.append("trim")
        params = {"from": parent.root, "parent": parent.case.case_id, "mutations": "+".join(applied)}
        case = Case(points=points, dim=dim, family=SEARCH_FAMILY, params=params, seed=generation,
                    size=len(points), source=SEARCH_FAMILY)
        return case, parent.root


def _configs_by_dim(tasks: list[Task]) -> dict[int, tuple[AlgorithmConfig, ...]]:
    """Every config the plan runs on cases of each dimension, in first-seen order."""
    out: dict[int, dict[AlgorithmConfig, None]] = {}
    for task in tasks:
        out.setdefault(task.case.dim, {}).update(dict.fromkeys(task.configs))
    return {dim: tuple(found) for dim, found in out.items()}


def _serial(batch: list[Task], runner: RunnerOptions) -> list[list[ResultRow]]:
    """``--workers 0``: the batch in this process (no isolation), rows per task in config order."""
    found: dict[tuple[str, str], ResultRow] = {}
    execute(batch, runner, lambda row: found.__setitem__((str(row["case_id"]), str(row["config"])), row))
    return [[found[(t.case.case_id, c.label)] for c in t.configs if (t.case.case_id, c.label) in found]
            for t in batch]
