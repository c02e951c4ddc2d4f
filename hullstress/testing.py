"""Assertions for your own test suite: certify a hull, compare two hulls.

Both helpers run hullstress's exact checker (:func:`hullstress.checker.check`)
and raise ``AssertionError`` whose message shows both sides: what a hull of
the points must be (extreme points, Qhull's volume) next to what the given
surface is (faces, vertices, volume), which checks failed, and the offending
point indices with their coordinates.

>>> import numpy as np
>>> from scipy.spatial import ConvexHull
>>> from hullstress.testing import assert_valid_hull
>>> pts = np.random.default_rng(0).standard_normal((30, 2))
>>> assert_valid_hull(pts, ConvexHull(pts).vertices).ok
True
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

import numpy as np

from .contract import FaceSet, normalize_output
from .errors import ContractViolation, UsageError
from .verdict import Verdict
from .records import Severity

__all__ = ["assert_valid_hull", "assert_same_hull"]

_MAX_SHOWN = 10  # items listed per offending group or vertex difference


def _as_points(points: Any) -> np.ndarray:
    try:
        arr = np.ascontiguousarray(points, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise UsageError(
            f"points must be an (n, 2) or (n, 3) array of floats, got {type(points).__name__}: {exc}"
        ) from None
    if arr.ndim != 2 or arr.shape[1] not in (2, 3):
        raise UsageError(f"points must have shape (n, 2) or (n, 3), got {arr.shape}")
    return arr


def _normalize(points: np.ndarray, faces: Any, label: str, *, min_face_size: int = 3) -> np.ndarray | FaceSet:
    __tracebackhide__ = True
    try:
        return normalize_output(faces, len(points), points.shape[1], min_face_size=min_face_size)
    except ContractViolation as exc:
        raise AssertionError(f"{label} breaks the output contract: {exc}") from None


def _coords(points: np.ndarray, i: int) -> str:
    if 0 <= i < len(points):
        return "(" + ", ".join(repr(float(x)) for x in points[i]) + ")"
    return "(out of range)"


def _measure(dim: int) -> str:
    return "area" if dim == 2 else "volume"


def _face_text(faces: np.ndarray | FaceSet, i: int) -> str:
    if isinstance(faces, FaceSet):
        return f"face {i} {faces.face(i).tolist()}" if 0 <= i < faces.n_faces else f"face {i} (out of range)"
    k = len(faces)  # 2D: "face" i is the edge from vertex i to vertex i + 1
    if not 0 <= i < k:
        return f"edge {i} (out of range)"
    return f"edge {i} {[int(faces[i]), int(faces[(i + 1) % k])]}"


def _offending_lines(
    points: np.ndarray, faces: np.ndarray | FaceSet, offending: Mapping[str, Any]
) -> list[str]:
    lines = []
    for key in sorted(offending):
        idx = [int(i) for i in offending[key]]
        if not idx:
            continue
        # Keys ending in "faces" hold face indices; the others hold point indices (verdict.py).
        if key.endswith("faces"):
            items = [_face_text(faces, i) for i in idx[:_MAX_SHOWN]]
        else:
            items = [f"point {i} {_coords(points, i)}" for i in idx[:_MAX_SHOWN]]
        more = f", ... ({len(idx) - _MAX_SHOWN} more)" if len(idx) > _MAX_SHOWN else ""
        lines.append(f"  offending {key}: " + ", ".join(items) + more)
    return lines


def _expected_line(points: np.ndarray, verdict: Verdict) -> str:
    dim = points.shape[1]
    shape = (
        "simple counter-clockwise polygon"
        if dim == 2
        else "closed convex surface, counter-clockwise seen from outside,"
    )
    extreme = "all" if verdict.n_extreme is None else f"all {verdict.n_extreme}"
    text = f"  expected: a {shape} through {extreme} extreme points, containing every point"
    if verdict.qhull_volume is not None:
        text += f"; Qhull ({verdict.qhull_options}) {_measure(dim)} {verdict.qhull_volume!r}"
    return text


def _got_line(points: np.ndarray, verdict: Verdict) -> str:
    dim = points.shape[1]
    size = (
        f"a polygon on {verdict.n_hull_vertices} vertices"
        if dim == 2
        else f"{verdict.n_faces} faces on {verdict.n_hull_vertices} vertices"
    )
    return (
        f"  got:      {size}, {_measure(dim)} {verdict.volume!r}; "
        f"{verdict.n_missing_extreme} extreme point(s) missing, {verdict.n_outside} point(s) outside, "
        f"{verdict.n_nonconvex_edges} non-convex edge(s), {verdict.n_degenerate_faces} degenerate face(s), "
        f"{verdict.n_boundary_nonextreme} boundary non-extreme vertex(es) (allowed)"
    )


def assert_valid_hull(
    points: Any,
    faces: Any,
    *,
    qhull: bool = True,
    max_offending: int = 20,
) -> Verdict:
    """Assert that ``faces`` is a valid convex hull of ``points``, certified exactly.

    Parameters
    ----------
    points : array_like of shape (n, 2) or (n, 3), float
    faces : array_like
        In 2D, vertex indices counter-clockwise; in 3D, an (m, 3) integer array
        of triangles counter-clockwise seen from outside, or a list of polygons
        (docs/design.md's output contract).
    qhull : bool, default True
        Also require agreement with Qhull's extreme vertex set and volume.
    max_offending : int, default 20
        How many offending indices per check the checker keeps.

    Returns
    -------
    Verdict
        The checker's verdict, when every check passed.

    Raises
    ------
    AssertionError
        When ``faces`` breaks the output contract or any check fails.  The
        message lists the failed checks, what a hull of ``points`` must be
        next to what ``faces`` is, and offending indices with coordinates.
    UsageError
        When ``points`` is not an (n, 2) or (n, 3) float array.

    Examples
    --------
    >>> import numpy as np
    >>> square = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
    >>> assert_valid_hull(square, [0, 1, 2, 3]).ok
    True
    >>> assert_valid_hull(square, [0, 3, 2, 1])  # clockwise
    Traceback (most recent call last):
    ...
    AssertionError: not a valid convex hull of 4 points in 2D: failed ...
    """
    __tracebackhide__ = True  # pytest shows the caller's line, not this helper's internals
    from .checker import check  # imported here so that importing this module stays cheap

    pts = _as_points(points)
    # The same contract as ``check``: faces of one or two vertices are the right answer for a
    # one-point or collinear input (README "Lower-dimensional input"), so the face size is
    # left to ``check``, which knows the rank (issue 33, F5).
    normalized = _normalize(pts, faces, "faces", min_face_size=1)
    try:
        verdict = check(pts, normalized, qhull=qhull, max_offending=max_offending)
    except ContractViolation as exc:
        raise AssertionError(f"faces breaks the output contract: {exc}") from None
    if verdict.ok:
        return verdict
    dim = pts.shape[1]
    lines = [
        f"not a valid convex hull of {len(pts)} points in {dim}D: failed {', '.join(verdict.failed_checks)}",
        f"  checker: {verdict.detail}" if verdict.detail else "  checker: (no detail)",
        _expected_line(pts, verdict),
        _got_line(pts, verdict),
    ]
    if verdict.severity != Severity.NONE:
        from .checker.severity import describe_severity

        shown = describe_severity(verdict.severity, verdict.max_violation, manifoldness=verdict.manifoldness,
                                  detail=verdict.detail)
        lines.append(f"  worst violation: {shown}; DISTround {verdict.distround:.3g}")
    lines += _offending_lines(pts, normalized, verdict.offending)
    raise AssertionError("\n".join(lines))


def _vertex_coordinates(points: np.ndarray, faces: np.ndarray | FaceSet) -> dict[tuple[float, ...], int]:
    """Coordinates of the surface's vertices -> the lowest index with those coordinates."""
    used = faces.vertex_set() if isinstance(faces, FaceSet) else np.unique(faces)
    table: dict[tuple[float, ...], int] = {}
    for i in used.tolist():
        table.setdefault(tuple(points[i].tolist()), i)
    return table


def _side_line(label: str, points: np.ndarray, verdict: Verdict, n_vertices: int) -> str:
    state = "valid" if verdict.ok else f"NOT a valid hull (failed {', '.join(verdict.failed_checks)})"
    text = (
        f"  {label}: {state}; {n_vertices} distinct vertices by coordinates, "
        f"{verdict.n_boundary_nonextreme} of them boundary non-extreme, "
        f"{_measure(points.shape[1])} {verdict.volume!r}"
    )
    if not verdict.ok and verdict.detail:
        text += f"; {verdict.detail}"
    return text


def _difference_line(points: np.ndarray, label: str, only: dict[tuple[float, ...], int]) -> str:
    items = [f"{i} {_coords(points, i)}" for i in sorted(only.values())[:_MAX_SHOWN]]
    more = f", ... ({len(only) - _MAX_SHOWN} more)" if len(only) > _MAX_SHOWN else ""
    return f"  vertices only in {label}: " + (", ".join(items) + more if items else "none")


def assert_same_hull(
    points: Any,
    faces_a: Any,
    faces_b: Any,
    *,
    rtol: float = 1e-9,
) -> None:
    """Assert that two outputs are the same convex hull of ``points``.

    Both outputs are certified with the exact checks (convexity, containment,
    manifoldness; Qhull is not consulted).  The convex hull of a point set is
    unique, so two outputs that both pass bound the same polytope: the same
    extreme vertices by coordinates and the same volume.  They may still
    differ in how flat faces are triangulated, in which of several identical
    rows stands for a point, and in boundary vertices that are not extreme;
    none of that counts as a difference.  The volumes (areas) are compared
    as well, to ``rtol``, because they are summed in floating point.

    Parameters
    ----------
    points : array_like of shape (n, 2) or (n, 3), float
    faces_a, faces_b : array_like
        Two outputs under docs/design.md's output contract.
    rtol : float, default 1e-9
        Relative tolerance for the volume (area) comparison.

    Raises
    ------
    AssertionError
        When either output breaks the contract or is not a valid hull, or the
        volumes differ.  The message shows both sides: validity, vertex counts,
        volumes, and the vertices (with coordinates) found on one side only.
    UsageError
        When ``points`` is not an (n, 2) or (n, 3) float array.

    Examples
    --------
    >>> import numpy as np
    >>> square = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0], [1.0, 0.0]])
    >>> assert_same_hull(square, [0, 1, 2, 3], [3, 0, 4, 2])  # index 4 duplicates 1
    >>> assert_same_hull(square, [0, 1, 2, 3], [0, 1, 2])
    Traceback (most recent call last):
    ...
    AssertionError: not the same hull: b is not a valid hull...
    """
    __tracebackhide__ = True  # pytest shows the caller's line, not this helper's internals
    from .checker import check

    pts = _as_points(points)
    fa = _normalize(pts, faces_a, "a")
    fb = _normalize(pts, faces_b, "b")
    va = check(pts, fa, qhull=False)
    vb = check(pts, fb, qhull=False)
    problems = [f"{label} is not a valid hull" for label, v in (("a", va), ("b", vb)) if not v.ok]
    if not problems and not math.isclose(va.volume, vb.volume, rel_tol=rtol, abs_tol=0.0):
        # Both certified, so this can only be rounding beyond rtol (or a checker bug).
        problems.append(f"{_measure(pts.shape[1])}s differ beyond rtol={rtol:g}")
    if not problems:
        return
    ca, cb = _vertex_coordinates(pts, fa), _vertex_coordinates(pts, fb)
    only_a = {c: i for c, i in ca.items() if c not in cb}
    only_b = {c: i for c, i in cb.items() if c not in ca}
    lines = [
        "not the same hull: " + "; ".join(problems),
        _side_line("a", pts, va, len(ca)),
        _side_line("b", pts, vb, len(cb)),
        _difference_line(pts, "a", only_a),
        _difference_line(pts, "b", only_b),
    ]
    raise AssertionError("\n".join(lines))
