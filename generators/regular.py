"""Regular shapes: regular polygons, Platonic solids, rbox's spiral and simplex.

Regular shapes are degenerate by symmetry.  In a regular n-gon or on a helix
every point is extreme and, for large n, every three (2D) or four (3D)
consecutive points are nearly collinear / coplanar, so rounding decides which
of them are vertices.  Platonic solids have exactly (cube, octahedron,
tetrahedron) or nearly (dodecahedron: the golden ratio is rounded) coplanar
faces with more than three vertices, and their symmetry makes every
"farthest point" or "lowest point" choice a tie.  rbox's simplex squeezed
with ``W`` puts nearly every point within rounding of a facet.

rbox equivalents: ``r`` (regular polygon), ``l`` (spiral), ``c`` / ``d``
(cube / diamond = octahedron vertices), ``x`` / ``y`` (simplex, ``W`` width).
"""

from __future__ import annotations

import math
from functools import lru_cache

import numpy as np

from hullstress.registry import register_generator

from ._common import (
    GeneratorValueError,
    apply_matrix,
    check_choice,
    check_dim,
    check_n,
    check_positive,
    combine,
    declare_min_size,
    finish,
    lattice as _lattice,
    random_rotation,
    row_dot,
    uniform_ball,
)

__all__ = ["regular_polygon", "regular_polyhedron", "spiral", "simplex_points", "SOLIDS"]


@register_generator(
    "regular-polygon",
    dims=(2,),
    variants=({}, {"center": 1e6}, {"phase": "zero"}, {"order": "random"}),
)
def regular_polygon(
    rng: np.random.Generator,
    n: int,
    *,
    dim: int = 2,
    radius: float = 1.0,
    center: float = 0.0,
    phase: str = "random",
    order: str = "cyclic",
) -> np.ndarray:
    """The n vertices of a regular n-gon (rbox r): all extreme, neighbours nearly collinear.

    Parameters
    ----------
    rng : numpy.random.Generator
    n : int
        Number of vertices (>= 3).
    dim : {2}
    radius : float
        Circumradius.
    center : float
        Both coordinates of the centre: a large centre (1e6) costs the
        polygon most of its significant bits.
    phase : {"random", "zero"}
        A random rotation of the polygon, or rbox's layout with a vertex at
        angle 0 (the rows then start at a random vertex).
    order : {"cyclic", "random"}
        Vertices in counter-clockwise order or shuffled.

    Returns
    -------
    points : ndarray of shape (n, 2), float64

    Notes
    -----
    For large n the turn at each vertex is 2 pi / n, so consecutive triples
    have orientation ~ (2 pi / n)**2 * radius**2 / 2, soon below rounding: after
    rounding some vertices may not even be extreme any more, which an exact
    checker sees and a tolerant algorithm does not.

    Examples
    --------
    >>> pts = regular_polygon(np.random.default_rng(0), 4, dim=2, phase="zero")
    >>> sorted(np.round(pts, 12).tolist())
    [[-1.0, 0.0], [-0.0, -1.0], [0.0, 1.0], [1.0, 0.0]]
    """
    fam = "regular-polygon"
    dim = check_dim(fam, dim, (2,))
    n = check_n(fam, n, 3, "a polygon needs 3 vertices")
    radius = check_positive(fam, "radius", radius)
    check_choice(fam, "phase", phase, ("random", "zero"))
    check_choice(fam, "order", order, ("cyclic", "random"))
    try:
        c = float(center)
    except (TypeError, ValueError):
        c = math.nan
    if not math.isfinite(c):
        raise GeneratorValueError(f"{fam}: center must be a finite float, got {center!r}")
    start = rng.uniform(0.0, 2.0 * math.pi) if phase == "random" else 0.0
    theta = start + 2.0 * math.pi * np.arange(n) / n
    pts = c + radius * np.column_stack([np.cos(theta), np.sin(theta)])
    if order == "random":
        pts = pts[rng.permutation(n)]
    elif phase == "zero":
        pts = np.roll(pts, -int(rng.integers(0, n)), axis=0)  # same cyclic order, random first row
    return finish(pts)


_PHI = (1.0 + math.sqrt(5.0)) / 2.0


def _cyclic(v: list[tuple[float, float, float]]) -> np.ndarray:
    rows = []
    for x, y, z in v:
        rows += [(x, y, z), (z, x, y), (y, z, x)]
    return np.array(rows, dtype=np.float64)


def _solid(name: str) -> np.ndarray:
    """Vertices of a Platonic solid centred at the origin."""
    cube = (_lattice(2, 3) * 2 - 1).astype(np.float64)
    signs = [(s1, s2) for s1 in (1.0, -1.0) for s2 in (1.0, -1.0)]
    if name == "tetrahedron":
        return cube[np.prod(cube, axis=1) > 0]
    if name == "cube":
        return cube
    if name == "octahedron":
        return np.concatenate([np.eye(3), -np.eye(3)])
    if name == "icosahedron":
        return _cyclic([(0.0, s1, s2 * _PHI) for s1, s2 in signs])
    return np.concatenate([cube, _cyclic([(0.0, s1 / _PHI, s2 * _PHI) for s1, s2 in signs])])


SOLIDS = ("tetrahedron", "cube", "octahedron", "icosahedron", "dodecahedron")
_SOLID_SIZE = {"tetrahedron": 4, "cube": 8, "octahedron": 6, "icosahedron": 12, "dodecahedron": 20}


def _fan_triangles(verts: np.ndarray) -> np.ndarray:
    """Triangles (vertex index triples) fanning every face of the convex solid, in a fixed order.

    Faces are found by brute force over vertex triples (V <= 20): a triple's
    plane is a face plane when no vertex lies beyond it (tolerance 1e-9, far
    above the golden ratio's rounding and far below the solids' features).
    """
    tris = []
    seen: list[np.ndarray] = []
    v = len(verts)
    for i in range(v):
        for j in range(i + 1, v):
            for k in range(j + 1, v):
                u = np.cross(verts[j] - verts[i], verts[k] - verts[i])
                if np.linalg.norm(u) < 1e-9:
                    continue
                u = u / np.linalg.norm(u)
                if u @ verts[i] < 0:
                    u = -u
                h = verts @ u - u @ verts[i]
                if np.any(h > 1e-9) or any(np.allclose(u, w) for w in seen):
                    continue
                seen.append(u)
                face = np.flatnonzero(np.abs(h) <= 1e-9)
                centre = verts[face].mean(axis=0)
                e1 = verts[face[0]] - centre
                e2 = np.cross(u, e1)
                ang = np.arctan2((verts[face] - centre) @ e2, (verts[face] - centre) @ e1)
                ring = face[np.argsort(ang, kind="stable")]
                tris += [(ring[0], ring[a], ring[a + 1]) for a in range(1, len(ring) - 1)]
    return np.array(tris, dtype=np.int64)


@lru_cache(maxsize=None)
def _solid_triangles(name: str) -> np.ndarray:
    return _fan_triangles(_solid(name))


@register_generator(
    "regular-polyhedron",
    dims=(3,),
    variants=(
        {"solid": "tetrahedron"},
        {"solid": "cube"},
        {"solid": "octahedron"},
        {"solid": "icosahedron"},
        {"solid": "dodecahedron"},
        {"solid": "dodecahedron", "rotate": True},
        {"solid": "cube", "extra": "interior"},
    ),
)
def regular_polyhedron(
    rng: np.random.Generator,
    n: int,
    *,
    dim: int = 3,
    solid: str = "cube",
    extra: str = "faces",
    rotate: bool = False,
) -> np.ndarray:
    """A Platonic solid's vertices plus points on its faces (or inside): coplanar faces, symmetric ties.

    Parameters
    ----------
    rng : numpy.random.Generator
    n : int
        Number of points (>= the solid's vertex count: 4, 8, 6, 12, 20).
    dim : {3}
    solid : {"tetrahedron", "cube", "octahedron", "icosahedron", "dodecahedron"}
        Tetrahedron, cube and octahedron (rbox ``c``, ``d``) have exact integer
        vertices; icosahedron and dodecahedron use the rounded golden ratio, so
        a dodecahedron's pentagons are coplanar only up to rounding.
    extra : {"faces", "interior"}
        The other n - V points: random points on random faces (convex
        combinations of a fan triangle, rounded) or in a ball of radius 1/4.
    rotate : bool
        Apply a random rotation.

    Returns
    -------
    points : ndarray of shape (n, 3), float64
        Rows in random order.

    Notes
    -----
    Square and pentagonal faces are coplanar quadruples / quintuples (exactly
    for the cube, nearly for the dodecahedron); the symmetry gives many exact
    ties in "farthest point" and "lowest point" choices.

    Examples
    --------
    >>> pts = regular_polyhedron(np.random.default_rng(0), 8, solid="cube")
    >>> sorted(map(tuple, pts.tolist()))[0]
    (-1.0, -1.0, -1.0)
    """
    fam = "regular-polyhedron"
    dim = check_dim(fam, dim, (3,))
    check_choice(fam, "solid", solid, SOLIDS)
    check_choice(fam, "extra", extra, ("faces", "interior"))
    verts = _solid(solid)
    n = check_n(fam, n, len(verts), f"a {solid} has {len(verts)} vertices")
    m = n - len(verts)
    if extra == "faces":
        tris = _solid_triangles(solid)
        pick = tris[rng.integers(0, len(tris), m)]
        w = rng.dirichlet(np.ones(3), m)
        more = combine(w, verts[pick])
    else:
        more = uniform_ball(rng, m, 3) * 0.25
    pts = np.concatenate([verts, more])[rng.permutation(n)]
    if rotate:
        pts = apply_matrix(pts, random_rotation(rng, 3))
    return finish(pts)


@register_generator("spiral", dims=(3,), variants=({}, {"order": "random"}))
def spiral(
    rng: np.random.Generator,
    n: int,
    *,
    dim: int = 3,
    order: str = "cyclic",
) -> np.ndarray:
    """rbox l: a regular helix on the unit cylinder, every point extreme, neighbours nearly coplanar.

    Parameters
    ----------
    rng : numpy.random.Generator
    n : int
        Number of points (>= 2).
    dim : {3}
    order : {"cyclic", "random"}
        Points along the helix, or shuffled.

    Returns
    -------
    points : ndarray of shape (n, 3), float64
        ``(cos(a + 2 pi i/(n-1)), sin(a + 2 pi i/(n-1)), 2 i/(n-1) - 1)`` with a
        random phase a.

    Notes
    -----
    One full turn: the first and last points share (x, y) up to rounding, so
    the hull has a (nearly) vertical edge; every other point is a vertex of a
    thin band of nearly coplanar facets.

    Examples
    --------
    >>> spiral(np.random.default_rng(0), 5).shape
    (5, 3)
    """
    fam = "spiral"
    dim = check_dim(fam, dim, (3,))
    n = check_n(fam, n, 2, "the helix parameter divides by n - 1")
    check_choice(fam, "order", order, ("cyclic", "random"))
    i = np.arange(n)
    theta = rng.uniform(0.0, 2.0 * math.pi) + 2.0 * math.pi * i / (n - 1)
    pts = np.column_stack([np.cos(theta), np.sin(theta), 2.0 * i / (n - 1) - 1.0])
    if order == "random":
        pts = pts[rng.permutation(n)]
    return finish(pts)


@register_generator(
    "simplex-points",
    dims=(2, 3),
    variants=({}, {"width": 1e-10}, {"vertices": False, "width": 1e-13}),
)
def simplex_points(
    rng: np.random.Generator,
    n: int,
    *,
    dim: int,
    width: float = 1.0,
    vertices: bool = True,
) -> np.ndarray:
    """rbox y W<width>: random points in a simplex, squeezed towards its facets, plus its vertices.

    Parameters
    ----------
    rng : numpy.random.Generator
    n : int
        Number of points (>= dim + 1 with ``vertices``, else >= 1).
    dim : {2, 3}
    width : float
        rbox ``W``: one random vertex's barycentric weight is multiplied by
        width, so small widths put each point within ~width of the opposite
        facet (1: uniform-ish points, rbox ``x``).
    vertices : bool
        rbox ``y``: the first dim + 1 rows are the simplex's vertices
        ``e_1, ..., e_dim, (-1, ..., -1)``.

    Returns
    -------
    points : ndarray of shape (n, dim), float64

    Notes
    -----
    With a small width nearly every point is within rounding of a facet of
    the simplex: points that are inside in exact arithmetic look coplanar with
    (or outside) the facet to float code.

    Examples
    --------
    >>> simplex_points(np.random.default_rng(0), 5, dim=2)[:3].tolist()
    [[1.0, 0.0], [0.0, 1.0], [-1.0, -1.0]]
    """
    fam = "simplex-points"
    dim = check_dim(fam, dim, (2, 3))
    n = check_n(fam, n, dim + 1 if vertices else 1, "the simplex's vertices come first" if vertices else "")
    width = check_positive(fam, "width", width)
    if width > 1.0:
        raise GeneratorValueError(f"{fam}: width must be <= 1, got {width!r}")
    verts = np.concatenate([np.eye(dim), -np.ones((1, dim))])
    m = n - (dim + 1 if vertices else 0)
    f = rng.random((m, dim + 1))
    apex = rng.integers(0, dim + 1, m)
    f[np.arange(m), apex] *= width
    f[~f.any(axis=1)] = 1.0  # rng.random can return 0.0; never divide by zero
    pts = combine(f, verts) / row_dot(f, np.ones(dim + 1))[:, None]
    if vertices:
        pts = np.concatenate([verts, pts])
    return finish(pts)


declare_min_size("regular-polygon", lambda dim, **p: 3)
declare_min_size("regular-polyhedron", lambda dim, solid="cube", **p: _SOLID_SIZE[solid])
declare_min_size("spiral", lambda dim, **p: 2)
declare_min_size("simplex-points", lambda dim, vertices=True, **p: dim + 1 if vertices else 1)
