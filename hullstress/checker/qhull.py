"""Qhull (through scipy) as a witness: its hull, its options, its own exact health.

:func:`qhull_reference` runs ``scipy.spatial.ConvexHull`` once per case with
default options and, when Qhull raises, retries with the option sets of
:data:`RETRY_OPTIONS` in order, recording which produced the reference.  It
then certifies Qhull's own output with the same exact checks as any other
hull (``qhull_ok``): Qhull is a witness, not the judge.  It never raises:
every problem (NaN, wrong shape, too few points, every option set failing) is
recorded in ``error``.
"""

from __future__ import annotations

import math

import warnings
from dataclasses import dataclass

import numpy as np
from scipy.spatial import ConvexHull, QhullError

from ..contract import FaceSet
from ._geometry import Interior, distround, exact_scale
from .certify import Certificate, certify
from .extreme import exact_extreme_2d, first_of_each
from .predicates import orient3d_mean
from .rank import witness_simplex

__all__ = ["QhullReference", "qhull_reference", "certified_extremes", "DEFAULT_OPTIONS", "RETRY_OPTIONS", "REPAIR_OPTIONS"]

#: What scipy runs by default: it always adds ``Qt`` (triangulated output).
DEFAULT_OPTIONS = "Qt"
#: Option sets tried in order after the default raised, as passed to scipy
#: (scipy adds ``Qt``; ``QJ`` joggles the input instead of merging facets).
#: ``Q12`` allows wide facets (needed e.g. for ``rbox 10000 s Z1 G1e-13``),
#: ``Qbb Qc Qz`` are Qhull's usual precision helpers, ``QJ`` always succeeds
#: on non-empty input (even flat or repeated points) at the price of
#: non-extreme vertices.
RETRY_OPTIONS = ("Q12", "Qbb Qc Qz Q12", "QJ", "QJ Q12")
#: Option sets for :func:`certified_extremes` (Qhull on rescaled candidate points).
REPAIR_OPTIONS = ("", "QJ")


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
    volume, area : float or None
        Qhull's volume and surface area (area and perimeter in 2D).
    options : str or None
        The options that produced the reference (``"Qt"``, ``"Qt Q12"``, ``"QJ"``, ...).
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
    """

    vertices: np.ndarray | None
    faces: np.ndarray | FaceSet | None
    volume: float | None
    area: float | None
    options: str | None
    attempts: tuple[str, ...]
    error: str | None
    qhull_ok: bool | None
    qhull_detail: str
    distround: float
    extreme: np.ndarray | None
    affine_rank: int | None
    simplex: np.ndarray | None
    n_points: int
    dim: int

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


#: Outside this magnitude range Qhull runs on exactly rescaled points (see qhull_reference).
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
        label = DEFAULT_OPTIONS if not opts else (opts if "QJ" in opts else f"Qt {opts}")
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")  # Qhull's precision warnings are recorded as outcomes, not emitted
                hull = ConvexHull(points, qhull_options=opts or None)
        except (QhullError, ValueError, RuntimeError) as exc:
            attempts.append(f"{label}: {_first_line(exc)}")
            continue
        return hull, label, tuple(attempts)
    return None, None, tuple(attempts)


def _oriented_faces(scaled: np.ndarray, hull: ConvexHull, interior: Interior | None) -> np.ndarray:
    """Qhull's triangles, each turned counter-clockwise seen from outside.

    scipy's ``simplices`` are not consistently oriented; Qhull's outward facet
    normals (``equations``) say which way each one faces.  Where the float test
    is too close to call, the exact side of the interior point decides.
    """
    tri = np.array(hull.simplices, dtype=np.int64)
    a, b, c = scaled[tri[:, 0]], scaled[tri[:, 1]], scaled[tri[:, 2]]
    with np.errstate(all="ignore"):
        n = np.cross(b - a, c - a)
        dot = np.einsum("ij,ij->i", n, hull.equations[:, :3])
        scale = np.linalg.norm(n, axis=1) * np.linalg.norm(hull.equations[:, :3], axis=1)
    flip = dot < 0
    unsure = ~(np.abs(dot) > 1e-8 * scale)
    if unsure.any() and interior is not None:
        u = np.flatnonzero(unsure)
        side = orient3d_mean(a[u], b[u], c[u], interior.rows)
        flip[u[side < 0]] = True
    tri[flip] = tri[flip][:, [0, 2, 1]]
    return tri


def _invalid(reason: str, points: np.ndarray | None = None) -> QhullReference:
    n = dim = 0
    if isinstance(points, np.ndarray) and points.ndim == 2:
        n, dim = points.shape
    return QhullReference(None, None, None, None, None, (), reason, None, "", 0.0, None, None, None, n, dim)


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
    scaled, exponent = exact_scale(pts)
    simplex = witness_simplex(scaled)
    rank = len(simplex) - 1
    interior = Interior.from_simplex(scaled[simplex]) if rank == dim else None
    dr = distround(pts)
    # Qhull overflows near the ends of the double range (and was seen to die with
    # SIGSEGV on a cube's faces at 1e300): there it runs on the exactly rescaled
    # copy, which has the same hull up to the power-of-two factor, and says so.
    top = float(np.abs(pts).max())
    rescale = exponent != 0 and not (_QHULL_SAFE_LOW <= top <= _QHULL_SAFE_HIGH)
    hull, options, attempts = _run_qhull(scaled if rescale else pts, options)
    if rescale and options is not None:
        options = f"{options} (on input scaled by 2^{exponent})"
    if hull is None:
        return QhullReference(
            None, None, None, None, None, attempts, "Qhull failed with every option set: " + attempts[-1],
            None, "", dr, np.sort(exact_extreme_2d(scaled)) if dim == 2 else None, rank, simplex, n, dim,
        )
    vertices = np.asarray(hull.vertices, dtype=np.int64)
    faces: np.ndarray | FaceSet
    if dim == 2:
        faces = vertices.copy()
    else:
        faces = FaceSet.from_triangles(_oriented_faces(scaled, hull, interior))
    cert = certify(scaled, faces)
    ok = cert.certified
    if ok:
        extreme = first_of_each(scaled, cert.extreme)
    elif dim == 2:
        extreme = np.sort(exact_extreme_2d(scaled))
    else:
        # Qhull's default run on exactly rescaled points repeats the failed run unless
        # rescaling avoided an overflow or underflow: then only the joggle is new.
        retry = REPAIR_OPTIONS if exponent != 0 else tuple(o for o in REPAIR_OPTIONS if o)
        extreme = certified_extremes(scaled, np.arange(n), interior, options=retry)
    return QhullReference(
        vertices=vertices,
        faces=faces,
        volume=_unscale(float(hull.volume), -exponent * dim) if rescale else float(hull.volume),
        area=_unscale(float(hull.area), -exponent * (dim - 1)) if rescale else float(hull.area),
        options=options,
        attempts=attempts,
        error=None,
        qhull_ok=ok,
        qhull_detail=_summary(cert),
        distround=dr,
        extreme=extreme,
        affine_rank=rank,
        simplex=simplex,
        n_points=n,
        dim=dim,
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
    candidates = np.unique(np.asarray(candidates, dtype=np.int64))
    if interior is None or len(candidates) < 4:
        return None
    sub = scaled[candidates]
    for opts in options or REPAIR_OPTIONS:
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                hull = ConvexHull(sub, qhull_options=opts or None)
        except (QhullError, ValueError, RuntimeError):
            continue
        faces = FaceSet.from_triangles(candidates[_oriented_faces(sub, hull, interior)])
        cert = certify(scaled, faces)
        if cert.certified:
            return first_of_each(scaled, cert.extreme)
    return None
