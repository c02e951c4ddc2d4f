"""Two hazards at once: any family, then placed, scaled, jittered, duplicated, rounded or shuffled.

Real inputs rarely have one problem.  A survey's coplanar patch sits a
million metres from the origin and carries measurement noise; a mesh with
duplicated seam vertices is in micrometres or in kilometres; a lattice was
jittered by a solver; a GIS ring was digitised in centimetres, stored in
metres at UTM offsets.  Each family of this package isolates one hazard;
:func:`compose` puts a placement and precision hazard on top of any of them
and :data:`COMPOSITIONS` lists the combinations the profiles sweep.

The steps run in a fixed order, the order data goes through in practice
(shape, units, placement, noise, seams, storage, reading order)::

    base family (n - k rows) -> * scale -> + offset -> + jitter -> ± ulps
        -> k repeated rows appended -> float32 rounding -> row permutation

A neutral step (scale 1, offset 0, jitter 0, ulps 0, repeat 0, False) draws
nothing from the generator, so ``compose`` with neutral steps gives exactly
the base family's bytes for the same seed.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from types import MappingProxyType
from typing import Any

import numpy as np

from hullstress.registry import register_generator
from hullstress._registry import get_generator

from ._common import (
    MIN_SIZE_RULES,
    GeneratorValueError,
    check_bool,
    check_dim,
    check_int,
    check_n,
    check_positive,
    declare_min_size,
    finish,
    random_ulp_offsets,
    round_to_float32,
    ulp_shift,
)
from .spec import parse_spec

__all__ = ["compose", "Composition", "COMPOSITIONS", "compose_min_size"]

#: Families compose refuses as a base (besides fixed-size ones): itself and the contract breaker.
_NOT_A_BASE = frozenset({"compose", "bad-input"})


@dataclass(frozen=True)
class Composition:
    """One curated combination of two hazards, with the real failure it imitates.

    Attributes
    ----------
    label : str
        A short name for reports and docs.
    params : mapping
        The ``compose`` parameters (a variant of the family).
    why : str
        What it stresses and the report it imitates.
    """

    label: str
    params: Mapping[str, Any]
    why: str


#: The combinations the profiles run (``compose``'s variants), each in 2D and 3D.
COMPOSITIONS: tuple[Composition, ...] = (
    Composition(
        "far-plane-ulps",
        MappingProxyType({"base": "coplanar-grid(plane=tilted)", "offset": 1e6, "ulps": 2}),
        "a tilted planar patch at UTM-like coordinates with two ulps of noise at that magnitude: "
        "near-coplanar far from the origin (georust/geo#1028, PointCloudLibrary/pcl#6161)",
    ),
    Composition(
        "far-cube-jitter",
        MappingProxyType({"base": "cube-faces", "offset": 1e6, "jitter": 1e-9}),
        "a box's faces jittered by 1e-9 of its size (17 ulps at 1e6): offset plus near-coplanar "
        "(qhull's rbox W1e-13 O1e6 made coarse; isl-org/Open3D#2022 unstable hulls of a plane cloud)",
    ),
    Composition(
        "huge-duplicates",
        MappingProxyType({"base": "duplicates(mode=every-point)", "scale": 1e200}),
        "every point twice at 1e200, where orientation products overflow: zero-length edges whose "
        "determinants are inf - inf (isl-org/Open3D#3587: Qhull errors on a cloud full of repeated rows)",
    ),
    Composition(
        "grid-jitter",
        MappingProxyType({"base": "lattice-block(order=random)", "jitter": 1e-12}),
        "an integer lattice jittered by 1e-12 of its extent: near-coplanar faces and near-collinear rows "
        "(ContinuumIO/anaconda-issues#10483: shapely's hull of a grid was not convex)",
    ),
    Composition(
        "float32-far-edges",
        MappingProxyType({"base": "collinear-edges(shape=simplex)", "offset": 1e5, "float32": True}),
        "collinear runs on a simplex's slanted edges, moved to 1e5 and stored as float32 (spacing "
        "2**-7): the runs stop being collinear (georust/geo#1028, dimforge/ncollide#352)",
    ),
    Composition(
        "parcel-utm",
        MappingProxyType({"base": "closed-ring(shape=rectangle)", "scale": 0.01, "offset": 5e5}),
        "a parcel digitised in centimetres, stored in metres at a UTM easting: the ring's exactly "
        "collinear edge vertices become near-collinear (shapely/shapely#541, DelaunayTriangulation.jl#109)",
    ),
    Composition(
        "sphere-seams",
        MappingProxyType({"base": "sphere(mode=lattice)", "repeat": 0.25, "permute": True}),
        "exactly cospherical points with a quarter duplicated (mesh seams) in random order "
        "(eoineoineoin/glTF_Physics_Blender_Exporter#7: hulls of meshes with split seam vertices)",
    ),
    Composition(
        "micro-uniform-repeat",
        MappingProxyType({"base": "uniform(shape=ball)", "scale": 1e-6, "repeat": 0.1, "float32": True}),
        "a micrometre-sized part in metres, float32, a tenth of the rows repeated: an absolute epsilon "
        "of 1e-9 swallows the shape (mikedh/trimesh#2301: 1e-6-scale cuboids collapsed to zero extent)",
    ),
)


def _base(base: Any, dim: int) -> tuple[str, dict[str, Any]]:
    """Parse and check the base spec for ``dim`` (without running it)."""
    if not isinstance(base, str):
        raise GeneratorValueError(f"compose: base must be a generator spec string, got {base!r}")
    name, params = parse_spec(base, validate=False)
    spec = get_generator(name)
    if name in _NOT_A_BASE or spec.fixed_size:
        raise GeneratorValueError(
            f"compose: base must be a family that takes n and keeps the output contract, got {name!r}"
        )
    if dim not in spec.dims:
        raise GeneratorValueError(f"compose: base {name!r} supports dim {spec.dims}, got dim={dim}")
    return name, params


def _repeats(n: int, repeat: float) -> int:
    return max(1, int(n * repeat)) if repeat > 0 else 0


def _check_repeat(value: Any) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not 0.0 <= float(value) < 1.0:
        raise GeneratorValueError(f"compose: repeat must be a float in [0, 1), got {value!r}")
    return float(value)


def compose_min_size(dim: int, *, base: str = "uniform", repeat: float = 0.0, **_: Any) -> int:
    """Smallest n for which ``n - repeated rows`` reaches the base family's own minimum."""
    name, params = _base(base, dim)
    repeat = _check_repeat(repeat)
    spec = get_generator(name)
    rule = MIN_SIZE_RULES.get(name)
    need = int(rule(dim, **{**spec.defaults, **params})) if rule is not None else 1
    # n - floor(n * repeat) < n * (1 - repeat) + 1, so no n <= (need - 1) / (1 - repeat) works:
    # start there and step (a handful of steps), instead of walking up from need
    n = max(need, int((need - 1) / (1.0 - repeat))) if repeat > 0 else need
    while n - _repeats(n, repeat) < need:
        n += 1
    return n


@register_generator("compose", dims=(2, 3), variants=tuple(c.params for c in COMPOSITIONS))
def compose(
    rng: np.random.Generator,
    n: int,
    *,
    dim: int,
    base: str = "uniform",
    scale: float = 1.0,
    offset: float = 0.0,
    jitter: float = 0.0,
    ulps: int = 0,
    repeat: float = 0.0,
    float32: bool = False,
    permute: bool = False,
) -> np.ndarray:
    """Any family with a placement hazard on top: offset, scale, jitter, ulps, repeats, float32, shuffle.

    Parameters
    ----------
    rng : numpy.random.Generator
    n : int
        Number of rows (at least the base's minimum plus the repeated rows).
    dim : {2, 3}
        Must be one of the base family's dims.
    base : str
        The base family as a spec: ``"cube-faces"`` or
        ``"near-coplanar(surface=plane,ulps=2)"`` (see :mod:`generators.spec`).
        Not ``compose``, ``bad-input`` or a fixed-size family.
    scale : float
        Multiplier (> 0).
    offset : float
        Added to every coordinate (>= 0).
    jitter : float
        Uniform noise in ``[-a, a]`` per coordinate with
        ``a = jitter * extent`` (>= 0), extent being the largest side of the
        scaled base's bounding box; added after the offset, so noise below
        the offset's spacing is rounded away, as it is in real data.
    ulps : int
        Move every coordinate by a random number of ulps in ``[-ulps, ulps]``
        at its final magnitude (0..1024): noise that survives any offset.
    repeat : float
        Share of rows that are exact copies of other rows, in [0, 1):
        ``k = max(1, floor(n * repeat))`` copies when > 0.
    float32 : bool
        Round every coordinate to float32 last (see :mod:`generators.float32`).
    permute : bool
        Shuffle the rows (the base's structured order, vertices first or
        lexicographic, is gone).

    Returns
    -------
    points : ndarray of shape (n, dim), float64

    Notes
    -----
    The result is still a deterministic generator function: the base draws
    from ``rng`` first, then each non-neutral step in the fixed order.  The
    parameters are plain scalars and one spec string, so the case's params
    JSON is stable.

    Examples
    --------
    >>> pts = compose(np.random.default_rng(0), 8, dim=2, base="cube-faces", offset=1e6, float32=True)
    >>> bool(np.array_equal(pts, pts.astype(np.float32))), bool(np.all(np.abs(pts - 1e6) <= 1.0))
    (True, True)
    >>> plain = get_generator("cube-faces").func(np.random.default_rng(0), 8, dim=2)
    >>> bool(np.array_equal(compose(np.random.default_rng(0), 8, dim=2, base="cube-faces"), plain))
    True
    """
    fam = "compose"
    dim = check_dim(fam, dim, (2, 3))
    name, base_params = _base(base, dim)
    scale = check_positive(fam, "scale", scale)
    off = check_positive(fam, "offset", offset, allow_zero=True)
    jitter = check_positive(fam, "jitter", jitter, allow_zero=True)
    ulps = check_int(fam, "ulps", ulps, 0, 1024)
    repeat = _check_repeat(repeat)
    float32 = check_bool(fam, "float32", float32)
    permute = check_bool(fam, "permute", permute)
    n = check_n(fam, n, compose_min_size(dim, base=base, repeat=repeat), f"base {name!r} plus the repeated rows")
    k = _repeats(n, repeat)
    pts = np.array(get_generator(name).func(rng, n - k, dim=dim, **base_params), dtype=np.float64)
    if pts.shape != (n - k, dim):
        raise GeneratorValueError(f"compose: base {name!r} returned shape {pts.shape}, expected {(n - k, dim)}")
    with np.errstate(over="ignore", invalid="ignore"):
        if scale != 1.0:
            pts = pts * scale
        extent = float(np.max(np.ptp(pts, axis=0))) if len(pts) else 0.0
        if off != 0.0:
            pts = pts + off
        if jitter > 0.0:
            amplitude = jitter * (extent if extent > 0 else scale)
            pts = pts + rng.uniform(-amplitude, amplitude, pts.shape)
    if not np.all(np.isfinite(pts)):
        raise GeneratorValueError(f"compose: scale {scale!r} and offset {off!r} overflow the base {name!r}")
    if ulps:
        pts = ulp_shift(pts, random_ulp_offsets(rng, pts.shape, ulps, nonzero_rows=False))
    if k:
        pts = np.concatenate([pts, pts[rng.integers(0, n - k, k)]])
    if float32:
        pts = round_to_float32(pts, fam)
    if permute:
        pts = pts[rng.permutation(n)]
    return finish(pts)


def _min_rule(dim: int, **params: Any) -> int:
    return compose_min_size(dim, base=params.get("base", "uniform"), repeat=params.get("repeat", 0.0))


declare_min_size("compose", _min_rule)
