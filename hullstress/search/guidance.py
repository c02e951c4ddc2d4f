"""Guidance: which evaluated inputs the search keeps, and why.

An input is kept (becomes a parent of later candidates) when its rows show
at least one of:

``signature``
    A failure signature (:func:`hullstress.triage.signature.signature_of`)
    not seen on any earlier input: new behaviour, as a coverage-guided
    fuzzer keeps inputs that reach new code.
``score``
    A part of its exact degeneracy score (:mod:`.score`) above the best of
    every earlier input of its dimension: closer to a degenerate decision,
    as Hypothesis's ``target()`` climbs.
``differential``
    Two or more algorithms (sphere off, so on the same points) answered with
    different sets of extreme points (:func:`extreme_answer`), in a way not
    seen before (which configs side with which).

Decisions depend only on the rows' verdict columns and the points, never on
timings, so the same inputs in the same order give the same decisions.
"""

from __future__ import annotations

import json
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..case import Case
from ..records import Sphere, Status
from ..triage.signature import Signature, signature_of
from .score import DegeneracyScore, degeneracy_score

__all__ = ["Guidance", "Verdict", "extreme_answer", "score_of"]


def _missing(value: Any) -> bool:
    return value is None or (isinstance(value, float) and value != value)


def extreme_answer(row: Mapping[str, Any] | Any) -> tuple[int, tuple[int, ...]] | None:
    """Which extreme points a row's hull has: ``(missing count, missing indices)``, or None without a hull.

    The checker counts the input's exact extreme points that a hull misses
    (``n_missing_extreme``) and names them (``offending``'s
    ``missing_extreme``); two hulls of the same points with the same pair
    name the same set of extreme points.

    Examples
    --------
    >>> extreme_answer({"status": "pass", "n_hull_vertices": 4, "n_missing_extreme": 0, "offending": "{}"})
    (0, ())
    >>> extreme_answer({"status": "error", "n_hull_vertices": None})
    """
    if row.get("status") not in (Status.PASS, Status.FAIL) or _missing(row.get("n_hull_vertices")) \
            or _missing(row.get("n_missing_extreme")):
        return None
    offending = row.get("offending")
    named: tuple[int, ...] = ()
    if isinstance(offending, str) and offending:
        named = tuple(int(i) for i in json.loads(offending).get("missing_extreme", ()))
    return int(row.get("n_missing_extreme")), named


def score_of(case: Case) -> DegeneracyScore | None:
    """The case's degeneracy score, or None for points that have none (wrong shape, NaN or infinity)."""
    try:
        return degeneracy_score(case.points)
    except ValueError:
        return None


@dataclass(frozen=True)
class Verdict:
    """Why an input was kept (an empty ``reasons`` means it was not).

    Attributes
    ----------
    reasons : tuple of str
        One line per reason: ``signature: ...``, ``score: margin_bits 40 -> 57``, ``differential: ...``.
    new_signatures : tuple of Signature
    score : DegeneracyScore or None
    """

    reasons: tuple[str, ...]
    new_signatures: tuple[Signature, ...] = ()
    score: DegeneracyScore | None = None

    @property
    def kept(self) -> bool:
        return bool(self.reasons)


@dataclass
class Guidance:
    """What the search has seen so far: signatures, the best score parts per dimension, differential splits."""

    signatures: dict[Signature, str] = field(default_factory=dict)
    best: dict[tuple[int, str], int] = field(default_factory=dict)
    splits: set[tuple[tuple[str, ...], ...]] = field(default_factory=set)

    def judge(self, case: Case, rows: Sequence[Mapping[str, Any] | Any]) -> Verdict:
        """Record what ``case``'s rows show and say whether it is worth keeping."""
        reasons: list[str] = []
        new: list[Signature] = []
        for row in rows:
            sig = signature_of(row)
            if sig is not None and sig not in self.signatures:
                self.signatures[sig] = case.case_id
                new.append(sig)
                reasons.append(f"signature: {sig.label}")
        split = self._split(rows)
        if split is not None and split not in self.splits:
            self.splits.add(split)
            reasons.append("differential: " + " vs ".join(",".join(group) for group in split))
        score = score_of(case)
        if score is not None:
            for part, value in score.parts().items():
                key = (case.dim, part)
                before = self.best.get(key)
                if before is None or value > before:
                    self.best[key] = value
                    if before is not None:  # the first input of a dimension sets the bar, it does not raise it
                        reasons.append(f"score: {part} {before} -> {value}")
        return Verdict(tuple(reasons), tuple(new), score)

    @staticmethod
    def _split(rows: Sequence[Mapping[str, Any] | Any]) -> tuple[tuple[str, ...], ...] | None:
        """Configs grouped by the extreme points their hulls name (sphere off), when there are two groups or more."""
        groups: dict[tuple[int, tuple[int, ...]], list[str]] = {}
        for row in rows:
            if row.get("sphere") != Sphere.OFF:
                continue
            answer = extreme_answer(row)
            if answer is not None:
                groups.setdefault(answer, []).append(str(row.get("config")))
        if len(groups) < 2:
            return None
        return tuple(sorted(tuple(sorted(g)) for g in groups.values()))


def finite_points(case: Case) -> bool:
    """Whether ``case`` can be a parent: an (n, dim) array of finite numbers with n >= 1."""
    p = case.points
    return p.ndim == 2 and p.shape[0] >= 1 and p.shape[1] == case.dim and bool(np.isfinite(p).all())
