"""Exact and near duplicates.

Repeated points break hull code in several places at once: a zero-length edge
has no direction, a triangle with two equal corners has a zero normal, and
visibility tests against such facets return 0 for everything, so an
incremental algorithm may attach a point to a degenerate facet or insert the
same vertex twice.  Kenwright's Figure 3(a) ("multiple overlapping points") and
his step 1 (remove duplicates within a tolerance) exist because of this.
Near-duplicates a few ulps apart are worse: tolerance-based de-duplication
merges some pairs and not others, and exact predicates see tiny but genuine
edges.

rbox equivalents: ``C2`` (exact copies of every point), ``P0 P0 P0 P0 P0``
(identical points), ``C1,r`` with a radius of a few ulps.
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
    declare_min_size,
    finish,
    random_ulp_offsets,
    ulp_shift,
    uniform_ball,
)

__all__ = ["duplicates"]

MODES = ("some", "every-point", "one-point", "all-identical", "ulp-near")


@register_generator(
    "duplicates",
    dims=(2, 3),
    variants=(
        {"mode": "some"},
        {"mode": "every-point", "copies": 2},
        {"mode": "every-point", "copies": 5},
        {"mode": "one-point"},
        {"mode": "all-identical"},
        {"mode": "ulp-near", "ulps": 1},
        {"mode": "ulp-near", "ulps": 4},
    ),
)
def duplicates(
    rng: np.random.Generator,
    n: int,
    *,
    dim: int,
    mode: str = "some",
    fraction: float = 0.5,
    copies: int = 2,
    ulps: int = 1,
    scale: float = 1.0,
) -> np.ndarray:
    """Exact repeats, many copies of one extreme point, identical sets, ulp-near twins.

    Parameters
    ----------
    rng : numpy.random.Generator
        The only source of randomness.
    n : int
        Number of rows (>= 1).
    dim : {2, 3}
        Dimension.
    mode : {"some", "every-point", "one-point", "all-identical", "ulp-near"}
        ``some``: ``max(1, floor(n * fraction))`` rows are exact copies of other
        rows (n >= 2).  ``every-point``: each point appears ``copies`` times
        (rbox ``C<copies>`` with no radius; the last one possibly fewer times).
        ``one-point``: ``n // 2`` rows are copies of one extreme point (the
        point of largest first coordinate, a true hull vertex).
        ``all-identical``: every row is the same point (rbox ``P0 P0 P0``).
        ``ulp-near``: ``ceil(n / 2)`` distinct points, the other rows copies of
        them with each coordinate moved by an integer number of ulps in
        ``[-ulps, ulps]``, never all zero: distinct, but within ``ulps`` ulps.
    fraction : float
        Share of repeated rows for ``mode="some"`` (0 < fraction < 1).
    copies : int
        Copies per point for ``mode="every-point"`` (>= 2).
    ulps : int
        Maximum ulp distance per coordinate for ``mode="ulp-near"`` (>= 1).
    scale : float
        Radius of the ball the distinct points are drawn from.

    Returns
    -------
    points : ndarray of shape (n, dim), float64
        Rows in random order.

    Notes
    -----
    Stresses zero-length edges, zero-area facets, vertex de-duplication, and
    tolerance-based merging (ulp-near pairs are closer than any sane epsilon
    yet not equal, so exact predicates and tolerant ones disagree).

    Examples
    --------
    >>> pts = duplicates(np.random.default_rng(0), 6, dim=2, mode="all-identical")
    >>> len(np.unique(pts, axis=0))
    1
    >>> pts = duplicates(np.random.default_rng(0), 8, dim=3, mode="every-point", copies=2)
    >>> len(np.unique(pts, axis=0))
    4
    """
    fam = "duplicates"
    dim = check_dim(fam, dim, (2, 3))
    n = check_n(fam, n, 1)
    check_choice(fam, "mode", mode, MODES)
    scale = check_positive(fam, "scale", scale)
    if mode == "all-identical":
        point = uniform_ball(rng, 1, dim) * scale
        return finish(np.repeat(point, n, axis=0))
    if mode == "some":
        if isinstance(fraction, bool) or not isinstance(fraction, (int, float)) or not 0.0 < fraction < 1.0:
            raise GeneratorValueError(f"{fam}: fraction must be a float in (0, 1), got {fraction!r}")
        k = max(1, int(n * float(fraction))) if n >= 2 else 0
        base = uniform_ball(rng, n - k, dim) * scale
        picks = rng.integers(0, n - k, k)
        pts = np.concatenate([base, base[picks]])
    elif mode == "every-point":
        copies = check_int(fam, "copies", copies, 2)
        m = -(-n // copies)
        base = uniform_ball(rng, m, dim) * scale
        pts = np.repeat(base, copies, axis=0)[:n]
    elif mode == "one-point":
        k = n // 2
        base = uniform_ball(rng, n - k, dim) * scale
        extreme = base[np.argmax(base[:, 0])]
        pts = np.concatenate([base, np.repeat(extreme[None, :], k, axis=0)])
    else:  # ulp-near
        ulps = check_int(fam, "ulps", ulps, 1)
        m = -(-n // 2)
        base = uniform_ball(rng, m, dim) * scale
        src = rng.integers(0, m, n - m)
        shift = random_ulp_offsets(rng, (n - m, dim), ulps, nonzero_rows=True)
        pts = np.concatenate([base, ulp_shift(base[src], shift)])
    return finish(pts[rng.permutation(n)])


declare_min_size("duplicates", lambda dim, **p: 1)
