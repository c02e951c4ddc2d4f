"""Slivers: needle, cap, wedge and sliver triangles / tetrahedra; rbox's narrow cone and lens.

A sliver's volume is tiny compared with its edge lengths, so its facet
normals are computed from nearly parallel edge vectors and lose most of their
bits (Kenwright's Figure 3(d): "long and thin causes issues when calculating
face normals").  Visibility tests against such facets are noise; an
algorithm that starts from the first d+1 points (Kenwright's step 11) starts
from a nearly flat simplex.  rbox's narrow cone puts n-1 points within 1e-13
of a circle on a sphere (a wide, almost flat base polygon); its narrow lens
puts every point on two spherical caps of radius 1e5 (an almost flat hull
with every point on it).

rbox equivalents: ``s Z1 G1e-13`` (narrow cone), ``L100000 s G1e-6``
(narrow lens); Qhull notes that ``rbox 10000 s Z1 G1e-13 D3`` needs ``Q12``.
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
    check_n,
    check_positive,
    combine,
    declare_min_size,
    finish,
    random_rotation,
    row_dot,
    row_norms,
)

__all__ = ["sliver_triangle", "sliver_tetrahedron", "narrow_cone", "narrow_lens"]

KINDS = {2: ("needle", "cap"), 3: ("needle", "wedge", "cap", "sliver")}


def _sliver_vertices(kind: str, dim: int, t: float) -> np.ndarray:
    if dim == 2:
        if kind == "needle":  # angle ~t at the origin, one edge of length t
            return np.array([[0.0, 0.0], [1.0, 0.0], [1.0, t]])
        return np.array([[0.0, 0.0], [1.0, 0.0], [0.5, t]])  # cap: apex on the base edge
    if kind == "needle":  # all four vertices near one line: volume ~ t**2
        return np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, t, 0.0], [1.0, 0.0, t]])
    if kind == "wedge":  # one edge of length t
        return np.array([[0.0, 0.0, 0.0], [t, 0.0, 0.0], [0.5, 1.0, 0.0], [0.5, 0.0, 1.0]])
    if kind == "cap":  # a vertex at height t over the opposite facet's interior
        return np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.25, 0.25, t]])
    # sliver: four vertices near a circle, all edges ~1.4, volume ~ t
    return np.array([[1.0, 0.0, 0.0], [-1.0, 0.0, 0.0], [0.0, 1.0, t], [0.0, -1.0, t]])


def _sliver(
    fam: str, rng: np.random.Generator, n: int, dim: int, kind: str, thinness: float, rotate: bool
) -> np.ndarray:
    check_choice(fam, "kind", kind, KINDS[dim])
    n = check_n(fam, n, dim + 1, f"the simplex has {dim + 1} vertices")
    t = check_positive(fam, "thinness", thinness)
    if t >= 1.0:
        raise GeneratorValueError(f"{fam}: thinness must be < 1, got {thinness!r}")
    verts = _sliver_vertices(kind, dim, t)
    w = rng.dirichlet(np.ones(dim + 1), n - dim - 1)
    pts = np.concatenate([verts, combine(w, verts)])
    if rotate:
        pts = apply_matrix(pts, random_rotation(rng, dim)) + rng.uniform(-1.0, 1.0, dim)
    return finish(pts)


@register_generator(
    "sliver-triangle",
    dims=(2,),
    variants=(
        {"kind": "needle"},
        {"kind": "cap"},
        {"kind": "cap", "rotate": False},
        {"kind": "needle", "thinness": 1e-15},
    ),
)
def sliver_triangle(
    rng: np.random.Generator,
    n: int,
    *,
    dim: int = 2,
    kind: str = "needle",
    thinness: float = 1e-12,
    rotate: bool = True,
) -> np.ndarray:
    """A needle or cap triangle, vertices first, then points inside: a barely 2D input.

    Parameters
    ----------
    rng : numpy.random.Generator
    n : int
        Number of points (>= 3).  Rows 0, 1, 2 are the triangle's vertices (so
        "first three points" code starts from the sliver); the other rows are
        random convex combinations of them, rounded (rounding may put a few
        just outside, which is part of the stress).
    dim : {2}
    kind : {"needle", "cap"}
        ``needle``: (0, 0), (1, 0), (1, t): an angle and an edge of size t.
        ``cap``: (0, 0), (1, 0), (1/2, t): a vertex at height t over the middle
        of the opposite edge (an angle near 180 degrees).
    thinness : float
        The small length t (0 < t < 1).
    rotate : bool
        Apply a random rotation and a random offset in [-1, 1]**2, so the thin
        direction is not axis-aligned.

    Returns
    -------
    points : ndarray of shape (n, 2), float64

    Notes
    -----
    The exact area of the vertex triangle is positive and about t / 2 (for
    t = 1e-12, four orders of magnitude above rounding of unit coordinates):
    orientation tests involving the short edge or the flat angle are decided
    by rounding once the triangle is rotated.

    Examples
    --------
    >>> pts = sliver_triangle(np.random.default_rng(0), 4, kind="cap", rotate=False)
    >>> pts[:3].tolist()
    [[0.0, 0.0], [1.0, 0.0], [0.5, 1e-12]]
    """
    fam = "sliver-triangle"
    dim = check_dim(fam, dim, (2,))
    return _sliver(fam, rng, n, dim, kind, thinness, rotate)


@register_generator(
    "sliver-tetrahedron",
    dims=(3,),
    variants=(
        {"kind": "needle"},
        {"kind": "wedge"},
        {"kind": "cap"},
        {"kind": "cap", "rotate": False},
        {"kind": "sliver"},
        {"kind": "sliver", "thinness": 1e-15},
    ),
)
def sliver_tetrahedron(
    rng: np.random.Generator,
    n: int,
    *,
    dim: int = 3,
    kind: str = "sliver",
    thinness: float = 1e-12,
    rotate: bool = True,
) -> np.ndarray:
    """A needle, wedge, cap or sliver tetrahedron, vertices first, then points inside.

    Parameters
    ----------
    rng : numpy.random.Generator
    n : int
        Number of points (>= 4).  Rows 0..3 are the tetrahedron's vertices
        (Kenwright's step 11 builds its first tetrahedron from the first four
        points); the other rows are random convex combinations, rounded.
    dim : {3}
    kind : {"needle", "wedge", "cap", "sliver"}
        ``needle``: four vertices near a line (volume ~ t**2);
        ``wedge``: one edge of length t; ``cap``: a vertex at height t over
        the opposite facet's interior; ``sliver``: four vertices near a circle
        with every edge long, (1, 0, 0), (-1, 0, 0), (0, 1, t), (0, -1, t).
    thinness : float
        The small length t (0 < t < 1).
    rotate : bool
        Apply a random rotation and a random offset in [-1, 1]**3.

    Returns
    -------
    points : ndarray of shape (n, 3), float64

    Notes
    -----
    The exact volume is positive and at most about t times the diameter
    cubed: full-dimensional, but only barely.  The facet normals of a sliver
    are cross products of nearly parallel (or nearly coplanar) edges.

    Examples
    --------
    >>> pts = sliver_tetrahedron(np.random.default_rng(0), 4, kind="sliver", rotate=False)
    >>> pts[2].tolist()
    [0.0, 1.0, 1e-12]
    """
    fam = "sliver-tetrahedron"
    dim = check_dim(fam, dim, (3,))
    return _sliver(fam, rng, n, dim, kind, thinness, rotate)


@register_generator(
    "narrow-cone",
    dims=(2, 3),
    variants=({"gap": 1e-13}, {"gap": 1e-6}, {"gap": 1.0}, {"gap": 1e-13, "regular": True}),
)
def narrow_cone(
    rng: np.random.Generator,
    n: int,
    *,
    dim: int,
    radius: float = 1.0,
    gap: float = 1e-13,
    regular: bool = False,
) -> np.ndarray:
    """rbox s Z<radius> G<gap>: an apex plus n-1 points within gap of a circle on the unit sphere.

    Parameters
    ----------
    rng : numpy.random.Generator
    n : int
        Number of points (>= 1).  Row 0 is the apex ``(0, ..., 0, -1)``.
    dim : {2, 3}
    radius : float
        rbox ``Z``: the disk radius before projection (1: a 45 degree circle).
    gap : float
        rbox ``G``: disk points have radius ``radius * (1 - gap * u)``, u uniform
        in [0, 1]; 1 fills the disk (a spherical cap), 1e-13 a thin ring.
    regular : bool
        Equally spaced angles (with a random phase) instead of random ones.

    Returns
    -------
    points : ndarray of shape (n, dim), float64

    Notes
    -----
    Each disk point ``(x, y)`` becomes ``(x, y, 1) / sqrt(1 + x**2 + y**2)``,
    as in rbox.  With a small gap the n-1 base points are nearly coplanar and
    nearly cocircular: the big base facet is a polygon of almost-coplanar
    triangles, the case where Qhull needs ``Q12``.  In 2D the disk is the
    segment [-radius, radius]: two clusters on the circle plus the apex.

    Examples
    --------
    >>> pts = narrow_cone(np.random.default_rng(0), 5, dim=3)
    >>> pts[0].tolist()
    [0.0, 0.0, -1.0]
    """
    fam = "narrow-cone"
    dim = check_dim(fam, dim, (2, 3))
    n = check_n(fam, n, 1)
    radius = check_positive(fam, "radius", radius)
    gap = check_positive(fam, "gap", gap)
    if gap > 1.0:
        raise GeneratorValueError(f"{fam}: gap must be <= 1, got {gap!r}")
    m = n - 1
    r = radius * (1.0 - gap * rng.random(m))
    if dim == 3:
        if regular:
            theta = rng.uniform(0.0, 2.0 * math.pi) + 2.0 * math.pi * np.arange(m) / max(m, 1)
        else:
            theta = rng.uniform(0.0, 2.0 * math.pi, m)
        disk = np.column_stack([r * np.cos(theta), r * np.sin(theta)])
    else:
        sign = np.where(np.arange(m) % 2 == 0, 1.0, -1.0) if regular else np.where(rng.random(m) < 0.5, -1.0, 1.0)
        disk = (r * sign)[:, None]
    lifted = np.column_stack([disk, np.ones(m)])
    norm = np.sqrt(1.0 + row_dot(disk * disk, np.ones(disk.shape[1])))
    base = lifted / norm[:, None]
    apex = np.zeros((1, dim))
    apex[0, -1] = -1.0
    return finish(np.concatenate([apex, base]))


@register_generator(
    "narrow-lens",
    dims=(2, 3),
    variants=({"radius": 1e5, "gap": 1e-6}, {"radius": 1e5}, {"radius": 2.0}),
)
def narrow_lens(
    rng: np.random.Generator,
    n: int,
    *,
    dim: int,
    radius: float = 1e5,
    gap: float = 1.0,
) -> np.ndarray:
    """rbox L<radius> s G<gap>: points on two spherical caps of a huge sphere (a thin lens).

    Parameters
    ----------
    rng : numpy.random.Generator
    n : int
        Number of points (>= 1).
    dim : {2, 3}
    radius : float
        rbox ``L``: the caps' sphere radius (> 1).  The lens has rim radius 1
        and thickness ``2 * (radius - sqrt(radius**2 - 1))``, about ``1/radius``.
    gap : float
        rbox ``G``: rim-plane radius ``1 - gap * u``; 1 covers the whole cap,
        1e-6 keeps every point within 1e-6 of the rim (nearly cocircular too).

    Returns
    -------
    points : ndarray of shape (n, dim), float64

    Notes
    -----
    Follows rbox: a point ``q`` of the rim disk gets last coordinate
    ``lensbase = radius * cos(asin(1/radius))``, is scaled to length
    ``radius``, then moved down by lensbase and mirrored with probability 1/2.
    Every point is (nearly) extreme but the hull is almost flat, so the facet
    normals come from nearly parallel vectors.

    Examples
    --------
    >>> pts = narrow_lens(np.random.default_rng(0), 50, dim=3)
    >>> bool(np.abs(pts[:, 2]).max() < 1e-5)
    True
    """
    fam = "narrow-lens"
    dim = check_dim(fam, dim, (2, 3))
    n = check_n(fam, n, 1)
    radius = check_positive(fam, "radius", radius)
    gap = check_positive(fam, "gap", gap)
    if radius <= 1.0 or gap > 1.0:
        raise GeneratorValueError(f"{fam}: radius must be > 1 and gap <= 1, got radius={radius!r}, gap={gap!r}")
    lensbase = radius * math.cos(math.asin(1.0 / radius))
    rim = 1.0 - gap * rng.random(n)
    if dim == 3:
        theta = rng.uniform(0.0, 2.0 * math.pi, n)
        q = np.column_stack([rim * np.cos(theta), rim * np.sin(theta), np.full(n, lensbase)])
    else:
        sign = np.where(rng.random(n) < 0.5, -1.0, 1.0)
        q = np.column_stack([rim * sign, np.full(n, lensbase)])
    q = q * (radius / row_norms(q))[:, None]
    q[:, -1] -= lensbase
    flip = rng.random(n) < 0.5
    q[flip, -1] = -q[flip, -1]
    return finish(q)


declare_min_size("sliver-triangle", lambda dim, **p: 3)
declare_min_size("sliver-tetrahedron", lambda dim, **p: 4)
declare_min_size("narrow-cone", lambda dim, **p: 1)
declare_min_size("narrow-lens", lambda dim, **p: 1)
