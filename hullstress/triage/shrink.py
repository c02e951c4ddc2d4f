"""Shrinking one failing case to a small point set that fails the same way.

Three passes, each change kept only when the failure survives it (same
config, same failed check, see :func:`~hullstress.triage.oracle.fails_same_way`):

An ``error`` keeps its exception type too (the first call fixes it), and a
harness-internal error (the checker raising) never counts as the failure.

1. **ddmin over rows** (:func:`~hullstress.triage.ddmin.ddmin`): drop points.
2. **Coordinate simplification**: scale by a power of two so the largest
   coordinate lies in [1, 2) (exact); round every coordinate to the fewest
   mantissa bits that keep the failure; then, coordinate by coordinate, try
   0, the nearest integer and fewer bits.
3. **ddmin again**: simpler coordinates sometimes make more points redundant.

The work is bounded by ``budget_seconds`` and ``max_calls``; when either runs
out the best case found so far is returned, marked ``exhausted``.
"""

from __future__ import annotations

import time

import numpy as np

from ..case import Case, points_digest
from ..config import AlgorithmConfig
from ..options import DEFAULTS
from ..results import ResultRow
from .ddmin import ddmin
from .oracle import IsolationUnavailable, error_kind, run_config, same_failure
from .records import ShrinkResult
from .signature import Signature, signature_of
from .simplify import coordinate_candidates, mantissa_bits, pow2_normalize, round_mantissa

__all__ = ["ShrinkResult", "shrink", "derive_case"]

#: Global mantissa widths tried, fewest first.
_GLOBAL_BITS = (1, 2, 3, 4, 6, 8, 12, 16, 20, 24, 32, 40, 48)


class _Stop(Exception):
    """The shrink budget (time or calls) is spent."""


def derive_case(original: Case, points: np.ndarray) -> Case:
    """A case with new points and the original's provenance plus ``shrunk_from``."""
    params = dict(original.params)
    params.setdefault("shrunk_from", original.case_id)
    return Case(points=points, dim=original.dim, family=original.family, params=params,
                seed=original.seed, size=original.size, source="shrink")


class _Oracle:
    """Counts, caches and budgets the judged calls of one shrink."""

    def __init__(self, original: Case, config: AlgorithmConfig, signature: Signature, *,
                 deadline: float, max_calls: int, timeout: float | None, isolate: bool | None,
                 qhull_options: str | None = None) -> None:
        self.original, self.config, self.signature = original, config, signature
        self.deadline, self.max_calls = deadline, max_calls
        self.timeout, self.isolate = timeout, isolate
        self.qhull_options = qhull_options
        self.calls = 0
        self.cache: dict[str, ResultRow | None] = {}
        self.best: tuple[np.ndarray, ResultRow] | None = None
        self.error: str | None = None  # the original's exception type, fixed by the first call

    def __call__(self, points: np.ndarray) -> bool:
        key = points_digest(points)
        if key in self.cache:
            cached = self.cache[key]
            if cached is not None:
                self.best = (np.array(points), cached)
            return cached is not None
        if self.calls >= self.max_calls or time.perf_counter() >= self.deadline:
            raise _Stop()
        case = derive_case(self.original, points)
        row = run_config(case, self.config, timeout=self.timeout, isolate=self.isolate,
                         dangerous=self.signature.check in ("timeout", "crash"), qhull_options=self.qhull_options)
        self.calls += 1
        hit = same_failure(row, self.signature, error=self.error)
        if hit and self.error is None and self.signature.check == "error":
            self.error = error_kind(row)
        self.cache[key] = row if hit else None
        if hit:
            self.best = (np.array(points), row)
        return hit

    def row_for(self, points: np.ndarray) -> ResultRow | None:
        return self.cache.get(points_digest(points))


def shrink(
    case: Case,
    config: AlgorithmConfig,
    signature: Signature | None = None,
    *,
    budget_seconds: float = 10.0,
    max_calls: int = DEFAULTS.shrink_max_calls,
    timeout: float | None = None,
    isolate: bool | None = None,
    simplify: bool = True,
    qhull_options: str | None = None,
) -> ShrinkResult:
    """Minimise ``case`` to a small point set on which ``config`` fails the same way.

    Parameters
    ----------
    case : Case
        A failing case.
    config : AlgorithmConfig
    signature : Signature, optional
        The failure to keep; default: whatever ``case`` fails with now.
    budget_seconds : float
        Wall-time cap for the whole shrink.
    max_calls : int
        Cap on judged calls.
    timeout : float, optional
        Per-call timeout of isolated calls (reuse the sweep's for timeouts).
    isolate : bool, optional
        See :func:`~hullstress.triage.oracle.run_config`.
    simplify : bool
        Run the coordinate simplification passes after ddmin.
    qhull_options : str, optional
        Qhull options tried first for each call's reference (the run's ``--qhull-options``).

    Returns
    -------
    ShrinkResult

    Examples
    --------
    >>> res = shrink(case, AlgorithmConfig("my-hull"), budget_seconds=5)  # doctest: +SKIP
    >>> res.original_size, res.minimal_size  # doctest: +SKIP
    (500, 4)
    """
    start = time.perf_counter()
    oracle_sig = signature
    if oracle_sig is None:
        row = run_config(case, config, timeout=timeout, isolate=isolate, qhull_options=qhull_options)
        oracle_sig = signature_of(row)
        if oracle_sig is None:
            return _unshrunk(case, Signature(config.algorithm, config.sphere, config.eps, "none", case.family),
                             start, 1, f"the case does not fail ({row.status})", row=None)
    oracle = _Oracle(case, config, oracle_sig, deadline=start + budget_seconds,
                     max_calls=max_calls, timeout=timeout, isolate=isolate, qhull_options=qhull_options)
    steps: list[str] = []
    try:
        if not oracle(case.points):
            return _unshrunk(case, oracle_sig, start, oracle.calls,
                             "the failure did not reproduce on a re-run (flaky or resource-dependent)")
    except IsolationUnavailable as exc:
        return _unshrunk(case, oracle_sig, start, oracle.calls, f"not shrunk: {exc}")
    except _Stop:
        return _unshrunk(case, oracle_sig, start, oracle.calls, "not shrunk: budget spent before the first call")
    points = np.array(case.points)
    exhausted = False
    try:
        points = _ddmin_pass(points, oracle, steps)
        if simplify and points.ndim == 2:
            points = _simplify_pass(points, oracle, steps)
            points = _ddmin_pass(points, oracle, steps)
    except _Stop:
        exhausted = True
        if oracle.best is not None and len(oracle.best[0]) <= len(points):
            points = oracle.best[0]
    minimal = derive_case(case, points)
    row = oracle.row_for(points)
    return ShrinkResult(
        case=minimal, original=case, signature=oracle_sig, original_size=case.n_points,
        minimal_size=minimal.n_points, calls=oracle.calls, seconds=time.perf_counter() - start,
        reproduced=True, exhausted=exhausted, row=row, steps=tuple(steps),
        note="budget spent: the case is smaller but may not be minimal" if exhausted else "",
    )


def _unshrunk(case: Case, sig: Signature, start: float, calls: int, note: str,
              row: ResultRow | None = None) -> ShrinkResult:
    return ShrinkResult(case=case, original=case, signature=sig, original_size=case.n_points,
                        minimal_size=case.n_points, calls=calls, seconds=time.perf_counter() - start,
                        reproduced=False, row=row, note=note)


def _ddmin_pass(points: np.ndarray, oracle: _Oracle, steps: list[str]) -> np.ndarray:
    """Drop rows.  On a spent budget the oracle's ``best`` holds the last accepted subset."""
    n = len(points)
    if n <= 1:
        return points
    keep = ddmin(n, lambda subset: oracle(points[list(subset)]))
    if len(keep) < n:
        steps.append(f"ddmin: {n} -> {len(keep)} points")
    return points[list(keep)]


def _simplify_pass(points: np.ndarray, oracle: _Oracle, steps: list[str]) -> np.ndarray:
    def accept(candidate: np.ndarray, what: str) -> bool:
        nonlocal points
        if np.array_equal(candidate, points, equal_nan=True):
            return False
        if oracle(candidate):
            points = candidate
            steps.append(what)
            return True
        return False

    scaled = pow2_normalize(points)
    if scaled is not None:
        accept(scaled, "scaled by a power of two into [1, 2)")
    width = int(mantissa_bits(points).max()) if points.size else 0
    for bits in _GLOBAL_BITS:
        if bits >= width:
            break
        if accept(round_mantissa(points, bits), f"all coordinates rounded to {bits} mantissa bits"):
            break
    changed = 0
    for i in range(points.shape[0]):
        for j in range(points.shape[1]):
            for value in coordinate_candidates(float(points[i, j])):
                candidate = points.copy()
                candidate[i, j] = value
                if accept(candidate, ""):
                    steps.pop()
                    changed += 1
                    break
    if changed:
        steps.append(f"{changed} coordinates simplified one by one (0, integers, fewer bits)")
    return points
