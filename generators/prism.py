"""Prisms and extrusions: a polygon copied to several heights (cylinder meshes, CAD extrusions).

An extruded polygon is the most common solid in CAD, games and GIS (a
building footprint times a height): every side face is an exactly planar
rectangle (its corners share x and y), every ring lies exactly in a plane of
constant z, and a regular ring is cocircular, so neighbouring side faces are
nearly coplanar and the cap is a large exactly coplanar polygon whose
triangulation is arbitrary.  A tessellated cylinder adds more rings at
intermediate heights (vertices exactly on the side faces, not extreme) and
the cap centres (coplanar with the caps, not extreme).

Real reports this imitates:

- karimnaaji/3d-quickhull#2: an extruded integer octagon (and a box with
  points inside its faces) produced an invalid face because the visibility
  test used ``dot >= 0`` on exactly coplanar points (``polygon="lattice"``).
- mikedh/trimesh#2266 (``extrude_polygon`` of a square was not a volume) and
  elalish/manifold#1785 (the hull of a cylinder (+) sphere cloud, seven points
  exactly on the z = 5 plane, had an inverted face): ``layers > 2``,
  ``caps=True``.
- openscad/openscad#3791: hulling two rotated regular pentagons/circles gave
  inconsistent results, the cocircular rings being nearly collinear with the
  hull's edges (``polygon="regular"``).
- dimforge/ncollide#352: a box (the square prism) misbehaving in ``f32``.
"""

from __future__ import annotations

import math

import numpy as np

from hullstress.registry import register_generator

from ._common import (
    GeneratorValueError,
    apply_matrix,
    check_bool,
    check_choice,
    check_dim,
    check_int,
    check_n,
    check_positive,
    declare_min_size,
    finish,
    random_rotation,
    sector_polygon,
)
from .classics import circle_lattice_points

__all__ = ["prism", "POLYGONS"]

POLYGONS = ("regular", "lattice", "star")


def _ring(rng: np.random.Generator, k: int, polygon: str) -> tuple[np.ndarray, float]:
    """k polygon vertices in counter-clockwise angular order around the origin, and the ring's radius.

    Consecutive vertices turn by less than pi around the origin, so the origin
    (where the cap centres and the axis points sit) is strictly inside.
    """
    if polygon == "lattice":
        j = 0
        while 3**j < k:  # at least 4 circle points per ring vertex
            j += 1
        radius, pts = circle_lattice_points(j)
        # atan2 only orders the points; they stay exact integers
        pts = pts[np.argsort(np.arctan2(pts[:, 1], pts[:, 0]), kind="stable")]
        step = np.floor(np.arange(k) * (len(pts) / k)).astype(np.int64)
        for start in rng.permutation(len(pts))[:16]:
            ring = pts[(start + step) % len(pts)]
            # Python integers: coordinates reach R ~ 5e14, their products overflow int64 and float64
            exact = ring.astype(object)
            nxt = np.roll(exact, -1, axis=0)
            if np.all(exact[:, 0] * nxt[:, 1] - exact[:, 1] * nxt[:, 0] > 0):
                return ring.astype(np.float64), float(radius)
        raise GeneratorValueError(f"prism: no lattice ring of {k} points around the origin")  # pragma: no cover
    if polygon == "star":
        return sector_polygon(rng, k, wobble=True), 1.0
    angles = rng.uniform(0.0, 2.0 * math.pi) + 2.0 * math.pi * np.arange(k) / k  # random phase
    return np.column_stack([np.cos(angles), np.sin(angles)]), 1.0


@register_generator(
    "prism",
    dims=(3,),
    variants=(
        {"polygon": "regular"},
        {"polygon": "lattice"},
        {"polygon": "regular", "layers": 4, "caps": True},
        {"polygon": "star"},
        {"polygon": "regular", "rotate": True},
    ),
)
def prism(
    rng: np.random.Generator,
    n: int,
    *,
    dim: int,
    polygon: str = "regular",
    layers: int = 2,
    height: float = 1.0,
    caps: bool = False,
    rotate: bool = False,
) -> np.ndarray:
    """An extruded polygon: rings of equal (x, y) at several heights, planar caps and rectangular sides.

    Parameters
    ----------
    rng : numpy.random.Generator
    n : int
        Number of points (>= ``3 * layers``, plus 2 with ``caps``).
    dim : {3}
    polygon : {"regular", "lattice", "star"}
        The ring: ``regular``: a regular k-gon on the unit circle at a random
        phase (cocircular up to rounding).  ``lattice``: k integer points exactly on a circle of
        radius R (a product of primes 1 mod 4), in angular order.  ``star``:
        random angles and radii in [0.5, 1] (a non-convex polygon: some ring
        vertices are not extreme).  Every ring surrounds its axis, so the
        cap centres and the leftover axis points are strictly inside.
    layers : int
        Copies of the ring (2..64) at heights ``j * height * R / (layers - 1)``
        (R = 1 except for the lattice ring).
    height : float
        Extrusion length in units of the ring's radius (> 0).
    caps : bool
        Add the centre of the bottom and the top cap (coplanar with the caps,
        never extreme).
    rotate : bool
        Rotate the solid randomly: the caps and sides stop being exactly planar.

    Returns
    -------
    points : ndarray of shape (n, 3), float64
        Ring j occupies rows ``j*k .. (j+1)*k - 1`` with
        ``k = (n - 2*caps) // layers``; the cap centres follow, then the
        leftover points, on the axis strictly between the caps.

    Notes
    -----
    Unrotated, the corners of side face i on all layers (2 * layers points)
    are exactly coplanar and every ring is exactly coplanar (equal z).  The
    lattice ring is exactly cocircular, so any four of its points on two
    layers are also exactly cospherical, a tie for any "furthest point" rule.

    Examples
    --------
    >>> pts = prism(np.random.default_rng(0), 12, dim=3)
    >>> sorted(set(pts[:, 2].tolist()))
    [0.0, 1.0]
    >>> bool(np.array_equal(pts[:6, :2], pts[6:, :2]))  # the same ring on both layers
    True
    """
    fam = "prism"
    dim = check_dim(fam, dim, (3,))
    check_choice(fam, "polygon", polygon, POLYGONS)
    layers = check_int(fam, "layers", layers, 2, 64)
    height = check_positive(fam, "height", height)
    caps = check_bool(fam, "caps", caps)
    rotate = check_bool(fam, "rotate", rotate)
    n = check_n(fam, n, 3 * layers + 2 * caps, f"{layers} rings of at least 3 points")
    k = (n - 2 * caps) // layers
    ring, radius = _ring(rng, k, polygon)
    z = np.arange(layers) * (height * radius / (layers - 1))
    parts = [np.column_stack([ring, np.full(k, zj)]) for zj in z]
    if caps:
        parts.append(np.array([[0.0, 0.0, z[0]], [0.0, 0.0, z[-1]]]))
    rest = n - k * layers - 2 * caps
    parts.append(np.column_stack([np.zeros((rest, 2)), rng.uniform(0.25, 0.75, rest) * z[-1]]))
    pts = np.concatenate(parts)
    if rotate:
        pts = apply_matrix(pts, random_rotation(rng, 3))
    return finish(pts)


declare_min_size("prism", lambda dim, layers=2, caps=False, **p: 3 * layers + 2 * bool(caps))
