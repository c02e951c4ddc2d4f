"""Shrinking one failing case to a small point set that fails with exactly the same signature.

A change is kept only when the candidate fails with the group's whole
:class:`~.signature.Signature` (config, stage, status, every failed check and
the severity, or the exception type and the frame that raised it), never
with "some other failure", the way Hypothesis keeps an error's type and
location while it shrinks.  Passes, in order:

1. **Delete points** (:func:`~.deletion.delete_rows`): greedy block deletion
   until no single point can go.
2. **Simplify coordinates**: scale by a power of two so the largest lies in
   [1, 2) (exact); round every coordinate to the fewest mantissa bits that
   keep the failure (bisecting a ladder of widths); delete points again if
   that changed anything; round point by point to fewer bits (bisected
   again); then coordinate by coordinate try 0 and the nearest integer.

The budget is counted in **evaluations** (judged calls, cache hits free), so
what a shrink produces depends only on the case, the config and the
budget, never on the machine's speed or load: two runs with the same seed
give the same minimal cases.  When the budget runs out the best case so far
is kept and the result says which pass was cut short.

A shrink may first *try* small inputs known to fail some other way (other
groups' minimal cases, see :mod:`.stage`), one evaluation each: the first on
which the config fails with exactly this signature becomes the start, and
the shrink then only checks that no point of it can go, keeping it as it is
when none can (its coordinates were simplified already).  When none does,
it shrinks its own case.

:class:`Shrinker` is the shrink as a state machine that asks one question at
a time (:meth:`Shrinker.ask`, :meth:`Shrinker.answer`), so that the triage
stage can run hundreds of them in lockstep on a pool of isolated workers;
:func:`shrink` drives one with single isolated calls.
"""

from __future__ import annotations

import dataclasses
import time
from collections.abc import Generator, Sequence

import numpy as np

from ..case import Case, points_digest
from ..config import AlgorithmConfig
from ..options import DEFAULTS
from ..results import ResultRow
from .deletion import delete_rows
from .oracle import IsolationUnavailable, run_config
from ..records import Status
from .records import ShrinkResult
from .signature import Signature, signature_of
from .simplify import coordinate_candidates, mantissa_bits, pow2_normalize, round_mantissa

__all__ = ["ShrinkResult", "Shrinker", "shrink", "derive_case", "candidate_case"]

#: Global mantissa widths, fewest first (bisected: the fewest that keeps the failure wins).
_GLOBAL_BITS = (1, 2, 3, 4, 6, 8, 12, 16, 20, 24, 32, 40, 48)

#: What each pass is called in notes.
_PASSES = {"verify": "looking for a starting case", "delete": "deleting points",
           "simplify": "simplifying coordinates"}


class _Spent(Exception):
    """The evaluation budget of this shrink is spent."""


class _SimplifyDone(Exception):
    """The evaluations allowed for simplifying coordinates are spent (the points are deleted already)."""


def derive_case(original: Case, points: np.ndarray) -> Case:
    """A case with new points and the original's provenance plus ``shrunk_from``."""
    params = dict(original.params)
    params.setdefault("shrunk_from", original.case_id)
    return Case(points=points, dim=original.dim, family=original.family, params=params,
                seed=original.seed, size=original.size, source="shrink")


def candidate_case(points: np.ndarray, dim: int) -> Case:
    """The case a shrink candidate is run as: the points alone, with a neutral provenance.

    Every shrink that asks about the same points gets the same case (one id),
    so a batch runs it once, with one set of case facts, for all of them.
    """
    return Case(points=points, dim=dim, family="shrink", source="shrink")


#: A question: the points to run, and whether the Qhull reference is needed for the answer.
Question = tuple[np.ndarray, bool]
Questions = Generator[Question, ResultRow, None]


def matches_without_reference(row: ResultRow, signature: Signature) -> bool:
    """Could ``row``, judged without the Qhull reference, have ``signature`` once the reference is there?

    Without the reference nothing fails ``qhull_agreement`` and the severity
    lacks the volume disagreement; every other part of a signature (status,
    stage, the other checks, the exception and its frame) is the same with
    or without it.  A False here is final; a True still needs the exact check.

    Examples
    --------
    >>> sig = Signature("a", "off", "n/a", checks="containment,qhull_agreement", severity="gross")
    >>> row = {"algorithm": "a", "sphere": "off", "eps": "n/a", "status": "fail", "failed_checks": "containment",
    ...        "severity": "roundoff"}
    >>> matches_without_reference(row, sig), matches_without_reference({**row, "status": "pass"}, sig)
    (True, False)
    """
    cheap = signature_of(row)
    if cheap is None:
        return False
    checks = ",".join(c for c in signature.checks.split(",") if c and c != "qhull_agreement")
    severity = cheap.severity if "qhull_agreement" in signature.checks.split(",") else signature.severity
    return cheap == dataclasses.replace(signature, checks=checks, severity=severity)


class Shrinker:
    """One shrink as a question-and-answer state machine.

    Parameters
    ----------
    case : Case
        The failing case (provenance of the result).
    signature : Signature
        The failure to keep, exactly.
    max_calls : int
        Evaluation budget (judged calls; repeated candidates are free).  One
        call is kept for re-running the minimal case at the end.
    simplify : bool
        Run the coordinate passes after deleting points.
    simplify_calls : int, optional
        At most this many evaluations for the coordinate passes (within
        ``max_calls``); when they are spent the case keeps the coordinates
        simplified so far, and a step says so.
    candidates : sequence of (ndarray, str)
        Inputs to try first, in order, with where each came from: the first
        that fails with ``signature`` is the start instead of ``case``.
    qhull : bool
        The signature was judged with Qhull references (False after ``--no-qhull``).
    row : ResultRow, optional
        The row ``case`` got in the sweep (exact): kept when no smaller case is confirmed.

    Notes
    -----
    For a ``fail`` (unless ``qhull_agreement`` is all it fails), candidates
    are first judged without the Qhull reference, which costs more than the
    algorithm and the check together on small inputs
    (:func:`matches_without_reference` is exact about what it rejects).  The
    minimal case is then re-run with the reference; should the two disagree
    (a candidate kept that the reference would have rejected), the kept
    cases are bisected for the latest one the reference confirms, and the
    shrink goes on from there with the reference on every candidate.  For
    every other signature the final re-run checks that the failure is not
    flaky.

    Examples
    --------
    >>> s = Shrinker(case, sig, max_calls=100)  # doctest: +SKIP
    >>> question = s.ask()  # doctest: +SKIP
    >>> while question is not None:  # doctest: +SKIP
    ...     points, with_reference = question
    ...     question = s.answer(run(points, qhull=with_reference))
    >>> s.result().minimal_size  # doctest: +SKIP
    4
    """

    def __init__(self, case: Case, signature: Signature, *, max_calls: int, simplify: bool = True,
                 candidates: Sequence[tuple[np.ndarray, str]] = (), qhull: bool = True,
                 row: ResultRow | None = None, simplify_calls: int | None = None) -> None:
        self.case, self.signature = case, signature
        self.max_calls = int(max_calls)
        self.simplify = simplify
        self.simplify_calls = simplify_calls
        self._simplify_until: int | None = None  # the evaluation count at which simplifying stops
        self.calls = 0
        self.steps: list[str] = []
        self.phase = "verify"
        self.started = time.perf_counter()
        self._reference = qhull and signature.status == Status.FAIL
        # Without the reference every candidate of a qhull_agreement-only failure would "pass".
        self._lazy = self._reference and signature.checks != "qhull_agreement"
        self._candidates = list(candidates)
        self._finished = False
        self._question: Question | None = None
        self._exhausted = False
        self._note = ""
        self._row: ResultRow | None = None  # the exact row of the minimal case
        self._verified: bool | None = None
        self._sweep_row = row  # the case's own row, judged exactly
        self._rerun = False  # the pending question re-runs a case on purpose
        self._reset()
        self._gen = self._run()

    def _reset(self) -> None:
        self._cache: dict[str, bool] = {}
        self._points = np.array(self.case.points)
        self._best: np.ndarray | None = None
        self._rows: dict[str, ResultRow] = {}  # exact rows of the failing candidates (exact mode only)
        self._trail: list[np.ndarray] = []  # the candidates kept without the reference, in order
        self._reproduced = False
        self._adopted = False

    # -- the protocol -------------------------------------------------------

    @property
    def finished(self) -> bool:
        return self._finished

    @property
    def rerun(self) -> bool:
        """The pending question re-runs a case on purpose (the minimal case's exact confirmation).

        Its answer must come from a new call, never from a cache of earlier
        calls: a flaky or state-dependent failure shows only that way.
        """
        return self._rerun and self._question is not None

    def ask(self) -> Question | None:
        """The first question (None when the shrink needs no call at all)."""
        return self._advance(None, first=True)

    def answer(self, row: ResultRow) -> Question | None:
        """Give the row of the last question; get the next question, or None when done."""
        if self._question is None:
            raise RuntimeError("answer() without a pending question")
        return self._advance(row)

    def stop(self, note: str) -> ShrinkResult:
        """End now (an interrupt, the wall-clock safety net): the best exact case so far, with ``note``."""
        if not self._finished:
            self._gen.close()
            if self._lazy:
                # Candidates judged without the reference are not exact yet: keep the sweep's case.
                self._reproduced, self._best = False, None
            self._row = self._best_row()
            self._finish(exhausted=True, note=note)
        return self.result()

    def result(self) -> ShrinkResult:
        """What the shrink produced (call when :attr:`finished`)."""
        if not self._finished:
            raise RuntimeError("the shrink has not finished")
        points = self._best if self._best is not None else np.array(self.case.points)
        minimal = derive_case(self.case, points) if self._reproduced else self.case
        return ShrinkResult(
            case=minimal, original=self.case, signature=self.signature, original_size=self.case.n_points,
            minimal_size=minimal.n_points, calls=self.calls, seconds=time.perf_counter() - self.started,
            reproduced=self._reproduced, exhausted=self._exhausted, row=self._row, steps=tuple(self.steps),
            note=self._note, adopted=self._adopted and self._reproduced, verified=self._verified,
        )

    # -- driving the generator ------------------------------------------------

    def _advance(self, row: ResultRow | None, *, first: bool = False) -> Question | None:
        if self._finished:
            return None
        try:
            question = next(self._gen) if first else self._gen.send(row)
        except StopIteration:
            self._question = None
            self._finished = True
            return None
        self._question = question
        return question

    def _finish(self, *, exhausted: bool, note: str) -> None:
        self._finished = True
        self._question = None
        self._exhausted = exhausted
        self._note = note

    # -- the shrink itself -------------------------------------------------

    def _holds(self, points: np.ndarray) -> Generator[Question, ResultRow, bool]:
        """Does ``points`` fail with the signature?  One evaluation unless cached."""
        key = points_digest(points)
        if key not in self._cache:
            if self.calls >= self.max_calls - 1:  # the last call is for re-running the minimal case
                raise _Spent()
            if self._simplify_until is not None and self.calls >= self._simplify_until:
                raise _SimplifyDone()
            row = yield (points, self._reference and not self._lazy)
            self.calls += 1
            if self._lazy:
                self._cache[key] = matches_without_reference(row, self.signature)
                if self._cache[key]:
                    self._trail.append(np.array(points))
            else:
                self._cache[key] = signature_of(row) == self.signature
                if self._cache[key]:
                    self._rows[key] = row
        hit = self._cache[key]
        if hit and (self._best is None or len(points) <= len(self._best)):
            self._best = np.array(points)
        return hit

    def _best_row(self) -> ResultRow | None:
        return self._rows.get(points_digest(self._best)) if self._best is not None else None

    def _confirm(self, points: np.ndarray) -> Generator[Question, ResultRow, ResultRow | None]:
        """Re-run the minimal case exactly (with the reference when the signature needs it)."""
        self._rerun = True
        try:
            row = yield (points, self._reference)
        finally:
            self._rerun = False
        self.calls += 1
        return row if signature_of(row) == self.signature else None

    def _run(self) -> Questions:
        note = yield from self._passes(np.array(self.case.points), tries=True)
        if not self._reproduced:
            self._finish(exhausted=bool(note), note=note or "the failure did not reproduce on a re-run "
                         "(flaky, state- or resource-dependent)")
            return
        row = yield from self._confirm(self._best)
        if row is None and self._lazy:
            # Judged without the reference, a step was kept that the reference rejects.  Find a kept
            # case the reference confirms (bisecting the steps), and shrink on from there, exactly.
            good, row = yield from self._last_confirmed()
            self._lazy = False
            self._cache, self._rows = {points_digest(good): True}, {points_digest(good): row}
            self._best = np.array(good)
            self.steps.append(f"a step judged without the Qhull reference did not hold with it: shrunk on from "
                              f"{len(good)} points with the reference on every candidate")
            if self.calls < self.max_calls - 1:
                note = yield from self._passes(good, tries=False)
                row = yield from self._confirm(self._best)
            else:
                note = note or f"evaluation budget ({self.max_calls}) spent: the case may not be minimal"
        # A flaky case keeps the row it failed with during the shrink.
        self._row = row if row is not None else self._best_row()
        self._verified = row is not None
        self._finish(exhausted=bool(note), note=note)

    def _last_confirmed(self) -> Generator[Question, ResultRow, tuple[np.ndarray, ResultRow | None]]:
        """The latest kept case the reference confirms, bisecting the kept cases (the sweep's case is exact)."""
        trail = self._trail
        good, good_row = np.array(self.case.points), self._sweep_row
        lo, hi = -1, len(trail) - 1  # trail[hi], the last kept case, failed its check with the reference
        while hi - lo > 1 and self.calls < self.max_calls - 1:
            mid = (lo + hi) // 2
            row = yield from self._confirm(trail[mid])
            if row is not None:
                lo, good, good_row = mid, trail[mid], row
            else:
                hi = mid
        return good, good_row

    def _passes(self, start: np.ndarray, *, tries: bool) -> Generator[Question, ResultRow, str]:
        """Try the candidates, check the start, delete points, simplify; return a note if the budget ran out."""
        self._points = start
        try:
            for points, label in (self._candidates if tries else ()):
                if points.shape[1:] == self._points.shape[1:] and (yield from self._holds(points)):
                    self._points, self._adopted = np.array(points), True
                    self.steps.append(f"started from {label} ({len(points)} points): it fails the same way")
                    break
            if not (yield from self._holds(self._points)):
                return ""
            self._reproduced = True
            self._best = np.array(self._points)
            self.phase = "delete"
            before = len(self._points)
            self._points = yield from self._delete(self._points)
            if self._adopted and len(self._points) == before:
                self.steps.append("kept as it is: no point of it can go (its coordinates are simplified already)")
            elif self.simplify and self._points.ndim == 2 and self._points.size:
                self.phase = "simplify"
                if self.simplify_calls is not None:
                    self._simplify_until = self.calls + self.simplify_calls
                try:
                    self._points = yield from self._simplify(self._points)
                except _SimplifyDone:
                    self._points = self._best
                    self.steps.append(f"coordinates simplified within {self.simplify_calls} evaluations")
                finally:
                    self._simplify_until = None
            return ""
        except _Spent:
            return (f"evaluation budget ({self.max_calls}) spent while {_PASSES[self.phase]}: "
                    "the case is smaller but may not be minimal")

    def _delete(self, points: np.ndarray) -> Generator[Question, ResultRow, np.ndarray]:
        n = len(points) if points.ndim >= 1 else 0
        if points.ndim != 2 or n <= 1:
            return points
        steps = delete_rows(tuple(range(n)))
        try:
            subset = next(steps)
            while True:
                holds = yield from self._holds(points[list(subset)])
                subset = steps.send(holds)
        except StopIteration as done:
            keep = list(done.value)
        if len(keep) < n:
            self.steps.append(f"deleted points: {n} -> {len(keep)}")
        return points[keep]

    def _fewest_bits(self, points: np.ndarray, rows: slice | int, what: str
                     ) -> Generator[Question, ResultRow, np.ndarray]:
        """Round ``points[rows]`` to the fewest bits of the ladder that keep the failure (bisected)."""
        width = int(mantissa_bits(points[rows]).max()) if points[rows].size else 0
        ladder = [b for b in _GLOBAL_BITS if b < width]
        lo, hi = -1, len(ladder)  # all `width` bits keep the failure
        while hi - lo > 1:
            mid = (lo + hi) // 2
            candidate = points.copy()
            candidate[rows] = round_mantissa(points[rows], ladder[mid])
            if (yield from self._holds(candidate)):
                hi = mid
            else:
                lo = mid
        if hi < len(ladder):
            points = points.copy()
            points[rows] = round_mantissa(points[rows], ladder[hi])
            if what:
                self.steps.append(f"{what} rounded to {ladder[hi]} mantissa bits")
        return points

    def _simplify(self, points: np.ndarray) -> Generator[Question, ResultRow, np.ndarray]:
        scaled = pow2_normalize(points)
        if scaled is not None and (yield from self._holds(scaled)):
            points = scaled
            self.steps.append("scaled by a power of two into [1, 2)")
        before = points
        points = yield from self._fewest_bits(points, slice(None), "all coordinates")
        if points is not before:
            n = len(points)
            points = yield from self._delete(points)
            if len(points) < n:
                self.steps[-1] += " (after rounding)"
        # Point by point, fewer bits; then coordinate by coordinate, 0 or the nearest integer.
        widths = int(mantissa_bits(points).max()) if points.size else 0
        for i in range(points.shape[0]):
            points = yield from self._fewest_bits(points, i, "")
        if int(mantissa_bits(points).max() if points.size else 0) < widths:
            self.steps.append("points rounded one by one to fewer mantissa bits")
        changed = 0
        for i in range(points.shape[0]):
            for j in range(points.shape[1]):
                for value in coordinate_candidates(float(points[i, j]), ladder=()):
                    candidate = points.copy()
                    candidate[i, j] = value
                    if (yield from self._holds(candidate)):
                        points = candidate
                        changed += 1
                        break
        if changed:
            self.steps.append(f"{changed} coordinates replaced by 0 or an integer")
        return points


def shrink(
    case: Case,
    config: AlgorithmConfig,
    signature: Signature | None = None,
    *,
    max_calls: int = DEFAULTS.shrink_max_calls,
    budget_seconds: float | None = None,
    timeout: float | None = None,
    isolate: bool | None = None,
    simplify: bool = True,
    simplify_calls: int | None = None,
) -> ShrinkResult:
    """Minimise ``case`` to a small point set on which ``config`` fails with exactly ``signature``.

    Parameters
    ----------
    case : Case
        A failing case.
    config : AlgorithmConfig
    signature : Signature, optional
        The failure to keep; default: whatever ``case`` fails with now.
    max_calls : int
        Evaluation budget: judged calls (the result depends on it, not on time).
    budget_seconds : float, optional
        Wall-clock safety net: stop after this long, keeping the best case so
        far, and say so in the note (the result then depends on the machine).
    timeout : float, optional
        Per-call timeout of isolated calls (reuse the sweep's for timeouts).
    isolate : bool, optional
        See :func:`~hullstress.triage.oracle.run_config`.
    simplify : bool
        Run the coordinate simplification passes after deleting points.
    simplify_calls : int, optional
        At most this many of the evaluations simplify coordinates (None: no separate limit).

    Returns
    -------
    ShrinkResult

    Examples
    --------
    >>> res = shrink(case, AlgorithmConfig("my-hull"), max_calls=300)  # doctest: +SKIP
    >>> res.original_size, res.minimal_size  # doctest: +SKIP
    (500, 4)
    """
    start = time.perf_counter()
    row = None
    if signature is None:
        row = run_config(case, config, timeout=timeout, isolate=isolate)
        signature = signature_of(row)
        if signature is None:
            sig = Signature(config.algorithm, config.sphere, config.eps, status=row.status)
            return ShrinkResult(case=case, original=case, signature=sig, original_size=case.n_points,
                                minimal_size=case.n_points, calls=1, seconds=time.perf_counter() - start,
                                reproduced=False, note=f"the case does not fail ({row.status})")
    shrinker = Shrinker(case, signature, max_calls=max_calls, simplify=simplify, row=row,
                        simplify_calls=simplify_calls)
    question = shrinker.ask()
    while question is not None:
        if budget_seconds is not None and time.perf_counter() - start > budget_seconds:
            return shrinker.stop(f"stopped by the wall-clock safety net ({budget_seconds:g} s): "
                                 "the case is smaller but may not be minimal, and may differ between runs")
        points, with_reference = question
        try:
            row = run_config(candidate_case(points, case.dim), config, timeout=timeout, isolate=isolate,
                             dangerous=signature.dangerous, qhull=with_reference)
        except IsolationUnavailable as exc:
            return shrinker.stop(f"not shrunk: {exc}")
        question = shrinker.answer(row)
    return shrinker.result()
