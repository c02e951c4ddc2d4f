"""Mutation operators: new inputs from kept ones, each aimed at a hazard of hull code.

Every operator is a function ``(points, rng, *, other=None) -> ndarray or None``:

* ``points`` is an (n, d) float64 array, d in (2, 3), n >= 1, finite; it is never written to.
* The result is a new C-contiguous (m, d) float64 array with the same d,
  finite, 1 <= m; the engine (:mod:`hullstress.search.engine`) caps m.
* None means the operator does not apply to this input (a snap needs a
  full-dimensional hull, a merge needs a second input of the same
  dimension, a scaling would overflow); the engine then draws another one
  and records only what applied.
* Every random choice comes from ``rng``, so an operator is a pure function
  of its input and the generator's state.

==========================  =================================================================
name                        what it does
==========================  =================================================================
``transform:<name>``        a metamorphic transform (:mod:`generators.transforms`): same hull,
                            other order, scale, axes or duplicated rows
``nudge-ulp``               one coordinate of one row moved by 1 to 4 ulps
``duplicate-vertex``        an exact copy of an extreme point appended (the point with the
                            largest or smallest coordinate along an axis, ties broken
                            lexicographically, is always a vertex)
``snap-edge``               one row replaced by a point of a hull edge, rounded to float:
                            exactly on it when the arithmetic is exact, within an ulp or so
                            of it otherwise: a near-degenerate trigger either way
``snap-face``               (3D) the same onto a hull triangle
``scale``                   every coordinate times a factor that is not a power of two
                            (rounding moves every point a little)
``offset``                  the input moved far from the origin (2**8 to 2**40 times its
                            size), where its coordinates keep fewer bits of its shape
``merge``                   the rows of a second input appended (its hazards with these)
``drop``                    a random quarter to half of the rows removed (at least d + 1 stay)
==========================  =================================================================
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

__all__ = ["MUTATIONS", "Mutation", "mutations_for", "extreme_row"]

#: ``(points, rng, *, other) -> points or None``.
Mutation = Callable[..., "np.ndarray | None"]


def _finished(points: np.ndarray) -> np.ndarray | None:
    """The operator's result as promised (C-contiguous float64), or None when it is not finite."""
    out = np.ascontiguousarray(points, dtype=np.float64)
    return out if len(out) and np.isfinite(out).all() else None


def _transform(name: str) -> Mutation:
    def mutate(points: np.ndarray, rng: np.random.Generator, *, other: np.ndarray | None = None) -> np.ndarray | None:
        from generators import apply_transforms
        from generators._common import GeneratorValueError

        try:
            moved = apply_transforms(points, name, seed=int(rng.integers(2**62)))
        except GeneratorValueError:  # e.g. add-interior on a flat input: no interior to add to
            return None
        return _finished(moved.points)

    mutate.__doc__ = f"The metamorphic transform {name!r} (:mod:`generators.transforms`)."
    return mutate


def nudge_ulp(points: np.ndarray, rng: np.random.Generator, *, other: np.ndarray | None = None) -> np.ndarray:
    """Move one coordinate of one row by 1 to 4 ulps, up or down (towards zero at the edge of the range).

    Examples
    --------
    >>> p = np.array([[1.0, 2.0], [3.0, 4.0]])
    >>> q = nudge_ulp(p, np.random.default_rng(0))
    >>> int((q != p).sum()), q.shape
    (1, (2, 2))
    """
    out = np.array(points, dtype=np.float64)
    i, j = int(rng.integers(len(out))), int(rng.integers(out.shape[1]))
    steps, up = int(rng.integers(1, 5)), bool(rng.integers(2))
    x = out[i, j]
    for _ in range(steps):
        nxt = np.nextafter(x, np.inf if up else -np.inf)
        if not np.isfinite(nxt):
            up = not up  # the largest float: step back inside the range
            nxt = np.nextafter(x, np.inf if up else -np.inf)
        x = nxt
    out[i, j] = x
    return out


def extreme_row(points: np.ndarray, axis: int, largest: bool) -> int:
    """The row with the largest (smallest) coordinate on ``axis``, ties broken lexicographically: an extreme point.

    Examples
    --------
    >>> extreme_row(np.array([[0.0, 0], [1, 0], [1, 1], [0.5, 0.5]]), 0, True)
    2
    """
    sign = 1.0 if largest else -1.0
    keys = [sign * points[:, k] for k in range(points.shape[1]) if k != axis][::-1] + [sign * points[:, axis]]
    return int(np.lexsort(keys)[-1])


def duplicate_vertex(points: np.ndarray, rng: np.random.Generator, *, other: np.ndarray | None = None) -> np.ndarray:
    """Append an exact copy of an extreme point (see :func:`extreme_row`)."""
    row = extreme_row(points, int(rng.integers(points.shape[1])), bool(rng.integers(2)))
    return np.ascontiguousarray(np.vstack([points, points[row:row + 1]]))


def _hull_simplices(points: np.ndarray) -> np.ndarray | None:
    """Qhull's facets of ``points`` (edges in 2D, triangles in 3D), or None for a flat input.

    Only a choice of where to snap: a wrong facet makes a less useful
    candidate, never a wrong verdict (every candidate is judged exactly).
    """
    from scipy.spatial import ConvexHull, QhullError

    try:
        with np.errstate(all="ignore"):
            return np.asarray(ConvexHull(points, qhull_options="Qt").simplices, dtype=np.int64)
    except (QhullError, ValueError):
        return None


def _snap(points: np.ndarray, rng: np.random.Generator, corners: int) -> np.ndarray | None:
    if points.shape[1] < corners or len(points) <= points.shape[1]:
        return None
    simplices = _hull_simplices(points)
    if simplices is None:
        return None
    facet = simplices[int(rng.integers(len(simplices)))]
    chosen = rng.choice(facet, size=corners, replace=False) if corners < len(facet) else facet
    weights = rng.dirichlet(np.ones(corners))
    if rng.integers(2):
        weights = np.full(corners, 1.0 / corners)  # the midpoint or centroid: exact more often
    with np.errstate(all="ignore"):
        target = weights @ points[chosen]
    out = np.array(points, dtype=np.float64)
    out[int(rng.integers(len(out)))] = target
    return _finished(out)


def snap_edge(points: np.ndarray, rng: np.random.Generator, *, other: np.ndarray | None = None) -> np.ndarray | None:
    """Replace one row by a point of a hull edge (rounded to float); None for a flat input."""
    return _snap(points, rng, 2)


def snap_face(points: np.ndarray, rng: np.random.Generator, *, other: np.ndarray | None = None) -> np.ndarray | None:
    """Replace one row by a point of a hull triangle (3D; rounded to float); None in 2D or for a flat input."""
    return _snap(points, rng, 3) if points.shape[1] == 3 else None


def scale(points: np.ndarray, rng: np.random.Generator, *, other: np.ndarray | None = None) -> np.ndarray | None:
    """Multiply every coordinate by a factor that is not a power of two; None when that overflows."""
    factor = float(rng.choice([3.0, 0.1, 1.0 / 3.0, 7.0, 1e-7, 1e7])) * float(2.0 ** int(rng.integers(-20, 21)))
    with np.errstate(all="ignore"):
        return _finished(points * factor)


def offset(points: np.ndarray, rng: np.random.Generator, *, other: np.ndarray | None = None) -> np.ndarray | None:
    """Translate far from the origin: by 2**8 to 2**40 times the input's size, per axis; None on overflow."""
    with np.errstate(all="ignore"):
        size = float(np.max(np.abs(points))) or 1.0
        shift = size * np.ldexp(1.0, rng.integers(8, 41, size=points.shape[1])) * rng.choice([-1.0, 1.0], points.shape[1])
        return _finished(points + shift)


def merge(points: np.ndarray, rng: np.random.Generator, *, other: np.ndarray | None = None) -> np.ndarray | None:
    """Append the rows of ``other`` (an input of the same dimension); None without one."""
    if other is None or other.shape[1] != points.shape[1]:
        return None
    return _finished(np.vstack([points, other]))


def drop(points: np.ndarray, rng: np.random.Generator, *, other: np.ndarray | None = None) -> np.ndarray | None:
    """Remove a random quarter to half of the rows, keeping at least d + 1; None when too few rows."""
    n, d = points.shape
    if n <= d + 1:
        return None
    keep = max(d + 1, n - int(n * rng.uniform(0.25, 0.5)))
    rows = np.sort(rng.choice(n, size=keep, replace=False))
    return np.ascontiguousarray(points[rows])


def _registry() -> dict[str, Mutation]:
    from generators import TRANSFORMS

    table: dict[str, Mutation] = {f"transform:{name}": _transform(name) for name in sorted(TRANSFORMS)}
    table.update({"nudge-ulp": nudge_ulp, "duplicate-vertex": duplicate_vertex, "snap-edge": snap_edge,
                  "snap-face": snap_face, "scale": scale, "offset": offset, "merge": merge, "drop": drop})
    return table


#: Every operator by name (the ``mutations`` column of a searched case lists the ones applied).
MUTATIONS: dict[str, Mutation] = _registry()


def mutations_for(dim: int) -> tuple[str, ...]:
    """The operator names that can apply to ``dim``-dimensional inputs, in a fixed order.

    Examples
    --------
    >>> "snap-face" in mutations_for(2), "snap-face" in mutations_for(3)
    (False, True)
    """
    return tuple(name for name in MUTATIONS if not (dim == 2 and name == "snap-face"))
