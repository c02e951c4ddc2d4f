"""John Henckel's direct convex hull (1998), registered as ``henckel`` (literal) and ``henckel-normalised``.

Seed document: ``001_9cf2e85d43cd0c3f.txt`` (J. Henckel, "A Direct Convex
Hull Algorithm").  The code follows its numbered lists.

"Finding the initial edge" (:func:`_initial_edge`):

1. ``D``: a random unit vector, a normalised ``standard_normal(3)`` draw from
   ``numpy.random.default_rng(seed)``, so one input and seed give one output.
2. ``A``: the point with the largest ``P . D``.
3. If *more than three* points share that maximum (exact float equality),
   draw again; otherwise ``A`` is the lowest index among them.
4. ``B``: the point (not ``A``) with the smallest angle at ``A`` to the plane
   ``M`` perpendicular to ``D``.  The seed computes the signed sine
   ``((B - A)/|B - A|) . D``; every value is <= 0 in exact arithmetic (``A``
   is extreme), so the smallest angle is the largest signed value, which is
   what is taken (a value rounded to a tiny positive number still counts as
   the nearest the plane).  A point equal to ``A`` gives 0/0 = NaN, which
   never compares larger and so is never chosen.
5. Ties on that value (exact equality): the point nearest to ``A``, then the
   lowest index.

"Algorithm" (:func:`_henckel_trace` and :func:`_find_face`):

* Steps 1-3: ``n < 3`` is the seed's error (:class:`ValueError`); the face,
  edge and to-do lists start empty.
* Step 4: the initial edge above.
* Step 5: ``C`` is the lowest index (not ``A``, ``B``) whose
  ``(A - B) x (C - B)`` is not exactly the zero vector.  If there is none the
  points are collinear, or ``A`` and ``B`` are copies of one point (a to-do
  edge from a misordered face with duplicates), and the seed has no answer:
  :class:`ValueError`, naming which.
* Steps 6-8: ``NM = (A - B) x (C - B)``; ``dist(P) = (P - B) . NM`` for every
  point except ``A, B, C``; ``P`` is the largest (lowest index on ties); if it
  is "above", ``C = P`` and repeat.
* Step 9: the face is every point "on the plane", gathered in index order;
  ``A``, ``B`` and ``C`` are included outright, as the seed states they are.
  Interior points of a polygonal face are on the plane too, so they are in
  the face (quirk kept).
* Step 10, ``henckel`` (literal): every point of the face, ``B`` included, is
  sorted by ``angle(P) = (P - B) . (A - B)`` exactly as the seed writes it,
  ascending, with a stable sort (exact ties keep index order).  Ascending is
  the only direction in which the list can run ``B, ..., A`` (``B``'s value
  is 0, ``A``'s is ``|A - B|^2``), the seed's clockwise perimeter that holds
  the edge ``A -> B`` the face was built on.  The value is a projection onto
  ``BA``, not an angle: a point whose projection falls beyond ``A`` (an
  obtuse angle at ``A``) or behind ``B`` (an obtuse angle at ``B``) is sorted
  out of rotational order, and a triangle face then comes out the wrong way
  round.  **This is the seed's weakness, kept**: such a face does not contain
  its own edge ``A -> B``, the to-do list never loses that edge (steps
  13-14), and the run ends in the main-loop guard,
  :class:`~hullstress.errors.AlgorithmStepLimit`.  It happens on almost
  every input in general position (every random cloud of 20 or more points
  tried).  A face with a right angle at its edge ties (``B`` and its
  neighbour both have the value 0) and index order decides, so the unit cube
  and a flat square end at the guard too; a regular tetrahedron, all of
  whose angles are 60 degrees, comes out right.
* Step 10, ``henckel-normalised`` (the named variant, an improvement on the
  seed): the same dot product divided by ``|P - B|``, i.e. the cosine of the
  angle at ``B`` between ``BA`` and ``BP`` times the constant ``|A - B|``,
  which is what the name "angle" asks for.  ``B`` is put first (its value is
  0/0) and the rest sorted ascending (stable; points equal to ``B``, NaN,
  last): ``B, ..., A`` for every convex face, whatever its angles.  The
  docs/findings.md compares the two.
* Steps 11-12: for each perimeter edge ``E = (P1, P2)`` (consecutive points,
  cyclically), with ``ER = (P2, P1)``: if ``ER`` is in the edge list, one copy
  of ``E`` is removed from the to-do list if present; otherwise ``E`` is
  appended to the edge list and ``ER`` to the to-do list.
* Steps 13-14: "get the next edge in the to-do list" reads the *front* of the
  list without removing it; only step 12 removes to-do entries (a correctly
  sorted face built on ``(A, B)`` contains ``A -> B`` and so removes it).  When
  a face does not contain its own to-do edge (the literal sort above, or, in
  either variant, a tie in the sort that put a collinear point after ``A``, a
  duplicate of ``B``...), the same edge comes back forever; the iteration
  guard turns that into :class:`~hullstress.errors.AlgorithmStepLimit`.

Tolerance reading.  The seed compares ``dist(P, M) > 0`` ("above") and asks
for the points "on the plane M".  ``dist`` is not normalised (it carries the
factor ``|NM|``), while eps is a length (Nathan's formula), so the
comparisons are ``dist > eps * |NM|`` (above) and ``|dist| <= eps * |NM|``
(on the plane): ``dist / |NM| = (P - B) . NM/|NM|`` is the signed distance.
The maximum in step 7 is taken over the seed's unnormalised values.  The
initial edge's ties, the collinearity test of step 5 and the sort's ties are
exact comparisons, as the seed states no tolerance there.

Orientation.  ``NM`` points out of the hull (no point is above a face plane),
and with ``NM = (A - B) x (C - B)`` the order ``A, B, C`` turns clockwise seen
from outside: the seed's "clockwise".  The returned polygons are those lists
reversed, counter-clockwise seen from outside as the harness contract asks
(when step 10 sorted them into rotational order).

Guards (where one trips, the seed would loop forever): the random direction
is drawn at most 1000 times; one face takes at most ``2 n + 100`` pivots (in
exact arithmetic each pivot turns the plane further round ``AB``, so
``n - 2`` is enough; in floats, nearly coplanar input can make the pivots
cycle); at most ``4 n + 100`` faces are built (a hull on ``n`` points has at
most ``2 n - 4`` faces, and each iteration builds a new one).  Steps 5-10
depend only on the edge, so the face found for an edge is remembered and an
edge that comes back is answered from that memo.  A run is *stuck* when the
face built on its front to-do edge does not have that edge: only step 12
removes to-do entries, and only edges of the face being added, so the entry
stays at the front and every later iteration builds the same face on it until
the face guard.  The guard then trips at once, with the same error and
message it would give after ``4 n + 100`` faces.

Every dot product is written as elementwise products summed left to right
(:func:`_dots`), never BLAS, so one input gives the same faces on every
machine.
"""

from __future__ import annotations

import math
from collections import deque
from dataclasses import dataclass

import numpy as np

from .._registry import register_algorithm
from ..errors import AlgorithmStepLimit
from ._variant import SeedVariant
from .gift_wrap import _checked_eps, _checked_points

__all__ = ["henckel_hull", "henckel_normalised_hull"]

_MAX_DRAWS = 1000


#: Step 10 as written, and with the sort key divided by |P - B| (the improvement).
LITERAL = SeedVariant("henckel", improved=False)
NORMALISED = SeedVariant("henckel-normalised", improved=True)


@dataclass(frozen=True)
class HenckelTrace:
    """What one run did, for tests and debugging (not part of the contract).

    Attributes
    ----------
    eps : float
        The tolerance used.
    direction : ndarray of shape (3,), float64
        The random unit vector ``D`` that gave the initial edge.
    draws : int
        How many directions were drawn (more than one after a tie of 4+ points).
    initial_edge : tuple of int
        ``(A, B)``.
    faces : list of list of int
        The faces in the seed's order (step 10's sorted lists; clockwise seen
        from outside, ``B`` first, when the sort puts them in rotational order).
    face_edges : list of tuple of int
        The ``(A, B)`` each face was built on.
    edge_list : list of tuple of int
        The seed's edge list, in insertion order.
    pivots : int
        Total times step 8 replaced ``C``.
    """

    eps: float
    direction: np.ndarray
    draws: int
    initial_edge: tuple[int, int]
    faces: list[list[int]]
    face_edges: list[tuple[int, int]]
    edge_list: list[tuple[int, int]]
    pivots: int


class _ToDoList:
    """The seed's to-do list: a list of edges with ``in``, append, remove-first-copy and front.

    Same answers as a Python list (``remove`` drops the first copy, the front
    is the oldest entry still present), but every operation is O(1) amortised:
    a broken run can append the same edges thousands of times.
    """

    def __init__(self) -> None:
        self._entries: deque[tuple[tuple[int, int], int]] = deque()
        self._alive: dict[tuple[int, int], deque[int]] = {}
        self._dead: set[int] = set()
        self._serial = 0
        self._size = 0

    def __len__(self) -> int:
        return self._size

    def __contains__(self, edge: tuple[int, int]) -> bool:
        return bool(self._alive.get(edge))

    def append(self, edge: tuple[int, int]) -> None:
        self._entries.append((edge, self._serial))
        self._alive.setdefault(edge, deque()).append(self._serial)
        self._serial += 1
        self._size += 1

    def remove(self, edge: tuple[int, int]) -> None:
        self._dead.add(self._alive[edge].popleft())
        self._size -= 1

    def front(self) -> tuple[int, int]:
        while self._entries[0][1] in self._dead:
            self._dead.discard(self._entries.popleft()[1])
        return self._entries[0][0]


def _dots(q: np.ndarray, v: np.ndarray) -> np.ndarray:
    """Row-wise ``q[i] . v`` as elementwise products summed left to right (equal rows, equal bits)."""
    return q[:, 0] * v[0] + q[:, 1] * v[1] + q[:, 2] * v[2]


@np.errstate(divide="ignore", invalid="ignore", over="ignore")  # 0/0 -> NaN is the seed's behaviour
def _initial_edge(
    pts: np.ndarray, rng: np.random.Generator, name: str = LITERAL.name
) -> tuple[int, int, np.ndarray, int]:
    """"Finding the initial edge": return ``(A, B, D, draws)``."""
    for draw in range(1, _MAX_DRAWS + 1):
        d = rng.standard_normal(3)
        d = d / np.sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2])
        height = _dots(pts, d)
        top = np.flatnonzero(height == height.max())
        if len(top) > 3:
            continue  # the seed's "more than three points have the maximum distance"
        a = int(top[0])
        diff = pts - pts[a]
        length = np.sqrt(diff[:, 0] * diff[:, 0] + diff[:, 1] * diff[:, 1] + diff[:, 2] * diff[:, 2])
        sine = _dots(diff / length[:, None], d)
        sine[a] = np.nan
        ok = ~np.isnan(sine)
        if not ok.any():
            raise ValueError(f"{name}: initial edge: every point coincides with point A={a}")
        best = sine[ok].max()
        tied = np.flatnonzero(sine == best)
        b = int(tied[np.argmin(length[tied])])
        return a, b, d, draw
    raise AlgorithmStepLimit(
        f"{name}: initial edge step 3 drew {_MAX_DRAWS} random directions and every one "
        "had more than three points at the maximum"
    )


@np.errstate(divide="ignore", invalid="ignore")  # 0/0 -> NaN for points equal to B (normalised key)
def _sort_face(q: np.ndarray, ab: np.ndarray, members: np.ndarray, b: int, normalised: bool) -> list[int]:
    """Step 10: the face's points (``members``, ``b`` among them) in the order the sort key gives.

    ``q`` holds every point minus ``B``; ``ab`` is ``A - B``.
    """
    rel = q[members]
    key = _dots(rel, ab)  # angle(P) = (P - B) . (A - B), as the seed writes it
    if not normalised:
        return members[np.argsort(key, kind="stable")].tolist()
    rest = members[members != b]
    rel = q[rest]
    key = _dots(rel, ab) / np.sqrt(rel[:, 0] * rel[:, 0] + rel[:, 1] * rel[:, 1] + rel[:, 2] * rel[:, 2])
    return [b] + rest[np.argsort(key, kind="stable")].tolist()  # NaN (points equal to B) last


@np.errstate(divide="ignore", invalid="ignore", over="ignore")  # 0/0 -> NaN is the seed's behaviour
def _find_face(
    pts: np.ndarray, a: int, b: int, eps: float, max_pivots: int, variant: SeedVariant = LITERAL
) -> tuple[list[int], int]:
    """Steps 5-10 for the edge ``(a, b)``: the face in the seed's order, and the pivots taken."""
    n = len(pts)
    q = pts - pts[b]
    # Coordinate columns, contiguous: the same products and sums as on q's columns, fewer strides.
    qx, qy, qz = q.T.copy()
    abx, aby, abz = (pts[a] - pts[b]).tolist()
    # (A - B) x (C - B) for every candidate C at once.
    cross = np.empty((3, n))
    np.subtract(aby * qz, abz * qy, out=cross[0])
    np.subtract(abz * qx, abx * qz, out=cross[1])
    np.subtract(abx * qy, aby * qx, out=cross[2])
    off_line = (cross[0] != 0) | (cross[1] != 0) | (cross[2] != 0)
    off_line[a] = off_line[b] = False
    if not off_line.any():
        # An edge between two copies of one point (a misordered face can list one).
        if abx == 0 and aby == 0 and abz == 0:
            raise ValueError(
                f"{variant.name}: step 5 has no line through A={a} and B={b}: they are the same point "
                f"{pts[a].tolist()}"
            )
        raise ValueError(
            f"{variant.name}: step 5 found no point off the line through A={a} and B={b}: "
            "the points are collinear"
        )
    c = int(np.argmax(off_line))
    pivots = 0
    while True:
        nx, ny, nz = cross[0, c].item(), cross[1, c].item(), cross[2, c].item()
        dist = qx * nx + qy * ny + qz * nz  # _dots(q, cross[c]): the same operations in the same order
        tol = eps * math.sqrt(nx * nx + ny * ny + nz * nz)
        others = dist.copy()
        others[a] = others[b] = others[c] = -np.inf
        p = int(np.argmax(others))
        if others[p] > tol:  # with n = 3 every entry is -inf
            pivots += 1
            if pivots > max_pivots:
                raise AlgorithmStepLimit(
                    f"{variant.name}: steps 6-8 (pivoting) exceeded {max_pivots} pivots (2*n+100 for n={n}) "
                    f"for the face on edge ({a}, {b})"
                )
            c = p
            continue
        break
    on_plane = np.abs(dist) <= tol
    on_plane[a] = on_plane[b] = on_plane[c] = True
    return _sort_face(q, np.array([abx, aby, abz]), np.flatnonzero(on_plane), b, variant.improved), pivots


def _pivot_limit(n: int) -> int:
    """Pivots allowed for one face: ``2 n + 100`` (exact arithmetic needs at most ``n - 2``)."""
    return 2 * n + 100


def _face_limit(n: int) -> int:
    """Faces allowed in one run: ``4 n + 100`` (a hull on ``n`` points has at most ``2 n - 4``)."""
    return 4 * n + 100


def _henckel_trace(
    pts: np.ndarray, eps: float, rng: np.random.Generator, variant: SeedVariant = LITERAL
) -> HenckelTrace:
    """Run the seed's algorithm on validated points and record what happened."""
    n = len(pts)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        a, b, direction, draws = _initial_edge(pts, rng, variant.name)
        initial = (a, b)
        faces: list[list[int]] = []
        face_edges: list[tuple[int, int]] = []
        edge_list: list[tuple[int, int]] = []
        edge_set: set[tuple[int, int]] = set()
        todo = _ToDoList()
        max_faces = _face_limit(n)
        max_pivots = _pivot_limit(n)
        pivots = 0
        found_for: dict[tuple[int, int], tuple[list[int], int]] = {}
        stuck = False
        from_todo = False  # the initial edge is no to-do entry
        while True:
            if stuck or len(faces) >= max_faces:
                # One raise site for both: the error's frame is part of a failure's signature.
                raise AlgorithmStepLimit(
                    f"{variant.name}: steps 5-14 (main loop) built {max_faces} faces (4*n+100 for n={n}) "
                    f"and the to-do list is not empty (front edge ({a}, {b}))"
                )
            # Steps 5-10 are a pure function of the edge, so an edge that comes
            # back (a run that never loses its front edge) is answered from
            # this memo: the same faces, pivots and guard, without the cost.
            found = found_for.get((a, b))
            if found is None:
                found = found_for[(a, b)] = _find_face(pts, a, b, eps, max_pivots, variant)
            face, taken = found
            pivots += taken
            faces.append(list(face))
            face_edges.append((a, b))
            perimeter = list(zip(face, face[1:] + face[:1]))
            for p1, p2 in perimeter:
                if (p2, p1) in edge_set:
                    if (p1, p2) in todo:
                        todo.remove((p1, p2))
                else:
                    edge_set.add((p1, p2))
                    edge_list.append((p1, p2))
                    todo.append((p2, p1))
            if not todo:
                break
            # Stuck: (a, b) came from the front of the to-do list, and only step 12
            # removes a to-do entry, for an edge of the face just built.  If that face
            # (the same one each time: memoised) does not have the edge (a, b), the
            # entry is never removed, stays at the front, and every later iteration
            # builds the same face on it until the face guard trips with this front
            # edge: trip it now.
            stuck = from_todo and (a, b) not in perimeter
            a, b = todo.front()
            from_todo = True
    return HenckelTrace(
        eps=eps,
        direction=direction,
        draws=draws,
        initial_edge=initial,
        faces=faces,
        face_edges=face_edges,
        edge_list=edge_list,
        pivots=pivots,
    )


def _run(points: np.ndarray, eps: float | None, seed: int, variant: SeedVariant) -> list[list[int]]:
    """Validate, run, and turn the seed's clockwise lists into counter-clockwise polygons."""
    pts = _checked_points(points, variant.name, 3)
    trace = _henckel_trace(pts, _checked_eps(pts, eps, variant.name), np.random.default_rng(seed), variant)
    return [face[::-1] for face in trace.faces]


@register_algorithm(LITERAL.name, dim=3)
def henckel_hull(points: np.ndarray, /, *, eps: float | None = None, seed: int = 0) -> list[list[int]]:
    """John Henckel's direct convex hull (1998), as written: faces sorted by (P - B).(A - B).

    Parameters
    ----------
    points : ndarray of shape (n, 3), float64
        The input points, ``n >= 3`` (the seed's own minimum), finite.  Never
        written to.
    eps : float or None
        A point more than ``eps`` above a candidate plane makes it pivot; a
        point within ``eps`` of a face plane joins the face.  ``None`` uses
        ``hullstress.tolerance.tolerance(points, "scaled")``.
    seed : int
        Seeds ``numpy.random.default_rng`` for the random direction of the
        initial edge; the same points and seed always give the same faces.

    Returns
    -------
    list of list of int
        Polygon faces, the seed's step-10 lists reversed (counter-clockwise
        seen from outside when the sort put them in rotational order), with
        every point found on a face's plane, interior points included.

    Raises
    ------
    ValueError
        ``points`` is not ``(n, 3)``, has fewer than 3 rows or a non-finite
        value; ``eps`` is negative or non-finite; or the points are collinear
        (step 5 finds no third point) or all equal.
    hullstress.errors.AlgorithmStepLimit
        A guard tripped: the random direction kept tying four or more points,
        pivoting cycled, or a to-do edge kept coming back.  The last is the
        seed's usual ending on input in general position: the literal sort
        key misorders a face with an obtuse angle at its edge (see the module
        docstring); ``henckel-normalised`` is the variant without that flaw.

    See Also
    --------
    henckel_normalised_hull : the same algorithm with the sort key divided by ``|P - B|``.

    Examples
    --------
    A regular tetrahedron's faces have no obtuse angle, so the literal key
    sorts every face correctly:

    >>> tetrahedron = np.array([[1.0, 1, 1], [1, -1, -1], [-1, 1, -1], [-1, -1, 1]])
    >>> sorted(sorted(f) for f in henckel_hull(tetrahedron))
    [[0, 1, 2], [0, 1, 3], [0, 2, 3], [1, 2, 3]]

    A hexagonal prism: every edge of a hexagon face has a 135-degree angle at
    one end, so whichever edge that face is built on, the key sorts it out of
    rotational order, the face misses its own edge, and the edge comes back
    until the guard trips (for every seed):

    >>> hexagon = [(2.0, 0.0), (1.0, 1.0), (-1.0, 1.0), (-2.0, 0.0), (-1.0, -1.0), (1.0, -1.0)]
    >>> prism = np.array([[x, y, z] for z in (0.0, 1.0) for x, y in hexagon])
    >>> henckel_hull(prism)  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    hullstress.errors.AlgorithmStepLimit: henckel: steps 5-14 (main loop) built 148 faces ...
    """
    return _run(points, eps, seed, LITERAL)


@register_algorithm(NORMALISED.name, dim=3)
def henckel_normalised_hull(
    points: np.ndarray, /, *, eps: float | None = None, seed: int = 0
) -> list[list[int]]:
    """Henckel's hull with the sort key divided by the length of P - B (a named improvement on the seed).

    Parameters, returns and errors as :func:`henckel_hull`; only step 10
    differs: ``B`` first, then the face's other points by ascending
    ``(P - B).(A - B) / |P - B|``, which orders any convex face rotationally.

    Parameters
    ----------
    points : ndarray of shape (n, 3), float64
        The input points, ``n >= 3``, finite.  Never written to.
    eps : float or None
        As for :func:`henckel_hull`.
    seed : int
        As for :func:`henckel_hull`.

    Returns
    -------
    list of list of int
        Polygon faces, counter-clockwise seen from outside, with every point
        found on a face's plane, interior points included.

    Raises
    ------
    ValueError
        As for :func:`henckel_hull`.
    hullstress.errors.AlgorithmStepLimit
        A guard tripped (ties of four or more at the top, pivoting cycled on
        nearly coplanar input, or a face with an interior or collinear point
        that does not close).

    Examples
    --------
    The hexagonal prism that the literal key cannot close:

    >>> hexagon = [(2.0, 0.0), (1.0, 1.0), (-1.0, 1.0), (-2.0, 0.0), (-1.0, -1.0), (1.0, -1.0)]
    >>> prism = np.array([[x, y, z] for z in (0.0, 1.0) for x, y in hexagon])
    >>> sorted(len(f) for f in henckel_normalised_hull(prism))
    [4, 4, 4, 4, 4, 4, 6, 6]

    Flat input gives one face each way round; a face with a point inside it
    (here the centre of the square) never closes and trips the guard:

    >>> square = np.array([[0.0, 0, 0], [2, 0, 0], [2, 2, 0], [0, 2, 0]])
    >>> henckel_normalised_hull(square)
    [[1, 2, 3, 0], [3, 2, 1, 0]]
    >>> henckel_normalised_hull(np.vstack([square, [[1.0, 1, 0]]]))  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    hullstress.errors.AlgorithmStepLimit: henckel-normalised: steps 5-14 (main loop) built 120 faces ...
    """
    return _run(points, eps, seed, NORMALISED)
