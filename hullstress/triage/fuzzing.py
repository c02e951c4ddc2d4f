"""Fuzz mode: Hypothesis drives the generator families against one algorithm config.

Each example is a case built from a registered family through
:func:`hullstress.strategies.family_cases`: Hypothesis draws the family, one
of its swept parameter variants, the seed, the size and a metamorphic
transform or none, then optionally rounds every coordinate to a few mantissa
bits.  The search calls ``hypothesis.target`` with the checker's violation
magnitude (in DISTround units), so it climbs toward worse failures, and on
a failure Hypothesis shrinks the draw (fewer points, simpler family and
parameters, smaller seed).  The example database (``database``) remembers
failures between runs and replays them first (Hypothesis saves only unseeded
runs to it; see :func:`fuzz`).  Every failure found is then
shrunk once more over its points with :func:`~hullstress.triage.shrink`.

Several searches run in a row, each excluding the failed checks already
found, so one run can report distinct failures of the same config.
"""

from __future__ import annotations

import random
import time
import unittest
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from .._registry import get_algorithm, get_generator, generators
from ..case import Case
from ..config import AlgorithmConfig, single_config
from ..errors import UsageError
from ..results import ResultRow
from .oracle import run_config
from .shrink import ShrinkResult, shrink
from .signature import Signature, signature_of
from .simplify import round_mantissa

__all__ = ["FuzzFinding", "FuzzResult", "fuzz", "case_strategy"]


@dataclass(frozen=True)
class FuzzFinding:
    """One distinct failure found by fuzzing.

    Attributes
    ----------
    signature : Signature
    case : Case
        Hypothesis's minimal example.
    row : ResultRow
        Its failing row.
    shrunk : ShrinkResult or None
        The point-level shrink of ``case`` (None when turned off).
    """

    signature: Signature
    case: Case
    row: ResultRow
    shrunk: ShrinkResult | None


@dataclass
class FuzzResult:
    """What a fuzz run did: the findings and how many examples it tried."""

    config: AlgorithmConfig
    findings: list[FuzzFinding] = field(default_factory=list)
    examples: int = 0
    seconds: float = 0.0
    families: tuple[str, ...] = ()
    seed: int | None = None


def case_strategy(dim: int, families: Sequence[str] | None = None, *, min_size: int = 4,
                  max_size: int = 64) -> Any:
    """A Hypothesis strategy of :class:`Case` objects for fuzzing ``dim``-D algorithms.

    The families come through :func:`hullstress.strategies.family_cases`
    (family, variant, seed, size and one metamorphic transform or none, all
    shrinking toward the simplest); on top, every coordinate may be rounded to
    a few mantissa bits, which snaps points onto coarse grids (more
    duplicates, collinear and coplanar subsets).

    Parameters
    ----------
    dim : {2, 3}
    families : sequence of str, optional
        Family names (default: every registered family but ``bad-input``).
    min_size, max_size : int
        Bounds on the point count (a family's own minimum wins).

    Returns
    -------
    SearchStrategy of Case
    """
    from hypothesis import strategies as st

    from ..strategies import family_cases

    base = family_cases(dim, families, min_size=min_size, max_size=max_size, transforms=True)

    @st.composite
    def cases(draw: Any) -> Case:
        case = draw(base)
        bits = draw(st.sampled_from([None, 1, 2, 4, 8, 16, 24]))
        if bits is None:
            return case
        return Case(points=round_mantissa(case.points, bits), dim=case.dim, family=case.family,
                    params={**case.params, "fuzz_bits": bits}, seed=case.seed, size=case.size, source="fuzz")

    return cases()


def _search(strategy: Any, condition: Any, key: bytes, *, max_examples: int, database: Any,
            seed: int | None, search: int) -> Case | None:
    """One ``hypothesis.find``: the minimal example satisfying ``condition``, or None.

    Hypothesis neither reads nor saves its example database in a seeded run,
    so with both a seed and a database the stored failures are replayed first
    (an unseeded, replay-only pass), then the seeded search runs; a failure the
    seeded search finds is kept in the failure folders, not in the database.
    """
    from hypothesis import HealthCheck, Phase, find, settings
    from hypothesis.errors import NoSuchExample

    common = dict(deadline=None, suppress_health_check=list(HealthCheck))
    try:
        if seed is None:
            return find(strategy, condition, settings=settings(max_examples=max_examples, database=database,
                                                               **common), database_key=key)
        if database is not None and next(iter(database.fetch(key)), None) is not None:
            try:
                return find(strategy, condition, database_key=key, settings=settings(
                    max_examples=max_examples, database=database, phases=[Phase.reuse, Phase.shrink], **common))
            except (NoSuchExample, unittest.SkipTest):  # nothing stored fails any more
                pass
        return find(strategy, condition, settings=settings(max_examples=max_examples, database=None, **common),
                    random=random.Random(seed + search))
    except NoSuchExample:
        return None


def _default_config(algorithm: str, sphere: str, eps: str | None) -> AlgorithmConfig:
    return single_config(get_algorithm(algorithm), sphere, eps)


def fuzz(
    algorithm: str,
    *,
    sphere: str = "off",
    eps: str | None = None,
    families: Sequence[str] = (),
    max_examples: int = 200,
    database: str | Path | None = None,
    seed: int | None = None,
    timeout: float | None = None,
    max_findings: int = 3,
    min_size: int = 4,
    max_size: int = 64,
    shrink_budget_seconds: float = 10.0,
    isolate: bool | None = None,
) -> FuzzResult:
    """Search for inputs on which ``algorithm`` fails, with Hypothesis.

    Parameters
    ----------
    algorithm : str
        A registered algorithm.
    sphere : {"off", "on"}
    eps : {"scaled", "fixed"}, optional
        Ignored for algorithms without ``eps`` (default: ``scaled`` for in-house
        algorithms, not passed to plug-ins).
    families : sequence of str
        Generator families to draw from (default: every family for the algorithm's dim).
    max_examples : int
        Hypothesis's example budget per search.
    database : path, optional
        A directory for Hypothesis's example database (failures are replayed
        from it first next time); None keeps nothing.
    seed : int, optional
        Seeds Hypothesis's random choices: the same seed gives the same search.
        Hypothesis does not save seeded runs to the database (stored failures
        are still replayed first); without a seed the search is random and
        every failure found is saved.
    timeout : float, optional
        Per-call timeout of isolated calls.
    max_findings : int
        Stop after this many distinct failed checks.
    min_size, max_size : int
        Point counts requested from the families.
    shrink_budget_seconds : float
        Point-level shrink budget per finding (0 turns it off).
    isolate : bool, optional
        See :func:`~hullstress.triage.oracle.run_config`.

    Returns
    -------
    FuzzResult

    Examples
    --------
    >>> res = fuzz("my-hull", families=["coplanar-grid"], max_examples=50, seed=0)  # doctest: +SKIP
    >>> [f.signature.check for f in res.findings]  # doctest: +SKIP
    ['containment']
    """
    from hypothesis import target
    from hypothesis.database import DirectoryBasedExampleDatabase
    from hypothesis.errors import InvalidArgument

    if max_examples < 1:
        raise UsageError(f"max_examples must be at least 1, got {max_examples}")
    config = _default_config(algorithm, sphere, eps)
    dim = config.spec.dim
    if families:
        specs = [get_generator(name) for name in dict.fromkeys(families)]  # unknown names raise, listing valid ones
        specs = [s for s in specs if dim in s.dims]
        if not specs:
            raise UsageError(f"--generator: none of {sorted(families)} supports {dim}D points "
                             f"(algorithm {algorithm!r} is {dim}D)")
    else:
        specs = [s for s in generators(dim) if s.name != "bad-input"]
        if not specs:
            raise UsageError(f"no generator family supports {dim}D points")
    try:
        strategy = case_strategy(dim, [s.name for s in specs], min_size=min_size, max_size=max_size)
    except InvalidArgument as exc:
        raise UsageError(f"fuzz: {exc}") from None
    db = DirectoryBasedExampleDatabase(str(database)) if database is not None else None
    result = FuzzResult(config=config, families=tuple(s.name for s in specs), seed=seed)
    start = time.perf_counter()
    found: dict[str, FuzzFinding] = {}
    rows: dict[str, ResultRow] = {}

    def condition(case: Case) -> bool:
        result.examples += 1
        row = run_config(case, config, timeout=timeout, isolate=isolate)
        violation = row.get("max_violation")
        if violation is not None and np.isfinite(violation):
            target(float(violation), label="max_violation (DISTround units)")
        sig = signature_of(row)
        if sig is None or sig.check in found:
            return False
        rows[case.case_id] = row
        return True

    for search in range(max_findings):
        key = f"hullstress-fuzz|{config.label}|{','.join(result.families)}|{min_size}-{max_size}|{search}".encode()
        minimal = _search(strategy, condition, key, max_examples=max_examples, database=db, seed=seed,
                          search=search)
        if minimal is None:
            break
        row = rows.get(minimal.case_id) or run_config(minimal, config, timeout=timeout, isolate=isolate)
        sig = signature_of(row)
        if sig is None:  # flaky: failed during the search, passes now
            break
        shrunk = None
        if shrink_budget_seconds > 0:
            shrunk = shrink(minimal, config, sig, budget_seconds=shrink_budget_seconds, timeout=timeout,
                            isolate=isolate)
        found[sig.check] = FuzzFinding(signature=sig, case=minimal, row=row, shrunk=shrunk)
    result.findings = list(found.values())
    result.seconds = time.perf_counter() - start
    return result
