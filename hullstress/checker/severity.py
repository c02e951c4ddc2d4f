"""Severity of a verdict's violations, in units of Qhull's DISTround for the input.

Every geometric violation has a distance: a point outside a facet (its
distance above the facet's plane), a reflex edge (the neighbouring face's far
vertex above this face's plane), a non-planar or non-convex polygon (a vertex
off its plane or outside an edge's line), a face the interior point is above
(the interior point's distance above it), a Qhull volume disagreement (the
volume difference divided by Qhull's surface area: a mean thickness).  Divided
by DISTround, the largest is ``max_violation``:

* ``roundoff``: ``max_violation <= ROUNDOFF_MULTIPLE`` (what rounding in a
  correct float algorithm can produce, Qhull's own tolerance being a few
  DISTround);
* ``gross``: beyond, or any manifoldness failure (a hole, a repeated or
  missing face is not a rounding effect);
* ``none``: no check failed.

Degenerate faces without a distance (three distinct but collinear vertices, a
zero-length edge) count as magnitude 0: zero-area slivers are the typical
rounding artefact.
"""

from __future__ import annotations

import math
from collections.abc import Mapping

__all__ = ["ROUNDOFF_MULTIPLE", "VOLUME_TOLERANCE_MULTIPLE", "severity", "relative_magnitudes", "severity_reason",
           "describe_severity"]

#: Violations up to this many DISTround are ``roundoff``, beyond are ``gross``.
ROUNDOFF_MULTIPLE = 10.0
#: Qhull volume agreement: |V - V_qhull| <= this * DISTround * Qhull's surface area,
#: compared exactly (:func:`.measure.compare`), so with no slack for float sums.
VOLUME_TOLERANCE_MULTIPLE = 10.0


def relative_magnitudes(magnitudes: Mapping[str, float], unit: float) -> dict[str, float]:
    """Each distance divided by ``unit`` (DISTround); inf for a positive distance when unit is 0.

    Examples
    --------
    >>> relative_magnitudes({"outside": 3e-16, "degenerate": 0.0}, 1e-16)
    {'outside': 3.0, 'degenerate': 0.0}
    """
    out = {}
    for key, value in magnitudes.items():
        value = float(value) if math.isfinite(value) else math.inf
        if value <= 0.0:
            out[key] = 0.0
        elif unit > 0.0:
            out[key] = value / unit
        else:
            out[key] = math.inf
    return out


def severity(relative: Mapping[str, float], *, failed: bool, topological: bool) -> tuple[str, float]:
    """The verdict's severity and ``max_violation``.

    Parameters
    ----------
    relative : mapping of str to float
        Violation magnitudes in DISTround units (:func:`relative_magnitudes`).
    failed : bool
        Whether any check failed.
    topological : bool
        Whether manifoldness failed.

    Returns
    -------
    severity : {"none", "roundoff", "gross"}
    max_violation : float

    Examples
    --------
    >>> severity({"outside": 2.0}, failed=True, topological=False)
    ('roundoff', 2.0)
    >>> severity({}, failed=True, topological=True)
    ('gross', 0.0)
    >>> severity({}, failed=False, topological=False)
    ('none', 0.0)
    """
    worst = max(relative.values(), default=0.0)
    if not failed:
        return "none", worst
    if topological or worst > ROUNDOFF_MULTIPLE:
        return "gross", worst
    return "roundoff", worst


def severity_reason(grade: str, max_violation: float | None, *, manifoldness: object = True, detail: str = "") -> str:
    """Why a verdict has its severity, in a few words: what a reader needs next to "gross" or "roundoff".

    ``roundoff`` is always a distance (at most :data:`ROUNDOFF_MULTIPLE`
    DISTround); ``gross`` is either a distance beyond it or a structural
    failure no rounding explains, whatever the distances: a wrong orientation
    (faces inward, a clockwise polygon), a surface wrapping more than once, a
    surface that is not a closed manifold.

    Parameters
    ----------
    grade : str
        The severity (``none``, ``roundoff``, ``gross``).
    max_violation : float or None
        The worst violation in DISTround units.
    manifoldness : object
        The manifoldness check's result (False: it failed).
    detail : str
        The verdict's detail line (a row's ``reason``): names the structural failure.

    Returns
    -------
    str
        ``""`` for ``none`` or an unknown grade.

    Examples
    --------
    >>> severity_reason("roundoff", 0.0387)
    '0.0387 x DISTround'
    >>> severity_reason("gross", 0.0387, manifoldness=False, detail="manifoldness: clockwise orientation (signed area negative)")
    'wrong orientation, 0.0387 x DISTround'
    >>> severity_reason("gross", 31.0)
    '31 x DISTround'
    """
    distance = None
    try:
        value = float(max_violation) if max_violation is not None else None
    except (TypeError, ValueError):
        value = None
    if value is not None and not math.isnan(value):
        distance = f"{value:.3g} x DISTround"
    if grade == "roundoff":
        return distance or ""
    if grade != "gross":
        return ""
    if value is not None and value > ROUNDOFF_MULTIPLE:
        return distance or ""
    text = detail or ""
    if "orientation" in text:
        why = "wrong orientation"
    elif "wraps" in text:
        why = "the surface wraps more than once"
    elif manifoldness is False or str(manifoldness) == "False":
        why = "not a closed manifold"
    else:
        why = "structural"
    return f"{why}, {distance}" if distance else why


def describe_severity(grade: str, max_violation: float | None, *, manifoldness: object = True, detail: str = "") -> str:
    """``gross (wrong orientation, 0.0387 x DISTround)`` or ``roundoff (0.04 x DISTround)``: the grade with its reason.

    Examples
    --------
    >>> describe_severity("roundoff", 0.04)
    'roundoff (0.04 x DISTround)'
    >>> describe_severity("none", 0.0)
    'none'
    """
    why = severity_reason(grade, max_violation, manifoldness=manifoldness, detail=detail)
    return f"{grade} ({why})" if why else grade
