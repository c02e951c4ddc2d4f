"""Coplanar grids: lattices on a plane, on every face of a cube, lattice blocks, pyramids.

Exactly coplanar points make every orientation test among them return zero,
so facet selection depends on how an algorithm breaks ties: gift wrapping
picks one of many equally good candidates and may wrap a face twice or leave
a hole; Quickhull-style algorithms create zero-volume facets and must merge
them; Henckel-style polygon gathering must collect the whole face.  Lattices
add collinear rows and duplicate-looking diagonals on top.  Rotating a lattice
by a random rotation keeps it coplanar only up to rounding, which is worse:
orientation signs among the face points become essentially random.

rbox equivalents: ``W0`` (on a cube's faces), ``M3,4,5 z`` / ``M1,0,1`` /
``M1,0,0`` (rotated integer lattices, a flat lattice with duplicates),
Qhull's ``QR`` input rotation; scipy's "pathological-1" decimal grid.
"""

from __future__ import annotations

import numpy as np

from hullstress.registry import register_generator

from ._common import (
    apply_matrix,
    check_choice,
    check_dim,
    check_int,
    check_n,
    check_positive,
    cube_surface,
    declare_min_size,
    finish,
    lattice as _lattice,
    lattice_side,
    pow2_at_least,
    random_rotation,
)

__all__ = ["coplanar_grid", "cube_faces", "lattice_block", "grid_apex"]

LATTICES = ("integer", "decimal", "random")


def _plane_coordinates(rng: np.random.Generator, m: int, lattice_kind: str) -> tuple[np.ndarray, int]:
    """m in-plane (u, v) coordinates: the first m points of a square lattice, shifted."""
    s = lattice_side(m, 2)
    uv = _lattice(s, 2)[:m] + rng.integers(-s, s + 1, 2)
    if lattice_kind == "integer":
        return uv.astype(np.float64), s
    if lattice_kind == "decimal":
        # Step 0.1 is not representable: rows and columns stay exactly aligned
        # (equal coordinates), diagonals are only nearly collinear.
        return uv * 0.1, s
    return rng.uniform(-s / 2.0, s / 2.0, (m, 2)), s


@register_generator(
    "coplanar-grid",
    dims=(2, 3),
    variants=(
        {},
        {"plane": "tilted"},
        {"lattice": "decimal"},
        {"lattice": "random", "plane": "tilted"},
        {"rotate": True},
        {"lattice": "decimal", "plane": "tilted", "rotate": True},
    ),
)
def coplanar_grid(
    rng: np.random.Generator,
    n: int,
    *,
    dim: int,
    lattice: str = "integer",
    plane: str = "axis",
    rotate: bool = False,
    scale: float = 1.0,
) -> np.ndarray:
    """A lattice on one plane (3D) or in the plane (2D): all points coplanar, rows collinear.

    Parameters
    ----------
    rng : numpy.random.Generator
    n : int
        Number of points (>= 1): the first n points of a ceil(sqrt(n))-square
        lattice with a random integer origin, in random row order.
    dim : {2, 3}
    lattice : {"integer", "decimal", "random"}
        Integer steps (exact), steps of 0.1 (rounded, like scipy's
        "pathological-1" grid), or uniform random points on the plane.
    plane : {"axis", "tilted"}
        3D only: ``z = c`` or ``z = a*u + b*v + c`` with small random integers.
    rotate : bool
        Apply a random rotation: coplanarity and collinearity become inexact.
    scale : float
        Final multiplier.

    Returns
    -------
    points : ndarray of shape (n, dim), float64

    Notes
    -----
    Exactly coplanar (3D) when not rotated and either ``plane="axis"`` or
    ``lattice="integer"`` with a power-of-two ``scale``.  In 2D the whole set is
    a planar lattice: every hull edge carries a collinear run.

    Examples
    --------
    >>> pts = coplanar_grid(np.random.default_rng(1), 9, dim=3)
    >>> bool(np.all(pts[:, 2] == pts[0, 2]))
    True
    """
    fam = "coplanar-grid"
    dim = check_dim(fam, dim, (2, 3))
    n = check_n(fam, n, 1)
    check_choice(fam, "lattice", lattice, LATTICES)
    check_choice(fam, "plane", plane, ("axis", "tilted"))
    scale = check_positive(fam, "scale", scale)
    uv, s = _plane_coordinates(rng, n, lattice)
    if dim == 2:
        pts = uv
    elif plane == "axis":
        c = float(rng.integers(-s, s + 1))
        pts = np.column_stack([uv, np.full(n, c)])
    else:
        a, b = 0, 0
        while a == 0 and b == 0:  # a plane that really is tilted
            a, b = (int(x) for x in rng.integers(-3, 4, 2))
        c = float(rng.integers(-s, s + 1))
        pts = np.column_stack([uv, a * uv[:, 0] + b * uv[:, 1] + c])
    pts = pts[rng.permutation(n)]
    if rotate:
        pts = apply_matrix(pts, random_rotation(rng, dim))
    return finish(pts * scale)


@register_generator(
    "cube-faces",
    dims=(2, 3),
    variants=({}, {"layout": "grid"}, {"rotate": True}, {"layout": "grid", "rotate": True}),
)
def cube_faces(
    rng: np.random.Generator,
    n: int,
    *,
    dim: int,
    layout: str = "random",
    rotate: bool = False,
    scale: float = 1.0,
) -> np.ndarray:
    """Points exactly on the faces of a cube (rbox W0): 2*dim large coplanar faces.

    Parameters
    ----------
    rng : numpy.random.Generator
    n : int
        Number of points (>= 1).
    dim : {2, 3}
    layout : {"random", "grid"}
        ``random``: rbox ``W0`` (uniform in the cube, then one random coordinate
        set to exactly +-1).  ``grid``: boundary points of the integer lattice
        ``{-s..s}**dim`` (smallest s with enough points), corners first when
        n >= 2**dim, divided by a power of two (exact): faces are lattices, every
        cube edge a collinear run.
    rotate : bool
        Apply a random rotation (like Qhull's ``QR``): the faces become only
        nearly coplanar.
    scale : float
        Final multiplier (the unrotated cube has half-side <= scale).

    Returns
    -------
    points : ndarray of shape (n, dim), float64

    Notes
    -----
    Each face holds about n / (2 dim) exactly coplanar points; with ``grid``
    the face diagonals and edges add exact collinear runs.  Qhull's own test
    ``rbox 1000 W0 | qhull QR2 QJ s Fs Tv`` is the rotated variant.

    Examples
    --------
    >>> pts = cube_faces(np.random.default_rng(0), 50, dim=3)
    >>> bool(np.all(np.any(np.abs(pts) == 1.0, axis=1)))
    True
    """
    fam = "cube-faces"
    dim = check_dim(fam, dim, (2, 3))
    n = check_n(fam, n, 1)
    check_choice(fam, "layout", layout, ("random", "grid"))
    scale = check_positive(fam, "scale", scale)
    if layout == "random":
        pts = cube_surface(rng, n, dim, 0.0)
    else:
        s = 1
        while (2 * s + 1) ** dim - (2 * s - 1) ** dim < n:
            s += 1
        faces = []
        for axis in range(dim):
            face = _lattice(2 * s + 1, dim - 1) - s
            for sign in (-s, s):
                faces.append(np.insert(face, axis, sign, axis=1))
        boundary = np.unique(np.concatenate(faces), axis=0)  # sorted: order-independent
        is_corner = np.all(np.abs(boundary) == s, axis=1)
        corners, others = boundary[is_corner], boundary[~is_corner]
        if n <= len(corners):
            chosen = corners[rng.choice(len(corners), n, replace=False)]
        else:
            chosen = np.concatenate([corners, others[rng.choice(len(others), n - len(corners), replace=False)]])
        pts = chosen[rng.permutation(n)] / pow2_at_least(float(s))
    if rotate:
        pts = apply_matrix(pts, random_rotation(rng, dim))
    return finish(pts * scale)


@register_generator(
    "lattice-block",
    dims=(2, 3),
    variants=(
        {},
        {"order": "random"},
        {"a": 1, "b": 0, "c": 1},
        {"a": 3, "b": 4, "c": 0},
        {"a": 1, "b": 0, "c": 0},
        {"rotate": True, "order": "random"},
    ),
)
def lattice_block(
    rng: np.random.Generator,
    n: int,
    *,
    dim: int,
    a: int = 3,
    b: int = 4,
    c: int = 5,
    order: str = "rbox",
    rotate: bool = False,
) -> np.ndarray:
    """rbox M a,b,c: an integer lattice block mapped by [[a,-b,0],[b,a,0],[0,0,c]].

    Parameters
    ----------
    rng : numpy.random.Generator
    n : int
        Number of points (>= 1): the first n points of the
        ``ceil(n**(1/dim))``-per-side block, in rbox's order.
    dim : {2, 3}
        In 2D only ``a`` and ``b`` are used.
    a, b, c : int
        The rbox ``M`` parameters.  ``c = 0`` flattens a 3D block onto z = 0
        with exact duplicates (rbox ``M1,0,0``, ``M3,4,0``).
    order : {"rbox", "random"}
        ``rbox``: lattice order, first index fastest, so the first points are
        collinear (a flat initial simplex for "first d+1 points" code);
        ``random``: rows shuffled.
    rotate : bool
        Apply a random rotation (the lattice's planes become inexact).

    Returns
    -------
    points : ndarray of shape (n, dim), float64
        Integer coordinates (before rotation) shifted by a random integer vector.

    Notes
    -----
    The lattice has many exactly coplanar layers in several directions, exact
    collinear rows, and (with the 3,4 rotation) lattice directions that are not
    axis-aligned.  Qhull's tests: ``rbox 27 M1,0,1``, ``rbox 10 M3,4 C1,1E-14``,
    ``qtest.sh N '20000 M3,4,5 z D3'``.

    Examples
    --------
    >>> pts = lattice_block(np.random.default_rng(0), 8, dim=3, a=1, b=0, c=1)
    >>> bool(np.all(pts == np.round(pts)))
    True
    """
    fam = "lattice-block"
    dim = check_dim(fam, dim, (2, 3))
    n = check_n(fam, n, 1)
    a = check_int(fam, "a", a, -(2**20), 2**20)
    b = check_int(fam, "b", b, -(2**20), 2**20)
    c = check_int(fam, "c", c, -(2**20), 2**20)
    check_choice(fam, "order", order, ("rbox", "random"))
    s = lattice_side(n, dim)
    idx = _lattice(s, dim)[:, ::-1][:n]  # rbox counts mult[0] fastest
    i, j = idx[:, 0], idx[:, 1]
    cols = [i * a - j * b, i * b + j * a]
    if dim == 3:
        cols.append(idx[:, 2] * c)
    pts = np.column_stack(cols) + rng.integers(-s, s + 1, dim)
    if order == "random":
        pts = pts[rng.permutation(n)]
    pts = pts.astype(np.float64)
    if rotate:
        pts = apply_matrix(pts, random_rotation(rng, dim))
    return finish(pts)


@register_generator(
    "grid-apex",
    dims=(2, 3),
    variants=({}, {"height": 1e-9}, {"height": 1e-15}, {"lattice": "decimal"}, {"rotate": True}),
)
def grid_apex(
    rng: np.random.Generator,
    n: int,
    *,
    dim: int,
    height: float = 1.0,
    lattice: str = "integer",
    rotate: bool = False,
) -> np.ndarray:
    """A pyramid: n-1 lattice points on one plane (a line in 2D) and one apex above it.

    Parameters
    ----------
    rng : numpy.random.Generator
    n : int
        Number of points (>= dim + 1).
    dim : {2, 3}
    height : float
        Apex height relative to the lattice's side; tiny values give a nearly
        flat pyramid whose base facet is hard to tell from its side facets.
    lattice : {"integer", "decimal"}
        Base lattice steps (1 exact, or 0.1 rounded).
    rotate : bool
        Apply a random rotation (the base becomes only nearly coplanar).

    Returns
    -------
    points : ndarray of shape (n, dim), float64
        The apex is at a random row.

    Notes
    -----
    The base facet holds n - 1 exactly coplanar points (unrotated) and its
    boundary carries collinear runs; the apex is the only point off the plane,
    so an algorithm must find the one non-degenerate direction.  A near-flat
    apex makes the side facets almost coplanar with the base.

    Examples
    --------
    >>> pts = grid_apex(np.random.default_rng(0), 10, dim=3)
    >>> int(np.count_nonzero(pts[:, 2] != 0.0))
    1
    """
    fam = "grid-apex"
    dim = check_dim(fam, dim, (2, 3))
    n = check_n(fam, n, dim + 1, "a pyramid needs a base of dim points and an apex")
    height = check_positive(fam, "height", height)
    check_choice(fam, "lattice", lattice, ("integer", "decimal"))
    m = n - 1
    if dim == 3:
        s = lattice_side(m, 2)
        base = (_lattice(s, 2)[:m] + rng.integers(-s, s + 1, 2)).astype(np.float64)
    else:
        s = m
        base = (np.arange(m) + rng.integers(-s, s + 1))[:, None].astype(np.float64)
    centre = base.min(axis=0) + (base.max(axis=0) - base.min(axis=0)) / 2.0
    step = 0.1 if lattice == "decimal" else 1.0
    base = base * step
    apex = np.append(centre * step, height * s * step)
    pts = np.concatenate([np.column_stack([base, np.zeros(m)]), apex[None, :]])
    pts = pts[rng.permutation(n)]
    if rotate:
        pts = apply_matrix(pts, random_rotation(rng, dim))
    return finish(pts)


declare_min_size("coplanar-grid", lambda dim, **p: 1)
declare_min_size("cube-faces", lambda dim, **p: 1)
declare_min_size("lattice-block", lambda dim, **p: 1)
declare_min_size("grid-apex", lambda dim, **p: dim + 1)
