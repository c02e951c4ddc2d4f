"""``check(points, faces)``: the verdict on one hull, assembled from the exact certificate.

The steps: validate the points (finite, shape (n, 2|3)); normalise the faces
with :func:`hullstress.contract.normalize_output` (a malformed output raises
:class:`~hullstress.errors.ContractViolation`, which the caller turns into
status ``fail``); rescale by a power of two (exactly); certify containment,
convexity and manifoldness (:func:`.certify.certify`); settle the exact
extreme set; compare with Qhull; grade the severity.

The exact extreme set comes from the checked hull itself when it passes all
three checks (its corners are then exactly the extreme points), otherwise
from Qhull's hull when that one passes them, otherwise (2D) an exact monotone
chain; in 3D with neither hull certified it is unknown (``n_extreme=None``).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from ..contract import FaceSet, normalize_output
from ..errors import ContractViolation
from ..verdict import Verdict
from ._geometry import Interior, distround, exact_scale
from .certify import Certificate, certify
from .extreme import distinct_rows, exact_extreme_2d, first_of_each, rows_in
from .lowdim import verdict_if_degenerate
from .predicates import orient2d, orient2d_value, orient3d, orient3d_value
from .qhull import QhullReference, certified_extremes, qhull_reference
from .rank import witness_simplex
from .severity import VOLUME_TOLERANCE_MULTIPLE, relative_magnitudes, severity

__all__ = ["check", "validate_points"]


def validate_points(points: Any) -> np.ndarray:
    """``points`` as a finite float64 (n, 2|3) array, or ValueError with a one-line message."""
    try:
        pts = np.asarray(points, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise ValueError(f"points must be a numeric array of shape (n, 2) or (n, 3): {exc}") from None
    if pts.ndim != 2 or pts.shape[1] not in (2, 3):
        raise ValueError(f"points must have shape (n, 2) or (n, 3), got {pts.shape}")
    if not np.isfinite(pts).all():
        bad = int(np.argmax(~np.isfinite(pts).all(axis=1)))
        raise ValueError(f"points must be finite, got {pts[bad].tolist()} at row {bad}")
    return pts


def _normalise(faces: Any, n: int, dim: int) -> np.ndarray | FaceSet:
    if isinstance(faces, FaceSet):
        if dim != 3:
            raise ContractViolation("a FaceSet describes a 3D surface, got 2D points")
        if faces.indices.size and (faces.indices.min() < 0 or faces.indices.max() >= n):
            bad = int(faces.indices.min() if faces.indices.min() < 0 else faces.indices.max())
            raise ContractViolation(f"faces holds index {bad}, out of range for {n} points")
        if np.any(faces.sizes < 3):
            raise ContractViolation(f"face {int(np.argmax(faces.sizes < 3))} has fewer than 3 vertices")
        return faces
    return normalize_output(faces, n, dim)


def _volume(points: np.ndarray, faces: np.ndarray | FaceSet) -> float:
    if points.shape[1] == 2:
        poly = np.asarray(faces)
        if len(poly) < 3:
            return 0.0
        a, b = points[poly], points[np.roll(poly, -1)]
        return math.fsum(np.nan_to_num(orient2d_value(a, b, a[0])).tolist()) / 2.0
    tri, _ = faces.fan_triangles()
    if not len(tri):
        return 0.0
    vals = orient3d_value(points[tri[:, 0]], points[tri[:, 1]], points[tri[:, 2]], points[tri[0, 0]])
    return math.fsum(np.nan_to_num(vals).tolist()) / 6.0


def _surface_area(points: np.ndarray, faces: np.ndarray | FaceSet) -> float:
    with np.errstate(all="ignore"):
        if points.shape[1] == 2:
            poly = np.asarray(faces)
            return float(np.linalg.norm(points[np.roll(poly, -1)] - points[poly], axis=1).sum())
        tri, _ = faces.fan_triangles()
        a, b, c = points[tri[:, 0]], points[tri[:, 1]], points[tri[:, 2]]
        return float(np.linalg.norm(np.cross(b - a, c - a), axis=1).sum() / 2.0)


def _on_boundary(points: np.ndarray, idx: np.ndarray, faces: np.ndarray | FaceSet) -> np.ndarray:
    """Which of ``points[idx]`` lie on a facet plane of a certified convex hull (exact)."""
    if not len(idx):
        return np.zeros(0, dtype=bool)
    if points.shape[1] == 2:
        poly = np.asarray(faces)
        a, b = points[poly], points[np.roll(poly, -1)]
        m = len(a)
        s = orient2d(np.tile(a, (len(idx), 1)), np.tile(b, (len(idx), 1)), np.repeat(points[idx], m, axis=0))
    else:
        tri, _ = faces.fan_triangles()
        m = len(tri)
        a, b, c = points[tri[:, 0]], points[tri[:, 1]], points[tri[:, 2]]
        q = len(idx)
        s = orient3d(np.tile(a, (q, 1)), np.tile(b, (q, 1)), np.tile(c, (q, 1)), np.repeat(points[idx], m, axis=0))
    return np.any(s.reshape(len(idx), m) == 0, axis=1)


def _detail(cert: Certificate, rel: dict[str, float], agreement: bool | None, qhull_note: str, n_missing: int) -> str:
    parts = []
    for name in ("containment", "convexity", "manifoldness"):
        reasons = cert.reasons.get(name) or []
        if reasons:
            text = "; ".join(reasons)
            if name == "containment" and "outside" in rel:
                text += f" (max {rel['outside']:.3g} DISTround)"
            if name == "convexity" and "reflex" in rel:
                text += f" (max {rel['reflex']:.3g} DISTround)"
            parts.append(f"{name}: {text}")
    if n_missing:
        parts.append(f"extreme points: {n_missing} missing")
    if agreement is False:
        parts.append(f"qhull: {qhull_note}")
    if agreement is None and qhull_note:
        parts.append(qhull_note)
    if not parts or (agreement is None and len(parts) == 1 and qhull_note):
        return "; ".join([f"ok: {len(cert.hull_vertices)} vertices, {cert.n_faces} {'faces' if cert.dim == 3 else 'edges'}"] + parts)
    if not parts:
        return f"ok: {len(cert.hull_vertices)} vertices, {cert.n_faces} {'faces' if cert.dim == 3 else 'edges'}"
    return "; ".join(parts)


def check(
    points: Any,
    faces: Any,
    *,
    reference: QhullReference | None = None,
    qhull: bool = True,
    max_offending: int = 20,
) -> Verdict:
    """Certify a hull of ``points`` with exact predicates and return the verdict.

    Parameters
    ----------
    points : array_like of shape (n, 2) or (n, 3)
        Finite coordinates.
    faces : sequence of int (2D), (m, 3) int array or list of polygons (3D), FaceSet
        The hull: in 2D the vertex indices counter-clockwise; in 3D faces
        counter-clockwise seen from outside.
    reference : QhullReference or None
        From :func:`~hullstress.checker.qhull_reference` on the same points;
        computed here when None and ``qhull`` is true.
    qhull : bool
        Compare with Qhull (``qhull_agreement`` is None when false and no
        reference is given).
    max_offending : int
        At most this many indices per kind in ``offending``.

    Returns
    -------
    Verdict
        See :class:`hullstress.verdict.Verdict`.  ``offending`` keys:
        ``containment`` (points outside), ``missing_extreme`` (extreme points
        that are not hull vertices, one index per coordinate),
        ``manifold_vertices`` (point indices); 3D: ``degenerate_faces``,
        ``reflex_faces``, ``flipped_faces``, ``manifold_faces`` (face
        indices); 2D: ``degenerate_edges``, ``flipped_edges`` (edge ``i``
        runs from the ``i``-th to the next hull vertex), ``reflex_vertices``
        (point indices).

    Raises
    ------
    ValueError
        ``points`` is not a finite (n, 2|3) array, or ``reference`` belongs to other points.
    ContractViolation
        ``faces`` breaks the output contract (wrong type, indices out of range).

    Examples
    --------
    >>> pts = np.array([[0.0, 0], [1, 0], [1, 1], [0, 1], [0.5, 0.5]])
    >>> v = check(pts, [0, 1, 2, 3])
    >>> v.ok, v.n_extreme, v.qhull_agreement
    (True, 4, True)
    >>> v = check(pts, [0, 1, 4, 3])  # cuts the corner (1, 1) off
    >>> v.ok, v.failed_checks, v.offending["containment"]
    (False, ('containment', 'qhull_agreement'), (2,))
    """
    pts = validate_points(points)
    lower = verdict_if_degenerate(pts, faces, reference=reference, max_offending=max_offending)
    if lower is not None:  # a point, a segment or a flat polygon: README "Lower-dimensional input"
        return lower
    n, dim = pts.shape
    normalised = _normalise(faces, n, dim)
    if reference is None and qhull:
        reference = qhull_reference(pts)
    if reference is not None and (reference.n_points != n or reference.dim != dim):
        raise ValueError(
            f"reference was computed for {reference.n_points} points in {reference.dim}D, got {n} points in {dim}D"
        )
    scaled, k = exact_scale(pts)
    if reference is not None and reference.simplex is not None:
        simplex = reference.simplex
    else:
        simplex = witness_simplex(scaled)
    rank = len(simplex) - 1
    interior = Interior.from_simplex(scaled[simplex]) if rank == dim else None
    cert = certify(scaled, normalised)
    dr = distround(pts)
    dr_scaled = distround(scaled)

    # The exact extreme set and what the hull's vertices are relative to it.
    ref_certified = reference is not None and reference.qhull_ok is True
    if cert.certified:
        extreme = cert.extreme
    elif reference is not None and reference.extreme is not None:
        extreme = reference.extreme
    elif dim == 2:
        extreme = exact_extreme_2d(scaled)
    elif interior is not None and reference is None:
        # Every extreme point is a vertex of this hull or a point outside it.  (With a
        # reference, qhull_reference has already tried this repair on all points.)
        candidates = [cert.hull_vertices, cert.outside]
        extreme = certified_extremes(scaled, np.concatenate(candidates), interior)
    else:
        extreme = None
    hull_rows = distinct_rows(scaled, cert.hull_vertices)
    n_extreme = missing = None
    if extreme is not None:
        extreme_rows = distinct_rows(scaled, extreme)
        n_extreme = len(extreme_rows)
        rep = first_of_each(scaled, extreme)
        missing = rep[~rows_in(scaled[rep], hull_rows)]
        if cert.boundary_nonextreme is not None:
            n_boundary = len(distinct_rows(scaled, cert.boundary_nonextreme))
        else:
            hv = first_of_each(scaled, cert.hull_vertices)
            others = hv[~rows_in(scaled[hv], extreme_rows)]
            if ref_certified:
                others = others[_on_boundary(scaled, others, reference.faces)]
            n_boundary = len(others)
    else:
        n_boundary = len(distinct_rows(scaled, cert.boundary_nonextreme)) if cert.boundary_nonextreme is not None else 0

    # Qhull agreement.
    agreement: bool | None = None
    rel = relative_magnitudes(cert.magnitudes, dr_scaled)
    qhull_note = ""
    if reference is not None and reference.vertices is not None and cert.certified and not ref_certified:
        # The checked hull is proven exact and Qhull's is proven wrong: a disagreement
        # would be Qhull's failure, recorded as qhull_ok=False, not this hull's.
        agreement = None
        qhull_note = "qhull agreement not judged: Qhull's own hull fails the exact checks"
    elif reference is not None and reference.vertices is not None:
        q_rows = distinct_rows(scaled, reference.vertices)
        if extreme is not None:
            xh = hull_rows[rows_in(hull_rows, extreme_rows)]
            xq = q_rows[rows_in(q_rows, extreme_rows)]
        else:
            xh, xq = hull_rows, q_rows
        same_vertices = len(xh) == len(xq) and bool(rows_in(xh, xq).all())
        vol_h = cert.volume
        vol_q = _volume(scaled, reference.faces)
        area_q = _surface_area(scaled, reference.faces)
        diff = abs(vol_h - vol_q)
        tol = VOLUME_TOLERANCE_MULTIPLE * dr_scaled * area_q + 2.0**-40 * abs(vol_q)
        same_volume = diff <= tol
        agreement = bool(same_vertices and same_volume)
        if not agreement:
            notes = []
            if not same_vertices:
                notes.append(f"{len(xh)} extreme vertices against Qhull's {len(xq)}")
            if not same_volume:
                notes.append(f"volume differs by {diff / vol_q if vol_q else diff:.3g} (relative)")
                rel["qhull_volume"] = relative_magnitudes({"v": diff / area_q if area_q > 0 else diff}, dr_scaled)["v"]
            qhull_note = ", ".join(notes)
    failed = not cert.certified or agreement is False
    sev, worst = severity(rel, failed=failed, topological=not cert.manifoldness)

    offending = {
        key: tuple(int(x) for x in np.asarray(val)[:max_offending])
        for key, val in cert.offending.items()
        if len(val)
    }
    if missing is not None and len(missing):
        offending["missing_extreme"] = tuple(int(x) for x in missing[:max_offending])
    with np.errstate(over="ignore"):
        volume = float(np.ldexp(cert.volume, -k * dim))
    return Verdict(
        convexity=cert.convexity,
        containment=cert.containment,
        manifoldness=cert.manifoldness,
        qhull_agreement=agreement,
        severity=sev,
        max_violation=float(worst),
        distround=dr,
        n_faces=cert.n_faces,
        n_hull_vertices=len(cert.hull_vertices),
        n_extreme=n_extreme,
        n_missing_extreme=0 if missing is None else len(missing),
        n_boundary_nonextreme=n_boundary,
        n_outside=len(cert.outside),
        n_nonconvex_edges=cert.n_nonconvex_edges,
        n_degenerate_faces=cert.n_degenerate_faces,
        volume=volume,
        qhull_volume=None if reference is None else reference.volume,
        qhull_options=None if reference is None else reference.options,
        qhull_ok=None if reference is None else reference.qhull_ok,
        affine_rank=rank,
        offending=offending,
        detail=_detail(cert, rel, agreement, qhull_note, 0 if missing is None else len(missing)),
    )
