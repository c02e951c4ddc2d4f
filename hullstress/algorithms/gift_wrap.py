"""3D gift wrapping after Paul Nathan (2015), registered as ``gift-wrap-3d`` (literal) and ``gift-wrap-3d-dedup``.

Seed document: ``000_9121b2368187346b.txt`` (P. Nathan, "Obtaining the Convex
Hull from a Set of Points using the Gift Wrapping Algorithm", 10/04/2015).
The code follows its numbered steps:

* **Step 1** (:func:`_first_point`): flatten the points onto the X-Y plane and
  take the point with the *maximum* squared distance ``P'.P'`` from the origin.
  The seed allows "either the maximum or minimum"; only the maximum is always
  on the hull (the minimum is inside whenever the origin is), so that is the
  reading kept.  Ties go to the lowest index.  The "scaled" eps of the same
  step is :func:`hullstress.tolerance.tolerance` (one shared implementation).
* **Step 2** (:func:`_first_edge`): outer loop over the flattened points in
  index order, skipping the first point; the edge ``E = P'_c - P'_first`` has
  the outward normal ``n = E/|E| x z_hat = (E_y, -E_x, 0)/|E|`` and the
  signed distance ``d = n.(P' - V0)``; the first ``c`` with no point at
  ``d > eps`` gives the first edge ``(first, c)``.
* **Step 3**: the edge stack and the "dynamic array of edges" (a list, plus a
  set of unordered index pairs: the seed's linear duplicate search in both
  directions, answered by a hash lookup with the same result).
* **Step 4** (:func:`_gift_wrap_trace`): pop an edge ``(a, b)``; outer loop
  over all points in index order skipping ``a`` and ``b``; the candidate
  triangle ``(a, b, c)`` has the normal ``E01 x E12 / |E01 x E12|`` and is
  accepted when no point has ``d = n.(P - V0) > eps``.  The two new edges that
  share ``c`` are reversed, ``(c, b)`` then ``(a, c)``, and each is pushed
  (and recorded) unless it is in the edge array in either direction; then the
  outer loop exits and the triangle ``(a, b, c)`` is added to the array of
  hull triangles.  The loop ends when the stack is empty.

The triangles are ``(V0, V1, V2) = (a, b, c)``, the seed's "anti-clockwise
positive winding" with the outward normal ``E01 x E12``: counter-clockwise
seen from outside, as the harness contract asks.

**Repeated triangles: the seed's weakness, kept in** ``gift-wrap-3d``.  Every
undirected edge is pushed once and every pop that finds a candidate adds it,
so a closed hull of ``F`` triangles comes back as ``3F/2`` triangles: every
face, plus ``F/2`` exact repeats (an edge whose far side was already built
is still popped, and finds that triangle again, in another rotation; one
face can come back more than once).
The seed adds the candidate "to a dynamic array of convex hull triangles (the
required end product)" without a check, so the literal output is not a
manifold surface: the checker reports the repeated faces.
:attr:`GiftWrapTrace.refound` counts them.

**The named variant** ``gift-wrap-3d-dedup`` (an improvement on the seed)
does not add a candidate that is already in the array, the same triangle in
any rotation (same cyclic order); its two reversed edges are in the edge
array already, so nothing is pushed either.  Everything else is the same:
the stack, the pops (still ``3F/2`` on a closed hull in general position),
and a triangle with the same points in the *opposite* order is a different
triangle and is kept (that happens only on flat or degenerate input).

Quirks kept on purpose (the harness is meant to expose them):

* A zero-length edge or a zero-area candidate (duplicate or collinear points)
  has a 0/0 = NaN normal; NaN is never ``> eps``, so such a candidate *passes*
  and a degenerate triangle is accepted if it comes first in index order.
* The candidate's own vertices are tested too (the seed's "Additional notes"
  says they "will always pass").  In floats one of them can land an ulp or
  two above the plane, more than the scaled eps, and the true candidate is
  rejected: faces go missing, sometimes the whole hull (the first pop finds
  nothing).  On random clouds in the unit ball this happens to roughly 1 in
  150 inputs with the scaled eps, more often with the fixed one, and on most
  inputs far from unit scale with the fixed one.  Step 2 has the same test
  and can find no first edge at all.
* On coplanar points the first passing candidate in index order is taken,
  which gives skinny or overlapping triangles, and the same points can come
  back in both orientations.
* If no candidate passes for a popped edge the seed's outer loop simply ends:
  no triangle, no new edges.  If step 2 finds no first edge the seed gives no
  answer, and this raises :class:`RuntimeError`.

Input handling: ``points`` must be an ``(n, 3)`` array of finite numbers with
``n >= 3`` (a :class:`ValueError` otherwise); three points and any degenerate
set (coplanar, collinear, duplicates) run as the seed would.  Termination is
guaranteed: each undirected edge enters the stack at most once, so there are at
most ``n(n-1)/2 + 1`` pops; the guard at ``8 n^2 + 100`` pops only protects
against future edits.

Speed without changing the answer: "the first candidate in index order that
passes" is found by pivoting to the farthest point above (ordinary gift
wrapping, a few O(n) passes), using the points met on the way to reject most
candidates at once (a candidate with any point at ``d > eps`` fails, whoever
finds that point), then checking the survivors below the pivot winner with the
full test, in index order, in bounded blocks.  On small inputs (at most
``_WHOLE_BUDGET`` distances, about 128 points) every candidate is tested in
one block instead: one pass over a few thousand distances costs less than the
pivoting's dozens of small ones.  From ``_SCREEN_FROM`` distances up, that
block is screened first (:func:`_screened_out`): one matrix product gives
every distance to within a proven rounding bound, which rejects the candidates
that a point is above by more than that bound; only the others are tested with
the seed's own sums.  Every distance a decision rests on is computed with the
same elementwise float operations in the same order, so the choice is
bit-for-bit that of the sequential double loop, on every path.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .._registry import register_algorithm
from ..errors import AlgorithmStepLimit
from ..tolerance import tolerance
from ._variant import SeedVariant

__all__ = ["gift_wrap_3d", "gift_wrap_3d_dedup"]

#: Upper bound on the elements of one block of distances (about 16 MB of float64).
_BLOCK_BUDGET = 2_000_000
#: Largest number of candidates checked together in one block.
_MAX_BLOCK = 256
#: Pivots tried before falling back to the ordered block scan alone.
_MAX_PIVOTS = 64
#: Up to this many distances (points x candidates), every candidate is tested in one block.
_WHOLE_BUDGET = 16_384
#: From this many distances up (about 70 points), the one block is screened by a matrix
#: product first (below it the screen's set-up costs more than the sums it saves).
_SCREEN_FROM = 4_096
#: The unit roundoff of float64.
_UNIT = 2.0**-53
#: Covers the absolute error of underflowing products (at most ``2**-1075`` each, three per sum, two sums).
_UNDERFLOW = 2.0**-1068


@dataclass(frozen=True)
class GiftWrapTrace:
    """What one run did, for tests and debugging (not part of the contract).

    Attributes
    ----------
    eps : float
        The tolerance used.
    first_point : int
        Step 1's point.
    first_edge : tuple of int
        Step 2's edge ``(first_point, c)``.
    edges : list of tuple of int
        The dynamic array of edges, in the order they were recorded (each was
        pushed once).
    pops : int
        Edges popped from the stack.
    refound : int
        Pops whose candidate triangle was already in the array (the same
        triangle in any rotation): ``F/2`` on a closed hull of ``F``
        triangles, where ``pops == 3F/2``.  The literal run adds them again;
        the ``dedup`` variant does not.
    triangles : ndarray of shape (m, 3), int64
        The accepted triangles in the order they were added.
    """

    eps: float
    first_point: int
    first_edge: tuple[int, int]
    edges: list[tuple[int, int]]
    pops: int
    refound: int
    triangles: np.ndarray


def _checked_points(points: object, name: str, min_points: int) -> np.ndarray:
    """Validate ``points`` as an (n, 3) finite float array with ``n >= min_points``."""
    pts = np.asarray(points, dtype=np.float64)
    if pts.ndim != 2 or pts.shape[1] != 3:
        raise ValueError(f"{name}: points must have shape (n, 3), got {pts.shape}")
    if len(pts) < min_points:
        raise ValueError(f"{name}: points must hold at least {min_points} points, got {len(pts)}")
    if not np.isfinite(pts).all():
        row = int(np.flatnonzero(~np.isfinite(pts).all(axis=1))[0])
        raise ValueError(f"{name}: points must be finite, got {pts[row].tolist()} at row {row}")
    return pts


def _checked_eps(points: np.ndarray, eps: float | None, name: str) -> float:
    """Resolve ``eps=None`` to the scaled policy; reject negative or non-finite values."""
    if eps is None:
        return tolerance(points, "scaled")
    value = float(eps)
    if not np.isfinite(value) or value < 0:
        raise ValueError(f"{name}: eps must be a finite number >= 0 or None, got {eps!r}")
    return value


def _signed(q: np.ndarray, nrm: np.ndarray) -> np.ndarray:
    """Signed distances ``q[i] . nrm[j]`` as an (len(q), len(nrm)) array.

    Always the same elementwise products summed left to right, so one entry
    has the same bits whichever block or slice it is computed in.
    """
    out = q[:, 0, None] * nrm[None, :, 0]
    for j in range(1, q.shape[1]):
        out += q[:, j, None] * nrm[None, :, j]
    return out


def _screened_out(q: np.ndarray, nrm: np.ndarray, eps: float) -> np.ndarray | None:
    """Candidates that some point is certainly above, from one matrix product; None when no bound holds.

    ``nrm @ q.T`` sums the same three products as :func:`_signed`, in an
    order (and with fused multiply-adds) that the BLAS chooses, so an entry
    may differ from the seed's sum in its last bits.  Any way of summing
    three products is within ``gamma_3 * sum_k |q_k| |n_k|`` of the exact
    value (``gamma_3 = 3u / (1 - 3u)``, ``u = 2**-53``), plus at most
    ``2**-1075`` per underflowing product; so the two sums differ by less
    than ``8u * |q|_1 * max|n| + 2**-1068``, which also covers the rounding
    of that bound and of adding it to ``eps``.  A product above ``eps`` by
    more than that puts the seed's own distance above ``eps`` too: the
    candidate fails the seed's test, whoever looks.  Candidates not rejected
    here are decided by :func:`_signed` alone.

    Parameters
    ----------
    q : ndarray of shape (n, k), float64
        The points minus the base vertex (finite, or infinite after overflow).
    nrm : ndarray of shape (m, k), float64
        The candidates' normals (NaN or infinite when degenerate).
    eps : float

    Returns
    -------
    ndarray of shape (m,), bool, or None
        True where a point is certainly above the candidate; None when a
        normal is infinite (its products have no bound; the caller then tests
        every candidate).  A NaN normal, or a point whose bound overflowed,
        never rejects anything.
    """
    largest = np.fmax.reduce(np.abs(nrm), axis=None)  # NaN-ignoring: NaN normals reject nothing below
    if not np.isfinite(largest):
        return None
    bound = np.abs(q).sum(axis=1) * (8.0 * _UNIT * largest) + (eps + (4.0 * _UNIT * abs(eps) + _UNDERFLOW))
    return ((nrm @ q.T) > bound).any(axis=1)


def _first_passing(q: np.ndarray, nrm: np.ndarray, cand: np.ndarray, eps: float) -> int:
    """The lowest candidate ``c`` with no ``i`` such that ``q[i] . nrm[c] > eps``.

    Parameters
    ----------
    q : ndarray of shape (n, k), float64
        Every point minus the plane's (or line's) base vertex ``V0``.
    nrm : ndarray of shape (n, k), float64
        Row ``c``: the unit normal of candidate ``c`` (NaN when degenerate).
    cand : ndarray of shape (n,), bool
        Which rows are candidates.
    eps : float
        A point at ``d > eps`` rejects the candidate (NaN never does).

    Returns
    -------
    int
        The same index a double loop over candidates then points would give,
        or -1 when no candidate passes.
    """
    idx = np.flatnonzero(cand)
    if idx.size == 0:
        return -1
    if len(q) * idx.size <= _WHOLE_BUDGET:
        # Small inputs: the double loop's answer by definition, in one block of distances,
        # cheaper than the dozens of small passes of the pivoting below.
        if len(q) * idx.size >= _SCREEN_FROM:
            rejected = _screened_out(q, nrm[idx], eps)
            if rejected is not None:
                idx = idx[~rejected]
                if idx.size == 0:
                    return -1
        bad = (_signed(q, nrm[idx]) > eps).any(axis=0)
        return -1 if bad.all() else int(idx[int(np.argmin(bad))])
    # Pivot phase: ordinary gift wrapping towards the farthest point above.
    # It finds a passing candidate (the "winner") and, on the way, points that
    # lie above many candidate planes.
    violators: list[int] = []
    winner = -1
    c = int(idx[0])
    visited = {c}
    for _ in range(_MAX_PIVOTS):
        d = _signed(q, nrm[c : c + 1])[:, 0]
        if not (d > eps).any():
            winner = c
            break
        s = int(np.argmax(d))
        violators.append(s)
        if not cand[s] or s in visited:
            break
        visited.add(s)
        c = s
    if winner == idx[0]:
        return winner
    rest = idx if winner < 0 else idx[idx < winner]
    if violators and rest.size:
        v = np.unique(np.asarray(violators))
        rest = rest[~(_signed(q[v], nrm[rest]) > eps).any(axis=0)]
    # Ordered scan of the survivors with the full test; failures contribute
    # their worst point to filter the rest.
    max_block = int(np.clip(_BLOCK_BUDGET // max(len(q), 1), 1, _MAX_BLOCK))
    block = 1
    while rest.size:
        take = rest[:block]
        dist = _signed(q, nrm[take])
        bad = (dist > eps).any(axis=0)
        if not bad.all():
            return int(take[int(np.argmin(bad))])
        rest = rest[block:]
        if rest.size:
            v = np.unique(np.argmax(dist, axis=0))
            rest = rest[~(_signed(q[v], nrm[rest]) > eps).any(axis=0)]
        block = min(2 * block, max_block)
    return winner


def _first_point(pts: np.ndarray) -> int:
    """Step 1: the flattened point farthest from the origin (lowest index on ties)."""
    r2 = pts[:, 0] * pts[:, 0] + pts[:, 1] * pts[:, 1]
    return int(np.argmax(r2))


@np.errstate(divide="ignore", invalid="ignore", over="ignore")  # 0/0 -> NaN is the seed's behaviour
def _first_edge(pts: np.ndarray, first: int, eps: float) -> int:
    """Step 2: the first point ``c`` whose flattened edge from ``first`` has no point beyond eps."""
    flat = pts[:, :2]
    v0 = flat[first]
    e = flat - v0
    length = np.sqrt(e[:, 0] * e[:, 0] + e[:, 1] * e[:, 1])
    ex = e[:, 0] / length
    ey = e[:, 1] / length
    # (E/|E|) x z_hat = (E_y, -E_x, 0)/|E|; the zero z component adds nothing.
    nrm = np.stack([ey, -ex], axis=1)
    cand = np.ones(len(pts), dtype=bool)
    cand[first] = False
    return _first_passing(e, nrm, cand, eps)


@np.errstate(divide="ignore", invalid="ignore", over="ignore")  # 0/0 -> NaN is the seed's behaviour
def _triangle_normals(pts: np.ndarray, a: int, b: int) -> tuple[np.ndarray, np.ndarray]:
    """``P - V0`` and the unit normals ``E01 x E12 / |E01 x E12|`` of triangles ``(a, b, c)`` for every ``c``."""
    v0 = pts[a]
    v1 = pts[b]
    e01 = v1 - v0
    e12 = pts - v1
    cx = e01[1] * e12[:, 2] - e01[2] * e12[:, 1]
    cy = e01[2] * e12[:, 0] - e01[0] * e12[:, 2]
    cz = e01[0] * e12[:, 1] - e01[1] * e12[:, 0]
    norm = np.sqrt(cx * cx + cy * cy + cz * cz)
    nrm = np.empty((len(pts), 3))
    np.divide(cx, norm, out=nrm[:, 0])
    np.divide(cy, norm, out=nrm[:, 1])
    np.divide(cz, norm, out=nrm[:, 2])
    return pts - v0, nrm


def _rotation_key(a: int, b: int, c: int) -> tuple[int, int, int]:
    """Triangle ``(a, b, c)`` rotated to start at its smallest index.

    Equal keys mean the same triangle with the same cyclic order; the reversed
    triangle ``(a, c, b)`` has a different key.
    """
    if a <= b and a <= c:
        return (a, b, c)
    if b <= c:
        return (b, c, a)
    return (c, a, b)


def _pop_limit(n: int) -> int:
    """The main-loop guard: ``8 n^2 + 100`` pops (the duplicate check allows at most ``n(n-1)/2 + 1``)."""
    return 8 * n * n + 100


#: Every found triangle added, as written; and a re-found triangle not added again (the improvement).
LITERAL = SeedVariant("gift-wrap-3d", improved=False)
DEDUP = SeedVariant("gift-wrap-3d-dedup", improved=True)


def _gift_wrap_trace(pts: np.ndarray, eps: float, variant: SeedVariant = LITERAL) -> GiftWrapTrace:
    """Run steps 1-4 on validated points and record what happened."""
    n = len(pts)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        first = _first_point(pts)
        second = _first_edge(pts, first, eps)
        if second < 0:
            raise RuntimeError(
                f"{variant.name}: step 2 found no first edge: every edge from point {first} "
                f"has a point at signed distance > eps={eps!r}"
            )
        # Step 3: the stack, and the dynamic array of edges for the duplicate check.
        stack = [(first, second)]
        edges = [(first, second)]
        seen = {(min(first, second), max(first, second))}
        triangles: list[tuple[int, int, int]] = []
        # Rotation keys of the triangles in the array: a triangle found again
        # from the far side of one of its edges is counted (and, in the dedup
        # variant, not added twice).
        built: set[tuple[int, int, int]] = set()
        limit = _pop_limit(n)
        pops = 0
        refound = 0
        cand = np.ones(n, dtype=bool)
        # Step 4.
        while stack:
            pops += 1
            if pops > limit:
                raise AlgorithmStepLimit(
                    f"{variant.name}: step 4 (main loop) exceeded {limit} edge pops (8*n^2+100 for n={n})"
                )
            a, b = stack.pop()
            q, nrm = _triangle_normals(pts, a, b)
            cand[a] = cand[b] = False
            c = _first_passing(q, nrm, cand, eps)
            cand[a] = cand[b] = True
            if c < 0:
                continue  # the seed's outer loop ends without a triangle
            # Reversed copies of the triangle's edges (b, c) and (c, a).
            for u, v in ((c, b), (a, c)):
                key = (u, v) if u < v else (v, u)
                if key not in seen:
                    seen.add(key)
                    edges.append((u, v))
                    stack.append((u, v))
            # A triangle already in the array has both its edges recorded, so
            # the loop above pushed nothing.  The seed adds it again.
            key = _rotation_key(a, b, c)
            if key in built:
                refound += 1
                if variant.improved:
                    continue
            built.add(key)
            triangles.append((a, b, c))
    tri = np.array(triangles, dtype=np.int64).reshape(-1, 3)
    return GiftWrapTrace(
        eps=eps,
        first_point=first,
        first_edge=(first, second),
        edges=edges,
        pops=pops,
        refound=refound,
        triangles=tri,
    )


def _run(points: np.ndarray, eps: float | None, variant: SeedVariant) -> np.ndarray:
    """Validate, then run steps 1-4; the triangles the array holds at the end."""
    pts = _checked_points(points, variant.name, 3)
    return _gift_wrap_trace(pts, _checked_eps(pts, eps, variant.name), variant).triangles


@register_algorithm(LITERAL.name, dim=3)
def gift_wrap_3d(points: np.ndarray, /, *, eps: float | None = None) -> np.ndarray:
    """3D gift wrapping after Paul Nathan (2015), as written: triangles from an edge stack, repeats included.

    Parameters
    ----------
    points : ndarray of shape (n, 3), float64
        The input points, ``n >= 3``, finite.  Never written to.
    eps : float or None
        A point at signed distance ``d > eps`` from a candidate's line or plane
        rejects the candidate.  ``None`` uses
        ``hullstress.tolerance.tolerance(points, "scaled")``, the seed's
        ``eps_machine * (sqrt(max P'.P') - sqrt(min P'.P'))``.

    Returns
    -------
    ndarray of shape (m, 3), int64
        Triangles, counter-clockwise seen from outside, in the order the seed
        adds them: one per pop that found a candidate, so a closed hull of
        ``F`` triangles comes with ``F/2`` repeats (in other rotations); see
        the module docstring.  On flat or degenerate input they
        can overlap, and the same points can come back in both orientations.

    Raises
    ------
    ValueError
        ``points`` is not ``(n, 3)``, has fewer than 3 rows or a non-finite
        value; or ``eps`` is negative or non-finite.
    RuntimeError
        Step 2 found no first edge (possible only through rounding).
    hullstress.errors.AlgorithmStepLimit
        The main-loop guard tripped (it cannot with the seed's duplicate check).

    See Also
    --------
    gift_wrap_3d_dedup : the same, without adding a triangle already in the array.

    Examples
    --------
    >>> tet = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]])
    >>> gift_wrap_3d(tet).tolist()  # 6 edges popped, 6 triangles: (2, 0, 3) three times
    [[1, 2, 3], [1, 3, 0], [1, 0, 2], [2, 0, 3], [0, 3, 2], [3, 2, 0]]

    A duplicated point gives zero-area triangles (their NaN normal passes the
    test); here rows 0 and 2 are equal, and all that comes back is one
    zero-area triangle in both orientations, one of them twice:

    >>> dup = np.vstack([tet[1:2], tet])
    >>> gift_wrap_3d(dup).tolist()
    [[0, 2, 1], [0, 1, 2], [1, 2, 0]]
    """
    return _run(points, eps, LITERAL)


@register_algorithm(DEDUP.name, dim=3)
def gift_wrap_3d_dedup(points: np.ndarray, /, *, eps: float | None = None) -> np.ndarray:
    """Nathan's 3D gift wrapping, each triangle added once (a named improvement on the seed).

    Parameters
    ----------
    points : ndarray of shape (n, 3), float64
        The input points, ``n >= 3``, finite.  Never written to.
    eps : float or None
        As for :func:`gift_wrap_3d`.

    Returns
    -------
    ndarray of shape (m, 3), int64
        Triangles, counter-clockwise seen from outside, in the order the seed
        adds them, each once: a triangle found again from the far side of one
        of its edges (the same triangle in any rotation) is not added twice.
        On flat or degenerate input they can overlap, and the same points can
        come back in both orientations.

    Raises
    ------
    ValueError, RuntimeError, hullstress.errors.AlgorithmStepLimit
        As for :func:`gift_wrap_3d`.

    Examples
    --------
    >>> tet = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]])
    >>> gift_wrap_3d_dedup(tet).tolist()  # the 4 faces, each once
    [[1, 2, 3], [1, 3, 0], [1, 0, 2], [2, 0, 3]]
    >>> dup = np.vstack([tet[1:2], tet])
    >>> gift_wrap_3d_dedup(dup).tolist()
    [[0, 2, 1], [0, 1, 2]]
    """
    return _run(points, eps, DEDUP)
