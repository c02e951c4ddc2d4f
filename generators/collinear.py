"""Collinear runs: one line, runs along hull edges, near-collinear runs, columns of equal x.

Collinear triples have orientation zero.  Code that treats "zero" as "left" or
"right" keeps or drops interior edge points inconsistently (the Jarvis march
seed's collinear rule exists for this), zig-zags along the run, or loops
forever when the next-point choice ties (Jarvis march revisiting a point).
All points on one line is the extreme case: no triangle, and a 3D algorithm's
initial simplex cannot be built.  Near-collinear runs (a few ulps off the line)
make float orientation signs random, so the chain may fold back on itself.
The Cardiff lecture warns that points with the same x coordinate break the
incremental (monotone chain) hull unless the sort is lexicographic; columns of
equal x are that warning made into a family.

rbox has no direct equivalent (its lattices contain collinear rows); CGAL's
and scipy's hull tests include all-collinear inputs.
"""

from __future__ import annotations

import math

import numpy as np

from hullstress.registry import register_generator

from ._common import (
    GeneratorValueError,
    apply_matrix,
    check_choice,
    check_dim,
    check_int,
    check_n,
    check_positive,
    declare_min_size,
    finish,
    lattice,
    lattice_side,
    on_sphere,
    pow2_at_least,
    random_rotation,
    random_ulp_offsets,
    ulp_shift,
)

__all__ = ["collinear_line", "collinear_edges", "near_collinear", "equal_x_columns"]


def _integer_direction(rng: np.random.Generator, dim: int, lo: int = -5, hi: int = 5) -> np.ndarray:
    d = np.zeros(dim, dtype=np.int64)
    while not d.any():  # a deterministic redraw: the rng stream decides
        d = rng.integers(lo, hi + 1, dim)
    return d


@register_generator(
    "collinear-line",
    dims=(2, 3),
    variants=({}, {"distinct": False}, {"exact": False}, {"exact": False, "scale": 1e6}),
)
def collinear_line(
    rng: np.random.Generator,
    n: int,
    *,
    dim: int,
    exact: bool = True,
    distinct: bool = True,
    scale: float = 1.0,
) -> np.ndarray:
    """All points on one line: no triangle exists, the hull is a segment.

    Parameters
    ----------
    rng : numpy.random.Generator
    n : int
        Number of points (>= 1).
    dim : {2, 3}
    exact : bool
        True: ``a + t*d`` with integer a, d and t (exactly collinear).  False:
        a random float line, points rounded onto it (collinear only nearly).
    distinct : bool
        False: parameters t drawn with repetition (exact duplicates on the line).
    scale : float
        Final multiplier (exactness kept only for powers of two).

    Returns
    -------
    points : ndarray of shape (n, dim), float64

    Notes
    -----
    Every hull algorithm must either reject this input (affinely degenerate)
    or return the two end points; gift wrapping and Quickhull cannot build an
    initial triangle / tetrahedron and may divide by a zero normal.

    Examples
    --------
    >>> pts = collinear_line(np.random.default_rng(0), 5, dim=2)
    >>> d = pts - pts[0]
    >>> bool(np.all(d[:, 0] * d[1, 1] == d[:, 1] * d[1, 0]))
    True
    """
    fam = "collinear-line"
    dim = check_dim(fam, dim, (2, 3))
    n = check_n(fam, n, 1)
    scale = check_positive(fam, "scale", scale)
    if exact:
        a = rng.integers(-n, n + 1, dim)
        d = _integer_direction(rng, dim)
        if distinct:
            t = rng.permutation(n) - n // 2
        else:
            t = rng.integers(0, max(1, (n + 1) // 2), n)
        pts = (a + t[:, None] * d).astype(np.float64)
    else:
        a = rng.uniform(-1.0, 1.0, dim)
        d = on_sphere(rng, 1, dim)[0]
        if distinct:
            t = rng.uniform(-1.0, 1.0, n)
        else:
            t = rng.uniform(-1.0, 1.0, max(1, (n + 1) // 2))[rng.integers(0, max(1, (n + 1) // 2), n)]
        pts = a + t[:, None] * d
    return finish(pts * scale)


def _edge_count(shape: str, m: int, dim: int) -> int:
    """Number of lattice points on the edges of the box / simplex of size m."""
    corners, edges = (2**dim, dim * 2 ** (dim - 1)) if shape == "box" else (dim + 1, dim * (dim + 1) // 2)
    return corners + edges * (m - 1)


def _edge_points(shape: str, m: int, dim: int) -> tuple[np.ndarray, np.ndarray]:
    """(corners, other edge points) of the box [0, m]**dim or the simplex 0, m e_1, ..., m e_dim.

    Built directly without duplicates (each edge's interior points k = 1..m-1),
    in a fixed order.
    """
    inner = np.arange(1, m, dtype=np.int64)[:, None]
    runs = []
    if shape == "box":
        corners = lattice(2, dim) * m
        for axis in range(dim):
            for rest in lattice(2, dim - 1) * m:
                pts = np.zeros((m - 1, dim), dtype=np.int64)
                pts[:, axis] = inner[:, 0]
                pts[:, [j for j in range(dim) if j != axis]] = rest
                runs.append(pts)
    else:
        corners = np.vstack([np.zeros(dim, dtype=np.int64), np.eye(dim, dtype=np.int64) * m])
        for i in range(dim + 1):
            for j in range(i + 1, dim + 1):
                # v_i + k (v_j - v_i) / m: integer because the vertices are 0 or m e_*.
                runs.append(corners[i] + (inner * (corners[j] - corners[i])) // m)
    others = np.concatenate(runs) if runs else np.zeros((0, dim), dtype=np.int64)
    return corners, others


@register_generator(
    "collinear-edges",
    dims=(2, 3),
    variants=(
        {"shape": "box"},
        {"shape": "simplex"},
        {"shape": "box", "interior": 0.5},
        {"shape": "simplex", "interior": 0.5},
        {"shape": "box", "rotate": True},
    ),
)
def collinear_edges(
    rng: np.random.Generator,
    n: int,
    *,
    dim: int,
    shape: str = "box",
    interior: float = 0.0,
    rotate: bool = False,
) -> np.ndarray:
    """Collinear runs along every hull edge of a box or simplex (lattice points on the edges).

    Parameters
    ----------
    rng : numpy.random.Generator
    n : int
        Number of points (>= 1).  The shape's corners come first when n allows.
    dim : {2, 3}
    shape : {"box", "simplex"}
        ``[0, m]**dim`` or the corner simplex ``0, m e_1, ..., m e_dim``; m is
        the smallest size giving enough edge points.  Simplex edges include
        diagonals (``x + y = m``), still exact on the integer lattice.
    interior : float
        Share of the points placed strictly inside instead (0 <= interior < 1).
    rotate : bool
        Apply a random rotation: the runs become only nearly collinear.

    Returns
    -------
    points : ndarray of shape (n, dim), float64
        Coordinates divided by a power of two (exact) to lie in [0, 1].

    Notes
    -----
    Every edge of the true hull carries collinear points that are on the hull
    but are not vertices; an algorithm must neither report them as vertices in
    a way that breaks convexity nor lose the true corners among them.

    Examples
    --------
    >>> pts = collinear_edges(np.random.default_rng(0), 12, dim=2)
    >>> bool(np.all(np.any((pts == 0.0) | (pts == pts.max()), axis=1)))
    True
    """
    fam = "collinear-edges"
    dim = check_dim(fam, dim, (2, 3))
    n = check_n(fam, n, 1)
    check_choice(fam, "shape", shape, ("box", "simplex"))
    if isinstance(interior, bool) or not isinstance(interior, (int, float)) or not 0.0 <= interior < 1.0:
        raise GeneratorValueError(f"{fam}: interior must be a float in [0, 1), got {interior!r}")
    n_in = int(n * float(interior))
    n_edge = n - n_in
    m = 1
    while _edge_count(shape, m, dim) < n_edge:
        m *= 2  # powers of two keep the final exact rescaling trivial
    corners, others = _edge_points(shape, m, dim)
    if n_edge <= len(corners):
        chosen = corners[rng.choice(len(corners), n_edge, replace=False)]
    else:
        chosen = np.concatenate([corners, others[rng.choice(len(others), n_edge - len(corners), replace=False)]])
    pts = chosen.astype(np.float64)
    if n_in:
        if shape == "box":
            inner = rng.uniform(0.25 * m, 0.75 * m, (n_in, dim))
        else:
            w = rng.dirichlet(np.ones(dim + 1), n_in)
            inner = m * (0.1 / (dim + 1) + 0.9 * w[:, 1:])  # margin >= 0.1 m / (dim + 1) from every facet
        pts = np.concatenate([pts, inner])
    pts = pts[rng.permutation(n)] / pow2_at_least(float(m))
    if rotate:
        pts = apply_matrix(pts, random_rotation(rng, dim))
    return finish(pts)


@register_generator(
    "near-collinear",
    dims=(2, 3),
    variants=(
        {"ulps": 1},
        {"ulps": 16},
        {"ulps": 1, "apex": True},
        {"ulps": 0, "direction": "random"},
        {"ulps": 0, "direction": "random", "apex": True},
    ),
)
def near_collinear(
    rng: np.random.Generator,
    n: int,
    *,
    dim: int,
    ulps: int = 1,
    direction: str = "integer",
    apex: bool = False,
) -> np.ndarray:
    """Points within a few ulps of one line; optionally plus apexes, so the run lies on a hull edge.

    Parameters
    ----------
    rng : numpy.random.Generator
    n : int
        Number of points (>= 1; >= dim + 1 with ``apex``).
    dim : {2, 3}
    ulps : int
        Each coordinate is moved by a random integer number of ulps in
        ``[-ulps, ulps]`` (0: no perturbation).
    direction : {"integer", "random"}
        ``integer``: an exact integer line ``a + t*d`` away from the axes (so
        ulps are relative, never subnormal); ``random``: a float line whose
        points are rounded (near-collinear even with ``ulps=0``).
    apex : bool
        Replace ``dim - 1`` rows by points well off the line: the run becomes
        one edge of a triangle (2D) or tetrahedron (3D).

    Returns
    -------
    points : ndarray of shape (n, dim), float64
        Rows in random order.

    Notes
    -----
    Float orientation of three run points is decided by rounding noise: code
    that trusts it builds reflex "hull" vertices or crossing edges along the
    run (the Kettner et al. failures in a family).

    Examples
    --------
    >>> pts = near_collinear(np.random.default_rng(0), 6, dim=2, ulps=2)
    >>> pts.shape
    (6, 2)
    """
    fam = "near-collinear"
    dim = check_dim(fam, dim, (2, 3))
    ulps = check_int(fam, "ulps", ulps, 0, 2**20)
    check_choice(fam, "direction", direction, ("integer", "random"))
    n = check_n(fam, n, dim + 1 if apex else 1, "apex needs dim - 1 apexes and two line points" if apex else "")
    m = n - (dim - 1 if apex else 0)
    if direction == "integer":
        d = _integer_direction(rng, dim)
        a = rng.integers(8 * m, 16 * m + 1, dim)  # |t d| <= 2.5 m: coordinates stay >= 5.5 m > 0
        t = rng.permutation(m) - m // 2
        line = (a + t[:, None] * d).astype(np.float64)
        length = math.sqrt(float(d @ d)) * m  # integer d: exact dot
    else:
        a = rng.uniform(-1.0, 1.0, dim)
        d = on_sphere(rng, 1, dim)[0]
        line = a + rng.uniform(-1.0, 1.0, m)[:, None] * d
        length = 2.0
    if ulps:
        line = ulp_shift(line, random_ulp_offsets(rng, line.shape, ulps, nonzero_rows=False))
    pts = line
    if apex:
        # Apexes perpendicular-ish to the line at distance ~ its length.
        centre = line[np.argsort(t, kind="stable")[m // 2]] if direction == "integer" else a
        basis = random_rotation(rng, dim)
        dn = [float(x) for x in d]
        dn_norm = math.sqrt(sum(x * x for x in dn))
        dn = [x / dn_norm for x in dn]
        offs = []
        for k in range(dim - 1):
            col = [float(basis[j, k]) for j in range(dim)]
            along = sum(c * e for c, e in zip(col, dn))
            v = [c - along * e for c, e in zip(col, dn)]
            v_norm = math.sqrt(sum(x * x for x in v))
            offs.append([c + length * x / v_norm for c, x in zip(centre, v)])
        pts = np.concatenate([line, np.array(offs)])
    return finish(pts[rng.permutation(n)])


@register_generator(
    "equal-x-columns",
    dims=(2, 3),
    variants=({"columns": 2}, {"columns": 3}, {"columns": 1}, {"columns": 8, "spacing": "integer"}),
)
def equal_x_columns(
    rng: np.random.Generator,
    n: int,
    *,
    dim: int,
    columns: int = 3,
    spacing: str = "random",
) -> np.ndarray:
    """Points on a few vertical columns of equal x (equal x and y in 3D): the lecture's warning.

    Parameters
    ----------
    rng : numpy.random.Generator
    n : int
        Number of points (>= columns: every column gets a point).
    dim : {2, 3}
    columns : int
        Number of distinct columns.  2D: x in ``{0, ..., columns-1}``; 3D:
        (x, y) the first ``columns`` points of a small integer lattice.
        ``columns=1`` puts every point on one line.
    spacing : {"random", "integer"}
        The free coordinate: uniform in [-1, 1], or small integers (duplicates
        and horizontal collinear rows across columns too).

    Returns
    -------
    points : ndarray of shape (n, dim), float64

    Notes
    -----
    Sorting by x alone leaves ties in arbitrary order; Andrew's monotone chain
    then picks a wrong end of a column, and the leftmost / rightmost columns
    are collinear runs on the hull.

    Examples
    --------
    >>> pts = equal_x_columns(np.random.default_rng(0), 9, dim=2, columns=3)
    >>> sorted(set(pts[:, 0].tolist()))
    [0.0, 1.0, 2.0]
    """
    fam = "equal-x-columns"
    dim = check_dim(fam, dim, (2, 3))
    columns = check_int(fam, "columns", columns, 1, 2**20)
    n = check_n(fam, n, columns, "every column needs a point")
    check_choice(fam, "spacing", spacing, ("random", "integer"))
    if dim == 2:
        spots = np.arange(columns)[:, None]
    else:
        spots = lattice(lattice_side(columns, 2), 2)[:columns]
    which = np.concatenate([np.arange(columns), rng.integers(0, columns, n - columns)])
    if spacing == "random":
        free = rng.uniform(-1.0, 1.0, n)
    else:
        half = max(1, n // (2 * columns))
        free = rng.integers(-half, half + 1, n).astype(np.float64)
    pts = np.column_stack([spots[which].astype(np.float64), free])
    return finish(pts[rng.permutation(n)])


declare_min_size("collinear-line", lambda dim, **p: 1)
declare_min_size("collinear-edges", lambda dim, **p: 1)
declare_min_size("near-collinear", lambda dim, apex=False, **p: dim + 1 if apex else 1)
declare_min_size("equal-x-columns", lambda dim, columns=3, **p: int(columns))
