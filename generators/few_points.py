"""A handful of points: exactly d, d+1 or d+2 of them, with and without a repeated row.

Public bug reports of hull libraries are dominated by tiny inputs, because
that is where the set-up code (find d+1 affinely independent points, orient
the initial simplex) is the whole algorithm:

- CGAL/cgal#639: four points in 3D, the fourth a copy of the third; the
  inexact kernel's coplanarity test said "not coplanar" and ``convex_hull_3``
  erased the same list iterator twice (a crash).  That is ``count="d+1",
  repeat=True``: only three distinct points, so no tetrahedron exists.
- CGAL/cgal#2320: the unit tetrahedron, exactly d+1 = 4 points, came out as
  an inward-oriented polyhedron (``count="d+1"``: nothing is left after the
  initial simplex, so its orientation is the answer).
- PointCloudLibrary/pcl#6161: four 2D points with integer coordinates in the
  thousands, three of them collinear: Qhull's "initial simplex is flat" or a
  crash depending on the input order (``count="d+2", shape="flat"`` and
  ``shape="lattice", scale=1e4``).
- akuukka/quickhull#1 and jscad/OpenJSCAD.org#1347: four or five coplanar
  (or 1e-15-off-plane) points in 3D handed over as a solid
  (``shape="flat"``, ``shape="near-flat"``).
- JuliaReach/LazySets.jl#892: three or four 2D points with a repeated row
  gave a wrong hull; trimesh#1446 is Qhull's "not enough points(3) to
  construct initial simplex" (``count="d"`` in 3D: a triangle in space).

The family ignores ``n`` (it is fixed-size); the seed picks the coordinates.
"""

from __future__ import annotations

import numpy as np

from hullstress.registry import register_generator

from ._common import (
    GeneratorValueError,
    affine_rank_exact,
    check_bool,
    check_choice,
    check_dim,
    check_positive,
    declare_min_size,
    finish,
    ulp_shift,
    uniform_ball,
)

__all__ = ["few_points", "COUNTS", "SHAPES"]

COUNTS = ("d", "d+1", "d+2")
SHAPES = ("generic", "lattice", "flat", "near-flat")
_LATTICE = 4  # small integer coordinates in [-4, 4]: exact in any arithmetic
_TRIES = 64


def _count(count: str, dim: int) -> int:
    return {"d": dim, "d+1": dim + 1, "d+2": dim + 2}[count]


def _flat(rng: np.random.Generator, k: int, dim: int) -> np.ndarray:
    """k distinct integer points spanning exactly one hyperplane (a line in 2D, a plane in 3D)."""
    for _ in range(_TRIES):
        base = rng.integers(-_LATTICE, _LATTICE + 1, dim)
        span = rng.integers(-2, 3, (dim - 1, dim))  # dim-1 integer directions
        # (0,..), e_1, .., e_{d-1} first, so the points span the whole hyperplane
        coef = np.concatenate([np.zeros((1, dim - 1), np.int64), np.eye(dim - 1, dtype=np.int64)])
        extra = rng.integers(-3, 4, (max(0, k - dim), dim - 1))
        coef = np.concatenate([coef, extra])[:k]
        pts = base + coef @ span
        if len(np.unique(pts, axis=0)) == k and affine_rank_exact(pts) == min(k - 1, dim - 1):
            return pts.astype(np.float64)
    raise GeneratorValueError(f"few-points: no flat configuration of {k} points found in {_TRIES} draws")


def _independent(rng: np.random.Generator, k: int, dim: int, shape: str) -> np.ndarray:
    """k points of full affine rank min(k-1, dim): random in the ball or small integers."""
    for _ in range(_TRIES):
        if shape == "lattice":
            pts = rng.integers(-_LATTICE, _LATTICE + 1, (k, dim)).astype(np.float64)
        else:
            pts = uniform_ball(rng, k, dim)
        if len(np.unique(pts, axis=0)) == k and affine_rank_exact(pts) == min(k - 1, dim):
            return pts
    raise GeneratorValueError(f"few-points: no independent configuration of {k} points found in {_TRIES} draws")


def _lift_one_ulp(rng: np.random.Generator, pts: np.ndarray, dim: int) -> np.ndarray | None:
    """Move one point of a flat set by one ulp along an axis that leaves the hyperplane (None: no such move)."""
    out = pts.copy()
    for i in rng.permutation(len(pts)):
        for axis in rng.permutation(dim):
            if out[i, axis] == 0:
                continue  # one ulp of 0 is a subnormal: a different hazard, not this one
            trial = out.copy()
            trial[i, axis] = float(ulp_shift(trial[i, axis], 1 if rng.random() < 0.5 else -1))
            if affine_rank_exact(trial) == min(len(pts) - 1, dim):
                return trial
    return None  # e.g. the plane z = 0 with every z zero: only subnormal moves would leave it


@register_generator(
    "few-points",
    dims=(2, 3),
    fixed_size=True,
    variants=(
        {"count": "d+1"},
        {"count": "d+1", "repeat": True},
        {"count": "d+2"},
        {"count": "d+2", "repeat": True},
        {"count": "d+2", "shape": "flat"},
        {"count": "d+2", "shape": "near-flat"},
        {"count": "d"},
        {"count": "d+1", "shape": "lattice", "scale": 1e4},
    ),
)
def few_points(
    rng: np.random.Generator,
    n: int,
    *,
    dim: int,
    count: str = "d+1",
    repeat: bool = False,
    shape: str = "generic",
    scale: float = 1.0,
) -> np.ndarray:
    """Exactly d, d+1 or d+2 points (3 points in 3D...), optionally one row repeated: the set-up code alone.

    Parameters
    ----------
    rng : numpy.random.Generator
    n : int
        Ignored (the size is ``count``).
    dim : {2, 3}
    count : {"d", "d+1", "d+2"}
        Number of rows: ``dim``, ``dim + 1`` or ``dim + 2`` (``"d"`` in 3D is
        three points, a triangle in space).
    repeat : bool
        One row is an exact copy of another: ``count - 1`` distinct points.
    shape : {"generic", "lattice", "flat", "near-flat"}
        ``generic``: uniform in the unit ball, affinely independent (rank
        ``min(k - 1, dim)`` for k distinct points, checked exactly).
        ``lattice``: the same with small integer coordinates in [-4, 4].
        ``flat``: distinct integer points spanning exactly one hyperplane
        (collinear in 2D, coplanar in 3D).  ``near-flat``: ``flat`` with one
        coordinate of one point moved by one ulp, off the hyperplane (full
        rank, barely).
    scale : float
        Multiplier (> 0) applied last; a power of ten times small integers
        stays exact (``lattice``, ``flat`` with ``scale=1e4``).

    Returns
    -------
    points : ndarray of shape (k, dim), float64
        Rows in random order (the repeated row anywhere).

    Notes
    -----
    With d+1 points every point is a vertex and the initial simplex is the
    hull: an implementation that orients it wrongly, or that assumes a
    (d+2)-th point exists to test it against, fails here and nowhere else.
    With a repeated row the d+1 affinely independent points the set-up code
    looks for do not exist (``count="d+1", repeat=True``), or exist only if
    the duplicate is skipped (``count="d+2", repeat=True``).

    Examples
    --------
    >>> pts = few_points(np.random.default_rng(0), 0, dim=3, count="d+1", repeat=True)
    >>> pts.shape, len(np.unique(pts, axis=0))
    ((4, 3), 3)
    >>> few_points(np.random.default_rng(0), 0, dim=3, count="d").shape  # a triangle in space
    (3, 3)
    """
    fam = "few-points"
    dim = check_dim(fam, dim, (2, 3))
    check_choice(fam, "count", count, COUNTS)
    repeat = check_bool(fam, "repeat", repeat)
    check_choice(fam, "shape", shape, SHAPES)
    scale = check_positive(fam, "scale", scale)
    k = _count(count, dim)
    distinct = k - 1 if repeat else k
    if shape == "near-flat" and distinct <= dim:
        raise GeneratorValueError(
            f"{fam}: shape 'near-flat' needs at least {dim + 1} distinct points, got count={count!r}, repeat={repeat}"
        )
    if shape == "flat":
        pts = _flat(rng, distinct, dim)
    elif shape == "near-flat":
        for _ in range(_TRIES):
            lifted = _lift_one_ulp(rng, _flat(rng, distinct, dim), dim)
            if lifted is not None:
                break
        else:
            raise GeneratorValueError(f"{fam}: no near-flat configuration found in {_TRIES} draws")
        pts = lifted
    else:
        pts = _independent(rng, distinct, dim, shape)
    if repeat:
        pts = np.concatenate([pts, pts[rng.integers(0, distinct)][None, :]])
    return finish(pts[rng.permutation(k)] * scale)


declare_min_size("few-points", lambda dim, **p: 1)
