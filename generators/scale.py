"""Scale and offset: the same shapes at 1e-300 and 1e300, far from the origin, mixed, subnormal.

Orientation determinants are products of d coordinate differences: at 1e300
they overflow to inf (and inf - inf is NaN), at 1e-300 they underflow to zero
or to subnormals with few significant bits, so "every point is coplanar".
Absolute tolerances (the seed's ``fixed`` eps) are meaningless at either end.
An offset of 1e15 leaves 3 bits below the binary point: a unit ball is
quantised to a grid of step 1/8, full of duplicates and collinear runs.
Mixed magnitudes (1e-30 next to 1e30, Kettner et al.'s unbounded-area case,
or y spanning 1e8 as in scipy issue 14185) make relative errors in one
coordinate swamp the other.  Subnormal coordinates lose precision gradually
and every product of two of them is zero.

Between the extremes lie the moderate scales where real data lives and a
fixed epsilon breaks: millimetres of a part (x1e3), coordinates in metres of
a projected map (x1e6, offsets of 5e5 to 1e7 in UTM), nanometres or
micrometres expressed in metres, 1e9..1e12 in astronomy and chip layout.  A
tolerance of 1e-10 chosen at unit scale is 1e-16 relative at x1e6, below the
rounding of a single coordinate: the seed's gift-wrapping with a ``fixed``
eps fails every cloud at x1e6 and none with ``scaled`` eps.  Reports:
PointCloudLibrary/pcl#6161 (four 2D points with coordinates 5939..12000:
Qhull's flat initial simplex, order dependent), georust/geo#1028 (a hull
near (813580, 817846) keeping a point below its neighbours' chord),
shapely/shapely#555 (a point at (2.8e8, 7.6e6) beside a cluster at 1e-4: a
segmentation fault).

rbox equivalents: ``B<n>`` (box size), ``O<n>`` (offset), ``z`` (integer output).
"""

from __future__ import annotations

import numpy as np

from hullstress.registry import register_generator

from ._common import (
    GeneratorValueError,
    check_choice,
    check_dim,
    check_int,
    check_n,
    check_positive,
    cube_surface,
    declare_min_size,
    finish,
    fit_unit_pow2,
    lattice,
    lattice_side,
    on_sphere,
    uniform_ball,
)

__all__ = ["scaled", "offset", "mixed_magnitude", "subnormal", "base_shape"]

BASES = ("ball", "cube-faces", "grid")


def base_shape(rng: np.random.Generator, n: int, dim: int, base: str) -> np.ndarray:
    """n points of a unit-size shape: uniform ball, rbox W0 cube faces, or an exact grid.

    ``grid`` is the first n points of an integer lattice block centred on the
    origin, divided by a power of two (exact) so it fits in [-1, 1]**dim; its
    rows are shuffled.
    """
    if base == "ball":
        return uniform_ball(rng, n, dim)
    if base == "cube-faces":
        return cube_surface(rng, n, dim, 0.0)
    s = lattice_side(n, dim)
    pts = (lattice(s, dim)[:n] * 2 - (s - 1)).astype(np.float64)  # odd steps around 0
    return fit_unit_pow2(pts[rng.permutation(n)])


@register_generator(
    "scaled",
    dims=(2, 3),
    variants=(
        {"scale": 1e3},
        {"scale": 1e6},
        {"scale": 1e9},
        {"scale": 1e12},
        {"base": "grid", "scale": 1e6},
        {"scale": 1e-300},
        {"scale": 1e-150},
        {"scale": 1e150},
        {"scale": 1e300},
        {"scale": 1.7976931348623157e308},
        {"base": "grid", "scale": 1e300},
        {"base": "grid", "scale": 1e-300},
        {"base": "cube-faces", "scale": 1e300},
    ),
)
def scaled(
    rng: np.random.Generator,
    n: int,
    *,
    dim: int,
    base: str = "ball",
    scale: float = 1e300,
) -> np.ndarray:
    """A unit shape multiplied by scale (1e3..1e12 where fixed epsilons break; 1e-300..1e308: over/underflow).

    Parameters
    ----------
    rng : numpy.random.Generator
    n : int
        Number of points (>= 1).
    dim : {2, 3}
    base : {"ball", "cube-faces", "grid"}
        The unit shape (see :func:`base_shape`).
    scale : float
        Multiplier, 0 < scale <= 1.7976931348623157e308 (the largest double:
        coordinates up to it, every difference of two of them may overflow).
        The sweeps run the moderate 1e3, 1e6, 1e9, 1e12 and the extremes.

    Returns
    -------
    points : ndarray of shape (n, dim), float64

    Notes
    -----
    Equal coordinates stay equal after scaling, so the cube's faces and the
    grid's planes stay exactly coplanar; only the magnitude changes.  Scale-
    invariant code passes; code with absolute epsilons or unguarded products
    does not.

    Examples
    --------
    >>> pts = scaled(np.random.default_rng(0), 10, dim=3, scale=1e300)
    >>> bool(np.all(np.isfinite(pts)) and np.abs(pts).max() > 1e299)
    True
    """
    fam = "scaled"
    dim = check_dim(fam, dim, (2, 3))
    n = check_n(fam, n, 1)
    check_choice(fam, "base", base, BASES)
    scale = check_positive(fam, "scale", scale)
    pts = base_shape(rng, n, dim, base) * scale
    return finish(pts)


@register_generator(
    "offset",
    dims=(2, 3),
    variants=(
        {"offset": 1e6},
        {"offset": 1e8},
        {"offset": 1e9},
        {"base": "grid", "offset": 1e6},
        {"offset": 1e12},
        {"offset": 1e15},
        {"base": "grid", "offset": 1e15},
        {"base": "cube-faces", "offset": 1e8},
    ),
)
def offset(
    rng: np.random.Generator,
    n: int,
    *,
    dim: int,
    base: str = "ball",
    offset: float = 1e8,
) -> np.ndarray:
    """A unit shape translated by offset (rbox O): most significant bits spent on the offset.

    Parameters
    ----------
    rng : numpy.random.Generator
    n : int
        Number of points (>= 1).
    dim : {2, 3}
    base : {"ball", "cube-faces", "grid"}
        The unit shape (see :func:`base_shape`).
    offset : float
        Added to every coordinate (>= 0; 1e6 to 1e15 in the sweeps: 1e6 is a
        UTM coordinate in metres).  At 1e15 the spacing of doubles is 1/8, so
        the shape is quantised.

    Returns
    -------
    points : ndarray of shape (n, dim), float64

    Notes
    -----
    Differences of coordinates are exact (Sterbenz) but the points themselves
    were rounded when the offset was added: the rounded set's hull is not the
    unit shape's hull moved, and orientation tests computed from absolute
    coordinates (not differences) lose everything.

    Examples
    --------
    >>> pts = offset(np.random.default_rng(0), 10, dim=2, offset=1e15)
    >>> bool(np.all(pts * 8 == np.round(pts * 8)))  # quantised to steps of 1/8
    True
    """
    fam = "offset"
    dim = check_dim(fam, dim, (2, 3))
    n = check_n(fam, n, 1)
    check_choice(fam, "base", base, BASES)
    off = check_positive(fam, "offset", offset, allow_zero=True)
    if off > 1e300:
        raise GeneratorValueError(f"{fam}: offset must be <= 1e300, got {offset!r}")
    return finish(base_shape(rng, n, dim, base) + off)


@register_generator(
    "mixed-magnitude",
    dims=(2, 3),
    variants=(
        {"mode": "radial", "span": 30},
        {"mode": "radial", "span": 300},
        {"mode": "axes", "span": 8},
        {"mode": "axes", "span": 30},
    ),
)
def mixed_magnitude(
    rng: np.random.Generator,
    n: int,
    *,
    dim: int,
    mode: str = "radial",
    span: int = 30,
) -> np.ndarray:
    """Points whose magnitudes (or axes) span many decades: 1e-30 beside 1e30, y spanning 1e8.

    Parameters
    ----------
    rng : numpy.random.Generator
    n : int
        Number of points (>= 2).
    dim : {2, 3}
    mode : {"radial", "axes"}
        ``radial``: random directions with lengths ``10**U(-span, span)``; rows 0
        and 1 have lengths exactly ``10**-span`` and ``10**span`` (rounded), so
        the range is always present.  ``axes``: uniform in a box whose half-
        sides are ``10**(span * j / (dim - 1))`` for axis j (x in [-1, 1], the
        last axis in [-10**span, 10**span]).
    span : int
        Decades (1..300).

    Returns
    -------
    points : ndarray of shape (n, dim), float64

    Notes
    -----
    Like Kettner et al.'s "global unbounded area" case (0.1 next to 1.27e30),
    the small points are numerically on top of each other at the scale of the
    big ones; an algorithm that normalises by the bounding box or uses an
    absolute epsilon mislabels them.  The ``axes`` mode is scipy issue 14185
    (a true vertex dropped when y spans 1e8).

    Examples
    --------
    >>> pts = mixed_magnitude(np.random.default_rng(0), 4, dim=2, span=30)
    >>> norms = np.linalg.norm(pts, axis=1)
    >>> bool(norms.max() / norms.min() > 1e59)
    True
    """
    fam = "mixed-magnitude"
    dim = check_dim(fam, dim, (2, 3))
    n = check_n(fam, n, 2, "the two extreme magnitudes")
    check_choice(fam, "mode", mode, ("radial", "axes"))
    span = check_int(fam, "span", span, 1, 300)
    if mode == "radial":
        exps = np.concatenate([[-span, span], rng.uniform(-span, span, n - 2)])
        pts = on_sphere(rng, n, dim) * (10.0**exps)[:, None]
    else:
        half = 10.0 ** (span * np.arange(dim) / (dim - 1))
        pts = rng.uniform(-1.0, 1.0, (n, dim)) * half
    return finish(pts)


_MIN_SUBNORMAL_EXP = -1074  # 2**-1074 = 5e-324, the smallest positive double


@register_generator(
    "subnormal",
    dims=(2, 3),
    variants=({"units": 1000}, {"units": 2**40}, {"mode": "mixed"}),
)
def subnormal(
    rng: np.random.Generator,
    n: int,
    *,
    dim: int,
    mode: str = "all",
    units: int = 1000,
) -> np.ndarray:
    """Subnormal coordinates: integer multiples of 2**-1074, where every product underflows to 0.

    Parameters
    ----------
    rng : numpy.random.Generator
    n : int
        Number of points (>= 1).
    dim : {2, 3}
    mode : {"all", "mixed"}
        ``all``: every coordinate is ``k * 2**-1074`` with random integer k in
        [-units, units] (an integer point set scaled exactly into the
        subnormal range).  ``mixed``: half the points uniform in [-1, 1]**dim,
        the rest subnormal as in ``all`` (a cloud at the origin).
    units : int
        Largest |k| (1 .. 2**52 - 1, so every coordinate stays subnormal).

    Returns
    -------
    points : ndarray of shape (n, dim), float64

    Notes
    -----
    The set is an exact scaled integer configuration, so its hull is well
    defined, but any float determinant of differences is 0 (the products
    underflow): every triple looks collinear.  Flush-to-zero builds differ
    from IEEE ones here.

    Examples
    --------
    >>> pts = subnormal(np.random.default_rng(0), 5, dim=2)
    >>> bool(np.all(np.abs(pts) < np.finfo(np.float64).tiny))
    True
    """
    fam = "subnormal"
    dim = check_dim(fam, dim, (2, 3))
    n = check_n(fam, n, 1)
    check_choice(fam, "mode", mode, ("all", "mixed"))
    units = check_int(fam, "units", units, 1, 2**52 - 1)
    m = n if mode == "all" else n // 2
    k = rng.integers(-units, units + 1, (m, dim))
    tiny = np.ldexp(k.astype(np.float64), _MIN_SUBNORMAL_EXP)
    if mode == "mixed":
        tiny = np.concatenate([tiny, rng.uniform(-1.0, 1.0, (n - m, dim))])[rng.permutation(n)]
    return finish(tiny)


declare_min_size("scaled", lambda dim, **p: 1)
declare_min_size("offset", lambda dim, **p: 1)
declare_min_size("mixed-magnitude", lambda dim, **p: 2)
declare_min_size("subnormal", lambda dim, **p: 1)
