"""Classic distributions: uniform clouds, cospherical points, the paraboloid lift.

Uniform clouds are the control group (an algorithm failing on them is broken
outright).  The others are "classics" because they are degenerate in a way
that looks innocent: every point of a sphere is extreme, so nothing can be
discarded and neighbouring points are nearly coplanar; exact lattice points
on a sphere are cospherical with no rounding at all; the lift
``z = x**2 + y**2`` of an integer grid (the Delaunay lift of the gift-wrapping
seed) turns every co-circular quadruple of grid points into an exactly
coplanar quadruple on the paraboloid.  Regular shapes live in :mod:`.regular`.

rbox equivalents: default (cube), ``s`` (sphere), ``c`` / ``d`` (cube /
diamond vertices added to a cloud).
"""

from __future__ import annotations

import math
from functools import lru_cache

import numpy as np

from hullstress.registry import register_generator

from ._common import (
    GeneratorValueError,
    check_choice,
    check_dim,
    check_int,
    check_n,
    check_positive,
    declare_min_size,
    finish,
    lattice as _lattice,
    lattice_side,
    on_sphere,
    pow2_at_least,
    row_dot,
    uniform_ball,
)

__all__ = ["uniform", "sphere", "paraboloid_lift", "circle_lattice_points", "sphere_lattice_points"]


def _added(kind: str, dim: int) -> np.ndarray:
    if kind == "cube":
        return (_lattice(2, dim) * 2 - 1).astype(np.float64)
    if kind == "diamond":
        return np.concatenate([np.eye(dim), -np.eye(dim)])
    return np.zeros((0, dim))


@register_generator(
    "uniform",
    dims=(2, 3),
    variants=(
        {"shape": "cube"},
        {"shape": "ball"},
        {"shape": "gaussian"},
        {"shape": "cube", "add": "cube"},
        {"shape": "ball", "add": "diamond"},
    ),
)
def uniform(
    rng: np.random.Generator,
    n: int,
    *,
    dim: int,
    shape: str = "cube",
    add: str = "none",
    scale: float = 1.0,
) -> np.ndarray:
    """Uniform points in a cube or ball, or Gaussian: the control group (rbox default, c, d).

    Parameters
    ----------
    rng : numpy.random.Generator
    n : int
        Number of points (>= 1, >= the number of added vertices).
    dim : {2, 3}
    shape : {"cube", "ball", "gaussian"}
        [-1, 1]**dim, the unit ball, or a standard normal cloud.
    add : {"none", "cube", "diamond"}
        Replace random rows by the cube's corners (rbox ``c``: every hull facet
        of the cube then holds 4 exactly coplanar corners) or the diamond's
        (octahedron's) vertices (rbox ``d``).
    scale : float
        Final multiplier.

    Returns
    -------
    points : ndarray of shape (n, dim), float64

    Notes
    -----
    Random points are in general position with probability one; a failure
    here is a plain bug, not a robustness problem.  With ``add="cube"`` the
    hull is exactly the cube and its faces are exactly coplanar quadruples.

    Examples
    --------
    >>> pts = uniform(np.random.default_rng(0), 10, dim=3, add="cube")
    >>> int(np.count_nonzero(np.all(np.abs(pts) == 1.0, axis=1)))
    8
    """
    fam = "uniform"
    dim = check_dim(fam, dim, (2, 3))
    check_choice(fam, "shape", shape, ("cube", "ball", "gaussian"))
    check_choice(fam, "add", add, ("none", "cube", "diamond"))
    extra = _added(add, dim)
    n = check_n(fam, n, max(1, len(extra)), f"add={add!r} adds {len(extra)} vertices" if len(extra) else "")
    scale = check_positive(fam, "scale", scale)
    m = n - len(extra)
    if shape == "cube":
        cloud = rng.uniform(-1.0, 1.0, (m, dim))
    elif shape == "ball":
        cloud = uniform_ball(rng, m, dim)
    else:
        cloud = rng.standard_normal((m, dim))
    pts = np.concatenate([cloud, extra])[rng.permutation(n)]
    return finish(pts * scale)


_PYTHAGOREAN_PRIMES = (5, 13, 17, 29, 37, 41, 53, 61, 73, 89)  # p = 1 (mod 4)


@lru_cache(maxsize=16)
def circle_lattice_points(k: int) -> tuple[int, np.ndarray]:
    """All integer points on the circle of radius R = product of the first k primes = 1 mod 4.

    Each such prime is a*a + b*b = (a+bi)(a-bi); the points on x**2 + y**2 = R**2
    are, by unique factorisation in the Gaussian integers, the products of one
    of (a+bi)**2, p, (a-bi)**2 per prime, times a unit: 4 * 3**k distinct points.

    Returns
    -------
    R : int
    points : ndarray of shape (4 * 3**k, 2), int64, sorted
    """
    if not 0 <= k <= len(_PYTHAGOREAN_PRIMES):
        raise GeneratorValueError(f"circle_lattice_points: k must be in [0, {len(_PYTHAGOREAN_PRIMES)}], got {k!r}")
    re, im = np.array([1], dtype=np.int64), np.array([0], dtype=np.int64)
    radius = 1
    for p in _PYTHAGOREAN_PRIMES[:k]:
        a = next(x for x in range(1, p) if math.isqrt(p - x * x) ** 2 == p - x * x)
        b = math.isqrt(p - a * a)
        # (a+bi)**2, (a+bi)(a-bi) = p, (a-bi)**2; every component stays <= R < 2**53.
        choices = ((a * a - b * b, 2 * a * b), (p, 0), (a * a - b * b, -2 * a * b))
        re, im = (
            np.concatenate([re * u - im * v for u, v in choices]),
            np.concatenate([re * v + im * u for u, v in choices]),
        )
        radius *= p
    # times the units 1, i, -1, -i
    pts = np.concatenate(
        [np.column_stack([re, im]), np.column_stack([-im, re]), np.column_stack([-re, -im]), np.column_stack([im, -re])]
    )
    return radius, np.unique(pts, axis=0)


@lru_cache(maxsize=16)
def sphere_lattice_points(radius: int) -> np.ndarray:
    """Integer points on the sphere x**2 + y**2 + z**2 = radius**2 from quaternions.

    For integers a, b, c, d with a*a + b*b + c*c + d*d = radius, the rotation of
    (1, 0, 0) by the quaternion a + bi + cj + dk, scaled by its norm, is the
    integer point (a²+b²-c²-d², 2(bc+ad), 2(bd-ac)) of norm exactly ``radius``
    (Euler's four-square identity).  Not every lattice point on the sphere
    arises, but every point returned is exact.

    Returns
    -------
    points : ndarray of shape (m, 3), int64, sorted and distinct
    """
    r = math.isqrt(radius)
    span = np.arange(-r, r + 1, dtype=np.int64)
    b, c = (g.ravel() for g in np.meshgrid(span, span, indexing="ij"))
    out = []
    for a in range(0, r + 1):  # q and -q give the same point: a >= 0 suffices
        rest = radius - a * a - b * b - c * c
        ok = rest >= 0
        d = np.sqrt(rest[ok].astype(np.float64)).round().astype(np.int64)
        good = d * d == rest[ok]
        bb, cc, dd = b[ok][good], c[ok][good], d[good]
        for b2, c2, d2 in ((bb, cc, dd), (bb[dd > 0], cc[dd > 0], -dd[dd > 0])):
            out.append(
                np.column_stack([a * a + b2 * b2 - c2 * c2 - d2 * d2, 2 * (b2 * c2 + a * d2), 2 * (b2 * d2 - a * c2)])
            )
    return np.unique(np.concatenate(out), axis=0)


#: Radii for the 3D lattice sphere, each with more quaternion points than the last.
_SPHERE_RADII = (1, 3, 9, 15, 45, 75, 105, 225, 315, 525, 1155, 3465, 15015, 45045)


@register_generator(
    "sphere",
    dims=(2, 3),
    variants=({"mode": "float"}, {"mode": "lattice"}, {"mode": "float", "scale": 1e-3}),
)
def sphere(
    rng: np.random.Generator,
    n: int,
    *,
    dim: int,
    mode: str = "float",
    scale: float = 1.0,
) -> np.ndarray:
    """Cospherical / cocircular points (rbox s): every point extreme, exactly so in lattice mode.

    Parameters
    ----------
    rng : numpy.random.Generator
    n : int
        Number of points (>= 1; lattice mode: <= 236196 in 2D, <= 162240 in 3D).
    dim : {2, 3}
    mode : {"float", "lattice"}
        ``float``: normalised Gaussians (on the unit sphere within a few ulps,
        like rbox ``s``).  ``lattice``: a random subset of integer points on a
        circle / sphere of integer radius R (2D: R a product of primes = 1 mod
        4; 3D: quaternion points), divided by the power of two just above R:
        exactly cospherical, radius R / 2**k in (1/2, 1].
    scale : float
        Final multiplier (float mode only; lattice mode stays exact).

    Returns
    -------
    points : ndarray of shape (n, dim), float64

    Notes
    -----
    All points are on the hull, so no point can be discarded early, and for
    large n neighbouring points are nearly coplanar: the insphere predicate
    and facet orientation are both degenerate.  The lattice mode has no
    rounding at all: it is degenerate in exact arithmetic (four cocircular
    points in 2D are not a problem for hulls, but five or more cospherical
    points in 3D make the triangulation of the surface non-unique).

    Examples
    --------
    >>> pts = sphere(np.random.default_rng(0), 12, dim=2, mode="lattice")
    >>> r2 = {x * x + y * y for x, y in (pts * 8).astype(int).tolist()}  # R = 5, 2**k = 8
    >>> r2
    {25}
    """
    fam = "sphere"
    dim = check_dim(fam, dim, (2, 3))
    n = check_n(fam, n, 1)
    check_choice(fam, "mode", mode, ("float", "lattice"))
    scale = check_positive(fam, "scale", scale)
    if mode == "float":
        return finish(on_sphere(rng, n, dim) * scale)
    if dim == 2:
        k = 0
        while 4 * 3**k < n:
            k += 1
            if k > len(_PYTHAGOREAN_PRIMES):
                most = 4 * 3 ** len(_PYTHAGOREAN_PRIMES)
                raise GeneratorValueError(f"{fam}: lattice mode supports n <= {most} in 2D, got {n}")
        radius, pts = circle_lattice_points(k)
    else:
        for radius in _SPHERE_RADII:
            pts = sphere_lattice_points(radius)
            if len(pts) >= n:
                break
        else:
            raise GeneratorValueError(f"{fam}: lattice mode supports n <= {len(pts)} in 3D, got {n}")
    chosen = pts[rng.choice(len(pts), n, replace=False)]
    return finish(chosen.astype(np.float64) / pow2_at_least(float(radius)))


@register_generator(
    "paraboloid-lift",
    dims=(2, 3),
    variants=({}, {"offset": 1_000_000}, {"lattice": "random"}),
)
def paraboloid_lift(
    rng: np.random.Generator,
    n: int,
    *,
    dim: int,
    lattice: str = "integer",
    offset: int = 0,
) -> np.ndarray:
    """The Delaunay lift z = x**2 + y**2 of a grid: co-circular grid points become coplanar.

    Parameters
    ----------
    rng : numpy.random.Generator
    n : int
        Number of points (>= 1).
    dim : {2, 3}
        3D: (x, y, x**2 + y**2); 2D: (x, x**2) (a parabola: points in convex
        position, consecutive triples nearly collinear).
    lattice : {"integer", "random"}
        ``integer``: the first n points of a square grid with a random integer
        origin plus ``offset``, lifted exactly (every coordinate an integer below
        2**53).  ``random``: uniform (x, y) in [-1, 1]**2, lifted in float.
    offset : int
        Added to x and y of the integer grid: the lift's values grow to about
        2 * offset**2, so orientation determinants cancel catastrophically.

    Returns
    -------
    points : ndarray of shape (n, dim), float64
        Rows in random order.

    Notes
    -----
    The gift-wrapping seed computes a Delaunay triangulation as the lower hull
    of this lift.  Four grid points on a common circle (every unit square of
    the grid, and many more) lift to four exactly coplanar points, so the
    lower hull is full of coplanar facets that must be triangulated
    consistently; every lifted point is a hull vertex.

    Examples
    --------
    >>> pts = paraboloid_lift(np.random.default_rng(0), 9, dim=3)
    >>> bool(np.all(pts[:, 2] == pts[:, 0] ** 2 + pts[:, 1] ** 2))
    True
    """
    fam = "paraboloid-lift"
    dim = check_dim(fam, dim, (2, 3))
    n = check_n(fam, n, 1)
    check_choice(fam, "lattice", lattice, ("integer", "random"))
    offset = check_int(fam, "offset", offset, 0, 2**25)
    k = dim - 1
    if lattice == "random":
        base = rng.uniform(-1.0, 1.0, (n, k))
    else:
        s = lattice_side(n, k)
        base = (_lattice(s, k)[:n] + rng.integers(-s, s + 1, k) + offset).astype(np.float64)
        if 2 * (offset + 2 * s) ** 2 >= 2**53:
            raise GeneratorValueError(f"{fam}: offset {offset} with n={n} makes the lift inexact (>= 2**53)")
    z = row_dot(base * base, np.ones(k))
    pts = np.column_stack([base, z])
    return finish(pts[rng.permutation(n)])


declare_min_size("uniform", lambda dim, add="none", **p: max(1, len(_added(add, dim))))
declare_min_size("sphere", lambda dim, **p: 1)
declare_min_size("paraboloid-lift", lambda dim, **p: 1)
