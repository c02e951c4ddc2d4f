"""Tiny magnitudes mixed with ordinary ones: 6e-17 where a 0 was meant.

Coordinates produced by floating-point pipelines rarely keep their zeros:
``cos(pi/2)`` is 6.123e-17, a rotation by 90 degrees leaves residues of
1e-16 times the other coordinates, a unit conversion or a projection leaves
1e-10 next to 6378137.  The shape is still "a box" to the eye, but its faces
are no longer exactly planar and its edges no longer exactly straight; the
residues are far below any tolerance, yet exact predicates see them, and
relative tolerances computed per coordinate (|x| < eps * |x|) treat 1e-17 as
a full-size value.  Products of two residues underflow or vanish beside the
ordinary terms.

Real reports this imitates:

- mikedh/trimesh#535: a box-like mesh with a vertex at
  (1.14e-17, -4.33e-18, 2.37e-15) instead of the origin gave a non-watertight
  hull (``base="box", source="noise"``).
- ContinuumIO/anaconda-issues#10483: shapely's ``convex_hull`` of points with
  x = -6.8e-17 .. -3.9e-10 and y = -6378137 (the Earth's radius, from a
  projection) was not convex (``source="trig", scale=6378137``).
- mikedh/trimesh#2301: cuboid corners at -1.73e-18 instead of 0 next to
  8.5e-6 collapsed to zero extents.

``source="trig"`` uses the correctly rounded cos and sin of the doubles
``k * (pi/2)`` as literals (no libm call), so the bytes do not depend on the
platform's trigonometry.
"""

from __future__ import annotations

import numpy as np

from hullstress.registry import register_generator

from ._common import (
    apply_matrix,
    box_points,
    check_choice,
    check_dim,
    check_n,
    check_positive,
    declare_min_size,
    finish,
    lattice,
    lattice_side,
)

__all__ = ["tiny_residue", "QUARTER_TURNS"]

BASES = ("box", "grid")
SOURCES = ("noise", "trig")

#: (cos, sin) of the doubles k * (pi/2), k = 1, 2, 3, correctly rounded (what a good libm returns).
QUARTER_TURNS = (
    (6.123233995736766e-17, 1.0),
    (-1.0, 1.2246467991473532e-16),
    (-1.8369701987210297e-16, -1.0),
)


def _base(rng: np.random.Generator, n: int, dim: int, base: str) -> np.ndarray:
    """The unit box [0, 1]**dim (corners, then points on its faces) or an integer grid block."""
    if base == "box":
        return (box_points(rng, n, dim) + 1.0) / 2.0  # exact: +1 and /2 map [-1, 1] onto [0, 1]
    return lattice(lattice_side(n, dim), dim)[:n].astype(np.float64)


def _quarter_turns(rng: np.random.Generator, pts: np.ndarray, dim: int) -> np.ndarray:
    """Rotate by a random multiple of 90 degrees in the xy plane (and the yz plane in 3D), in floats."""
    out = pts
    planes = [(0, 1)] if dim == 2 else [(0, 1), (1, 2)]
    for i, j in planes:
        c, s = QUARTER_TURNS[int(rng.integers(0, 3))]
        m = np.eye(dim)
        m[i, i], m[i, j], m[j, i], m[j, j] = c, -s, s, c
        out = apply_matrix(out, m)
    return out


@register_generator(
    "tiny-residue",
    dims=(2, 3),
    variants=(
        {"source": "trig"},
        {"source": "noise", "tiny": 1e-17},
        {"source": "noise", "tiny": 1e-300},
        {"base": "grid", "source": "trig"},
        {"source": "trig", "scale": 6378137.0},
    ),
)
def tiny_residue(
    rng: np.random.Generator,
    n: int,
    *,
    dim: int,
    base: str = "box",
    source: str = "noise",
    tiny: float = 1e-17,
    scale: float = 1.0,
) -> np.ndarray:
    """An exact box or grid whose zeros became tiny residues (1e-17, 1e-300) next to ordinary values.

    Parameters
    ----------
    rng : numpy.random.Generator
    n : int
        Number of points (>= 2**dim for ``base="box"``: its corners).
    dim : {2, 3}
    base : {"box", "grid"}
        ``box``: the 2**dim corners of [0, 1]**dim and points exactly on its
        faces.  ``grid``: the first n points of an integer lattice block
        {0..s-1}**dim.
    source : {"noise", "trig"}
        ``noise``: every coordinate that is exactly 0 becomes
        ``±U(0.5, 1) * tiny`` (the others are untouched).  ``trig``: the shape
        is rotated by random multiples of 90 degrees using the floating-point
        cos and sin (:data:`QUARTER_TURNS`), which leaves residues of about
        1e-16 times the other coordinates where zeros should be.
    tiny : float
        Residue magnitude for ``source="noise"`` (> 0; 1e-17 is trig noise,
        1e-300 underflows every product).
    scale : float
        Multiplier of the shape (> 0), applied before the residues.

    Returns
    -------
    points : ndarray of shape (n, dim), float64
        Rows in random order.

    Notes
    -----
    With ``noise`` the ordinary coordinates are exactly the shape's (0 and
    ``scale`` for the box's planes), so zeroing every |x| <= tiny gives back
    the exact shape.  With ``trig`` no coordinate is moved by more than a few
    ulps of the rotated shape's scale, but no planar face stays planar.

    Examples
    --------
    >>> pts = tiny_residue(np.random.default_rng(0), 6, dim=2)
    >>> small = np.abs(pts) <= 1e-17
    >>> bool(small.any() and np.all(pts[small] != 0))  # residues, never an exact zero
    True
    >>> on_face = np.isin(np.where(small, 0.0, pts), [0.0, 1.0]).any(axis=1)
    >>> bool(on_face.all())  # zeroing the residues gives back points on the box's faces
    True
    """
    fam = "tiny-residue"
    dim = check_dim(fam, dim, (2, 3))
    check_choice(fam, "base", base, BASES)
    check_choice(fam, "source", source, SOURCES)
    n = check_n(fam, n, 2**dim if base == "box" else 1, "the box's corners" if base == "box" else "")
    tiny = check_positive(fam, "tiny", tiny)
    scale = check_positive(fam, "scale", scale)
    pts = _base(rng, n, dim, base) * scale
    if source == "noise":
        zero = pts == 0.0
        sign = np.where(rng.random(pts.shape) < 0.5, -1.0, 1.0)
        residue = sign * rng.uniform(0.5, 1.0, pts.shape) * tiny
        pts = np.where(zero, residue, pts)
    else:
        pts = _quarter_turns(rng, pts, dim)
    return finish(pts[rng.permutation(n)])


declare_min_size("tiny-residue", lambda dim, base="box", **p: 2**dim if base == "box" else 1)
