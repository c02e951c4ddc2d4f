"""A sweep: build the cases, run every config on them, collect one table.

The case set depends only on the options (profile, generators, sizes, seed,
transforms, points files): every case's seed is derived from the base seed
and the case's provenance by hashing, so it does not depend on the order
cases are built or run in, nor on the number of workers.

Sizes: an explicit ``--sizes`` runs every family variant at every size.  A
profile's own sizes are planned: the quick profile gives each variant one of
its sizes, rotating through them, so that every family meets several sizes
at the cost of one; the nightly profile crosses every variant with every
size.  A profile may cap the size an algorithm is given (the O(n^3) seed at
thousands of points would spend the night on one case): those calls are
listed among the cases not run.

Schedule: the runner receives the tasks round robin over families, smallest
cases first, so a ``--time-budget`` that ends the sweep early still touches
every family; the table itself is sorted in build order.
"""

from __future__ import annotations

import dataclasses
import hashlib
import os
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import numpy as np
import pandas as pd

from ._registry import GeneratorSpec, algorithms, get_algorithm, get_generator, generators
from .case import Case, canonical_params
from .config import AlgorithmConfig, expand_configs
from .errors import UsageError
from .options import DEFAULTS, Profile, case_memory_bytes, get_profile, memory_ceiling_bytes
from .rbox import RBOX_SEED_MODULUS, is_rbox_spec, parse_rbox_spec, rbox_count, rbox_points
from .results import ResultRow, to_frame
from .runner import ExecutionStats, RunnerOptions, Task, execute
from .records import FAILED_STATUSES

__all__ = ["SweepOptions", "SweepResult", "build_cases", "build_tasks", "case_seed", "check_sizes", "run_sweep",
           "sort_table"]


@dataclass(frozen=True)
class SweepOptions:
    """Everything that decides which cases and configs a sweep runs (see ``run --help``)."""

    profile: str = "quick"
    algorithms: tuple[str, ...] = ()
    generators: tuple[str, ...] = ()
    #: None: each algorithm's default variants (see hullstress.config.default_variants).
    sphere: str | None = None
    eps: str | None = None
    sizes: tuple[int, ...] | None = None
    seed: int = 0
    points_files: tuple[str, ...] = ()
    workers: int | None = None
    timeout: float | None = None
    time_budget: float | None = None
    qhull: bool = True
    #: Dask scheduler address; None runs on this machine.
    scheduler: str | None = None
    #: Address-space limit per isolated worker in MiB (0 or None: none).
    memory_limit_mb: float | None = DEFAULTS.memory_limit_mb
    #: Metamorphic transforms (generators.transforms.TRANSFORMS): each adds a transformed copy of every case.
    transforms: tuple[str, ...] = ()
    #: Qhull options tried first for the reference hull (None: scipy's default, then the fallbacks).
    qhull_options: str | None = None

    @property
    def profile_spec(self) -> Profile:
        return get_profile(self.profile)

    def runner_options(self) -> RunnerOptions:
        workers = self.workers if self.workers is not None else (os.cpu_count() or 1)
        timeout = self.timeout if self.timeout is not None else self.profile_spec.timeout
        return RunnerOptions(workers=workers, timeout=timeout, time_budget=self.time_budget, qhull=self.qhull,
                             scheduler=self.scheduler, memory_limit_mb=self.memory_limit_mb,
                             qhull_options=self.qhull_options)


@dataclass
class SweepResult:
    """The table of one sweep plus what happened along the way."""

    table: pd.DataFrame
    cases: list[Case]
    configs: dict[int, list[AlgorithmConfig]]
    stats: ExecutionStats
    skipped: list[str] = field(default_factory=list)

    @property
    def n_failed(self) -> int:
        return int(self.table["status"].isin(FAILED_STATUSES).sum())


def case_seed(base_seed: int, family: str, params_json: str, dim: int, size: int | None, replicate: int) -> int:
    """A 63-bit seed for one case, from the base seed and the case's provenance."""
    key = f"{base_seed}|{family}|{params_json}|{dim}|{size}|{replicate}".encode()
    return int.from_bytes(hashlib.sha256(key).digest()[:8], "big") >> 1


def _selected_families(options: SweepOptions) -> list[tuple[GeneratorSpec, tuple[dict, ...]]]:
    """Each selected family with the parameter sets to run: all its variants, or the one a spec names.

    ``--generator near-coplanar`` runs every variant; ``--generator
    near-coplanar:surface=plane`` runs exactly that variant (over the family's
    defaults).  Specs are parsed and validated by :func:`generators.parse_spec`.
    """
    if not options.generators:
        if options.points_files:
            return []  # files given and no --generator: only the files run
        return [(spec, tuple({**spec.defaults, **v} for v in spec.variants)) for spec in generators()]
    from generators import parse_spec

    out: dict[str, tuple[GeneratorSpec, list[dict]]] = {}
    for text in dict.fromkeys(options.generators):
        if is_rbox_spec(text):
            continue  # rbox:'...' specs are Qhull's generator, handled by _rbox_cases
        name, params = parse_spec(text)
        spec = get_generator(name)
        runs = [{**spec.defaults, **params}] if params else [{**spec.defaults, **v} for v in spec.variants]
        _, chosen = out.setdefault(name, (spec, []))
        chosen.extend(r for r in runs if r not in chosen)
    return [(spec, tuple(runs)) for spec, runs in out.values()]


def _sizes_for(options: SweepOptions, dim: int, family: str, variant_index: int) -> tuple[tuple[int, ...], bool]:
    """The sizes of one family variant, and whether they are alternatives (rotation) or all to run."""
    if options.sizes is not None:
        return options.sizes, False
    profile = options.profile_spec
    sizes = profile.sizes[dim]
    if not profile.rotate_sizes or len(sizes) <= 1:
        return sizes, False
    # Rotate through the sizes by variant, offset per family and dimension, so that
    # families with one variant do not all land on the same size.  The other sizes
    # follow as fall-backs for a variant that cannot be made that small or large.
    offset = int.from_bytes(hashlib.sha256(f"{family}|{dim}".encode()).digest()[:2], "big")
    first = (variant_index + offset) % len(sizes)
    return sizes[first:] + sizes[:first], True


def _transformed(case: Case, name: str) -> Case:
    """A metamorphic copy of ``case``: the same hull, other coordinates or order (provenance says which)."""
    from generators import apply_transforms

    moved = apply_transforms(case.points, name, seed=case.seed)
    return Case(points=moved.points, dim=case.dim, family=case.family,
                params={**case.params, "transform": name}, seed=case.seed, size=case.size, source=case.source)


def check_sizes(options: SweepOptions, dims: Sequence[int] = (2, 3)) -> None:
    """Refuse, before anything is allocated, sizes whose cases would not fit in memory.

    Raises
    ------
    UsageError
        Naming the size, the estimate and the limit it exceeds.
    """
    ceiling, what = memory_ceiling_bytes(options.memory_limit_mb)
    if ceiling is None:
        return
    sizes = {d: options.sizes if options.sizes is not None else tuple(options.profile_spec.sizes[d]) for d in dims}
    wanted = [(n, d, f"--sizes {n}" if options.sizes is not None else f"profile {options.profile}'s size {n}")
              for d in dims for n in sizes[d]]
    for spec in options.generators:
        if is_rbox_spec(spec):
            n = rbox_count(parse_rbox_spec(spec))
            if n is not None:
                wanted.append((n, 3, f"--generator {spec!r}"))
    for n, dim, where in wanted:
        need = case_memory_bytes(n, dim)
        if need > ceiling:
            raise UsageError(
                f"{where}: a case of {n} {dim}D points needs about {need / 2**30:.3g} GiB while it is generated, "
                f"hulled and checked ({DEFAULTS.case_bytes_per_coordinate} bytes per coordinate), more than "
                f"{what}; use smaller sizes or a larger --memory-limit")


def _rbox_cases(options: SweepOptions) -> list[Case]:
    """One case per replicate of every ``rbox:ARGS`` generator, seeded from the base seed."""
    cases = []
    for spec in dict.fromkeys(g for g in options.generators if is_rbox_spec(g)):
        args = parse_rbox_spec(spec)
        for rep in range(options.profile_spec.replicates):
            seed = case_seed(options.seed, "rbox", args, 0, None, rep) % RBOX_SEED_MODULUS
            pts = rbox_points(args, seed)
            cases.append(Case(points=pts, dim=pts.shape[1], family="rbox", params={"args": args}, seed=seed,
                              size=len(pts), source=f"rbox {args} t{seed}"))
    return cases


def build_cases(options: SweepOptions, dims: Sequence[int] = (2, 3)) -> tuple[list[Case], list[str]]:
    """Generate the sweep's cases.

    Returns
    -------
    cases : list of Case
        In a deterministic order (family, dim, variant, size, replicate, then
        files, then each transform's copies in the same order).
    skipped : list of str
        One line per (family, params, size) the generator declined, with its reason.
    """
    from .io import read_points

    profile = options.profile_spec
    cases: list[Case] = []
    skipped: list[str] = []
    for spec, runs in _selected_families(options):
        for dim in spec.dims:
            if dim not in dims:
                continue
            for index, params in enumerate(runs):
                params_json = canonical_params(params)
                sizes: tuple[int | None, ...]
                sizes, alternatives = ((None,), False) if spec.fixed_size else _sizes_for(
                    options, dim, spec.name, index)
                refused: list[str] = []
                for size in sizes:
                    made = []
                    for rep in range(profile.replicates):
                        seed = case_seed(options.seed, spec.name, params_json, dim, size, rep)
                        try:
                            pts = spec.func(np.random.default_rng(seed), size if size is not None else 0,
                                            dim=dim, **params)
                        except ValueError as exc:
                            refused.append(f"{spec.name} dim={dim} {params_json} n={size}: {exc}")
                            break
                        made.append(Case(points=pts, dim=dim, family=spec.name, params=params,
                                         seed=seed, size=size, source="generator"))
                    cases.extend(made)
                    if alternatives and made:
                        refused = []  # a fall-back size worked: the refusals are not worth reporting
                        break
                skipped.extend(refused)
    cases.extend(_rbox_cases(options))
    for path in dict.fromkeys(options.points_files):
        pts = read_points(path)
        cases.append(Case.from_points(pts, family="file", params={"file": os.path.basename(path)}, source=str(path)))
    if options.transforms:
        base = [c for c in cases if c.points.ndim == 2 and c.points.shape[1:] == (c.dim,)]
        for name in dict.fromkeys(options.transforms):
            cases.extend(_transformed(c, name) for c in base)
    # Identical provenance and points give the same id: keep the first.
    unique = list({c.case_id: c for c in reversed(cases)}.values())[::-1]
    return unique, skipped


def _schedule(cases: Sequence[Case]) -> list[Case]:
    """Round robin over families, each family's cases smallest first (ties: build order)."""
    by_family: dict[str, list[tuple[int, int, Case]]] = {}
    for order, case in enumerate(cases):
        by_family.setdefault(case.family, []).append((case.n_points, order, case))
    queues = [sorted(items, key=lambda t: (t[0], t[1])) for items in by_family.values()]
    out: list[Case] = []
    for rank in range(max((len(q) for q in queues), default=0)):
        out.extend(q[rank][2] for q in queues if rank < len(q))
    return out


def build_tasks(options: SweepOptions) -> tuple[list[Task], list[Case], dict[int, list[AlgorithmConfig]], list[str]]:
    """Cases crossed with the configs of their dimension, as runner tasks in schedule order.

    Returns
    -------
    tasks : list of Task
        Round robin over families, smallest cases first (see :func:`_schedule`).
    cases : list of Case
        Build order: the order of the results table.
    configs : dict of int to list of AlgorithmConfig
        Per dimension.
    skipped : list of str
        Cases not generated, and calls above a profile's size cap.
    """
    if options.algorithms:
        specs = [get_algorithm(name) for name in dict.fromkeys(options.algorithms)]
    else:
        specs = algorithms()
    configs = {d: expand_configs([s for s in specs if s.dim == d], sphere=options.sphere, eps=options.eps)
               for d in (2, 3)}
    dims = [d for d in (2, 3) if configs[d]]
    check_sizes(options, dims)
    cases, skipped = build_cases(options, dims=dims)
    for case in cases:
        if case.dim not in dims:
            skipped.append(f"{case.source}: no selected algorithm takes {case.dim}D points")
    caps = options.profile_spec.max_points if options.sizes is None else {}
    capped: dict[str, int] = {}
    tasks = []
    kept = [c for c in cases if c.dim in dims]
    for case in _schedule(kept):
        run = []
        for config in configs[case.dim]:
            cap = caps.get(config.algorithm)
            if cap is not None and case.n_points > cap:
                capped[config.algorithm] = capped.get(config.algorithm, 0) + 1
                continue
            run.append(config)
        if run:
            tasks.append(Task(index=len(tasks), case=case, configs=tuple(run)))
    for name, count in sorted(capped.items()):
        skipped.append(f"{name}: {count} calls on cases above the profile's cap of {caps[name]} points not run")
    in_tasks = {t.case.case_id for t in tasks}
    return tasks, [c for c in kept if c.case_id in in_tasks], configs, skipped


def _execute_with_budget(tasks: Sequence[Task], runner: RunnerOptions, collect: Callable[[ResultRow], None],
                         on_idle: Callable[[], None] | None = None) -> ExecutionStats:
    """Run each family's first (smallest) case whatever the budget, then the rest while it lasts.

    A time budget spends itself round robin over the schedule, but a budget
    shorter than one round would leave the last families with nothing; the
    first round is therefore never cut, and the budget counts from its start.
    """
    seen: set[str] = set()
    first, rest = [], []
    for task in tasks:
        (rest if task.case.family in seen else first).append(task)
        seen.add(task.case.family)
    start = time.perf_counter()
    # Only the last part's tail is the sweep's.
    stats = execute(first, dataclasses.replace(runner, time_budget=None), collect,
                    on_idle=None if rest else on_idle)
    remaining = runner.time_budget - (time.perf_counter() - start)
    if rest and remaining > 0:
        more = execute(rest, dataclasses.replace(runner, time_budget=remaining), collect, on_idle=on_idle)
        stats.merge_counts(more)
        stats.calls_done += more.calls_done
        stats.algorithm_seconds += more.algorithm_seconds
        stats.check_seconds += more.check_seconds
    elif rest:
        stats.budget_exhausted = True
    return stats.finish(time.perf_counter() - start)


def sort_table(df: pd.DataFrame, case_order: Sequence[str]) -> pd.DataFrame:
    """Rows in case order, then config label: independent of the order results arrived in."""
    order = {cid: i for i, cid in enumerate(case_order)}
    key = df["case_id"].map(order)
    return (
        df.assign(_case_order=key)
        .sort_values(["_case_order", "config"], kind="mergesort")
        .drop(columns="_case_order")
        .reset_index(drop=True)
    )


def run_sweep(
    options: SweepOptions,
    *,
    on_row: Callable[[ResultRow], None] | None = None,
    tasks: list[Task] | None = None,
    on_idle: Callable[[], None] | None = None,
) -> SweepResult:
    """Build the cases and run every config on them.

    Parameters
    ----------
    options : SweepOptions
    on_row : callable, optional
        Called with each row as it arrives (for streaming to disk).
    tasks : list of Task, optional
        Pre-built tasks (from :func:`build_tasks`), to skip rebuilding them.
    on_idle : callable, optional
        Called once when a core frees at the sweep's end (see
        :func:`hullstress.runner.execute`).

    Returns
    -------
    SweepResult
    """
    if tasks is None:
        tasks, cases, configs, skipped = build_tasks(options)
    else:
        cases = [t.case for t in tasks]
        configs = {}
        skipped = []
    rows: list[ResultRow] = []

    def collect(row: ResultRow) -> None:
        rows.append(row)
        if on_row is not None:
            on_row(row)

    runner = options.runner_options()
    if runner.time_budget is None:
        stats = execute(tasks, runner, collect, on_idle=on_idle)
    else:
        stats = _execute_with_budget(tasks, runner, collect, on_idle)
    table = sort_table(to_frame(rows), [c.case_id for c in cases])
    return SweepResult(table=table, cases=cases, configs=configs, stats=stats, skipped=skipped)
