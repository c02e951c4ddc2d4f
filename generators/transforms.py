"""Metamorphic transforms: new cases whose exact hull follows from the original's.

Each transform is exact in floating point (no rounding happens), so the true
hull of the result is known from the true hull of the input; an algorithm
whose verdict changes under a transform has a finding without any reference
hull at all.

=================  ===========================================================
name               exact relation to the original hull
=================  ===========================================================
``permute-rows``   same point set: same hull, indices mapped by ``source_rows``
``reverse-rows``   the rows in reverse order: same point set, and every
                   sort-based algorithm breaks its ties the other way
``scale-pow2``     multiplied by 2**k (checked exact): same combinatorial hull
                   (same vertex indices and faces, same orientation); volume
                   times 2**(k*d)
``permute-axes``   coordinates permuted: same vertex set and faces; the
                   orientation of every facet flips when the permutation is
                   odd (``orientation_preserved`` says which)
``reflect``        one axis negated: same vertex set and faces, orientation
                   flipped
``duplicate-all``  every row twice: same hull as a point set; each vertex now
                   has two indices (``source_rows`` maps both back)
``add-interior``   extra points strictly inside (certified exactly): same
                   hull, the new rows (``source_rows == -1``) are never on it
=================  ===========================================================

Every transform keeps the set of hull vertices, as points: a correct
algorithm's answer on the transformed input, mapped back through
``source_rows``, names the same input points as its answer on the original
(:func:`generators.metamorphic.vertex_set_change` compares them).

The functions take the parameters explicitly; :data:`TRANSFORMS` maps each
name to a ``(points, rng) -> Transformed`` callable that draws them from
``rng``; :mod:`generators.metamorphic` applies chains of them with seeded
generators, which is how :func:`generators.generate` applies
``transform=...`` and how a sweep applies them to a case.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ._common import GeneratorValueError, combine, orient_exact, orient_sign, row_dot, row_norms

__all__ = [
    "Transformed",
    "permute_rows",
    "reverse_rows",
    "scale_pow2",
    "permute_axes",
    "reflect",
    "duplicate_all",
    "add_interior",
    "TRANSFORMS",
    "apply_transform",
    "safe_pow2_range",
]


@dataclass(frozen=True, eq=False)
class Transformed:
    """The result of a metamorphic transform.

    Attributes
    ----------
    points : ndarray of shape (m, d), float64
        The transformed points.
    source_rows : ndarray of shape (m,), int64
        Row i of ``points`` is the image of input row ``source_rows[i]``; -1
        marks rows added by the transform (``add-interior``).
    name : str
        The transform's registry name.
    params : mapping
        The parameters used (``k``, ``perm``, ``axis``, ``m``...).
    orientation_preserved : bool
        Whether the coordinate map has positive determinant (counter-clockwise
        stays counter-clockwise).
    witness : ndarray of shape (k, d+1), int64, or None
        For ``add-interior``: for each added row (in order), input rows of a
        full-dimensional simplex that strictly contains it.
    """

    points: np.ndarray
    source_rows: np.ndarray
    name: str
    params: dict[str, Any] = field(default_factory=dict)
    orientation_preserved: bool = True
    witness: np.ndarray | None = None


def _as_points(points: Any, name: str) -> np.ndarray:
    arr = np.asarray(points, dtype=np.float64)
    if arr.ndim != 2 or arr.shape[1] not in (2, 3):
        raise GeneratorValueError(f"{name}: points must have shape (n, 2) or (n, 3), got {arr.shape}")
    return arr


def permute_rows(points: np.ndarray, rng: np.random.Generator) -> Transformed:
    """Shuffle the rows: the same point set, so the same hull up to the index map.

    Parameters
    ----------
    points : ndarray of shape (n, d), float64
    rng : numpy.random.Generator

    Returns
    -------
    Transformed
        ``points[i] == input[source_rows[i]]``.

    Examples
    --------
    >>> t = permute_rows(np.eye(3), np.random.default_rng(0))
    >>> bool(np.array_equal(t.points, np.eye(3)[t.source_rows]))
    True
    """
    p = _as_points(points, "permute_rows")
    perm = rng.permutation(len(p))
    return Transformed(np.ascontiguousarray(p[perm]), perm.astype(np.int64), "permute-rows", {"perm": perm.tolist()})


def reverse_rows(points: np.ndarray) -> Transformed:
    """Reverse the row order: the same point set, with every tie met in the opposite order.

    A random permutation almost never produces the reversed order, yet that
    is the one that flips which of two equal keys a stable sort puts first
    (lexicographic grids, duplicated rows, equal x columns).

    Examples
    --------
    >>> reverse_rows(np.array([[0.0, 1.0], [2.0, 3.0]])).points.tolist()
    [[2.0, 3.0], [0.0, 1.0]]
    """
    p = _as_points(points, "reverse_rows")
    rows = np.arange(len(p) - 1, -1, -1, dtype=np.int64)
    return Transformed(np.ascontiguousarray(p[rows]), rows, "reverse-rows", {})


def safe_pow2_range(points: np.ndarray) -> tuple[int, int]:
    """The range [kmin, kmax] of k for which ``points * 2**k`` is exact and finite.

    Scaling up is exact until overflow; scaling down is exact while every
    non-zero |coordinate| stays normal (>= 2**-1022), and never when some
    coordinate is already subnormal.
    """
    p = np.abs(np.asarray(points, dtype=np.float64))
    finite = p[np.isfinite(p)]
    nonzero = finite[finite > 0]
    if nonzero.size == 0:
        return -1074, 1074  # all zeros (or no finite values): anything is exact
    _, e_hi = math.frexp(float(nonzero.max()))  # max = m * 2**e_hi, 1/2 <= m < 1
    kmax = 1024 - e_hi
    lo = float(nonzero.min())
    if lo < np.finfo(np.float64).tiny:
        kmin = 0
    else:
        _, e_lo = math.frexp(lo)
        kmin = -1021 - e_lo
    return kmin, kmax


def scale_pow2(points: np.ndarray, k: int) -> Transformed:
    """Multiply by 2**k exactly: same combinatorial hull, volume times 2**(k d).

    Parameters
    ----------
    points : ndarray of shape (n, d), float64
    k : int
        The exponent; must keep every coordinate exact (see :func:`safe_pow2_range`).

    Returns
    -------
    Transformed

    Raises
    ------
    ValueError
        When the scaling would overflow or lose bits in the subnormal range.

    Examples
    --------
    >>> t = scale_pow2(np.array([[0.1, 0.2], [0.3, 1e-300]]), 3)
    >>> t.points.tolist()
    [[0.8, 1.6], [2.4, 8e-300]]
    """
    p = _as_points(points, "scale_pow2")
    if isinstance(k, bool) or not isinstance(k, (int, np.integer)):
        raise GeneratorValueError(f"scale_pow2: k must be an integer, got {k!r}")
    with np.errstate(over="ignore", under="ignore"):
        out = np.ldexp(p, int(k))
        back = np.ldexp(out, -int(k))
    if not np.array_equal(back, p, equal_nan=True) or np.any(np.isinf(out) & np.isfinite(p)):
        lo, hi = safe_pow2_range(p)
        raise GeneratorValueError(f"scale_pow2: k must keep the scaling exact (here {lo} <= k <= {hi}), got {k}")
    return Transformed(out, np.arange(len(p), dtype=np.int64), "scale-pow2", {"k": int(k)})


def permute_axes(points: np.ndarray, perm: tuple[int, ...] | list[int] | np.ndarray) -> Transformed:
    """Permute the coordinate axes: same vertex set, orientation flips for odd permutations.

    Parameters
    ----------
    points : ndarray of shape (n, d), float64
    perm : sequence of int
        A permutation of ``range(d)``; new axis j is old axis ``perm[j]``.

    Returns
    -------
    Transformed

    Examples
    --------
    >>> permute_axes(np.array([[1.0, 2.0, 3.0]]), (2, 0, 1)).points.tolist()
    [[3.0, 1.0, 2.0]]
    """
    p = _as_points(points, "permute_axes")
    d = p.shape[1]
    perm_l = [int(x) for x in perm]
    if sorted(perm_l) != list(range(d)):
        raise GeneratorValueError(f"permute_axes: perm must be a permutation of range({d}), got {perm_l}")
    inversions = sum(1 for i in range(d) for j in range(i + 1, d) if perm_l[i] > perm_l[j])
    return Transformed(
        np.ascontiguousarray(p[:, perm_l]),
        np.arange(len(p), dtype=np.int64),
        "permute-axes",
        {"perm": perm_l},
        orientation_preserved=inversions % 2 == 0,
    )


def reflect(points: np.ndarray, axis: int) -> Transformed:
    """Negate one coordinate axis (exact): same vertex set, every facet's orientation flips.

    Parameters
    ----------
    points : ndarray of shape (n, d), float64
    axis : int

    Returns
    -------
    Transformed

    Examples
    --------
    >>> reflect(np.array([[1.0, -2.0]]), 1).points.tolist()
    [[1.0, 2.0]]
    """
    p = _as_points(points, "reflect")
    if isinstance(axis, bool) or not isinstance(axis, (int, np.integer)) or not 0 <= axis < p.shape[1]:
        raise GeneratorValueError(f"reflect: axis must be an integer in [0, {p.shape[1] - 1}], got {axis!r}")
    out = p.copy()
    out[:, axis] = -out[:, axis]
    rows = np.arange(len(p), dtype=np.int64)
    return Transformed(out, rows, "reflect", {"axis": int(axis)}, orientation_preserved=False)


def duplicate_all(points: np.ndarray) -> Transformed:
    """Append an exact copy of every row: the same hull as a point set, each vertex twice.

    Parameters
    ----------
    points : ndarray of shape (n, d), float64

    Returns
    -------
    Transformed
        ``2n`` rows; ``source_rows`` is ``[0..n-1, 0..n-1]``.

    Examples
    --------
    >>> duplicate_all(np.array([[0.0, 1.0]])).points.tolist()
    [[0.0, 1.0], [0.0, 1.0]]
    """
    p = _as_points(points, "duplicate_all")
    idx = np.arange(len(p), dtype=np.int64)
    return Transformed(np.concatenate([p, p]), np.concatenate([idx, idx]), "duplicate-all", {})


def _normalised(p: np.ndarray) -> np.ndarray:
    """A power-of-two rescaled copy with max |coordinate| near 1, for float heuristics only."""
    finite = np.abs(p[np.isfinite(p)])
    peak = float(finite.max()) if finite.size else 0.0
    if peak == 0.0:
        return p.copy()
    _, e = math.frexp(peak)
    with np.errstate(under="ignore"):
        return np.ldexp(p, -e)


def _full_simplex(p: np.ndarray) -> np.ndarray:
    """Indices of d+1 rows spanning a full-dimensional simplex (exactly), greedy on volume."""
    n, d = p.shape
    q = _normalised(p)
    order = np.lexsort(q.T[::-1])
    chosen = [int(order[0])]
    with np.errstate(over="ignore", invalid="ignore", under="ignore"):
        for step in range(1, d + 1):
            base = q[chosen]
            if step == 1:
                diff = q - base[0]
                score = row_dot(diff * diff, np.ones(d))
            else:
                # squared distance of each candidate from the affine span of the
                # chosen points (Gram-Schmidt), i.e. the growth of the volume
                v = np.stack([base[i] - base[0] for i in range(1, step)], axis=0)
                w = q - base[0]
                basis: list[np.ndarray] = []
                for vec in v:
                    for b in basis:
                        vec = vec - row_dot(vec[None, :], b)[0] * b
                    basis.append(vec / row_norms(vec[None, :])[0])
                for b in basis:
                    w = w - row_dot(w, b)[:, None] * b[None, :]
                score = row_dot(w * w, np.ones(d))
            score = np.where(np.isfinite(score), score, -1.0)
            score[chosen] = -1.0
            ranked = np.argsort(-score, kind="stable")
            chosen.append(int(ranked[0]))
    if orient_exact(p[chosen]) != 0:
        return np.array(chosen, dtype=np.int64)
    # The float heuristic was fooled (nearly degenerate input): try the next
    # best last vertices exactly, a bounded number of times.
    for cand in ranked[1:64]:
        trial = chosen[:-1] + [int(cand)]
        if int(cand) not in chosen[:-1] and orient_exact(p[trial]) != 0:
            return np.array(trial, dtype=np.int64)
    raise GeneratorValueError(
        "add_interior: points must span a full-dimensional simplex (none found among the best candidates); "
        "the input looks affinely degenerate"
    )


def add_interior(points: np.ndarray, rng: np.random.Generator, m: int, *, max_rounds: int = 32) -> Transformed:
    """Append m points certified (exactly) to lie strictly inside the hull: the hull is unchanged.

    Parameters
    ----------
    points : ndarray of shape (n, d), float64
        Finite, not affinely degenerate.
    rng : numpy.random.Generator
    m : int
        Number of points to add (>= 1).
    max_rounds : int
        Rounds of redrawing candidates that rounding pushed out of their simplex.

    Returns
    -------
    Transformed
        Rows ``n..n+m-1`` are new (``source_rows == -1``); ``witness[i]`` lists
        the d+1 input rows of a simplex that strictly contains new point i.

    Raises
    ------
    ValueError
        When the input is degenerate, not finite, or too thin for rounded
        points to land strictly inside (e.g. a sliver thinner than an ulp).

    Notes
    -----
    A full-dimensional simplex S of input points is chosen greedily (largest
    volume, exact orientation check).  Candidates are convex combinations with
    positive random weights, rounded to doubles; rounding may push one out, so
    each is certified with exact orientation tests against all d+1 facets of S
    (strictly on the inner side of each) and redrawn if not.  Interior of S is
    inside the interior of the hull, so the hull's vertices and faces are
    unchanged and no new point lies on its boundary.

    Examples
    --------
    >>> tri = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]])
    >>> t = add_interior(tri, np.random.default_rng(0), 2)
    >>> t.points.shape, t.source_rows.tolist()
    ((5, 2), [0, 1, 2, -1, -1])
    """
    p = _as_points(points, "add_interior")
    n, d = p.shape
    if isinstance(m, bool) or not isinstance(m, (int, np.integer)) or m < 1:
        raise GeneratorValueError(f"add_interior: m must be an integer >= 1, got {m!r}")
    if not np.all(np.isfinite(p)):
        raise GeneratorValueError("add_interior: points must be finite, got NaN or infinity")
    if n < d + 1:
        raise GeneratorValueError(f"add_interior: points must have at least {d + 1} rows, got {n}")
    simplex = _full_simplex(p)
    verts = p[simplex]
    sign = orient_exact(verts)
    out = np.empty((m, d))
    todo = np.arange(m)
    for round_ in range(max_rounds):
        k = len(todo)
        # Later rounds pull the weights towards the centroid, the safest spot.
        w = rng.integers(1, 17, (k, d + 1)).astype(np.float64) + 16.0 * round_
        w /= row_dot(w, np.ones(d + 1))[:, None]
        with np.errstate(over="ignore", invalid="ignore"):
            cand = combine(w, verts)
        # facet i of S with vertex i replaced by the candidate must keep S's sign
        tests = np.repeat(verts[None, :, :], k * (d + 1), axis=0).reshape(k, d + 1, d + 1, d)
        for i in range(d + 1):
            tests[:, i, i, :] = cand
        signs = orient_sign(tests.reshape(k * (d + 1), d + 1, d)).reshape(k, d + 1)
        good = np.all(signs == sign, axis=1) & np.all(np.isfinite(cand), axis=1)
        out[todo[good]] = cand[good]
        todo = todo[~good]
        if len(todo) == 0:
            break
    else:
        raise GeneratorValueError(
            f"add_interior: points span a simplex too thin for {len(todo)} of {m} rounded points "
            "to land strictly inside"
        )
    witness = np.repeat(simplex[None, :], m, axis=0)
    return Transformed(
        np.concatenate([p, out]),
        np.concatenate([np.arange(n, dtype=np.int64), np.full(m, -1, dtype=np.int64)]),
        "add-interior",
        {"m": int(m)},
        witness=witness,
    )


# ---------------------------------------------------------------------------
# the registry: parameters drawn from the rng


def _t_permute_rows(points: np.ndarray, rng: np.random.Generator) -> Transformed:
    return permute_rows(points, rng)


def _t_reverse_rows(points: np.ndarray, rng: np.random.Generator) -> Transformed:
    return reverse_rows(points)


def _t_scale_pow2(points: np.ndarray, rng: np.random.Generator) -> Transformed:
    lo, hi = safe_pow2_range(_as_points(points, "scale-pow2"))
    choices = [k for k in range(-64, 65) if k != 0 and lo <= k <= hi]
    if not choices:
        raise GeneratorValueError(
            f"scale-pow2: no exact power-of-two scaling in [-64, 64] for these points (safe range {lo}..{hi})"
        )
    return scale_pow2(points, choices[int(rng.integers(0, len(choices)))])


def _t_permute_axes(points: np.ndarray, rng: np.random.Generator) -> Transformed:
    d = _as_points(points, "permute-axes").shape[1]
    perm = np.arange(d)
    while np.array_equal(perm, np.arange(d)):  # a real permutation; the rng stream decides
        perm = rng.permutation(d)
    return permute_axes(points, perm)


def _t_reflect(points: np.ndarray, rng: np.random.Generator) -> Transformed:
    d = _as_points(points, "reflect").shape[1]
    return reflect(points, int(rng.integers(0, d)))


def _t_duplicate_all(points: np.ndarray, rng: np.random.Generator) -> Transformed:
    return duplicate_all(points)


def _t_add_interior(points: np.ndarray, rng: np.random.Generator) -> Transformed:
    n = len(_as_points(points, "add-interior"))
    return add_interior(points, rng, max(1, n // 4))


#: name -> ``f(points, rng) -> Transformed`` with parameters drawn from ``rng``.
TRANSFORMS: dict[str, Callable[[np.ndarray, np.random.Generator], Transformed]] = {
    "permute-rows": _t_permute_rows,
    "reverse-rows": _t_reverse_rows,
    "scale-pow2": _t_scale_pow2,
    "permute-axes": _t_permute_axes,
    "reflect": _t_reflect,
    "duplicate-all": _t_duplicate_all,
    "add-interior": _t_add_interior,
}


def apply_transform(name: str, points: np.ndarray, rng: np.random.Generator) -> Transformed:
    """Apply the registered transform ``name`` with parameters drawn from ``rng``.

    Examples
    --------
    >>> t = apply_transform("duplicate-all", np.zeros((2, 3)), np.random.default_rng(0))
    >>> t.points.shape
    (4, 3)
    """
    try:
        func = TRANSFORMS[name]
    except (KeyError, TypeError):
        raise GeneratorValueError(
            f"transform must be one of {', '.join(sorted(TRANSFORMS))}, got {name!r}"
        ) from None
    return func(points, rng)
