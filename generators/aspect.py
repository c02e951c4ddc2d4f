"""Extreme aspect ratios: x in [0, 2] while y spans 1e8 (a needle), or a slab that thin in 3D.

An algorithm that measures "flatness" against the bounding box, scales one
tolerance by the largest extent, or normalises coordinates by their maximum
loses the thin direction entirely: its whole width is below the tolerance the
long direction implies.  Heights spread over many decades (1, 1e4, 1e8) put
true hull vertices at every magnitude, so a point that is extreme by a
margin of 1 next to one at 1e8 is discarded as "coplanar".

Real reports this imitates:

- scipy/scipy#14185: ``ConvexHull`` of (0, 1), (1, 1e4 + 1), (2, 1e8 + 1),
  (2, -1), (0, -1) dropped the true vertex (0, 1): x spans 2, y spans 1e8,
  with heights at 1, 1e4 and 1e8 (``heights="log"``, the default).
- mikedh/trimesh#24: Qhull's "initial hull is narrow" precision error on a
  long thin mesh, fixed by rescaling to the unit box (``QbB``), i.e. by
  removing the aspect ratio this family keeps.

The sibling :func:`generators.scale.mixed_magnitude` (``mode="axes"``) draws
uniform heights in a symmetric box; here the thin axis starts at 0 and the
heights can be log-spaced, as in the report.
"""

from __future__ import annotations

import math

import numpy as np

from hullstress.registry import register_generator

from ._common import (
    GeneratorValueError,
    check_choice,
    check_dim,
    check_n,
    check_positive,
    declare_min_size,
    finish,
)

__all__ = ["aspect_ratio"]

ORIENTATIONS = ("tall", "wide")
HEIGHTS = ("log", "uniform")


@register_generator(
    "aspect-ratio",
    dims=(2, 3),
    variants=(
        {"heights": "log"},
        {"heights": "uniform"},
        {"heights": "log", "span": 1e12},
        {"orientation": "wide", "heights": "log"},
    ),
)
def aspect_ratio(
    rng: np.random.Generator,
    n: int,
    *,
    dim: int,
    orientation: str = "tall",
    heights: str = "log",
    span: float = 1e8,
    width: float = 2.0,
) -> np.ndarray:
    """Needles and slabs: thin axes in [0, 2] while the long axes span 1e8 or more (scipy issue 14185).

    Parameters
    ----------
    rng : numpy.random.Generator
    n : int
        Number of points (>= 2: the extremes 1 and ``span`` are always present).
    dim : {2, 3}
    orientation : {"tall", "wide"}
        ``tall``: only the last axis is long (x in [0, width] while y spans
        ``span``; in 3D a needle along z).  ``wide``: every axis but the last
        is long (in 2D x spans and y is thin; in 3D a slab, thin in z).
    heights : {"log", "uniform"}
        Long coordinates: ``log``: ``±10**U(0, log10(span))`` with random sign,
        every decade equally likely, and rows 0 and 1 exactly ``span`` and 1
        on the first long axis (before the rows are shuffled).
        ``uniform``: uniform in [-span, span].
    span : float
        Largest |long coordinate| (> 1).
    width : float
        Thin coordinates are uniform in [0, width] (> 0).

    Returns
    -------
    points : ndarray of shape (n, dim), float64
        Rows in random order.

    Notes
    -----
    Every hull vertex can be decided exactly (the coordinates are ordinary
    doubles); only tolerances derived from the extent fail, because
    ``span / width`` is 5e7 by default and up to 1e15 and beyond.

    Examples
    --------
    >>> pts = aspect_ratio(np.random.default_rng(0), 8, dim=2)
    >>> float(np.abs(pts[:, 1]).max()), bool(np.all((0 <= pts[:, 0]) & (pts[:, 0] <= 2)))
    (100000000.0, True)
    """
    fam = "aspect-ratio"
    dim = check_dim(fam, dim, (2, 3))
    n = check_n(fam, n, 2, "the extremes 1 and span")
    check_choice(fam, "orientation", orientation, ORIENTATIONS)
    check_choice(fam, "heights", heights, HEIGHTS)
    span = check_positive(fam, "span", span)
    if span <= 1.0 or math.isinf(span):
        raise GeneratorValueError(f"{fam}: span must be a finite float > 1, got {span!r}")
    width = check_positive(fam, "width", width)
    long_axes = [dim - 1] if orientation == "tall" else list(range(dim - 1))
    pts = rng.uniform(0.0, width, (n, dim))
    for axis in long_axes:
        if heights == "log":
            mag = 10.0 ** rng.uniform(0.0, math.log10(span), n)
            sign = np.where(rng.random(n) < 0.5, -1.0, 1.0)
            pts[:, axis] = np.clip(mag, 1.0, span) * sign
        else:
            pts[:, axis] = rng.uniform(-span, span, n)
    if heights == "log":
        pts[0, long_axes[0]] = span
        pts[1, long_axes[0]] = 1.0
    return finish(pts[rng.permutation(n)])


declare_min_size("aspect-ratio", lambda dim, **p: 2)
