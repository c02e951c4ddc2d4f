"""hullstress's attack surface: point-set families that break convex hull code.

Importing this package registers every family with
:func:`hullstress.register_generator`.  Each family is a function
``family(rng, n, *, dim, **params) -> ndarray of shape (n, dim), float64``
that draws only from the ``numpy.random.Generator`` it is given, so the same
(family, params, seed, n, dim) always gives the same bytes.

==========================  =====================================================
module                      families
==========================  =====================================================
:mod:`.duplicates`          duplicates
:mod:`.coplanar`            coplanar-grid, cube-faces, lattice-block, grid-apex
:mod:`.collinear`           collinear-line, collinear-edges, near-collinear,
                            equal-x-columns
:mod:`.slivers`             sliver-triangle, sliver-tetrahedron, narrow-cone,
                            narrow-lens
:mod:`.minkowski`           minkowski-cubes
:mod:`.jitter`              near-coplanar, pinched
:mod:`.classics`            uniform, sphere, paraboloid-lift
:mod:`.regular`             regular-polygon, regular-polyhedron, spiral,
                            simplex-points
:mod:`.kettner`             kettner-classroom, kettner-ulp-grid
:mod:`.scale`               scaled, offset, mixed-magnitude, subnormal
:mod:`.few_points`          few-points (d, d+1, d+2 points, a repeated row)
:mod:`.float32`             float32 (values exactly representable in float32)
:mod:`.aspect`              aspect-ratio (needles and slabs, scipy 14185)
:mod:`.prism`               prism (extruded polygons, cocircular rings)
:mod:`.rings`               closed-ring (GIS rings, first point repeated last)
:mod:`.tiny`                tiny-residue (6e-17 where a zero was meant)
:mod:`.compose`             compose (any family plus a placement hazard;
                            :data:`~.compose.COMPOSITIONS` the curated pairs)
:mod:`.bad_input`           bad-input (breaks the output contract on purpose)
:mod:`.transforms`          metamorphic transforms (:data:`TRANSFORMS`)
:mod:`.metamorphic`         seeded chains of transforms, comparing two answers
:mod:`.spec`                generator specs as text (``name:key=value,...``)
==========================  =====================================================

Public API: :func:`generate`, :func:`min_size`, :func:`catalogue`,
:func:`family_names`, :data:`TRANSFORMS`, :func:`apply_transform`,
:func:`apply_transforms`, :func:`vertex_set_change`, :class:`Transformed`,
:func:`parse_spec`, :func:`format_spec`.
"""

from __future__ import annotations

import inspect
from collections.abc import Sequence
from typing import Any

import numpy as np

from hullstress.registry import GeneratorSpec, get_generator, generators as _registered

from . import (
    aspect,
    bad_input,
    classics,
    collinear,
    compose,
    coplanar,
    duplicates,
    few_points,
    float32,
    jitter,
    kettner,
    minkowski,
    prism,
    regular,
    rings,
    scale,
    slivers,
    tiny,
)
from ._common import MIN_SIZE_RULES, GeneratorValueError
from .spec import format_spec, parse_spec
from .metamorphic import apply_transforms, vertex_set_change
from .transforms import TRANSFORMS, Transformed, apply_transform

__all__ = [
    "generate",
    "min_size",
    "catalogue",
    "family_names",
    "TRANSFORMS",
    "Transformed",
    "apply_transform",
    "apply_transforms",
    "vertex_set_change",
    "parse_spec",
    "format_spec",
    "GeneratorValueError",
    "FAMILY_MODULES",
]

#: The modules that define the built-in families (imported above: they register on import).
FAMILY_MODULES = (
    duplicates, coplanar, collinear, slivers, minkowski, jitter, classics, regular, kettner, scale, bad_input,
    few_points, float32, aspect, prism, rings, tiny, compose,
)

#: Families whose output may break the (n, dim) float64 contract on purpose.
CONTRACT_EXEMPT = frozenset({"bad-input"})


def family_names(dim: int | None = None, *, builtin_only: bool = False) -> list[str]:
    """Registered family names (sorted), optionally only those supporting ``dim``.

    ``builtin_only`` restricts to the families defined in this package (not plug-ins).
    """
    return [
        s.name
        for s in _registered(dim)
        if not builtin_only or getattr(s.func, "__module__", "").startswith(__name__ + ".")
    ]


def _merged_params(spec: GeneratorSpec, params: dict[str, Any]) -> dict[str, Any]:
    unknown = sorted(set(params) - set(spec.defaults))
    if unknown:
        raise GeneratorValueError(
            f"generator {spec.name!r}: unknown parameters {unknown}; known: {sorted(spec.defaults)}"
        )
    merged = dict(spec.defaults)
    merged.update(params)
    return merged


def min_size(name: str, *, dim: int, **params: Any) -> int:
    """The smallest ``n`` family ``name`` accepts for ``dim`` and ``params`` (1 if it declares none).

    Examples
    --------
    >>> min_size("sliver-tetrahedron", dim=3)
    4
    >>> min_size("regular-polyhedron", dim=3, solid="dodecahedron")
    20
    """
    spec = get_generator(name)
    merged = _merged_params(spec, params)
    rule = MIN_SIZE_RULES.get(name)
    return int(rule(dim, **merged)) if rule is not None else 1


def generate(
    name: str,
    n: int,
    *,
    dim: int,
    seed: int,
    transform: str | Sequence[str] | None = None,
    **params: Any,
) -> np.ndarray:
    """Generate the point set of family ``name`` for (n, dim, seed, params), optionally transformed.

    Parameters
    ----------
    name : str
        A registered family (``python -m hullstress list generators``).
    n : int
        Number of points (ignored by fixed-size families).
    dim : {2, 3}
        Must be one of the family's dims.
    seed : int
        Non-negative; the generator receives ``numpy.random.default_rng(seed)``.
    transform : str or sequence of str, optional
        Names from :data:`TRANSFORMS`, applied in order; transform i draws its
        parameters from ``default_rng([seed, crc32(name_i), i])``, so the result
        is deterministic too.
    **params
        Family parameters (unknown names raise).

    Returns
    -------
    points : ndarray of shape (n, dim), float64
        C-contiguous.  The ``bad-input`` family may return other shapes and
        non-finite values on purpose.

    Raises
    ------
    hullstress.errors.UnknownNameError
        Unknown family (the message lists the valid ones).
    GeneratorValueError
        A bad dim, seed, n or parameter (a ValueError and a UsageError).

    Examples
    --------
    >>> pts = generate("duplicates", 6, dim=2, seed=0, mode="all-identical")
    >>> pts.shape, len(np.unique(pts, axis=0))
    ((6, 2), 1)
    >>> generate("collinear-line", 5, dim=3, seed=1, transform="duplicate-all").shape
    (10, 3)
    """
    spec = get_generator(name)
    if isinstance(dim, bool) or dim not in spec.dims:
        raise GeneratorValueError(f"generator {name!r}: dim must be one of {spec.dims}, got {dim!r}")
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
        raise GeneratorValueError(f"seed must be a non-negative integer, got {seed!r}")
    _merged_params(spec, params)
    points = spec.func(np.random.default_rng(int(seed)), n, dim=dim, **params)
    if name not in CONTRACT_EXEMPT:
        _check_contract(name, points, None if spec.fixed_size else n, dim)
    if transform is None or (not isinstance(transform, str) and not list(transform)):
        return points
    return np.ascontiguousarray(apply_transforms(points, transform, seed=int(seed)).points)


def _check_contract(name: str, points: Any, n: int | None, dim: int) -> None:
    ok = (
        isinstance(points, np.ndarray)
        and points.dtype == np.float64
        and points.ndim == 2
        and points.shape[1] == dim
        and (n is None or points.shape[0] == n)
        and points.flags.c_contiguous
    )
    if not ok:
        got = f"{type(points).__name__} {getattr(points, 'dtype', '')} {getattr(points, 'shape', '')}"
        want = f"({n if n is not None else 'k'}, {dim}) float64 C-contiguous"
        raise AssertionError(f"generator {name!r} broke the output contract: expected {want}, got {got}")


def catalogue(dim: int | None = None) -> list[dict[str, Any]]:
    """One row per registered family, for ``python -m hullstress list generators``.

    Each row: ``name``, ``dims``, ``params`` (name -> default, in signature
    order), ``variants`` (list of dicts), ``fixed_size``, ``min_size`` (per dim,
    with default params), ``summary`` (what the family stresses), ``module``.
    """
    rows = []
    for spec in _registered(dim):
        sig = inspect.signature(spec.func)
        ordered = {k: spec.defaults[k] for k in sig.parameters if k in spec.defaults}
        rule = MIN_SIZE_RULES.get(spec.name)
        rows.append(
            {
                "name": spec.name,
                "dims": spec.dims,
                "params": ordered,
                "variants": [dict(v) for v in spec.variants],
                "fixed_size": spec.fixed_size,
                "min_size": {d: (int(rule(d, **dict(spec.defaults))) if rule else 1) for d in spec.dims},
                "summary": spec.summary,
                "module": getattr(spec.func, "__module__", ""),
            }
        )
    return rows
