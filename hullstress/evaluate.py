"""Running one algorithm config on one case and judging the result.

This is the unit of work every backend (in-process, process pool, Dask)
executes.  It is split in three so that a runner can isolate the untrusted
part:

* :func:`case_facts` — computed once per case: input validity, exact affine
  rank, Qhull's reference hull.  Trusted code.
* :func:`call_algorithm` — preprocessing (sphere variant, eps set-up), the
  algorithm call itself, and the output contract.  Untrusted: this is what a
  runner puts behind a timeout in a separate process.
* :func:`judge` — status rules of docs/design.md and the exact checker.  Trusted.

:func:`evaluate` chains the three in-process, for tests, shrinking and replay.

Every row names the stage that produced its verdict
(:class:`~hullstress.records.Stage`):

* ``preprocess`` — the sphere method or the eps set-up.  An exception there
  (or a non-finite projection or tolerance for a finite input) is an
  ``error`` (``rejected`` on invalid or degenerate input); with sphere on, a
  correct hull of the projected points that, mapped back, is not the hull of
  the input is a ``fail``.  Either way a finding about the method, never the
  algorithm's.
* ``algorithm`` — the algorithm, judged on the points it was given: with
  sphere on, its hull of the projected points is checked against the
  projected points.
* ``check`` — the checker broke (an internal error of hullstress).
"""

from __future__ import annotations

import hashlib
import time
import warnings
import weakref
from collections import OrderedDict
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from .case import Case, points_digest
from .config import NO_EPS, AlgorithmConfig, sphere_duplicate_policy
from .contract import FaceSet, canonical_output, normalize_output, require_face_size, reverse_orientation
from .errors import CodeCrashed, ContractViolation, UnknownNameError, code_frame, one_line
from .records import CONTRACT_REASON, METHOD_REASON, Origin, Sphere, Stage, Status
from .results import ResultRow, make_row
from .tolerance import tolerance
from .verdict import Verdict

__all__ = [
    "CaseFacts",
    "CallOutcome",
    "case_facts",
    "points_facts",
    "call_algorithm",
    "judge",
    "evaluate",
    "input_problem",
    "PreprocessError",
]


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


class PreprocessError(Exception):
    """The variant's preprocessing (sphere method, eps set-up) gave no usable input for the algorithm."""


@dataclass(frozen=True)
class CallOutcome:
    """What the untrusted part produced.

    Attributes
    ----------
    kind : {"ok", "raised", "contract", "crash", "preprocess"}
        Returned a valid output, raised, returned output breaking the
        contract (or raised ContractViolation: a program's unreadable output),
        died (an executable killed by a signal), or never ran because
        preprocessing failed.
    faces : ndarray or FaceSet or None
        The output in the case's own rows (``kind == "ok"``): canonical
        (:func:`~hullstress.contract.canonical_output`), and with sphere on
        the canonical output mapped back (face ``k`` is the algorithm's
        canonical face ``k``).
    error : str
        ``TypeName: message`` or the contract violation, on one line.
    seconds : float
        Wall time of preprocessing plus the algorithm call.
    eps_value : float or None
        The tolerance passed as ``eps``.
    given : ndarray or None
        The points the algorithm was given when they are not the case's
        (sphere on): the projected points.
    given_faces : ndarray or FaceSet or None
        The canonical output in the indices of ``given``.
    index_map : ndarray or None
        Row ``i`` of ``given`` is input row ``index_map[i]``.
    frame : str
        For ``raised``: the innermost frame of the code under test
        (:func:`~hullstress.errors.code_frame`), part of a failure's signature.
    """

    kind: str
    faces: np.ndarray | FaceSet | None = None
    error: str = ""
    seconds: float = 0.0
    eps_value: float | None = None
    given: np.ndarray | None = None
    given_faces: np.ndarray | FaceSet | None = None
    index_map: np.ndarray | None = None
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


def points_facts(points: np.ndarray, dim: int, *, qhull: bool = True, qhull_options: str | None = None) -> CaseFacts:
    """Validity, exact affine rank and (optionally) Qhull reference of a point array (``qhull_options`` first)."""
    from .checker import affine_rank, qhull_reference

    problem = input_problem(points, dim)
    if problem is not None:
        return CaseFacts(invalid_input=problem, affine_rank=None, degenerate=True, reference=None)
    reference = qhull_reference(points, options=qhull_options) if qhull else None
    known = reference.affine_rank if reference is not None else None
    rank = int(known) if known is not None else int(affine_rank(points))
    return CaseFacts(invalid_input=None, affine_rank=rank, degenerate=rank < dim, reference=reference)


def case_facts(case: Case, *, qhull: bool = True, qhull_options: str | None = None) -> CaseFacts:
    """Compute a case's validity, exact affine rank and (optionally) Qhull reference (``qhull_options`` first)."""
    return points_facts(case.points, case.dim, qhull=qhull, qhull_options=qhull_options)


# The projected points of one case are the same for every algorithm with the
# same duplicate tolerance: their facts (a Qhull reference) are computed once.
_GIVEN_FACTS: OrderedDict[tuple[str, int, bool], CaseFacts] = OrderedDict()
_GIVEN_FACTS_SIZE = 8


def _given_facts(points: np.ndarray, dim: int, qhull: bool) -> CaseFacts:
    key = (points_digest(points), dim, qhull)
    facts = _GIVEN_FACTS.get(key)
    if facts is None:
        facts = points_facts(points, dim, qhull=qhull)
        _GIVEN_FACTS[key] = facts
        while len(_GIVEN_FACTS) > _GIVEN_FACTS_SIZE:
            _GIVEN_FACTS.popitem(last=False)
    return facts


def _finite(points: np.ndarray) -> bool:
    return points.ndim == 2 and bool(np.isfinite(points).all())


# The sphere method's projection depends only on the points and the duplicate
# tolerance, so every config of a case with sphere on and the same tolerance
# (each algorithm, per eps policy) gets the same projected points: computed once.
_PROJECTIONS: OrderedDict[tuple[str, float], tuple[np.ndarray, np.ndarray] | str] = OrderedDict()
_PROJECTIONS_SIZE = 8


def _projection(case: Case, duplicate_eps: float) -> tuple[np.ndarray, np.ndarray]:
    """The sphere method's projected points (read-only) and index map for ``case``, remembered.

    Raises
    ------
    PreprocessError
        The method raised, or its projected points are not finite (the same
        error every time for the same points and tolerance).
    """
    key = (case.content_hash, duplicate_eps)
    known = _PROJECTIONS.get(key)
    if known is None:
        known = _fresh_projection(case.points, duplicate_eps)
        if duplicate_eps == duplicate_eps:  # a NaN tolerance (non-finite input) would never be found again
            _PROJECTIONS[key] = known
            while len(_PROJECTIONS) > _PROJECTIONS_SIZE:
                _PROJECTIONS.popitem(last=False)
    else:
        _PROJECTIONS.move_to_end(key)
    if isinstance(known, str):
        raise PreprocessError(known)
    return known


def _fresh_projection(points: np.ndarray, duplicate_eps: float) -> tuple[np.ndarray, np.ndarray] | str:
    """:func:`~hullstress.sphere.sphere_project` as the preprocessing step: its result, or why it failed."""
    from .sphere import sphere_project  # scipy: imported when first needed

    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            projected, index_map = sphere_project(points, eps=duplicate_eps)
    except Exception as exc:  # the method's own exceptions (bad shape, NaN, an unprojectable point)
        return f"sphere projection: {one_line(exc)}"
    if not np.isfinite(projected).all():
        return "sphere projection: the projected points are not finite (the method's float arithmetic overflowed)"
    projected = np.ascontiguousarray(projected, dtype=np.float64)
    projected.setflags(write=False)
    index_map = np.asarray(index_map, dtype=np.int64)
    index_map.setflags(write=False)
    return projected, index_map


def _preprocess(case: Case, config: AlgorithmConfig) -> tuple[np.ndarray, np.ndarray | None, dict[str, Any]]:
    """The variant's preprocessing: the points the algorithm gets, the index map, its keywords.

    Raises
    ------
    PreprocessError
        Naming the step (sphere projection, eps set-up) and what went wrong.
    """
    points = case.points
    index_map: np.ndarray | None = None
    finite = _finite(points)
    if config.sphere == Sphere.ON:
        policy = sphere_duplicate_policy(config.eps)
        duplicate_eps = tolerance(points, policy)
        if finite and not np.isfinite(duplicate_eps):
            raise PreprocessError(f"eps set-up: the {policy} tolerance is {duplicate_eps!r} for finite input")
        points, index_map = _projection(case, duplicate_eps)
    kwargs: dict[str, Any] = {}
    if config.eps != NO_EPS:
        eps_value = tolerance(points, config.eps)
        # Non-finite input gives a non-finite eps by the seed's formula; that is passed on.
        if _finite(points) and not np.isfinite(eps_value):
            raise PreprocessError(f"eps set-up: the {config.eps} tolerance is {eps_value!r} for finite input")
        kwargs["eps"] = eps_value
    return points, index_map, kwargs


def call_algorithm(case: Case, config: AlgorithmConfig) -> CallOutcome:
    """Run ``config`` on ``case``: preprocessing, the call, the output contract, canonical order.

    Never raises for anything the algorithm does; the outcome records it.
    """
    spec = config.spec
    start = time.perf_counter()
    try:
        points, index_map, kwargs = _preprocess(case, config)
    except PreprocessError as exc:
        return CallOutcome("preprocess", error=str(exc), seconds=time.perf_counter() - start)
    eps_value = kwargs.get("eps")
    # What the algorithm was given, when not the case's points: judged against those.
    given = {} if index_map is None else {"given": points, "index_map": index_map}
    if spec.origin == Origin.EXECUTABLE:
        from .qhull_format import input_refusal

        # The documented rule for programs: input Qhull's format cannot carry is not given to them.
        refusal = input_refusal(points, case.dim)
        if refusal:
            return CallOutcome("raised", error=one_line(ValueError(f"{refusal}: not given to the program")),
                               seconds=time.perf_counter() - start, eps_value=eps_value, **given)
    try:
        with warnings.catch_warnings():
            # The code under test's own warnings (overflow in its cross products,
            # say) are not the harness's output; what it returns is judged instead.
            warnings.simplefilter("ignore")
            raw = spec.func(np.array(points) if spec.writable else points, **kwargs)
    except ContractViolation as exc:
        return CallOutcome("contract", error=str(exc), seconds=time.perf_counter() - start, eps_value=eps_value)
    except CodeCrashed as exc:
        return CallOutcome("crash", error=str(exc), seconds=time.perf_counter() - start, eps_value=eps_value)
    except (Exception, RecursionError) as exc:  # the code under test may raise anything
        return CallOutcome("raised", error=one_line(exc), seconds=time.perf_counter() - start, eps_value=eps_value,
                           frame=code_frame(exc.__traceback__, spec.module), **given)
    seconds = time.perf_counter() - start
    try:
        # Faces of one or two vertices are judged once the rank is known (see judge).
        faces = normalize_output(raw, len(points), case.dim, min_face_size=1)
        if spec.clockwise:  # --clockwise: the library's documented orientation, turned to the contract's
            faces = reverse_orientation(faces)
        faces = canonical_output(faces)
    except ContractViolation as exc:
        return CallOutcome("contract", error=str(exc), seconds=seconds, eps_value=eps_value, **given)
    if index_map is None:
        return CallOutcome("ok", faces=faces, seconds=seconds, eps_value=eps_value)
    from .sphere import map_back

    # Face k (a 2D vertex k) of the mapped-back output is face k of the canonical output.
    return CallOutcome("ok", faces=map_back(faces, index_map), seconds=seconds, eps_value=eps_value,
                       given_faces=faces, **given)


def _is_empty(faces: np.ndarray | FaceSet) -> bool:
    return faces.n_faces == 0 if isinstance(faces, FaceSet) else len(faces) == 0


class _Judged(Exception):
    """A judgement ended early in a row (contract violation, checker error)."""

    def __init__(self, status: str, stage: Stage, reason: str) -> None:
        super().__init__(reason)
        self.status, self.stage, self.reason = status, stage, reason


# Many configs of one case return the same output (eps scaled and fixed, a variant
# and its base algorithm, sphere on and off on a sphere already): the verdict is a
# function of the points, the (canonical) faces and the case facts, so each
# distinct output is judged once.  Keyed by content; the facts must be the very
# object the verdict was computed with (held weakly: the cache keeps no case alive).
_VERDICTS: OrderedDict[tuple[str, bytes], tuple[weakref.ref, Verdict]] = OrderedDict()
_VERDICTS_SIZE = 256


def _faces_key(faces: np.ndarray | FaceSet) -> bytes:
    """SHA-256 of an output's exact content (kind, shape, dtype, indices), like :func:`~hullstress.case.points_digest`.

    A digest, not the content: a worker keeps hundreds of keys, and a wrong
    hull of a large case can have millions of indices.
    """
    h = hashlib.sha256()
    if isinstance(faces, FaceSet):
        h.update(b"F")
        h.update(np.ascontiguousarray(faces.offsets).tobytes())
        h.update(b"|")
        h.update(np.ascontiguousarray(faces.indices).tobytes())
    else:
        arr = np.ascontiguousarray(faces)
        h.update(f"A{arr.dtype.str}{arr.shape}".encode())
        h.update(arr.tobytes())
    return h.digest()


def _verdict(points: np.ndarray, faces: np.ndarray | FaceSet, facts: CaseFacts) -> Verdict:
    """:func:`_fresh_verdict`, computed once per distinct output (see above); raises as it does."""
    key = (points_digest(points), _faces_key(faces))
    hit = _VERDICTS.get(key)
    if hit is not None and hit[0]() is facts:
        _VERDICTS.move_to_end(key)
        return _copy(hit[1])
    verdict = _fresh_verdict(points, faces, facts)
    _VERDICTS[key] = (weakref.ref(facts), verdict)
    while len(_VERDICTS) > _VERDICTS_SIZE:
        _VERDICTS.popitem(last=False)
    return _copy(verdict)


def _copy(verdict: Verdict) -> Verdict:
    """A shallow copy of a (frozen) verdict with its own ``offending`` dict: the cached one stays as it was."""
    out = object.__new__(Verdict)
    out.__dict__.update(verdict.__dict__, offending=dict(verdict.offending))
    return out


def _fresh_verdict(points: np.ndarray, faces: np.ndarray | FaceSet, facts: CaseFacts) -> Verdict:
    """The exact verdict on ``faces`` as a hull of ``points`` (lower-dimensional or full).

    Raises
    ------
    ContractViolation
        A face of fewer than three vertices where the input's rank asks for a surface.
    Exception
        Anything else is a checker bug.
    """
    from .checker import check
    from .checker.lowdim import judge_lower_dimensional

    reference = facts.reference
    if facts.degenerate:
        simplex = getattr(reference, "simplex", None)
        return judge_lower_dimensional(points, faces, simplex=simplex, reference=reference)
    if isinstance(faces, FaceSet):
        require_face_size(faces)
    return check(points, faces, reference=reference, qhull=reference is not None)


def _judged_verdict(points: np.ndarray, faces: np.ndarray | FaceSet, facts: CaseFacts, stage: Stage) -> Verdict:
    """:func:`_verdict`, turning its exceptions into a :class:`_Judged` row."""
    try:
        return _verdict(points, faces, facts)
    except ContractViolation as exc:
        raise _Judged(Status.FAIL, stage, f"{CONTRACT_REASON} {exc}") from None
    except Exception as exc:  # a checker bug must not lose the row, nor blame the algorithm silently
        raise _Judged(Status.ERROR, Stage.CHECK, f"internal: checker raised {one_line(exc)}") from None


def _in_input_rows(verdict: Verdict, index_map: np.ndarray) -> Verdict:
    """A verdict on the projected points with its point indices turned into input rows.

    Face and edge indices stay: face ``k`` of the mapped-back output is face ``k``.
    """
    offending = {key: tuple(int(i) for i in (idx if ("face" in key or "edge" in key) else index_map[list(idx)]))
                 for key, idx in verdict.offending.items()}
    return replace(verdict, offending=offending)


def _method_problem(facts: CaseFacts, given: CaseFacts) -> str:
    """Why the projection cannot give the input's hull whatever the algorithm does ("" if it can)."""
    if given.invalid_input and not facts.invalid_input:
        return f"the projection left {given.invalid_input} from a valid input"
    if given.affine_rank is not None and facts.affine_rank is not None and given.affine_rank < facts.affine_rank:
        return (f"the projection left a set of affine rank {given.affine_rank} from an input of rank "
                f"{facts.affine_rank}: its hull cannot map back to the input's hull")
    return ""


def judge(case: Case, config: AlgorithmConfig, outcome: CallOutcome, facts: CaseFacts) -> ResultRow:
    """Turn a call's outcome into a table row: docs/design.md's status rules per stage, then the declared contract.

    The contract (:mod:`hullstress.hull_contract`) can only add failures to
    what the rules and the exact checker found (:mod:`hullstress.contract_verdict`).
    """
    from .contract_verdict import apply_contract

    row = _judge_by_rules(case, config, outcome, facts)
    try:
        contract = config.spec.contract
    except UnknownNameError:  # an algorithm from a plug-in not loaded here: judged by the rules alone
        return row
    return apply_contract(row, contract, outcome.faces, degenerate=bool(facts.degenerate))


def _judge_by_rules(case: Case, config: AlgorithmConfig, outcome: CallOutcome, facts: CaseFacts) -> ResultRow:
    """A call's outcome as a table row under docs/design.md's status rules per stage (the lenient judgement)."""
    common = dict(seconds=outcome.seconds, eps_value=outcome.eps_value,
                  degenerate=facts.degenerate, invalid_input=facts.invalid_input)
    sphere = config.sphere == Sphere.ON
    if outcome.kind == "preprocess":
        status = Status.REJECTED if (facts.invalid_input or facts.degenerate) else Status.ERROR
        return make_row(case, config, status=status, stage=Stage.PREPROCESS, reason=f"preprocess: {outcome.error}",
                        sphere_method=status if sphere else "", **common)
    start = time.perf_counter()
    given = _given_facts(outcome.given, case.dim, facts.reference is not None) if outcome.given is not None else facts
    problem = _method_problem(facts, given) if sphere else ""
    if sphere and outcome.index_map is not None:
        # Why the method would lose the hull, whatever the algorithm does (sphere_causes.py).
        from .sphere_causes import sphere_causes

        common["sphere_causes"] = sphere_causes(
            case.points, facts.reference, given.reference, outcome.index_map,
            lambda faces: _verdict(case.points, faces, facts),
            duplicate_eps=tolerance(case.points, sphere_duplicate_policy(config.eps)),
            cache_key=(case.case_id, points_digest(outcome.given)))

    def row(status: str, reason: str = "", verdict: Verdict | None = None, **kw: Any) -> ResultRow:
        return make_row(case, config, status=status, reason=reason, verdict=verdict,
                        check_seconds=time.perf_counter() - start, **kw, **common)

    def method_failed(reason: str, verdict: Verdict | None = None) -> ResultRow:
        return row(Status.FAIL, f"{METHOD_REASON} {reason}", verdict, stage=Stage.PREPROCESS, sphere_method=Status.FAIL)

    if outcome.kind == "raised":
        # Any exception on an invalid or affinely degenerate input is acceptable
        # behaviour, except running out of memory or stack: that is no rejection.
        resource = outcome.error.startswith(("MemoryError", "RecursionError"))
        declined = bool(given.invalid_input or given.degenerate) and not resource
        if declined and problem:
            return method_failed(f"{problem} (the algorithm then raised {outcome.error})")
        return row(Status.REJECTED if declined else Status.ERROR, outcome.error, error_frame=outcome.frame)
    if outcome.kind == "contract":
        return row(Status.FAIL, f"{CONTRACT_REASON} {outcome.error}")
    if outcome.kind == "crash":
        return row(Status.CRASH, outcome.error)
    assert outcome.faces is not None
    if given.invalid_input:
        if problem:
            return method_failed(problem)
        # No hull is defined: a clear rejection or any well-formed output is acceptable (docs/lower-dimensional.md).
        if given.invalid_input == "no points":
            return row(Status.PASS, "empty input, empty hull" if _is_empty(outcome.faces) else "empty input")
        return row(Status.PASS, f"no hull is defined for invalid input ({given.invalid_input}): "
                           "well-formed output accepted, not checked")
    given_points = outcome.given if outcome.given is not None else case.points
    given_faces = outcome.given_faces if outcome.given is not None else outcome.faces
    try:
        verdict = _judged_verdict(given_points, given_faces, given, Stage.ALGORITHM)
        if outcome.index_map is not None:
            verdict = _in_input_rows(verdict, outcome.index_map)
        if not sphere or not verdict.ok:
            return row(Status.PASS if verdict.ok else Status.FAIL, "" if verdict.ok else verdict.detail, verdict)
        # The algorithm's hull of the projected points is right: now judge the sphere method.
        if problem:
            return method_failed(problem)
        method = _judged_verdict(case.points, outcome.faces, facts, Stage.PREPROCESS)
    except _Judged as judged:
        return row(judged.status, judged.reason, stage=judged.stage,
                   sphere_method=Status.FAIL if judged.stage is Stage.PREPROCESS else "")
    if method.ok:
        return row(Status.PASS, "", verdict, sphere_method=Status.PASS)
    return method_failed(f"mapped back, the algorithm's correct hull of the {len(given_points)} projected points "
                         f"is not the input's hull: {method.detail}", method)


def evaluate(case: Case, config: AlgorithmConfig, *, facts: CaseFacts | None = None, qhull: bool = True,
             qhull_options: str | None = None) -> ResultRow:
    """Run and judge one config on one case in this process (no isolation, no timeout)."""
    if facts is None:
        facts = case_facts(case, qhull=qhull, qhull_options=qhull_options)
    return judge(case, config, call_algorithm(case, config), facts)
