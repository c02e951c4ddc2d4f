"""Hypothesis strategies over hullstress's degeneracy families, for your own property tests.

Every strategy draws integers (family index, variant index, seed, size, ulp
offsets, lattice coordinates) rather than floats, so Hypothesis shrinks a
failure to the first family, the first variant, seed 0 and the smallest size
that still fails.

Examples
--------
>>> from hypothesis import given
>>> from hullstress.strategies import point_sets
>>> @given(point_sets(dim=2, max_size=20))
... def test_my_hull_contains_everything(points):
...     ...  # call your hull code on points, check the result
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
from hypothesis import reject
from hypothesis import strategies as st
from hypothesis.errors import InvalidArgument

import generators as _gen
from generators._common import random_rotation, ulp_shift
from generators.transforms import TRANSFORMS, Transformed, apply_transform

from ._registry import get_generator
from .case import Case

__all__ = [
    "seeds",
    "family_cases",
    "point_sets",
    "points_in_general_position",
    "coplanar_points",
    "collinear_points",
    "ulp_perturbed",
    "transformed",
]

_SEED_MAX = 2**32 - 1

#: Primes for the modular moment curve; each supports that many distinct points.
_PRIMES = (101, 1009, 32749)


def seeds() -> st.SearchStrategy[int]:
    """Generator seeds: integers in [0, 2**32 - 1], shrinking towards 0."""
    return st.integers(0, _SEED_MAX)


def _check_sizes(min_size: int, max_size: int, floor: int = 0) -> None:
    for name, v in (("min_size", min_size), ("max_size", max_size)):
        if isinstance(v, bool) or not isinstance(v, int) or v < floor:
            raise InvalidArgument(f"{name} must be an integer >= {floor}, got {v!r}")
    if min_size > max_size:
        raise InvalidArgument(f"min_size must be <= max_size, got min_size={min_size}, max_size={max_size}")


def _check_dims(dim: int | None) -> tuple[int, ...]:
    if dim is None:
        return (2, 3)
    if dim not in (2, 3) or isinstance(dim, bool):
        raise InvalidArgument(f"dim must be 2, 3 or None, got {dim!r}")
    return (int(dim),)


def _eligible(
    dims: tuple[int, ...], families: Sequence[str] | None, min_size: int, max_size: int, include_bad_input: bool
) -> list[tuple[str, int, dict[str, Any], int]]:
    """(family, dim, variant, smallest n) for every variant that fits in max_size, in a fixed order."""
    names = list(families) if families is not None else _gen.family_names()
    out = []
    for name in names:
        spec = get_generator(name)
        if name == "bad-input" and not include_bad_input and families is None:
            continue
        for dim in dims:
            if dim not in spec.dims:
                continue
            for variant in spec.variants:
                params = dict(variant)
                if spec.fixed_size:
                    size = len(_gen.generate(name, 1, dim=dim, seed=0, **params))
                    if min_size <= size <= max_size:
                        out.append((name, dim, params, size))
                    continue
                lo = max(min_size, _gen.min_size(name, dim=dim, **params))
                if lo <= max_size:
                    out.append((name, dim, params, lo))
    if not out:
        raise InvalidArgument(
            f"no family variant fits dims={dims}, families={families!r}, max_size={max_size}"
        )
    return out


def family_cases(
    dim: int | None = None,
    families: Sequence[str] | None = None,
    *,
    min_size: int = 1,
    max_size: int = 50,
    include_bad_input: bool = False,
    transforms: bool | Sequence[str] = False,
) -> st.SearchStrategy[Case]:
    """Cases drawn from the registered families: family, variant, seed and size all shrink.

    Parameters
    ----------
    dim : {2, 3} or None
        None draws the dimension too.
    families : sequence of str, optional
        Restrict to these family names (default: every registered family
        except ``bad-input``).
    min_size, max_size : int
        Bounds on n (a family's own minimum wins over ``min_size``; variants
        that need more than ``max_size`` points are left out).  Fixed-size
        families (the Kettner cases) keep their own size and are left out
        when it is outside the bounds.
    include_bad_input : bool
        Include the ``bad-input`` family (NaN, empty, wrong shapes).
    transforms : bool or sequence of str
        True (or a list of names) also draws one metamorphic transform (or
        none) to apply; the case's params then record it under ``"transform"``.
        Draws where the transform refuses the set (``add-interior`` on a
        degenerate one) are rejected, not silently left untransformed.

    Returns
    -------
    SearchStrategy of hullstress.case.Case
        ``source == "hypothesis"``; ``case.points`` is read-only.

    Examples
    --------
    >>> from hypothesis import find
    >>> case = find(family_cases(dim=2, families=["duplicates"]), lambda c: True)
    >>> case.family, case.seed, case.size
    ('duplicates', 0, 1)
    """
    dims = _check_dims(dim)
    _check_sizes(min_size, max_size)
    pool = _eligible(dims, families, min_size, max_size, include_bad_input)
    if transforms is True:
        tnames: list[str | None] = [None, *TRANSFORMS]
    elif transforms:
        bad = [t for t in transforms if t not in TRANSFORMS]
        if bad:
            raise InvalidArgument(f"transforms must be names from {sorted(TRANSFORMS)}, got {bad}")
        tnames = [None, *transforms]
    else:
        tnames = [None]

    @st.composite
    def _cases(draw: st.DrawFn) -> Case:
        name, d, params, lo = draw(st.sampled_from(pool))
        seed = draw(seeds())
        spec = get_generator(name)
        n = lo if spec.fixed_size else draw(st.integers(lo, max(lo, max_size)))
        t = draw(st.sampled_from(tnames))
        try:
            pts = _gen.generate(name, n, dim=d, seed=seed, transform=t, **params)
        except ValueError:
            # Only a transform can refuse here (add-interior on a degenerate
            # set, scale-pow2 with no exact exponent): discard the draw.
            if t is None:
                raise
            reject()
        recorded = dict(params)
        if t is not None:
            recorded["transform"] = t
        return Case(points=pts, dim=d, family=name, params=recorded, seed=seed, size=n, source="hypothesis")

    return _cases()


def point_sets(
    dim: int = 3,
    families: Sequence[str] | None = None,
    min_size: int = 4,
    max_size: int = 50,
) -> st.SearchStrategy[np.ndarray]:
    """Writable (n, dim) float64 arrays from the degeneracy families (no bad input).

    Examples
    --------
    >>> from hypothesis import find
    >>> pts = find(point_sets(dim=2, families=["collinear-line"], min_size=3), lambda p: True)
    >>> pts.shape
    (3, 2)
    """
    return family_cases(dim, families, min_size=min_size, max_size=max_size).map(lambda c: np.array(c.points))


def _unimodular(draw: st.DrawFn, dim: int) -> np.ndarray:
    """An integer matrix with determinant +-1 (lower triangular, shrinks to the identity)."""
    m = np.eye(dim, dtype=np.int64)
    for i in range(dim):
        for j in range(i):
            m[i, j] = draw(st.integers(-3, 3))
    return m


def points_in_general_position(
    dim: int = 3, min_size: int | None = None, max_size: int = 20
) -> st.SearchStrategy[np.ndarray]:
    """Integer-valued float64 points with no dim + 1 of them on a common hyperplane, exactly.

    Built on the modular moment curve ``(t, t**2 mod p, t**3 mod p)`` for a
    prime p and distinct t: any dim + 1 of its points have a Vandermonde
    determinant that is non-zero mod p, hence non-zero.  A unimodular integer
    map and an integer offset then vary the shape without losing the
    property.  Shrinks towards t = 0, 1, 2, ... and the identity map.

    Examples
    --------
    >>> from hypothesis import find
    >>> find(points_in_general_position(dim=2, min_size=3), lambda p: True).tolist()
    [[0.0, 0.0], [1.0, 1.0], [2.0, 4.0]]
    """
    dims = _check_dims(dim)
    lo = dims[0] + 1 if min_size is None else min_size
    _check_sizes(lo, max_size, floor=1)
    if max_size > _PRIMES[-1]:
        raise InvalidArgument(f"max_size must be <= {_PRIMES[-1]}, got {max_size}")

    @st.composite
    def _points(draw: st.DrawFn) -> np.ndarray:
        d = dims[0]
        p = draw(st.sampled_from([q for q in _PRIMES if q >= max_size]))
        ts = draw(st.lists(st.integers(0, p - 1), min_size=lo, max_size=max_size, unique=True))
        t = np.array(ts, dtype=np.int64)
        curve = np.column_stack([t] + [(t**k) % p for k in range(2, d + 1)])
        shear = _unimodular(draw, d)
        offset = np.array([draw(st.integers(-1000, 1000)) for _ in range(d)], dtype=np.int64)
        return (curve @ shear.T + offset).astype(np.float64)

    return _points()


def coplanar_points(
    dim: int = 3, min_size: int = 4, max_size: int = 50, *, exact: bool = True
) -> st.SearchStrategy[np.ndarray]:
    """Points on one plane (3D) or line (2D): integer lattice combinations o + u a + v b.

    With ``exact=True`` coordinates are integers and the set is exactly
    coplanar (collinear in 2D); with ``exact=False`` a random rotation
    (drawn from an integer seed) makes it coplanar only up to rounding.

    Examples
    --------
    >>> from hypothesis import find
    >>> pts = find(coplanar_points(dim=3), lambda p: True)
    >>> pts.shape
    (4, 3)
    """
    dims = _check_dims(dim)
    _check_sizes(min_size, max_size, floor=1)
    d = dims[0]
    vec = st.lists(st.integers(-5, 5), min_size=3, max_size=3).map(lambda v: np.array(v, dtype=np.int64))

    @st.composite
    def _points(draw: st.DrawFn) -> np.ndarray:
        n = draw(st.integers(min_size, max_size))
        origin = np.array([draw(st.integers(-100, 100)) for _ in range(d)], dtype=np.int64)
        if d == 2:
            direction = draw(
                st.lists(st.integers(-5, 5), min_size=2, max_size=2).filter(any).map(lambda v: np.array(v))
            )
            t = np.array(draw(st.lists(st.integers(-50, 50), min_size=n, max_size=n)), dtype=np.int64)
            pts = origin + t[:, None] * direction
        else:
            a, b = draw(st.tuples(vec, vec).filter(lambda ab: bool(np.cross(ab[0], ab[1]).any())))
            uv = np.array(draw(st.lists(st.tuples(st.integers(-50, 50), st.integers(-50, 50)), min_size=n, max_size=n)))
            pts = origin + uv[:, :1] * a + uv[:, 1:] * b
        pts = pts.astype(np.float64)
        if not exact:
            rot = random_rotation(np.random.default_rng(draw(seeds())), d)
            pts = pts @ rot.T
        return pts

    return _points()


def collinear_points(dim: int = 2, min_size: int = 3, max_size: int = 50) -> st.SearchStrategy[np.ndarray]:
    """Exactly collinear integer-valued points ``o + t d`` in 2D or 3D.

    Examples
    --------
    >>> from hypothesis import find
    >>> find(collinear_points(dim=3), lambda p: True).shape
    (3, 3)
    """
    dims = _check_dims(dim)
    _check_sizes(min_size, max_size, floor=1)
    d = dims[0]

    @st.composite
    def _points(draw: st.DrawFn) -> np.ndarray:
        n = draw(st.integers(min_size, max_size))
        origin = np.array([draw(st.integers(-100, 100)) for _ in range(d)], dtype=np.int64)
        direction = np.array(draw(st.lists(st.integers(-5, 5), min_size=d, max_size=d).filter(any)))
        t = np.array(draw(st.lists(st.integers(-50, 50), min_size=n, max_size=n)), dtype=np.int64)
        return (origin + t[:, None] * direction).astype(np.float64)

    return _points()


def ulp_perturbed(points: st.SearchStrategy[np.ndarray], max_ulps: int = 4) -> st.SearchStrategy[np.ndarray]:
    """Move every coordinate of drawn point sets by an integer number of ulps in [-max_ulps, max_ulps].

    The offsets are drawn as integers, so a failure shrinks towards the
    unperturbed set (offset 0) and the smallest perturbation that matters.

    Examples
    --------
    >>> from hypothesis import find
    >>> base = collinear_points(dim=2)
    >>> pts = find(ulp_perturbed(base, 1), lambda p: True)
    >>> pts.dtype, pts.shape
    (dtype('float64'), (3, 2))
    """
    if isinstance(max_ulps, bool) or not isinstance(max_ulps, int) or max_ulps < 0:
        raise InvalidArgument(f"max_ulps must be an integer >= 0, got {max_ulps!r}")

    @st.composite
    def _perturbed(draw: st.DrawFn) -> np.ndarray:
        pts = np.asarray(draw(points), dtype=np.float64)
        flat = draw(st.lists(st.integers(-max_ulps, max_ulps), min_size=pts.size, max_size=pts.size))
        return ulp_shift(pts, np.array(flat, dtype=np.int64).reshape(pts.shape))

    return _perturbed()


def transformed(
    points: st.SearchStrategy[np.ndarray], names: Sequence[str] | None = None
) -> st.SearchStrategy[tuple[np.ndarray, Transformed]]:
    """Pairs (original, Transformed) for metamorphic tests: same hull, predictable index map.

    Transforms that cannot apply to a drawn set (``add-interior`` on a
    degenerate one, ``scale-pow2`` with no exact exponent) are rejected with
    ``assume``-style filtering.

    Examples
    --------
    >>> from hypothesis import find
    >>> orig, t = find(transformed(points_in_general_position(dim=2), ["reflect"]), lambda pair: True)
    >>> t.name, bool(np.array_equal(-t.points[:, t.params["axis"]], orig[:, t.params["axis"]]))
    ('reflect', True)
    """
    chosen = list(names) if names is not None else list(TRANSFORMS)
    bad = [t for t in chosen if t not in TRANSFORMS]
    if bad or not chosen:
        raise InvalidArgument(f"names must be a non-empty list from {sorted(TRANSFORMS)}, got {names!r}")

    @st.composite
    def _pairs(draw: st.DrawFn) -> tuple[np.ndarray, Transformed] | None:
        pts = np.asarray(draw(points), dtype=np.float64)
        name = draw(st.sampled_from(chosen))
        seed = draw(seeds())
        try:
            return pts, apply_transform(name, pts, np.random.default_rng(seed))
        except ValueError:
            return None

    return _pairs().filter(lambda pair: pair is not None)  # type: ignore[return-value]
