"""Near-coplanar jitter and pinched near-coincident points.

Points within 1e-13 (or a few ulps) of a plane, of a cube's faces or of a
sphere are the hardest case for tolerance-based code: too far apart to be
merged by an exact test, too close for a float orientation to be trusted.
Qhull's own regression tests lean on them (``rbox 1000 W1e-13``,
``qtest.sh N '500000 W1e-13 D3'``, ``rbox 1000 s W1e-13``); pinched inputs
(``C1,2e-13``: every point followed by a twin within 2e-13) create edges far
shorter than the rounding error of any facet computed through them.
"""

from __future__ import annotations

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
    cube_surface,
    declare_min_size,
    finish,
    lattice,
    lattice_side,
    on_sphere,
    random_rotation,
    random_ulp_offsets,
    ulp_shift,
    uniform_ball,
)

__all__ = ["near_coplanar", "pinched"]

SURFACES = ("cube", "plane", "sphere")


@register_generator(
    "near-coplanar",
    dims=(2, 3),
    variants=(
        {"surface": "cube", "delta": 1e-13},
        {"surface": "cube", "delta": 1e-4},
        {"surface": "cube", "ulps": 1},
        {"surface": "plane", "delta": 1e-13},
        {"surface": "plane", "ulps": 2},
        {"surface": "plane", "delta": 1e-13, "rotate": True},
        {"surface": "sphere", "delta": 1e-13},
    ),
)
def near_coplanar(
    rng: np.random.Generator,
    n: int,
    *,
    dim: int,
    surface: str = "cube",
    delta: float = 1e-13,
    ulps: int = 0,
    rotate: bool = False,
) -> np.ndarray:
    """Points within delta (or within a few ulps) of a cube's faces, of one plane, or of a sphere.

    Parameters
    ----------
    rng : numpy.random.Generator
    n : int
        Number of points (>= 1).
    dim : {2, 3}
    surface : {"cube", "plane", "sphere"}
        ``cube``: rbox ``W<delta>``: uniform in [-1, 1]**dim, then one random
        coordinate moved to within delta of +-1.  ``plane``: uniform (x, y) in
        [-1, 1]**2 on the plane z = 1 (2D: the line y = 1), last coordinate
        moved by up to delta.  ``sphere``: rbox ``s W<delta>``: radius in
        [1 - delta, 1].
    delta : float
        Maximum distance from the surface (>= 0; 0 gives exact W0 / plane
        points, and the sphere within rounding).  Ignored when ``ulps > 0``.
    ulps : int
        When > 0, start exactly on the surface (cube and plane; the sphere
        within rounding) and move every coordinate by a random integer number
        of ulps in [-ulps, ulps] instead of using delta.
    rotate : bool
        Apply a random rotation afterwards.

    Returns
    -------
    points : ndarray of shape (n, dim), float64

    Notes
    -----
    The points are in general position in exact arithmetic but every float
    orientation test among points of one face is dominated by rounding.
    Qhull's ``Tv`` check and scipy need joggling or merging here.

    Examples
    --------
    >>> pts = near_coplanar(np.random.default_rng(0), 20, dim=3, surface="plane", delta=1e-13)
    >>> bool(np.all(np.abs(pts[:, 2] - 1.0) <= 1e-13))
    True
    """
    fam = "near-coplanar"
    dim = check_dim(fam, dim, (2, 3))
    n = check_n(fam, n, 1)
    check_choice(fam, "surface", surface, SURFACES)
    delta = check_positive(fam, "delta", delta, allow_zero=True)
    ulps = check_int(fam, "ulps", ulps, 0, 2**20)
    if delta >= 1.0:
        raise GeneratorValueError(f"{fam}: delta must be < 1, got {delta!r}")
    width = 0.0 if ulps else delta
    if surface == "cube":
        pts = cube_surface(rng, n, dim, width)
    elif surface == "plane":
        pts = rng.uniform(-1.0, 1.0, (n, dim))
        pts[:, -1] = 1.0 + width * rng.uniform(-1.0, 1.0, n)
    else:
        pts = on_sphere(rng, n, dim) * (1.0 - width * rng.random(n))[:, None]
    if ulps:
        pts = ulp_shift(pts, random_ulp_offsets(rng, pts.shape, ulps, nonzero_rows=False))
    if rotate:
        pts = apply_matrix(pts, random_rotation(rng, dim))
    return finish(pts)


@register_generator(
    "pinched",
    dims=(2, 3),
    variants=(
        {},
        {"radius": 0.0},
        {"base": "lattice", "radius": 1e-14},
        {"base": "ball", "copies": 3, "radius": 1e-9},
    ),
)
def pinched(
    rng: np.random.Generator,
    n: int,
    *,
    dim: int,
    base: str = "cube-faces",
    copies: int = 1,
    radius: float = 2e-13,
) -> np.ndarray:
    """rbox C<copies>,<radius>: every point followed by near-coincident twins within radius.

    Parameters
    ----------
    rng : numpy.random.Generator
    n : int
        Number of points (>= 1): ``ceil(n / (copies + 1))`` base points, each
        followed by its copies (rbox order), truncated to n.
    dim : {2, 3}
    base : {"cube-faces", "ball", "lattice"}
        The base points: rbox ``W0`` (exactly on the cube's faces), uniform in
        the unit ball, or rbox ``M3,4`` (the 3,4-rotated integer lattice).
    copies : int
        Twins per base point (>= 1).
    radius : float
        Each twin coordinate is the base coordinate plus a uniform offset in
        [-radius, radius] (rbox's box-shaped neighbourhood); 0 gives exact
        duplicates (rbox ``C2`` style).

    Returns
    -------
    points : ndarray of shape (n, dim), float64

    Notes
    -----
    Twins are closer than the rounding error of any facet through them, so
    they are "the same point" to float code and distinct to exact code.
    Qhull's tests: ``qtest.sh N '100000 W0 C1,2e-13 D3'``, ``rbox 10 M3,4 C1,1E-14``.

    Examples
    --------
    >>> pts = pinched(np.random.default_rng(0), 6, dim=2, radius=0.0)
    >>> len(np.unique(pts, axis=0))
    3
    """
    fam = "pinched"
    dim = check_dim(fam, dim, (2, 3))
    n = check_n(fam, n, 1)
    check_choice(fam, "base", base, ("cube-faces", "ball", "lattice"))
    copies = check_int(fam, "copies", copies, 1, 2**20)
    radius = check_positive(fam, "radius", radius, allow_zero=True)
    m = -(-n // (copies + 1))
    if base == "cube-faces":
        origin = cube_surface(rng, m, dim, 0.0)
    elif base == "ball":
        origin = uniform_ball(rng, m, dim)
    else:
        s = lattice_side(m, dim)
        idx = lattice(s, dim)[:, ::-1][:m]
        cols = [3 * idx[:, 0] - 4 * idx[:, 1], 4 * idx[:, 0] + 3 * idx[:, 1]]
        if dim == 3:
            cols.append(idx[:, 2])
        origin = np.column_stack(cols).astype(np.float64)
    twins = np.repeat(origin, copies, axis=0) + radius * rng.uniform(-1.0, 1.0, (m * copies, dim))
    pts = np.concatenate([origin[:, None, :], twins.reshape(m, copies, dim)], axis=1).reshape(-1, dim)
    return finish(pts[:n])


declare_min_size("near-coplanar", lambda dim, **p: 1)
declare_min_size("pinched", lambda dim, **p: 1)
