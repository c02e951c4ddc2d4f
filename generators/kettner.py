"""Published failures: the Kettner et al. classroom examples and their ulp grids.

Kettner, Mehlhorn, Pion, Schirra and Yap, "Classroom examples of robustness
problems in geometric computations" (ESA 2004; CGTA 40(1), 2008) give small
2D point sets on which the textbook incremental hull with a float
orientation test fails: it drops a true extreme point, inserts a point at an
edge it cannot see, finds no tangent and loops, or returns a non-convex or
self-intersecting polygon.  They also plot 256 x 256 grids of points one ulp
apart near a nearly collinear triple, on which the naive orientation
misclassifies thousands of points.

The coordinates ship with the package (``generators/data/kettner_classroom.json``,
as reproduced digit for digit by several independent test suites) and are
parsed exactly as written: ``float`` of the literal is correctly rounded, so
``1.267650600228229e30`` is that literal's double, not
``1.267650600228229 * 1e30`` (a different double).
"""

from __future__ import annotations

import json
from functools import lru_cache
from importlib import resources
from typing import Any

import numpy as np

from hullstress.registry import register_generator

from ._common import (
    GeneratorValueError,
    check_choice,
    check_dim,
    check_int,
    check_n,
    declare_min_size,
    finish,
    lattice_side,
)

__all__ = ["kettner_data", "kettner_case_names", "kettner_classroom", "kettner_ulp_grid", "ULP"]

#: The grid step of the paper's figures: one ulp of numbers in [1/2, 1).
ULP = 2.0**-53


@lru_cache(maxsize=1)
def _raw_text() -> str:
    return resources.files("generators").joinpath("data", "kettner_classroom.json").read_text(encoding="utf-8")


def kettner_data() -> dict[str, Any]:
    """The parsed data file (a fresh copy): source, formula, cases, orientation grids.

    Every number goes through ``float(literal)`` (``parse_float=float``;
    integers are converted afterwards, exactly).
    """
    return json.loads(_raw_text(), parse_float=float)


def kettner_case_names() -> tuple[str, ...]:
    """Names of the classroom cases, in the paper's order."""
    return tuple(case["name"] for case in kettner_data()["cases"])


_CASES = kettner_case_names()


@register_generator(
    "kettner-classroom",
    dims=(2,),
    variants=tuple({"case": name} for name in _CASES),
    fixed_size=True,
)
def kettner_classroom(
    rng: np.random.Generator,
    n: int | None = None,
    *,
    dim: int = 2,
    case: str = _CASES[0],
    order: str = "published",
) -> np.ndarray:
    """The Kettner et al. classroom examples: tiny 2D sets that break the float incremental hull.

    Parameters
    ----------
    rng : numpy.random.Generator
        Used only with ``order="random"``.
    n : int or None
        Ignored: each case has its own size (4 to 9 points).
    dim : {2}
    case : str
        One of :func:`kettner_case_names`: ``A1_outside_point_sees_no_edge``,
        ``A2_inside_point_sees_an_edge``, ``B1_outside_point_sees_all_edges``,
        ``B2_visible_edges_not_consecutive``, ``global_unbounded_area_error``,
        ``global_non_convex_result``.
    order : {"published", "random"}
        The published insertion order (the failures depend on it) or shuffled.

    Returns
    -------
    points : ndarray of shape (k, 2), float64

    Notes
    -----
    The failures reproduce with ``orient(p, q, r) = (qx-px)(ry-py) - (qy-py)(rx-px)``
    in float64 with p as pivot, inserting the points in the given order.  The
    data file's ``effect`` field says what goes wrong for each case.

    Examples
    --------
    >>> pts = kettner_classroom(np.random.default_rng(0), case="global_unbounded_area_error")
    >>> pts[3].tolist()
    [1.267650600228229e+30, 1.2676506002282291e+30]
    """
    fam = "kettner-classroom"
    check_dim(fam, dim, (2,))
    check_choice(fam, "case", case, _CASES)
    check_choice(fam, "order", order, ("published", "random"))
    (entry,) = [c for c in kettner_data()["cases"] if c["name"] == case]
    pts = np.array([[float(x) for x in p] for p in entry["points"]], dtype=np.float64)
    if order == "random":
        pts = pts[rng.permutation(len(pts))]
    return finish(pts)


@register_generator(
    "kettner-ulp-grid",
    dims=(2,),
    variants=({"grid": 0}, {"grid": 1}, {"grid": 2}),
)
def kettner_ulp_grid(
    rng: np.random.Generator,
    n: int,
    *,
    dim: int = 2,
    grid: int = 0,
) -> np.ndarray:
    """Kettner et al.'s ulp grids: points one ulp apart next to a nearly collinear triple p, q, r.

    Parameters
    ----------
    rng : numpy.random.Generator
    n : int
        Number of points (>= 3): rows 0 and 1 are q and r, the other n - 2 rows
        a random subset (in random order) of the grid ``p + (i*u, j*u)``,
        ``u = 2**-53``, i, j in ``0..side-1``, side = max(256, ceil(sqrt(n - 2))).
    dim : {2}
    grid : {0, 1, 2}
        Which of the paper's three (p, q, r) triples.

    Returns
    -------
    points : ndarray of shape (n, 2), float64

    Notes
    -----
    Every grid point is exactly ``p + (i*u, j*u)`` (p lies in [1/2, 1), where u
    is one ulp).  p, q and r are nearly collinear, so the float orientation of
    (grid point, q, r) is decided by rounding: the hull of the set is a thin
    sliver whose vertices among the grid points float code cannot find.

    Examples
    --------
    >>> pts = kettner_ulp_grid(np.random.default_rng(0), 5, grid=0)
    >>> pts[:2].tolist()
    [[12.0, 12.0], [24.0, 24.0]]
    """
    fam = "kettner-ulp-grid"
    check_dim(fam, dim, (2,))
    grids = kettner_data()["orientation_grids"]["grids"]
    grid = check_int(fam, "grid", grid, 0, len(grids) - 1)
    n = check_n(fam, n, 3, "q, r and at least one grid point")
    g = grids[grid]
    p, q, r = (np.array([float(x) for x in g[k]]) for k in ("p", "q", "r"))
    side = max(256, lattice_side(n - 2, 2))
    if not np.all((p >= 0.5) & (p + (side - 1) * ULP < 1.0)):
        raise GeneratorValueError(f"{fam}: grid {grid} with side {side} leaves [1/2, 1); steps would not be one ulp")
    flat = rng.choice(side * side, n - 2, replace=False)
    ij = np.column_stack([flat // side, flat % side]).astype(np.float64)
    pts = np.concatenate([q[None, :], r[None, :], p + ij * ULP])
    return finish(pts)


declare_min_size("kettner-classroom", lambda dim, **p: 1)
declare_min_size("kettner-ulp-grid", lambda dim, **p: 3)
