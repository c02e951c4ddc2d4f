"""Qhull (through scipy) as a witness: its hull, its options, its own exact health.

:func:`qhull_reference` runs ``scipy.spatial.ConvexHull`` once per case with
default options and, when Qhull raises, retries with the option sets of
:data:`RETRY_OPTIONS` in order, recording which produced the reference (and
every failed attempt).  It then certifies Qhull's own output with the same
exact checks as any other hull (``qhull_ok``): Qhull is a witness, not the
judge.  The certificate is kept with the reference, so a hull that is the
same face set as a certified reference needs no second certification (see
:func:`hullstress.checker.check`).  It never raises: every problem (NaN,
wrong shape, too few points, every option set failing) is recorded in
``error``.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, field
from fractions import Fraction
from typing import Any

import numpy as np
from scipy.spatial import ConvexHull, QhullError

from ..contract import FaceSet
from ._geometry import Interior, axis_extents, cross3, distround, exact_scale, triangle_array
from ._unique import unique_ints
from .certify import Certificate, certify
from .extreme import exact_extreme_2d, first_of_each
from .measure import canonical_triangles, rotated_to_lowest, surface_area, triangle_keys
from .predicates import orient3d_mean
from .rank import witness_simplex
from .severity import VOLUME_TOLERANCE_MULTIPLE

__all__ = [
    "QhullReference",
    "qhull_reference",
    "certified_extremes",
    "face_set_key",
    "volume_tolerance",
    "DEFAULT_OPTIONS",
    "RETRY_OPTIONS",
    "REPAIR_OPTIONS",
]

#: What scipy runs by default: it always adds ``Qt`` (triangulated output) unless ``QJ`` is given.
DEFAULT_OPTIONS = "Qt"
#: Option sets tried in order after the default raised, as passed to scipy.
#: ``Q12`` allows wide facets and dupridges (needed e.g. for ``rbox 10000 s Z1
#: G1e-13``); ``QbB`` scales the input to the unit cube first, which recovers
#: "initial simplex is flat" on offset, mixed-magnitude and nearly flat inputs
#: that are exactly full-dimensional; ``QJ`` joggles the input and succeeds on
#: any non-empty input (even flat or repeated points) at the price of
#: non-extreme vertices; ``QbB QJ`` is the only set that survives magnitudes
#: spanning 600 decades.  Every set is valid for a convex hull (``Qz``, an
#: earlier member, is a Delaunay-only option and ended in an option error).
RETRY_OPTIONS = ("Q12", "QbB", "QbB Q12", "QJ", "QbB QJ")
#: Option sets for :func:`certified_extremes` (Qhull on rescaled candidate points).
REPAIR_OPTIONS = ("", "QJ")


def options_label(options: str) -> str:
    """The Qhull options scipy actually runs for ``options`` (it adds ``Qt`` unless ``QJ`` is given).

    Examples
    --------
    >>> options_label(""), options_label("QbB Q12"), options_label("QJ")
    ('Qt', 'Qt QbB Q12', 'QJ')
    """
    if "QJ" in options.split():
        return options
    return f"{DEFAULT_OPTIONS} {options}".strip()


@dataclass(frozen=True, eq=False)
class QhullReference:
    """Qhull's hull of one input, computed once and reused for every output checked.

    Attributes
    ----------
    vertices : ndarray of int64 or None
        Qhull's vertex indices (counter-clockwise in 2D); None when every
        option set failed or the input is invalid.
    faces : ndarray of int64 or FaceSet or None
        Qhull's hull in the checker's form: the 2D vertex cycle, or the 3D
        triangles oriented outward by Qhull's own facet normals.
    volume : float or None
        The volume (area in 2D) of Qhull's faces over the input points,
        computed here like any hull's (:mod:`.measure`): independent of face
        order, not Qhull's own float figure (which, after ``QbB`` or ``QJ``,
        describes scaled or joggled points).
    options : str or None
        The options that produced the reference, as Qhull ran them (``"Qt"``,
        ``"Qt Q12"``, ``"Qt QbB"``, ``"QJ"``, ...), with a note when Qhull ran
        on rescaled points.
    attempts : tuple of str
        One line per failed option set, ``"<options>: <first line of the error>"``.
    error : str or None
        Why there is no reference (None when there is one).
    qhull_ok : bool or None
        Whether Qhull's hull passes the exact containment, convexity and
        manifoldness checks (None without a hull).
    qhull_detail : str
        What failed in Qhull's hull, if anything.
    distround : float
        Qhull's DISTround for the input (0.0 for an invalid input).
    extreme : ndarray of int64 or None
        Exactly the extreme points of the input, one index per distinct
        coordinate, sorted (a set, not a cycle): the corners of Qhull's hull
        when it is certified; otherwise in 2D from an exact monotone chain, in
        3D from :func:`certified_extremes`; None when nothing certifies (3D).
    affine_rank : int or None
        Exact affine rank (None for an invalid input).
    simplex : ndarray of int64 or None
        A witness simplex of input points (reused by :func:`~hullstress.checker.check`).
    n_points, dim : int
    points : ndarray or None
        The input the reference was computed for.
    scaled : ndarray or None
        ``points`` rescaled exactly by ``2**exponent`` (:func:`._geometry.exact_scale`).
    exponent : int
    certificate : Certificate or None
        The exact certificate of Qhull's hull (on ``scaled``).
    face_key : ndarray or None
        Qhull's faces in canonical form (:func:`face_set_key`).
    """

    vertices: np.ndarray | None
    faces: np.ndarray | FaceSet | None
    volume: float | None
    options: str | None
    attempts: tuple[str, ...]
    error: str | None
    qhull_ok: bool | None
    qhull_detail: str
    distround: float
    _extreme: np.ndarray | None
    affine_rank: int | None
    simplex: np.ndarray | None
    n_points: int
    dim: int
    points: np.ndarray | None = None
    scaled: np.ndarray | None = None
    exponent: int = 0
    certificate: Certificate | None = None
    face_key: np.ndarray | None = None
    #: Per-reference memo (e.g. the verdict on Qhull's own faces); not part of the record.
    memo: dict[str, Any] = field(default_factory=dict, repr=False, compare=False)

    @property
    def extreme(self) -> np.ndarray | None:
        """The exact extreme points, one index per distinct coordinate (deduplicated on first use)."""
        if self._extreme is None or self.qhull_ok is not True:
            return self._extreme
        if "extreme" not in self.memo:
            self.memo["extreme"] = first_of_each(self.scaled, self._extreme)
        return self.memo["extreme"]

    def tolerance(self) -> Fraction:
        """The volume agreement tolerance in scaled units (computed on first use, then kept)."""
        if "tolerance" not in self.memo:
            self.memo["tolerance"] = volume_tolerance(self.scaled, self.faces, distround(self.scaled))
        return self.memo["tolerance"]

    def same_faces(self, faces: np.ndarray | FaceSet) -> bool:
        """Whether ``faces`` (normalised) is exactly Qhull's face set, in any order and rotation."""
        if self.face_key is None:
            return False
        key = face_set_key(faces, self.n_points)
        return key is not None and key.shape == self.face_key.shape and bool(np.array_equal(key, self.face_key))

    def as_dict(self) -> dict:
        """Scalar fields, for tables and logs."""
        return {
            "qhull_options": self.options,
            "qhull_ok": self.qhull_ok,
            "qhull_volume": self.volume,
            "qhull_error": self.error,
            "distround": self.distround,
            "affine_rank": self.affine_rank,
        }


#: Outside this magnitude range Qhull runs on rescaled points (see qhull_reference).
_QHULL_SAFE_LOW = 2.0**-400
_QHULL_SAFE_HIGH = 2.0**400


def _unscale(value: float, exponent: int) -> float:
    """``value * 2**exponent``, inf when that overflows (a volume at 1e300 does)."""
    try:
        return math.ldexp(value, exponent)
    except OverflowError:
        return math.copysign(math.inf, value)


def _first_line(exc: BaseException) -> str:
    text = str(exc).strip()
    for line in text.splitlines():
        if line.strip():
            return f"{type(exc).__name__}: {line.strip()}"
    return type(exc).__name__


def _run_qhull(points: np.ndarray, first: str | None = None) -> tuple[ConvexHull | None, str | None, tuple[str, ...]]:
    attempts = []
    for opts in ((first,) if first else ("",)) + RETRY_OPTIONS:
        label = options_label(opts)
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")  # Qhull's precision warnings are recorded as outcomes, not emitted
                hull = ConvexHull(points, qhull_options=opts or None)
        except (QhullError, ValueError, RuntimeError) as exc:
            attempts.append(f"{label}: {_first_line(exc)}")
            continue
        return hull, label, tuple(attempts)
    return None, None, tuple(attempts)


def face_set_key(faces: np.ndarray | FaceSet, n_points: int) -> np.ndarray | None:
    """A canonical form of a face set: equal keys mean the same faces, orientation included.

    3D triangles: each rotated to start at its lowest index, then sorted (as
    one integer per triangle when the indices allow).  2D: the vertex cycle
    rotated to start at its lowest index.  None for polygon faces with more
    than three vertices (never compared).

    Examples
    --------
    >>> a = face_set_key(FaceSet.from_triangles([[2, 0, 1], [3, 1, 0]]), 4)
    >>> b = face_set_key(FaceSet.from_triangles([[0, 3, 1], [0, 1, 2]]), 4)
    >>> bool(np.array_equal(a, b))
    True
    """
    if isinstance(faces, FaceSet):
        if triangle_array(faces) is None:
            return None
        n = max(int(n_points), 1)
        if n < 2**21:  # one int64 per triangle (indices are below n_points)
            return np.sort(triangle_keys(triangle_array(faces), n))
        a, b, c = rotated_to_lowest(faces).indices.reshape(-1, 3).T
        return np.stack([a, b, c], axis=1)[np.lexsort((c, b, a))]
    poly = np.asarray(faces, dtype=np.int64)
    return np.roll(poly, -int(np.argmin(poly))) if len(poly) else poly


def volume_tolerance(scaled: np.ndarray, faces: np.ndarray | FaceSet, dr: float, area: float | None = None) -> Fraction:
    """``VOLUME_TOLERANCE_MULTIPLE * dr * area(faces)`` in the units of ``scaled``, as an exact Fraction.

    ``dr`` is DISTround of ``scaled``, ``area`` the faces' surface area if
    known (:func:`.measure.surface_area`).  Where the float area or product
    overflows (an input that could not be scaled exactly), they are taken on
    a copy brought to magnitude ~1 (rounded: only a tolerance is derived
    from it), so the tolerance is finite at every scale.
    """
    if area is None:
        area = surface_area(scaled, faces)
    if math.isfinite(area) and math.isfinite(dr) and math.isfinite(dr * area):
        return Fraction(VOLUME_TOLERANCE_MULTIPLE) * Fraction(dr) * Fraction(area)
    dim = scaled.shape[1]
    s = -int(np.frexp(float(np.abs(scaled).max()))[1])
    with np.errstate(all="ignore"):
        unit = np.ldexp(scaled, s)
    area, dr = surface_area(unit, faces), distround(unit)
    if not (math.isfinite(area) and math.isfinite(dr)):
        return Fraction(0)
    return Fraction(VOLUME_TOLERANCE_MULTIPLE) * Fraction(dr) * Fraction(area) / Fraction(2) ** (s * dim)


def _oriented_faces(scaled: np.ndarray, hull: ConvexHull, interior) -> np.ndarray:
    """Qhull's triangles, each turned counter-clockwise seen from outside.

    scipy's ``simplices`` are not consistently oriented; Qhull's outward facet
    normals (``equations``) say which way each one faces.  Where the float test
    is too close to call, the exact side of the interior point decides
    (``interior``: an Interior, None, or a callable giving one, asked only then).
    """
    tri = np.array(hull.simplices, dtype=np.int64)
    a, b, c = scaled[tri[:, 0]], scaled[tri[:, 1]], scaled[tri[:, 2]]
    with np.errstate(all="ignore"):
        n = cross3(b - a, c - a)
        eq = hull.equations[:, :3]
        dot = np.einsum("ij,ij->i", n, eq)
        # Sure when |dot| > 1e-8 |n| (squared: no square roots); Qhull's normals have unit length.
        unsure = ~(dot * dot > 1e-16 * np.einsum("ij,ij->i", n, n))
    flip = dot < 0
    if unsure.any():
        if callable(interior):
            interior = interior()
        if interior is not None:
            u = np.flatnonzero(unsure)
            side = orient3d_mean(a[u], b[u], c[u], interior.rows)
            flip[u[side < 0]] = True
    tri[flip] = tri[flip][:, [0, 2, 1]]
    return tri


def _invalid(reason: str, points: np.ndarray | None = None) -> QhullReference:
    n = dim = 0
    if isinstance(points, np.ndarray) and points.ndim == 2:
        n, dim = points.shape
    return QhullReference(None, None, None, None, (), reason, None, "", 0.0, None, None, None, n, dim)


def _summary(cert: Certificate) -> str:
    parts = [f"{name}: {'; '.join(r)}" for name, r in cert.reasons.items() if r]
    return " | ".join(parts)


def qhull_reference(points: np.ndarray, *, options: str | None = None) -> QhullReference:
    """Compute Qhull's hull of ``points`` once, with its options, health and exact extremes.

    Parameters
    ----------
    points : array_like of shape (n, 2) or (n, 3)
    options : str, optional
        Qhull options tried first instead of scipy's default (``--qhull-options``);
        the usual fallbacks follow if Qhull raises.

    Returns
    -------
    QhullReference
        Never raises: invalid input or a Qhull failure under every option set
        gives ``vertices=None`` and the reason in ``error``.

    Examples
    --------
    >>> ref = qhull_reference(np.array([[0.0, 0], [1, 0], [0, 1], [0.25, 0.25]]))
    >>> ref.options, ref.vertices.tolist(), ref.qhull_ok
    ('Qt', [0, 1, 2], True)
    >>> flat = qhull_reference(np.array([[0.0, 0], [1, 1], [2, 2]]))  # collinear
    >>> flat.options, flat.affine_rank, flat.qhull_ok
    ('QJ', 1, False)
    >>> qhull_reference(np.array([[0.0, np.nan]])).error
    'points must be finite, got NaN or inf coordinates'
    """
    try:
        pts = np.asarray(points, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        return _invalid(f"points must be a numeric array of shape (n, 2) or (n, 3): {exc}")
    if pts.ndim != 2 or pts.shape[1] not in (2, 3):
        return _invalid(f"points must have shape (n, 2) or (n, 3), got {pts.shape}")
    if not np.isfinite(pts).all():
        return _invalid("points must be finite, got NaN or inf coordinates", pts)
    n, dim = pts.shape
    if n == 0:
        return _invalid("points is empty", pts)
    extents = axis_extents(pts)
    top = max(extents)
    scaled, exponent = exact_scale(pts, top=top)
    dr = distround(pts, extents=extents)
    # Qhull overflows near the ends of the double range (and was seen to die with
    # SIGSEGV on a cube's faces at 1e300): there it runs on a rescaled copy, which has
    # the same hull up to the power-of-two factor (exactly, when the rescaling is exact;
    # otherwise up to the rounding of coordinates below 2**-1022, which the exact
    # certificate below judges like any other hull), and says so.
    qhull_input, note = pts, ""
    if top > 0 and not (_QHULL_SAFE_LOW <= top <= _QHULL_SAFE_HIGH):
        if exponent != 0:
            qhull_input, note = scaled, f" (on input scaled by 2^{exponent})"
        else:
            k = -int(np.frexp(top)[1])
            with np.errstate(under="ignore"):
                qhull_input = np.ldexp(pts, k)
            note = f" (on input scaled by 2^{k}, rounded)"
    hull, options, attempts = _run_qhull(qhull_input, options)
    if options is not None:
        options += note
    if hull is None:
        simplex = witness_simplex(scaled)
        return QhullReference(
            None, None, None, None, attempts, "Qhull failed with every option set: " + attempts[-1],
            None, "", dr, np.sort(exact_extreme_2d(scaled)) if dim == 2 else None, len(simplex) - 1, simplex, n, dim,
            points=pts, scaled=scaled, exponent=exponent,
        )
    # The input's interior point, needed only where Qhull's normals leave a facet's
    # orientation open or its hull fails: a witness simplex of all points, found once.
    found: dict[str, Any] = {}

    def interior() -> Interior | None:
        if "simplex" not in found:
            found["simplex"] = witness_simplex(scaled)
        simplex = found["simplex"]
        return Interior.from_simplex(scaled[simplex]) if len(simplex) == dim + 1 else None

    faces: np.ndarray | FaceSet
    face_key = None
    if dim == 2:
        faces = np.asarray(hull.vertices, dtype=np.int64)
    else:
        # Stored with every triangle starting at its lowest index (the canonical rotation);
        # the same keys give the face set's canonical form.
        tri = _oriented_faces(scaled, hull, interior)
        if n < 2**21:
            tri, keys = canonical_triangles(tri, n)
            face_key = np.sort(keys)
        faces = rotated_to_lowest(FaceSet.from_triangles(tri))
    cert = certify(scaled, faces)
    ok = cert.certified
    # A certified surface names a simplex of its own vertices (input points): full rank.
    simplex = cert.witness if cert.witness is not None else found.get("simplex")
    if simplex is None:
        simplex = found["simplex"] = witness_simplex(scaled)
    if ok:
        extreme = cert.extreme  # one index per coordinate on first use (QhullReference.extreme)
    elif dim == 2:
        extreme = np.sort(exact_extreme_2d(scaled))
    else:
        # Qhull's default run on exactly rescaled points repeats the failed run unless
        # rescaling avoided an overflow or underflow: then only the joggle is new.
        retry = REPAIR_OPTIONS if exponent != 0 else tuple(o for o in REPAIR_OPTIONS if o)
        extreme = certified_extremes(scaled, np.arange(n), interior(), options=retry)
    vertices = faces.copy() if dim == 2 else cert.hull_vertices
    return QhullReference(
        vertices=vertices,
        faces=faces,
        volume=_unscale(cert.volume, -exponent * dim),
        options=options,
        attempts=attempts,
        error=None,
        qhull_ok=ok,
        qhull_detail=_summary(cert),
        distround=dr,
        _extreme=extreme,
        affine_rank=len(simplex) - 1,
        simplex=simplex,
        n_points=n,
        dim=dim,
        points=pts,
        scaled=scaled,
        exponent=exponent,
        certificate=cert,
        face_key=face_key if face_key is not None else face_set_key(faces, n),
    )


def certified_extremes(
    scaled: np.ndarray, candidates: np.ndarray, interior: Interior | None, *, options: tuple[str, ...] = ()
) -> np.ndarray | None:
    """The exact extreme points of ``scaled``, from a Qhull hull of ``candidates`` that certifies.

    Qhull is run on the rescaled candidates (which avoids its overflow and
    underflow at extreme magnitudes) with :data:`REPAIR_OPTIONS`; the first
    hull that passes the exact checks against *all* points gives the extreme
    set (its corners).  None when no option set certifies: then the 3D extreme
    set stays unknown.

    Parameters
    ----------
    scaled : ndarray of shape (n, 3), float64
    candidates : ndarray of int64
        Indices that must include every extreme point for the repair to succeed.
    options : tuple of str
        Option sets to try (default :data:`REPAIR_OPTIONS`).
    interior : Interior or None
        The input's interior point (orients Qhull's facets where its normals are unsure).

    Returns
    -------
    ndarray of int64 (sorted, one index per coordinate) or None
    """
    candidates = unique_ints(np.asarray(candidates, dtype=np.int64))
    if interior is None or len(candidates) < 4:
        return None
    sub = scaled[candidates]
    # ``scaled`` is the input itself when no exact scaling exists (1.7e308 beside 0.1): Qhull,
    # which dies with SIGSEGV near the ends of the range, then runs on a rounded rescaled copy.
    # Its faces are only candidates; they are certified against the exact coordinates below.
    top = float(np.abs(sub).max())
    if top > 0 and not (_QHULL_SAFE_LOW <= top <= _QHULL_SAFE_HIGH):
        with np.errstate(under="ignore"):
            qhull_input = np.ldexp(sub, -int(np.frexp(top)[1]))
    else:
        qhull_input = sub
    for opts in options or REPAIR_OPTIONS:
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                hull = ConvexHull(qhull_input, qhull_options=opts or None)
        except (QhullError, ValueError, RuntimeError):
            continue
        faces = FaceSet.from_triangles(candidates[_oriented_faces(sub, hull, interior)])
        cert = certify(scaled, faces)
        if cert.certified:
            return first_of_each(scaled, cert.extreme)
    return None
