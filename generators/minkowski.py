"""Minkowski sums of cubes: Kenwright's procedural test family.

Kenwright evaluates his sphere-projection hull on the Minkowski sum of two
cubes, one rotated (his Figure 5), because the sum "generates a wide variety
of point data (e.g. degenerate cases ...)": the sum of two boxes has faces
that are parallelograms of four sums, and whenever the rotation keeps an axis
the top and bottom faces hold sixteen exactly coplanar points, with many
collinear runs; with no rotation at all the sums are a 3x3x3 lattice with
massive duplication.
"""

from __future__ import annotations

import math

import numpy as np

from hullstress.registry import register_generator

from ._common import (
    apply_matrix,
    check_choice,
    check_dim,
    check_n,
    cube_surface,
    declare_min_size,
    finish,
    lattice,
    random_rotation,
)

__all__ = ["minkowski_cubes"]

ROTATIONS = ("random", "axis", "none", "pythagorean")


def _rotation(rng: np.random.Generator, dim: int, rotation: str) -> tuple[np.ndarray, float]:
    """Return (matrix, scale of the first cube) for the second cube's rotation."""
    if rotation == "none":
        return np.eye(dim), 1.0
    if rotation == "random":
        return random_rotation(rng, dim), 1.0
    if rotation == "pythagorean":
        # [[3,-4],[4,3]] / 5 is a rotation with rational entries; applied to a
        # cube of half-side 5 it gives integer vertices (and the first cube is
        # scaled to half-side 5 as well): every sum is an exact integer.
        m = np.array([[3.0, -4.0], [4.0, 3.0]])
        if dim == 3:
            m = np.array([[3.0, -4.0, 0.0], [4.0, 3.0, 0.0], [0.0, 0.0, 5.0]])
        return m, 5.0
    theta = rng.uniform(0.0, 2.0 * math.pi)  # "axis": about z only, z stays exact
    c, s = math.cos(theta), math.sin(theta)
    if dim == 2:
        return np.array([[c, -s], [s, c]]), 1.0
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]]), 1.0


@register_generator(
    "minkowski-cubes",
    dims=(2, 3),
    variants=({"rotation": "random"}, {"rotation": "axis"}, {"rotation": "none"}, {"rotation": "pythagorean"}),
)
def minkowski_cubes(
    rng: np.random.Generator,
    n: int,
    *,
    dim: int,
    rotation: str = "random",
) -> np.ndarray:
    """Pairwise sums of the vertices of a cube and a rotated cube (Kenwright's Figure 5).

    Parameters
    ----------
    rng : numpy.random.Generator
    n : int
        Number of points (>= 1).  With n < 4**dim, a random subset of the
        4**dim vertex sums; with more, all of them plus sums of a random point
        on the first cube's surface and a random vertex of the second (points
        on or inside the sum).
    dim : {2, 3}
    rotation : {"random", "axis", "none", "pythagorean"}
        The second cube's rotation: a random rotation; a random rotation about
        the z axis (3D: the z = +-2 faces hold 16 exactly coplanar sums);
        none (sums form the lattice {-2, 0, 2}**dim, with repeats); or the
        rational rotation [[3, -4], [4, 3]] / 5 with both cubes of half-side 5
        (every coordinate an exact integer).

    Returns
    -------
    points : ndarray of shape (n, dim), float64
        Rows in random order.

    Notes
    -----
    Stresses coplanar clusters on parallelogram faces, collinear sums along
    edges, duplicates (``none``), and exact integer degeneracy with
    non-axis-aligned faces (``pythagorean``).

    Examples
    --------
    >>> pts = minkowski_cubes(np.random.default_rng(0), 64, dim=3, rotation="axis")
    >>> int(np.count_nonzero(pts[:, 2] == pts[:, 2].max()))
    16
    """
    fam = "minkowski-cubes"
    dim = check_dim(fam, dim, (2, 3))
    n = check_n(fam, n, 1)
    check_choice(fam, "rotation", rotation, ROTATIONS)
    rot, half = _rotation(rng, dim, rotation)
    corners = (lattice(2, dim) * 2 - 1).astype(np.float64)  # the 2**dim vertices of [-1, 1]**dim
    a = corners * half
    b = apply_matrix(corners, rot)
    sums = (a[:, None, :] + b[None, :, :]).reshape(-1, dim)
    total = len(sums)
    if n <= total:
        pts = sums[rng.choice(total, n, replace=False)]
    else:
        extra = n - total
        on_a = cube_surface(rng, extra, dim, 0.0) * half
        pts = np.concatenate([sums, on_a + b[rng.integers(0, len(b), extra)]])
        pts = pts[rng.permutation(n)]
    return finish(pts)


declare_min_size("minkowski-cubes", lambda dim, **p: 1)
