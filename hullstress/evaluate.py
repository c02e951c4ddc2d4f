"""Running one algorithm config on one case and judging the result.

This is the unit of work every backend (in-process, process pool, Dask)
executes.  It is split in three so that a runner can isolate the untrusted
part:

* :func:`case_facts` — computed once per case: input validity, exact affine
  rank, Qhull's reference hull.  Trusted code.
* :func:`call_algorithm` — preprocessing (sphere variant, eps policy), the
  algorithm call itself, and the output contract.  Untrusted: this is what a
  runner puts behind a timeout in a separate process.
* :func:`judge` — status rules of DESIGN.md and the exact checker.  Trusted.

:func:`evaluate` chains the three in-process, for tests, shrinking and replay.
"""

from __future__ import annotations

import time
import warnings
from dataclasses import dataclass
from typing import Any

import numpy as np

from .case import Case
from .config import NO_EPS, AlgorithmConfig
from .contract import FaceSet, normalize_output
from .errors import ContractViolation, code_frame, one_line
from .results import ResultRow, make_row
from .tolerance import tolerance

__all__ = ["CaseFacts", "CallOutcome", "case_facts", "call_algorithm", "judge", "evaluate", "input_problem"]


@dataclass(frozen=True)
class CaseFacts:
    """What is known about a case before any algorithm runs.

    Attributes
    ----------
    invalid_input : str or None
        Why the points are not a valid input (wrong shape, non-finite), or None.
    affine_rank : int or None
        Exact affine rank (None when the input is invalid).
    degenerate : bool
        Affinely degenerate: rank below ``dim`` (collinear in 2D, coplanar in
        3D, fewer than dim+1 distinct points).  An exception here is ``rejected``.
    reference : object or None
        The checker's Qhull reference for the case (None when not requested or invalid).
    """

    invalid_input: str | None
    affine_rank: int | None
    degenerate: bool
    reference: Any = None


@dataclass(frozen=True)
class CallOutcome:
    """What the untrusted part produced.

    Attributes
    ----------
    kind : {"ok", "raised", "contract"}
        Returned a valid output, raised, or returned output breaking the contract.
    faces : ndarray or FaceSet or None
        The normalised output in the case's original indices (``kind == "ok"``).
    error : str
        ``TypeName: message`` or the contract violation, on one line.
    seconds : float
        Wall time of preprocessing plus the algorithm call.
    eps_value : float or None
        The tolerance passed as ``eps``.
    frame : str
        For ``raised``: the innermost frame of the code under test
        (:func:`~hullstress.errors.code_frame`), part of a failure's signature.
    """

    kind: str
    faces: np.ndarray | FaceSet | None = None
    error: str = ""
    seconds: float = 0.0
    eps_value: float | None = None
    frame: str = ""


def input_problem(points: np.ndarray, dim: int) -> str | None:
    """Why ``points`` is not a valid ``(n, dim)`` finite input, or None if it is."""
    if points.ndim != 2 or points.shape[1] != dim:
        return f"points have shape {points.shape}, expected (n, {dim})"
    if points.shape[0] == 0:
        return "no points"
    finite = np.isfinite(points)
    if not finite.all():
        bad = points[~finite]
        kind = "NaN" if np.isnan(bad).any() else "infinity"
        return f"points contain {kind} ({int((~finite).any(axis=1).sum())} rows)"
    return None


def case_facts(case: Case, *, qhull: bool = True) -> CaseFacts:
    """Compute a case's validity, exact affine rank and (optionally) Qhull reference."""
    from .checker import affine_rank, qhull_reference

    problem = input_problem(case.points, case.dim)
    if problem is not None:
        return CaseFacts(invalid_input=problem, affine_rank=None, degenerate=True, reference=None)
    rank = int(affine_rank(case.points))
    reference = qhull_reference(case.points) if qhull else None
    return CaseFacts(invalid_input=None, affine_rank=rank, degenerate=rank < case.dim, reference=reference)


def call_algorithm(case: Case, config: AlgorithmConfig) -> CallOutcome:
    """Run ``config`` on ``case``: sphere preprocessing, eps policy, the call, the output contract.

    Never raises for anything the algorithm does; the outcome records it.
    """
    spec = config.spec
    start = time.perf_counter()
    eps_value: float | None = None
    try:
        points = case.points
        index_map: np.ndarray | None = None
        if config.sphere == "on":
            from .sphere import sphere_project

            policy = config.eps if config.eps != NO_EPS else "scaled"
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                points, index_map = sphere_project(points, eps=tolerance(points, policy))
            points = np.ascontiguousarray(points, dtype=np.float64)
            points.setflags(write=False)
        kwargs: dict[str, Any] = {}
        if config.eps != NO_EPS:
            eps_value = tolerance(points, config.eps)
            kwargs["eps"] = eps_value
        with warnings.catch_warnings():
            # The code under test's own warnings (overflow in its cross products,
            # say) are not the harness's output; what it returns is judged instead.
            warnings.simplefilter("ignore")
            raw = spec.func(points, **kwargs)
    except (Exception, RecursionError) as exc:  # the code under test may raise anything
        return CallOutcome("raised", error=one_line(exc), seconds=time.perf_counter() - start, eps_value=eps_value,
                           frame=code_frame(exc.__traceback__, spec.module))
    seconds = time.perf_counter() - start
    try:
        faces = normalize_output(raw, len(points), case.dim)
    except ContractViolation as exc:
        return CallOutcome("contract", error=str(exc), seconds=seconds, eps_value=eps_value)
    if index_map is not None:
        index_map = np.asarray(index_map, dtype=np.int64)
        if isinstance(faces, FaceSet):
            faces = FaceSet(index_map[faces.indices], faces.offsets)
        else:
            faces = index_map[faces]
    return CallOutcome("ok", faces=faces, seconds=seconds, eps_value=eps_value)


def _is_empty(faces: np.ndarray | FaceSet) -> bool:
    return faces.n_faces == 0 if isinstance(faces, FaceSet) else len(faces) == 0


def judge(case: Case, config: AlgorithmConfig, outcome: CallOutcome, facts: CaseFacts) -> ResultRow:
    """Turn a call's outcome into a table row, applying DESIGN.md's status rules."""
    common = dict(
        seconds=outcome.seconds,
        eps_value=outcome.eps_value,
        degenerate=facts.degenerate,
        invalid_input=facts.invalid_input,
    )
    if outcome.kind == "raised":
        # Any exception on an invalid or affinely degenerate input is acceptable
        # behaviour, except running out of memory or stack: that is no rejection.
        resource = outcome.error.startswith(("MemoryError", "RecursionError"))
        status = "rejected" if (facts.invalid_input or facts.degenerate) and not resource else "error"
        return make_row(case, config, status=status, reason=outcome.error, error_frame=outcome.frame, **common)
    if outcome.kind == "contract":
        return make_row(case, config, status="fail", reason=f"output contract: {outcome.error}", **common)
    assert outcome.faces is not None
    if facts.invalid_input:
        if facts.invalid_input == "no points" and _is_empty(outcome.faces):
            return make_row(case, config, status="pass", reason="empty input, empty hull", **common)
        return make_row(
            case, config, status="fail",
            reason=f"returned a hull for invalid input ({facts.invalid_input}) instead of rejecting it",
            **common,
        )
    from .checker import check

    start = time.perf_counter()
    try:
        verdict = check(case.points, outcome.faces, reference=facts.reference, qhull=facts.reference is not None)
    except Exception as exc:  # a checker bug must not lose the row, nor blame the algorithm silently
        return make_row(
            case, config, status="error", reason=f"internal: checker raised {one_line(exc)}",
            check_seconds=time.perf_counter() - start, **common,
        )
    check_seconds = time.perf_counter() - start
    status = "pass" if verdict.ok else "fail"
    return make_row(
        case, config, status=status, reason=verdict.detail if not verdict.ok else "",
        check_seconds=check_seconds, verdict=verdict, **common,
    )


def evaluate(case: Case, config: AlgorithmConfig, *, facts: CaseFacts | None = None, qhull: bool = True) -> ResultRow:
    """Run and judge one config on one case in this process (no isolation, no timeout)."""
    if facts is None:
        facts = case_facts(case, qhull=qhull)
    return judge(case, config, call_algorithm(case, config), facts)
