"""``check(points, faces)``: the verdict on one hull, assembled from the exact certificate.

The steps: validate the points (finite, shape (n, 2|3)); normalise the faces
with :func:`hullstress.contract.normalize_output` (a malformed output raises
:class:`~hullstress.errors.ContractViolation`, which the caller turns into
status ``fail``); rescale by a power of two (exactly); certify containment,
convexity and manifoldness (:func:`.certify.certify`); settle the exact
extreme set; compare with Qhull; grade the severity.

When the faces are exactly the face set of a Qhull reference whose own hull
passed the exact checks, that certificate is the certificate of the faces
(the same faces over the same points), so it is reused instead of
certifying them a second time; everything after it runs unchanged.  The
verdict is identical either way (``tests/test_checker_regressions.py`` runs
both paths on every case of the quick profile).

The exact extreme set comes from the checked hull itself when it passes all
three checks (its corners are then exactly the extreme points), otherwise
from Qhull's hull when that one passes them, otherwise (2D) an exact monotone
chain; in 3D with neither hull certified it is unknown (``n_extreme=None``).
"""

from __future__ import annotations

from fractions import Fraction
from typing import Any

import numpy as np

from ..contract import FaceSet, normalize_output
from ..errors import ContractViolation
from ..verdict import AGREE, DISAGREE, QHULL_WRONG, Verdict
from ._geometry import Interior, distround, exact_scale
from .certify import Certificate, certify
from .extreme import Coordinates, exact_extreme_2d
from .lowdim import verdict_if_degenerate
from .measure import compare, to_float
from .predicates import orient2d, orient3d
from .qhull import QhullReference, certified_extremes, qhull_reference
from .rank import witness_simplex
from .severity import VOLUME_TOLERANCE_MULTIPLE, relative_magnitudes, severity

__all__ = ["check", "validate_points"]

#: (point, facet) rows held at once by the on-boundary test.
_CHUNK = 1_000_000


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
    if isinstance(faces, FaceSet) and dim != 3:
        raise ContractViolation("a FaceSet describes a 3D surface, got 2D points")
    return normalize_output(faces, n, dim)  # a FaceSet is validated like any other output (F6)


def _on_boundary(points: np.ndarray, idx: np.ndarray, faces: np.ndarray | FaceSet) -> np.ndarray:
    """Which of ``points[idx]`` lie on a facet plane of a certified convex hull (exact), in chunks."""
    out = np.zeros(len(idx), dtype=bool)
    if not len(idx):
        return out
    if points.shape[1] == 2:
        poly = np.asarray(faces)
        planes = [points[poly], points[np.roll(poly, -1)]]
        side = orient2d
    else:
        tri, _ = faces.fan_triangles()
        planes = [points[tri[:, 0]], points[tri[:, 1]], points[tri[:, 2]]]
        side = orient3d
    m = len(planes[0])
    rows = max(1, _CHUNK // max(m, 1))
    for start in range(0, len(idx), rows):
        part = idx[start : start + rows]
        q = len(part)
        s = side(*[np.tile(p, (q, 1)) for p in planes], np.repeat(points[part], m, axis=0))
        out[start : start + q] = np.any(s.reshape(q, m) == 0, axis=1)
    return out


def _detail(cert: Certificate, rel: dict[str, float], agreement: str | None, qhull_note: str, n_missing: int) -> str:
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
    if agreement == DISAGREE:
        parts.append(f"qhull: {qhull_note}")
    elif qhull_note:
        parts.append(qhull_note)
    if not parts or (agreement != DISAGREE and len(parts) == 1 and qhull_note):
        ok = f"ok: {len(cert.hull_vertices)} vertices, {cert.n_faces} {'faces' if cert.dim == 3 else 'edges'}"
        return "; ".join([ok] + parts)
    return "; ".join(parts)


def _same_coordinates(points: np.ndarray, a: np.ndarray, b: np.ndarray) -> bool:
    """Whether two index sets without repeated coordinates name the same coordinates."""
    if len(a) != len(b):
        return False
    if np.array_equal(np.sort(a), np.sort(b)):
        return True
    pa, pb = points[a], points[b]
    pa, pb = pa[np.lexsort(pa.T[::-1])], pb[np.lexsort(pb.T[::-1])]
    return bool(np.all(pa == pb))


def _agreement(
    cert: Certificate, reference: QhullReference, same_vertices: bool, n_mine: int, n_theirs: int
) -> tuple[str, str, float | None]:
    """Qhull agreement: the value, a note for the detail line, and the volume gap in DISTround (if beyond).

    ``same_vertices``: whether the hull's extreme vertices and Qhull's are the
    same coordinates (``n_mine`` and ``n_theirs`` of them).
    """
    if not reference.qhull_ok:
        return QHULL_WRONG, "qhull agreement not judged: Qhull's own hull fails the exact checks", None
    if cert is reference.certificate:  # Qhull's own faces
        return AGREE, "", None
    tol = reference.tolerance()
    same_volume, gap = compare(cert.measure, reference.certificate.measure, tol)
    if same_vertices and same_volume:
        return AGREE, "", None
    notes = []
    if not same_vertices:
        notes.append(f"{n_mine} extreme vertices against Qhull's {n_theirs}")
    rel_gap = None
    if not same_volume:
        q = reference.certificate.measure
        q_abs = abs(q.exact_sum()) / q.denominator
        relative = to_float(gap / q_abs) if q_abs else to_float(gap)
        notes.append(f"volume differs by {relative:.3g} (relative)")
        # The gap as a mean thickness over Qhull's surface, in DISTround: tol is that many DISTround thick.
        rel_gap = to_float(gap * Fraction(VOLUME_TOLERANCE_MULTIPLE) / tol) if tol else float("inf")
    return DISAGREE, ", ".join(notes), rel_gap


def check(
    points: Any,
    faces: Any,
    *,
    reference: QhullReference | None = None,
    qhull: bool = True,
    max_offending: int = 20,
    reuse_reference: bool = True,
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
    reuse_reference : bool
        When ``faces`` is exactly the face set of a reference whose own hull
        passed the exact checks, reuse that certificate instead of
        certifying the same faces again (the verdict is the same; false
        forces the second certification, for tests).

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
    (True, 4, 'agree')
    >>> v = check(pts, [0, 1, 4, 3])  # cuts the corner (1, 1) off
    >>> v.ok, v.failed_checks, v.offending["containment"]
    (False, ('containment', 'qhull_agreement'), (2,))
    """
    pts = validate_points(points)
    n, dim = pts.shape
    if reference is None and qhull:
        # Built first: its witness simplex settles the rank exactly, so the
        # degeneracy test below needs no certificate of its own.
        built = qhull_reference(pts)
        if built.simplex is not None and len(built.simplex) - 1 >= dim:
            reference = built
    lower = verdict_if_degenerate(pts, faces, reference=reference, max_offending=max_offending)
    if lower is not None:  # a point, a segment or a flat polygon: docs/lower-dimensional.md
        return lower
    normalised = _normalise(faces, n, dim)
    if reference is None and qhull:
        reference = built
    if reference is not None and (reference.n_points != n or reference.dim != dim):
        raise ValueError(
            f"reference was computed for {reference.n_points} points in {reference.dim}D, got {n} points in {dim}D"
        )
    if reference is not None and reference.scaled is not None and (
        reference.points is pts or np.array_equal(reference.points, pts)
    ):
        scaled, k = reference.scaled, reference.exponent
    elif reference is not None and reference.points is not None:
        raise ValueError("reference was computed for other points (same shape, different coordinates)")
    else:
        scaled, k = exact_scale(pts)
    # verdict_if_degenerate settled the rank exactly (from the reference's witness
    # simplex or its own certificate): past it, the points are full-dimensional.
    rank = dim
    if reuse_reference and reference is not None and reference.qhull_ok and reference.same_faces(normalised):
        # The same faces over the same points: the verdict is a function of the reference alone.
        if "own verdict" not in reference.memo:
            reference.memo["own verdict"] = _assemble(pts, scaled, k, rank, reference.certificate, reference, max_offending)
        verdict = object.__new__(Verdict)  # a shallow copy (frozen record), with a fresh offending dict
        verdict.__dict__.update(reference.memo["own verdict"].__dict__, offending={})
        return verdict
    return _assemble(pts, scaled, k, rank, certify(scaled, normalised), reference, max_offending)


def _assemble(
    pts: np.ndarray,
    scaled: np.ndarray,
    k: int,
    rank: int,
    cert: Certificate,
    reference: QhullReference | None,
    max_offending: int,
) -> Verdict:
    """The verdict from a certificate: extreme set, Qhull agreement, severity, offending indices."""
    dim = pts.shape[1]
    dr = reference.distround if reference is not None else distround(pts)
    dr_scaled = dr if k == 0 else distround(scaled)

    # The exact extreme set and what the hull's vertices are relative to it.
    ref_certified = reference is not None and reference.qhull_ok is True
    if cert.certified:
        extreme = cert.extreme
    elif reference is not None and reference.extreme is not None:
        extreme = reference.extreme
    elif dim == 2:
        extreme = exact_extreme_2d(scaled)
    elif rank == dim and reference is None:
        # Every extreme point is a vertex of this hull or a point outside it.  (With a
        # reference, qhull_reference has already tried this repair on all points.)
        interior = Interior.from_simplex(scaled[witness_simplex(scaled)])
        extreme = certified_extremes(scaled, np.concatenate([cert.hull_vertices, cert.outside]), interior)
    else:
        extreme = None
    has_reference = reference is not None and reference.vertices is not None
    if cert.certified:
        # A certified surface never visits one coordinate twice (it would wrap twice
        # around its interior point there), nor does Qhull's when certified: index
        # sets are coordinate sets.
        n_extreme, missing = len(extreme), extreme[:0]
        n_boundary = len(cert.boundary_nonextreme)
        if has_reference and ref_certified and cert is not reference.certificate:
            theirs = reference.certificate.extreme
            same = _same_coordinates(scaled, extreme, theirs)
            n_mine, n_theirs = len(extreme), len(theirs)
        else:
            same, n_mine, n_theirs = True, 0, 0
    else:
        q_vertices = reference.vertices if has_reference else np.zeros(0, np.int64)
        ids = Coordinates(scaled, cert.hull_vertices, q_vertices, np.zeros(0, np.int64) if extreme is None else extreme)
        hull = ids.groups(cert.hull_vertices)
        n_extreme = missing = extreme_ids = None
        if extreme is not None:
            extreme_ids = ids.groups(extreme)
            n_extreme = len(extreme_ids)
            rep = ids.first_of_each(extreme)
            missing = rep[~ids.within(rep, hull)]
            # (cert.boundary_nonextreme is known for certified surfaces only.)
            hv = ids.first_of_each(cert.hull_vertices)
            others = hv[~ids.within(hv, extreme_ids)]
            if ref_certified:
                others = others[_on_boundary(scaled, others, reference.faces)]
            n_boundary = len(others)
        else:
            n_boundary = 0
        same, n_mine, n_theirs = True, 0, 0
        if has_reference:
            theirs = ids.groups(q_vertices)
            mine = hull
            if extreme_ids is not None:
                # (groups are sorted distinct ids: no unique pass needed)
                mine = np.intersect1d(hull, extreme_ids, assume_unique=True)
                theirs = np.intersect1d(theirs, extreme_ids, assume_unique=True)
            same, n_mine, n_theirs = np.array_equal(mine, theirs), len(mine), len(theirs)

    # Qhull agreement.
    agreement: str | None = None
    qhull_note = ""
    rel = relative_magnitudes(cert.magnitudes, dr_scaled)
    if has_reference:
        agreement, qhull_note, gap = _agreement(cert, reference, same, n_mine, n_theirs)
        if gap is not None:
            rel["qhull_volume"] = gap
    failed = not cert.certified or agreement == DISAGREE
    sev, worst = severity(rel, failed=failed, topological=cert.structural)

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
