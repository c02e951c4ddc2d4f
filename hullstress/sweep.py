"""A sweep: build the cases, run every config on them, collect one table.

The case set depends only on the options (profile, generators, sizes, seed,
points files): every case's seed is derived from the base seed and the case's
provenance by hashing, so it does not depend on the order cases are built or
run in, nor on the number of workers.
"""

from __future__ import annotations

import hashlib
import os
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

__all__ = ["SweepOptions", "SweepResult", "build_cases", "build_tasks", "case_seed", "check_sizes", "run_sweep",
           "sort_table"]


@dataclass(frozen=True)
class SweepOptions:
    """Everything that decides which cases and configs a sweep runs (see ``run --help``)."""

    profile: str = "quick"
    algorithms: tuple[str, ...] = ()
    generators: tuple[str, ...] = ()
    sphere: str = "both"
    eps: str = "both"
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
        return int(self.table["status"].isin(["fail", "error", "timeout", "crash"]).sum())


def case_seed(base_seed: int, family: str, params_json: str, dim: int, size: int | None, replicate: int) -> int:
    """A 63-bit seed for one case, from the base seed and the case's provenance."""
    key = f"{base_seed}|{family}|{params_json}|{dim}|{size}|{replicate}".encode()
    return int.from_bytes(hashlib.sha256(key).digest()[:8], "big") >> 1


def _selected_generators(options: SweepOptions) -> list[GeneratorSpec]:
    if options.generators:
        return [get_generator(name) for name in dict.fromkeys(options.generators) if not is_rbox_spec(name)]
    if options.points_files:
        return []  # files given and no --generator: only the files run
    return generators()


def _sizes_for(options: SweepOptions, dim: int) -> tuple[int, ...]:
    if options.sizes is not None:
        return options.sizes
    return options.profile_spec.sizes[dim]


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
    wanted = [(n, d, f"--sizes {n}") for d in dims for n in _sizes_for(options, d)]
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
        In a deterministic order (family, dim, variant, size, replicate, then files).
    skipped : list of str
        One line per (family, params, size) the generator declined, with its reason.
    """
    from .io import read_points

    profile = options.profile_spec
    cases: list[Case] = []
    skipped: list[str] = []
    for spec in _selected_generators(options):
        for dim in spec.dims:
            if dim not in dims:
                continue
            for variant in spec.variants:
                params = {**spec.defaults, **variant}
                params_json = canonical_params(params)
                sizes: tuple[int | None, ...] = (None,) if spec.fixed_size else _sizes_for(options, dim)
                for size in sizes:
                    for rep in range(profile.replicates):
                        seed = case_seed(options.seed, spec.name, params_json, dim, size, rep)
                        rng = np.random.default_rng(seed)
                        try:
                            pts = spec.func(rng, size if size is not None else 0, dim=dim, **params)
                        except ValueError as exc:
                            skipped.append(f"{spec.name} dim={dim} {params_json} n={size}: {exc}")
                            continue
                        cases.append(
                            Case(points=pts, dim=dim, family=spec.name, params=params,
                                 seed=seed, size=size, source="generator")
                        )
    cases.extend(_rbox_cases(options))
    for path in dict.fromkeys(options.points_files):
        pts = read_points(path)
        cases.append(Case.from_points(pts, family="file", params={"file": os.path.basename(path)}, source=str(path)))
    # Identical provenance and points give the same id: keep the first.
    unique = list({c.case_id: c for c in reversed(cases)}.values())[::-1]
    return unique, skipped


def build_tasks(options: SweepOptions) -> tuple[list[Task], list[Case], dict[int, list[AlgorithmConfig]], list[str]]:
    """Cases crossed with the configs of their dimension, as runner tasks."""
    if options.algorithms:
        specs = [get_algorithm(name) for name in dict.fromkeys(options.algorithms)]
    else:
        specs = algorithms()
    configs = {d: expand_configs([s for s in specs if s.dim == d], sphere=options.sphere, eps=options.eps) for d in (2, 3)}
    dims = [d for d in (2, 3) if configs[d]]
    check_sizes(options, dims)
    cases, skipped = build_cases(options, dims=dims)
    for case in cases:
        if case.dim not in dims:
            skipped.append(f"{case.source}: no selected algorithm takes {case.dim}D points")
    tasks = [
        Task(index=i, case=c, configs=tuple(configs[c.dim]))
        for i, c in enumerate(c for c in cases if c.dim in dims)
    ]
    return tasks, [t.case for t in tasks], configs, skipped


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
) -> SweepResult:
    """Build the cases and run every config on them.

    Parameters
    ----------
    options : SweepOptions
    on_row : callable, optional
        Called with each row as it arrives (for streaming to disk).
    tasks : list of Task, optional
        Pre-built tasks (from :func:`build_tasks`), to skip rebuilding them.

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

    stats = execute(tasks, options.runner_options(), collect)
    table = sort_table(to_frame(rows), [c.case_id for c in cases])
    return SweepResult(table=table, cases=cases, configs=configs, stats=stats, skipped=skipped)
