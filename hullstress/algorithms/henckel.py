"""John Henckel's direct convex hull (1998), registered as ``henckel``.

Seed document: ``001_9cf2e85d43cd0c3f.txt`` (J. Henckel, "A Direct Convex
Hull Algorithm").  The code follows its numbered lists.

"Finding the initial edge" (:func:`_initial_edge`):

1. ``D``: a random unit vector, a normalised ``standard_normal(3)`` draw from
   ``numpy.random.default_rng(seed)``, so one input and seed give one output.
2. ``A``: the point with the largest ``P . D``.
3. If *more than three* points share that maximum (exact float equality),
   draw again; otherwise ``A`` is the lowest index among them.
4. ``B``: the point (not ``A``) with the smallest angle at ``A`` to the plane
   ``M`` perpendicular to ``D``, i.e. the largest signed
   ``((B - A)/|B - A|) . D`` (every value is <= 0, so the largest is the one
   nearest the plane).  A point equal to ``A`` gives 0/0 = NaN, which never
   compares larger and so is never chosen.
5. Ties on that value (exact equality): the point nearest to ``A``, then the
   lowest index.

"Algorithm" (:func:`_henckel_trace` and :func:`_find_face`):

* Steps 1-3: ``n < 3`` is the seed's error (:class:`ValueError`); the face,
  edge and to-do lists start empty.
* Step 4: the initial edge above.
* Step 5: ``C`` is the lowest index (not ``A``, ``B``) whose
  ``(A - B) x (C - B)`` is not exactly the zero vector.  If there is none the
  points are collinear and the seed has no answer: :class:`ValueError`.
* Steps 6-8: ``NM = (A - B) x (C - B)``; ``dist(P) = (P - B) . NM`` for every
  point except ``A, B, C``; ``P`` is the largest (lowest index on ties); if it
  is "above", ``C = P`` and repeat.
* Step 9: the face is every point "on the plane", gathered in index order;
  ``A``, ``B`` and ``C`` are included outright, as the seed states they are.
  Interior points of a polygonal face are on the plane too, so they are in
  the face (quirk kept).
* Step 10: the face is sorted by ``angle(P)``.  The seed writes the value as
  ``(P - B) . (A - B)``; sorted as written, even a triangle often comes out in
  the wrong rotational order, so the natural reading is the angle that the
  name and the sort need: the same dot product divided by ``|P - B|`` (the
  cosine of the angle at ``B`` between ``BA`` and ``BP``, times the constant
  ``|A - B|``).  Sorting that value ascending (a stable sort, so exact ties
  keep index order) and putting ``B`` first, where its 0/0 value has no
  place, gives ``B, ..., A``: the seed's clockwise perimeter, which contains
  the edge ``A -> B``.  Points equal to ``B`` (NaN values) sort last.
* Steps 11-12: for each perimeter edge ``E = (P1, P2)`` (consecutive points,
  cyclically), with ``ER = (P2, P1)``: if ``ER`` is in the edge list, one copy
  of ``E`` is removed from the to-do list if present; otherwise ``E`` is
  appended to the edge list and ``ER`` to the to-do list.
* Steps 13-14: "get the next edge in the to-do list" reads the *front* of the
  list without removing it; only step 12 removes to-do entries (a correctly
  sorted face built on ``(A, B)`` contains ``A -> B`` and so removes it).  When
  a face does not contain its own to-do edge (a tie in the sort put a
  collinear point after ``A``, a duplicate of ``B``...), the same edge comes
  back forever; the iteration guard turns that into
  :class:`~hullstress.errors.AlgorithmStepLimit`.

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
reversed, ``A, ..., B``, counter-clockwise seen from outside as the harness
contract asks.

Guards (a correct run cannot reach them): the random direction is drawn at
most 1000 times; one face takes at most ``2 n + 100`` pivots (in exact
arithmetic each pivot turns the plane further round ``AB``, so ``n - 2`` is
enough); at most ``4 n + 100`` faces are built (a hull on ``n`` points has at
most ``2 n - 4`` faces, and each iteration builds a new one).
"""

from __future__ import annotations

from collections import deque
from dataclasses import dataclass

import numpy as np

from .._registry import register_algorithm
from ..errors import AlgorithmStepLimit
from .gift_wrap import _checked_eps, _checked_points

__all__ = ["henckel_hull"]

_NAME = "henckel"
_MAX_DRAWS = 1000


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
        The faces in the seed's order (clockwise seen from outside, ``B`` first).
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
def _initial_edge(pts: np.ndarray, rng: np.random.Generator) -> tuple[int, int, np.ndarray, int]:
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
            raise ValueError(f"{_NAME}: initial edge: every point coincides with point A={a}")
        best = sine[ok].max()
        tied = np.flatnonzero(sine == best)
        b = int(tied[np.argmin(length[tied])])
        return a, b, d, draw
    raise AlgorithmStepLimit(
        f"{_NAME}: initial edge step 3 drew {_MAX_DRAWS} random directions and every one "
        "had more than three points at the maximum"
    )


@np.errstate(divide="ignore", invalid="ignore", over="ignore")  # 0/0 -> NaN is the seed's behaviour
def _find_face(pts: np.ndarray, a: int, b: int, eps: float, max_pivots: int) -> tuple[list[int], int]:
    """Steps 5-10 for the edge ``(a, b)``: the face in the seed's order, and the pivots taken."""
    n = len(pts)
    q = pts - pts[b]
    ab = pts[a] - pts[b]
    # (A - B) x (C - B) for every candidate C at once.
    cross = np.stack(
        [
            ab[1] * q[:, 2] - ab[2] * q[:, 1],
            ab[2] * q[:, 0] - ab[0] * q[:, 2],
            ab[0] * q[:, 1] - ab[1] * q[:, 0],
        ],
        axis=1,
    )
    off_line = (cross != 0).any(axis=1)
    off_line[[a, b]] = False
    if not off_line.any():
        raise ValueError(
            f"{_NAME}: step 5 found no point off the line through A={a} and B={b}: the points are collinear"
        )
    c = int(np.argmax(off_line))
    pivots = 0
    while True:
        nm = cross[c]
        dist = _dots(q, nm)
        tol = eps * float(np.sqrt(nm[0] * nm[0] + nm[1] * nm[1] + nm[2] * nm[2]))
        others = dist.copy()
        others[[a, b, c]] = -np.inf
        p = int(np.argmax(others))
        if others[p] > tol:  # with n = 3 every entry is -inf
            pivots += 1
            if pivots > max_pivots:
                raise AlgorithmStepLimit(
                    f"{_NAME}: steps 6-8 (pivoting) exceeded {max_pivots} pivots (2*n+100 for n={n}) "
                    f"for the face on edge ({a}, {b})"
                )
            c = p
            continue
        break
    on_plane = np.abs(dist) <= tol
    on_plane[[a, b, c]] = True
    on_plane[b] = False
    members = np.flatnonzero(on_plane)
    rel = q[members]
    key = _dots(rel, ab) / np.sqrt(rel[:, 0] * rel[:, 0] + rel[:, 1] * rel[:, 1] + rel[:, 2] * rel[:, 2])
    order = np.argsort(key, kind="stable")  # NaN (points equal to B) last
    return [b] + members[order].tolist(), pivots


def _pivot_limit(n: int) -> int:
    """Pivots allowed for one face: ``2 n + 100`` (exact arithmetic needs at most ``n - 2``)."""
    return 2 * n + 100


def _face_limit(n: int) -> int:
    """Faces allowed in one run: ``4 n + 100`` (a hull on ``n`` points has at most ``2 n - 4``)."""
    return 4 * n + 100


def _henckel_trace(pts: np.ndarray, eps: float, rng: np.random.Generator) -> HenckelTrace:
    """Run the seed's algorithm on validated points and record what happened."""
    n = len(pts)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        a, b, direction, draws = _initial_edge(pts, rng)
        initial = (a, b)
        faces: list[list[int]] = []
        face_edges: list[tuple[int, int]] = []
        edge_list: list[tuple[int, int]] = []
        edge_set: set[tuple[int, int]] = set()
        todo = _ToDoList()
        max_faces = _face_limit(n)
        max_pivots = _pivot_limit(n)
        pivots = 0
        while True:
            if len(faces) >= max_faces:
                raise AlgorithmStepLimit(
                    f"{_NAME}: steps 5-14 (main loop) built {max_faces} faces (4*n+100 for n={n}) "
                    f"and the to-do list is not empty (front edge ({a}, {b}))"
                )
            face, taken = _find_face(pts, a, b, eps, max_pivots)
            pivots += taken
            faces.append(face)
            face_edges.append((a, b))
            for p1, p2 in zip(face, face[1:] + face[:1]):
                if (p2, p1) in edge_set:
                    if (p1, p2) in todo:
                        todo.remove((p1, p2))
                else:
                    edge_set.add((p1, p2))
                    edge_list.append((p1, p2))
                    todo.append((p2, p1))
            if not todo:
                break
            a, b = todo.front()
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


@register_algorithm(_NAME, dim=3)
def henckel_hull(points: np.ndarray, /, *, eps: float | None = None, seed: int = 0) -> list[list[int]]:
    """John Henckel's direct convex hull (1998): polygon faces by farthest-above pivoting.

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
        Polygon faces, counter-clockwise seen from outside (the seed's
        clockwise lists reversed), with every point found on a face's plane,
        interior points included.

    Raises
    ------
    ValueError
        ``points`` is not ``(n, 3)``, has fewer than 3 rows or a non-finite
        value; ``eps`` is negative or non-finite; or the points are collinear
        (step 5 finds no third point) or all equal.
    hullstress.errors.AlgorithmStepLimit
        A guard tripped: the random direction kept tying four or more points,
        pivoting cycled, or a to-do edge kept coming back.

    Examples
    --------
    >>> cube = np.array([[x, y, z] for x in (0.0, 1.0) for y in (0.0, 1.0) for z in (0.0, 1.0)])
    >>> sorted(len(f) for f in henckel_hull(cube))
    [4, 4, 4, 4, 4, 4]

    Flat input gives one face each way round; a face with a point inside it
    (here the centre of the square) never closes and trips the guard:

    >>> square = np.array([[0.0, 0, 0], [2, 0, 0], [2, 2, 0], [0, 2, 0]])
    >>> henckel_hull(square)
    [[1, 2, 3, 0], [3, 2, 1, 0]]
    >>> henckel_hull(np.vstack([square, [[1.0, 1, 0]]]))  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    hullstress.errors.AlgorithmStepLimit: henckel: steps 5-14 (main loop) built 120 faces ...
    """
    pts = _checked_points(points, _NAME, 3)
    trace = _henckel_trace(pts, _checked_eps(pts, eps, _NAME), np.random.default_rng(seed))
    return [face[::-1] for face in trace.faces]
