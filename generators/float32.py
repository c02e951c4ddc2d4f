"""Data that passed through a C/C++/Rust ``float``: every coordinate exactly a float32.

Game engines, mesh files (STL is float32 by definition), GPU buffers, point
cloud formats (PCD, PLY) and Rust's ``f32`` hand over coordinates with 24
significant bits.  Converted to double they are exact, but the geometry they
describe moved by up to 2**-24 relative: a rotated box's face corners are no
longer coplanar, points computed on a sphere are no longer cospherical, and
far from the origin the spacing is coarse (0.0625 at 8e5) so nearly collinear
points become exactly collinear or swap sides.

Real reports this imitates:

- dimforge/ncollide#352: the hull of a 1.5 x 3.5 x 89 box computed in
  ``f32`` came out skewed (``shape="box", rotate=True``: rotated, then stored
  as float).
- georust/geo#1028: an ``f32`` polygon near (813580, 817846) whose hull kept
  a point just below the chord of its neighbours (``offset=8e5``).
- leomccormack/convhull_3d#7 (single-precision build: the ``detA > 0``
  assertion fails on a box), gridap/MiniQhull.jl#31 (a Float32 cube gives a
  wrong triangulation), CGAL/cgal#8761 (``Simple_cartesian<float>`` crashes
  ``convex_hull_3``).

The points are built in float64 and rounded once (ties to even), as when a
program computes in double and stores ``float``.
"""

from __future__ import annotations

import numpy as np

from hullstress.registry import register_generator

from ._common import (
    apply_matrix,
    box_points,
    check_bool,
    check_choice,
    check_dim,
    check_n,
    check_positive,
    declare_min_size,
    finish,
    on_sphere,
    random_rotation,
    round_to_float32,
    uniform_ball,
)

__all__ = ["float32"]

SHAPES = ("ball", "box", "sphere")


@register_generator(
    "float32",
    dims=(2, 3),
    variants=(
        {"shape": "ball"},
        {"shape": "box", "rotate": True},
        {"shape": "sphere"},
        {"shape": "ball", "offset": 8e5},
        {"shape": "box", "rotate": True, "scale": 50.0, "offset": 1e3},
    ),
)
def float32(
    rng: np.random.Generator,
    n: int,
    *,
    dim: int,
    shape: str = "ball",
    rotate: bool = False,
    scale: float = 1.0,
    offset: float = 0.0,
) -> np.ndarray:
    """Float32-rounded inputs, as data from C/C++/Rust code arrives: rotated boxes, spheres, far offsets.

    Parameters
    ----------
    rng : numpy.random.Generator
    n : int
        Number of points (>= 1; ``shape="box"`` needs ``2**dim``: its corners).
    dim : {2, 3}
    shape : {"ball", "box", "sphere"}
        ``ball``: uniform in the unit ball.  ``box``: the corners of
        [-1, 1]**dim and points exactly on its faces (rows shuffled).  ``sphere``: on the unit
        sphere (cocircular in 2D).
    rotate : bool
        Apply a random rotation (in float64) before rounding: the box's faces
        stop being exactly coplanar.
    scale : float
        Multiplier (> 0) before the offset.
    offset : float
        Added to every coordinate (>= 0) before rounding; float32's spacing
        at the offset is ``2**(floor(log2(offset)) - 23)``.

    Returns
    -------
    points : ndarray of shape (n, dim), float64
        Every value exactly representable in float32:
        ``np.array_equal(points, points.astype(np.float32))``.

    Notes
    -----
    Without rotation the box stays exact: ±1 times a float32-exact scale plus
    an offset round identically on every face, so equal coordinates stay
    equal.  With rotation each corner rounds on its own, faces become
    near-coplanar at float32 resolution, which double-precision code sees as
    genuine (if tiny) creases.

    Examples
    --------
    >>> pts = float32(np.random.default_rng(0), 12, dim=3, shape="box", rotate=True)
    >>> bool(np.array_equal(pts, pts.astype(np.float32)))
    True
    """
    fam = "float32"
    dim = check_dim(fam, dim, (2, 3))
    check_choice(fam, "shape", shape, SHAPES)
    n = check_n(fam, n, 2**dim if shape == "box" else 1, "the box's corners" if shape == "box" else "")
    rotate = check_bool(fam, "rotate", rotate)
    scale = check_positive(fam, "scale", scale)
    off = check_positive(fam, "offset", offset, allow_zero=True)
    if shape == "ball":
        pts = uniform_ball(rng, n, dim)
    elif shape == "sphere":
        pts = on_sphere(rng, n, dim)
    else:
        pts = box_points(rng, n, dim)
    if rotate:
        pts = apply_matrix(pts, random_rotation(rng, dim))
    pts = round_to_float32(pts * scale + off, fam)
    return finish(pts[rng.permutation(n)] if shape == "box" else pts)


declare_min_size("float32", lambda dim, shape="ball", **p: 2**dim if shape == "box" else 1)
