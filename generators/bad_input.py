"""Bad input: NaN, infinities, empty and tiny sets, wrong shapes.

This family deliberately breaks the generator output contract.  A hull
algorithm given such input should reject it clearly (an exception with a
message); looping forever, crashing the process, or returning a "hull" is a
finding.  The runner records which of these happened; the case's ``dim``
still says which algorithms it is meant for.
"""

from __future__ import annotations

import numpy as np

from hullstress.registry import register_generator

from ._common import check_choice, check_dim, check_n, declare_min_size, uniform_ball

__all__ = ["bad_input", "KINDS", "CONTRACT_BREAKING"]

KINDS = (
    "nan",
    "inf",
    "neg-inf",
    "all-nan",
    "empty",
    "one-point",
    "two-points",
    "two-identical",
    "wrong-columns",
    "one-dimensional",
    "extra-axis",
)

#: Kinds whose output is not an (n, dim) array at all.
CONTRACT_BREAKING = ("wrong-columns", "one-dimensional", "extra-axis")


@register_generator("bad-input", dims=(2, 3), variants=tuple({"kind": k} for k in KINDS))
def bad_input(
    rng: np.random.Generator,
    n: int,
    *,
    dim: int,
    kind: str = "nan",
) -> np.ndarray:
    """Invalid inputs (NaN, inf, empty, 1-2 points, wrong shape): a clear rejection is the right answer.

    Parameters
    ----------
    rng : numpy.random.Generator
    n : int
        Size of the underlying cloud (>= 1); ignored by ``empty``,
        ``one-point``, ``two-points`` and ``two-identical``.
    dim : {2, 3}
    kind : str
        ``nan`` / ``inf`` / ``neg-inf``: a unit-ball cloud with one random
        coordinate replaced; ``all-nan``: every coordinate NaN; ``empty``: shape
        (0, dim); ``one-point``: (1, dim); ``two-points``: two distinct points;
        ``two-identical``: the same point twice; ``wrong-columns``: shape
        (n, dim + 1); ``one-dimensional``: shape (n * dim,) (the flattened
        cloud); ``extra-axis``: shape (n, dim, 1).

    Returns
    -------
    points : ndarray, float64
        Not (n, dim) in general: this family breaks the output contract on
        purpose (the kinds in ``CONTRACT_BREAKING`` break its shape).

    Notes
    -----
    Empty, one- and two-point sets and all-NaN sets have no full-dimensional
    hull; NaN compares false with everything, so a loop "until no point is
    outside" may never end, and inf - inf is NaN inside every predicate.

    Examples
    --------
    >>> bad_input(np.random.default_rng(0), 5, dim=3, kind="empty").shape
    (0, 3)
    >>> bad_input(np.random.default_rng(0), 5, dim=2, kind="wrong-columns").shape
    (5, 3)
    """
    fam = "bad-input"
    dim = check_dim(fam, dim, (2, 3))
    check_choice(fam, "kind", kind, KINDS)
    n = check_n(fam, n, 1)
    if kind == "empty":
        return np.zeros((0, dim), dtype=np.float64)
    if kind == "one-point":
        return uniform_ball(rng, 1, dim)
    if kind == "two-points":
        return uniform_ball(rng, 2, dim)
    if kind == "two-identical":
        return np.repeat(uniform_ball(rng, 1, dim), 2, axis=0)
    if kind == "all-nan":
        return np.full((n, dim), np.nan)
    if kind == "wrong-columns":
        return uniform_ball(rng, n, dim + 1)
    pts = uniform_ball(rng, n, dim)
    if kind == "one-dimensional":
        return np.ascontiguousarray(pts.ravel())
    if kind == "extra-axis":
        return np.ascontiguousarray(pts[:, :, None])
    value = {"nan": np.nan, "inf": np.inf, "neg-inf": -np.inf}[kind]
    pts[rng.integers(0, n), rng.integers(0, dim)] = value
    return pts


declare_min_size("bad-input", lambda dim, **p: 1)
