"""The families that imitate real bug reports: each produces exactly what its docstring says.

The generic contract and determinism tests of tests/test_generators.py run
over the registry and pick these families up; that module also runs the
checks below (``REACH_CHECKS``) on every variant, at two sizes and two seeds,
and the bad calls below (``REACH_BAD_CALLS``).  This module adds the tests
that need more than one generated set: compose's pipeline step by step,
float32 overflow, the neutral composition.

Every claim is checked exactly where the family promises exactness
(float32 round trips, Fraction orientations and ranks, bitwise row equality).
"""

from __future__ import annotations

import math
from fractions import Fraction
from itertools import product

import numpy as np
import pytest

import generators as G
from _exact import affine_rank, frac_rows, nextafter_steps, orient_frac
from generators.compose import COMPOSITIONS
from generators.tiny import QUARTER_TURNS
from hullstress._registry import get_generator


def _p(params, **defaults):
    out = dict(defaults)
    out.update(params)
    return out


def f32_exact(pts: np.ndarray) -> bool:
    return bool(np.array_equal(pts, pts.astype(np.float32).astype(np.float64)))


# ---------------------------------------------------------------------------
# checks: check(points, dim, params, n)


def check_few_points(pts, dim, params, n):
    p = _p(params, count="d+1", repeat=False, shape="generic", scale=1.0)
    k = {"d": dim, "d+1": dim + 1, "d+2": dim + 2}[p["count"]]
    distinct = k - (1 if p["repeat"] else 0)
    assert pts.shape == (k, dim)
    assert len(np.unique(pts, axis=0)) == distinct
    rank = affine_rank(pts)
    if p["shape"] in ("generic", "lattice"):
        assert rank == min(distinct - 1, dim)
    elif p["shape"] == "flat":
        assert rank == min(distinct - 1, dim - 1)
    else:  # near-flat: full rank, and one nextafter step of one coordinate makes it flat
        assert rank == dim
        flat_again = False
        for i, axis in product(range(k), range(dim)):
            for toward in (-math.inf, math.inf):
                trial = pts.copy()
                trial[i, axis] = math.nextafter(trial[i, axis], toward)
                flat_again = flat_again or affine_rank(trial) == dim - 1
        assert flat_again
    if p["shape"] in ("lattice", "flat"):
        units = pts / p["scale"]
        assert np.array_equal(units, np.round(units))
        if p["shape"] == "lattice":
            assert np.abs(units).max() <= 4


def check_float32(pts, dim, params, n):
    p = _p(params, shape="ball", rotate=False, scale=1.0, offset=0.0)
    assert f32_exact(pts)
    off, s = p["offset"], p["scale"]
    centred = pts - off  # exact for offsets whose spacing covers the shape (Sterbenz) or zero
    slack = float(np.spacing(np.float32(max(off, s)))) * 2
    norms = np.sqrt(np.sum(centred**2, axis=1))
    if p["shape"] == "ball":
        assert np.all(norms <= s + slack)
    elif p["shape"] == "sphere":
        assert np.all(np.abs(norms - s) <= slack + 4 * s * 2.0**-23)
    elif not p["rotate"]:
        levels = [float(np.float32(off - s)), float(np.float32(off + s))]
        assert np.all(np.isin(pts, levels).any(axis=1))  # every row exactly on a face
        corners = pts[np.isin(pts, levels).all(axis=1)]
        assert len(np.unique(corners, axis=0)) == 2**dim
    else:
        assert affine_rank(pts) == dim
        assert np.all(norms <= s * math.sqrt(dim) + slack) and norms.max() >= s * 0.99


def check_aspect_ratio(pts, dim, params, n):
    p = _p(params, orientation="tall", heights="log", span=1e8, width=2.0)
    long_axes = [dim - 1] if p["orientation"] == "tall" else list(range(dim - 1))
    thin = [a for a in range(dim) if a not in long_axes]
    assert np.all((pts[:, thin] >= 0) & (pts[:, thin] <= p["width"]))
    assert np.all(np.abs(pts[:, long_axes]) <= p["span"])
    if p["heights"] == "log":
        assert np.all(np.abs(pts[:, long_axes]) >= 1.0)
        first = pts[:, long_axes[0]]
        assert p["span"] in first and 1.0 in first
    extent_long = np.ptp(pts[:, long_axes], axis=0).min()
    assert extent_long / np.ptp(pts[:, thin], axis=0).max() > 1e6


def _turns_ccw(ring: np.ndarray) -> bool:
    """Exactly: every consecutive pair turns counter-clockwise about the origin (origin strictly inside)."""
    fr = frac_rows(ring)
    return all(a[0] * b[1] - a[1] * b[0] > 0 for a, b in zip(fr, fr[1:] + fr[:1]))


def check_prism(pts, dim, params, n):
    p = _p(params, polygon="regular", layers=2, height=1.0, caps=False, rotate=False)
    layers, caps = p["layers"], p["caps"]
    k = (n - 2 * caps) // layers
    rings = [pts[j * k : (j + 1) * k] for j in range(layers)]
    if p["rotate"]:
        assert affine_rank(rings[0]) == 3  # rotation broke the cap's exact planarity
        assert affine_rank(pts) == 3
        return
    for ring in rings:
        assert len(set(ring[:, 2].tolist())) == 1  # each ring exactly in a plane z = const
        assert np.array_equal(ring[:, :2], rings[0][:, :2])  # the same polygon on every layer
    assert len({float(r[0, 2]) for r in rings}) == layers
    for i in range(k):  # side face i: its corners on all layers are exactly coplanar
        side = np.concatenate([r[[i, (i + 1) % k]] for r in rings])
        assert affine_rank(side) == 2
    assert _turns_ccw(rings[0][:, :2])  # so cap centres and axis points are strictly inside
    if p["polygon"] == "lattice":
        r2 = {int(x) ** 2 + int(y) ** 2 for x, y in rings[0][:, :2]}
        assert len(r2) == 1 and np.array_equal(rings[0], np.round(rings[0]))  # exactly cocircular integers
    elif p["polygon"] == "regular":
        assert np.all(np.abs(np.hypot(rings[0][:, 0], rings[0][:, 1]) - 1.0) <= 4 * 2.0**-52)
    z0, z1 = rings[0][0, 2], rings[-1][0, 2]
    rest = pts[layers * k :]
    if caps:
        assert rest[:2].tolist() == [[0.0, 0.0, z0], [0.0, 0.0, z1]]
        rest = rest[2:]
    assert np.all(rest[:, :2] == 0.0) and np.all((rest[:, 2] > z0) & (rest[:, 2] < z1))


def split_rings(pts: np.ndarray) -> tuple[list[np.ndarray], np.ndarray]:
    """Cut rows into closed rings (each ends with an exact copy of its first row) and the leftover."""
    rings, i = [], 0
    while i < len(pts):
        ends = [j for j in range(i + 3, len(pts)) if np.array_equal(pts[j], pts[i])]
        if not ends:
            break
        rings.append(pts[i : ends[0] + 1])
        i = ends[0] + 1
    return rings, pts[i:]


def check_closed_ring(pts, dim, params, n):
    p = _p(params, shape="convex", scale=1.0)
    rings, rest = split_rings(pts)
    per_storey = 2 if p["shape"] == "holes" else 1
    assert len(rings) == per_storey * (dim - 1)
    assert len(rest) == (n % 2 if dim == 3 else 0)
    if len(rest):
        assert np.array_equal(rest[0], pts[-2])  # odd n in 3D: the roof's closing row once more
    for ring in rings:
        assert np.array_equal(ring[0], ring[-1])  # closed: first row repeated last, bitwise
        assert len(np.unique(ring[:-1], axis=0)) == len(ring) - 1
    if dim == 3:
        floor, roof = rings[:per_storey], rings[per_storey:]
        for a, b in zip(floor, roof):
            assert np.all(a[:, 2] == 0.0) and np.all(b[:, 2] == p["scale"])
            assert np.array_equal(a[:, :2], b[:, :2])
    ring2d = [r[:, :2] for r in rings[:per_storey]]
    r = np.hypot(ring2d[0][:, 0], ring2d[0][:, 1])
    if p["shape"] in ("convex", "holes"):
        assert np.all(np.abs(r - p["scale"]) <= 4 * 2.0**-52 * p["scale"])
    elif p["shape"] == "star":
        assert np.all((r >= 0.5 * p["scale"] * (1 - 1e-15)) & (r <= p["scale"] * (1 + 1e-15)))
    elif p["shape"] == "rectangle":
        ring = ring2d[0][:-1]
        assert np.array_equal(ring, np.round(ring)) and ring[0].tolist() == [0.0, 0.0]
        fr = frac_rows(ring)
        turns = [orient_frac([fr[i - 1], fr[i], fr[(i + 1) % len(fr)]]) for i in range(len(fr))]
        assert sum(t != 0 for t in turns) == 4  # four corners; every other vertex exactly on an edge
    if p["shape"] == "holes":
        outer, inner = (frac_rows(r[:-1]) for r in ring2d)
        sides = [orient_frac([a, b, q]) for a, b in zip(outer, outer[1:] + outer[:1]) for q in inner]
        assert all(s > 0 for s in sides) or all(s < 0 for s in sides)  # the hole strictly inside


def check_tiny_residue(pts, dim, params, n):
    p = _p(params, base="box", source="noise", tiny=1e-17, scale=1.0)
    s = p["scale"]
    if p["source"] == "noise":
        small = np.abs(pts) <= p["tiny"]
        assert small.any() and np.all(pts[small] != 0) and np.all(np.abs(pts[small]) >= p["tiny"] / 2)
        exact = np.where(small, 0.0, pts)
        if p["base"] == "box":
            assert np.all(np.isin(exact, [0.0, s]).any(axis=1)) and np.all((exact >= 0) & (exact <= s))
            corners = exact[np.isin(exact, [0.0, s]).all(axis=1)]
            assert len(np.unique(corners, axis=0)) == 2**dim
        else:
            assert np.array_equal(exact / s, np.round(exact / s))
        return
    top = np.abs(pts).max()
    residue = (pts != 0) & (np.abs(pts) <= 1e-15 * top)
    assert residue.any()  # zeros became residues
    clean = np.where(residue, 0.0, pts)
    if p["base"] == "grid":
        assert np.all(np.abs(pts / s - np.round(pts / s)) <= 1e-15 * top / s)
    else:  # every row still on a face of the rotated box: a coordinate at 0 or ±scale (within ulps)
        on_face = (clean == 0) | (np.abs(np.abs(clean) - s) <= 4 * np.spacing(s))
        assert np.all(on_face.any(axis=1))


def check_compose(pts, dim, params, n):
    p = _p(params, base="uniform", scale=1.0, offset=0.0, jitter=0.0, ulps=0, repeat=0.0, float32=False)
    assert pts.shape == (n, dim) and np.all(np.isfinite(pts))
    if p["float32"]:
        assert f32_exact(pts)
    if p["repeat"]:
        assert n - len(np.unique(pts, axis=0)) >= max(1, int(n * p["repeat"]))
    if p["offset"]:
        assert np.all(np.abs(np.median(pts, axis=0) - p["offset"]) <= 1e-3 * p["offset"])
    if p["scale"] >= 1e100:
        assert 1e-2 * p["scale"] <= np.abs(pts).max() <= p["scale"]


REACH_CHECKS = {
    "few-points": check_few_points,
    "float32": check_float32,
    "aspect-ratio": check_aspect_ratio,
    "prism": check_prism,
    "closed-ring": check_closed_ring,
    "tiny-residue": check_tiny_residue,
    "compose": check_compose,
}

REACH_BAD_CALLS = [
    ("few-points", {"count": "d+3"}, "count"),
    ("few-points", {"count": "d", "shape": "near-flat"}, "near-flat"),
    ("float32", {"shape": "cone"}, "shape"),
    ("float32", {"offset": 1e39}, "overflow float32"),
    ("aspect-ratio", {"span": 0.5}, "span"),
    ("prism", {"layers": 1}, "layers"),
    ("closed-ring", {"shape": "triangle"}, "shape"),
    ("tiny-residue", {"tiny": 0.0}, "tiny"),
    ("compose", {"base": "kettner-classroom"}, "base"),
    ("compose", {"base": "uniform", "repeat": 1.0}, "repeat"),
    ("compose", {"base": "uniform(shape=cube)", "scale": 1e308, "offset": 1e308}, "overflow"),
]


def test_the_checks_can_fail():
    """A generic cloud fails the exact claims (the checks are not tautologies)."""
    cloud = G.generate("uniform", 12, dim=3, seed=0)
    for check, params in [
        (check_float32, {}),
        (check_prism, {}),
        (check_closed_ring, {}),
        (check_tiny_residue, {}),
        (check_aspect_ratio, {}),
    ]:
        with pytest.raises(AssertionError):
            check(cloud, 3, params, 12)
    with pytest.raises(AssertionError):
        check_few_points(cloud[:4], 3, {"repeat": True}, 4)
    with pytest.raises(AssertionError):
        check_few_points(G.generate("few-points", 0, dim=3, seed=0, count="d+2"), 3, {"count": "d+2", "shape": "flat"}, 5)


# ---------------------------------------------------------------------------
# compose: the documented pipeline, one step at a time


def _base(name, n, dim, seed, **params):
    return get_generator(name).func(np.random.default_rng(seed), n, dim=dim, **params)


@pytest.mark.parametrize("base", ["uniform", "cube-faces", "collinear-edges(shape=simplex)", "closed-ring(shape=star)"])
@pytest.mark.parametrize("dim", [2, 3])
def test_neutral_compose_is_the_base_family(base, dim):
    name, params = G.parse_spec(base)
    got = G.generate("compose", 20, dim=dim, seed=9, base=base)
    assert got.tobytes() == _base(name, 20, dim, 9, **params).tobytes()


@pytest.mark.parametrize("dim", [2, 3])
def test_compose_steps_do_what_the_docstring_says(dim):
    base = _base("cube-faces", 30, dim, 4)
    assert G.generate("compose", 30, dim=dim, seed=4, base="cube-faces", scale=1e6).tobytes() == (base * 1e6).tobytes()
    shifted = G.generate("compose", 30, dim=dim, seed=4, base="cube-faces", offset=1e8)
    assert shifted.tobytes() == (base + 1e8).tobytes()
    rounded = G.generate("compose", 30, dim=dim, seed=4, base="cube-faces", offset=1e6, float32=True)
    assert rounded.tobytes() == (base + 1e6).astype(np.float32).astype(np.float64).tobytes()
    # ulps: every coordinate within 3 nextafter steps of base + offset, and some moved
    noisy = G.generate("compose", 30, dim=dim, seed=4, base="cube-faces", offset=1e6, ulps=3)
    steps = [nextafter_steps(a, b, 3) for a, b in zip((base + 1e6).ravel(), noisy.ravel())]
    assert None not in steps and max(steps) > 0
    # jitter: bounded by jitter times the extent (2 for the cube)
    jit = G.generate("compose", 30, dim=dim, seed=4, base="cube-faces", jitter=1e-9)
    assert 0 < np.abs(jit - base).max() <= 2e-9 * (1 + 1e-12)
    # repeat: the first n - k rows are the base at n - k, the last k copies of them
    rep = G.generate("compose", 30, dim=dim, seed=4, base="cube-faces", repeat=0.2)
    assert rep[:24].tobytes() == _base("cube-faces", 24, dim, 4).tobytes()
    assert all(any(np.array_equal(r, q) for q in rep[:24]) for r in rep[24:])
    # permute is the last step: the same rows in another order
    perm = G.generate("compose", 30, dim=dim, seed=4, base="cube-faces", repeat=0.2, permute=True)
    assert sorted(map(tuple, perm.tolist())) == sorted(map(tuple, rep.tolist()))
    assert perm.tobytes() != rep.tobytes()


def test_compose_refuses_bases_that_cannot_compose():
    with pytest.raises(ValueError, match="base 'prism' supports dim"):
        G.generate("compose", 20, dim=2, seed=0, base="prism")
    with pytest.raises(ValueError, match="unknown parameter 'jitter'"):
        G.generate("compose", 20, dim=2, seed=0, base="near-coplanar(jitter=1)")
    with pytest.raises(ValueError, match="takes n"):
        G.generate("compose", 20, dim=2, seed=0, base="compose")
    assert G.generate("compose", 20, dim=3, seed=0, base="prism(polygon=lattice)").shape == (20, 3)


def test_compose_min_size_counts_the_base_and_the_repeats():
    assert G.min_size("compose", dim=3, base="prism") == 6
    assert G.min_size("compose", dim=3, base="prism", repeat=0.5) == 11  # 5 copies of 6 prism rows
    assert G.generate("compose", 11, dim=3, seed=0, base="prism", repeat=0.5).shape == (11, 3)
    with pytest.raises(ValueError, match=r"\bn\b"):
        G.generate("compose", 10, dim=3, seed=0, base="prism", repeat=0.5)


def test_curated_compositions_are_the_variants_and_cite_a_report():
    assert [dict(c.params) for c in COMPOSITIONS] == [dict(v) for v in get_generator("compose").variants]
    assert len({c.label for c in COMPOSITIONS}) == len(COMPOSITIONS)
    for c in COMPOSITIONS:
        assert "#" in c.why  # names the issue it imitates
        name, _ = G.parse_spec(c.params["base"])  # every base is a valid spec in both dims
        assert get_generator(name).dims == (2, 3)


# ---------------------------------------------------------------------------
# single-family details


def test_float32_round_trip_and_overflow():
    pts = G.generate("float32", 50, dim=3, seed=1, shape="ball", offset=8e5)
    assert f32_exact(pts)
    assert np.all(pts * 16 == np.round(pts * 16))  # float32 spacing at 8e5 is 1/16
    with pytest.raises(ValueError, match="overflow float32"):
        G.generate("float32", 5, dim=2, seed=1, scale=1e39)


def _pi(terms: int = 45) -> Fraction:
    """pi to about 60 digits by Machin's formula, in exact rationals."""

    def arctan_inv(x: int) -> Fraction:
        return sum(Fraction((-1) ** k, (2 * k + 1) * x ** (2 * k + 1)) for k in range(terms))

    return 16 * arctan_inv(5) - 4 * arctan_inv(239)


def test_tiny_residue_trig_constants_are_the_correctly_rounded_ones():
    """The literals are cos and sin of the doubles k * (pi/2), rounded to nearest: no libm involved."""
    pi = _pi()
    for k, (c, s) in enumerate(QUARTER_TURNS, start=1):
        delta = Fraction(k * (math.pi / 2)) - k * pi / 2  # |delta| < 1e-15: two series terms are plenty
        sin_d, cos_d = delta - delta**3 / 6, 1 - delta**2 / 2 + delta**4 / 24
        true_cos, true_sin = [(-sin_d, cos_d), (-cos_d, -sin_d), (sin_d, -cos_d)][k - 1]
        for literal, true in ((c, true_cos), (s, true_sin)):
            below, above = math.nextafter(literal, -math.inf), math.nextafter(literal, math.inf)
            err = abs(Fraction(literal) - true)
            assert err <= abs(Fraction(below) - true) and err <= abs(Fraction(above) - true)


def test_few_points_ignores_n_but_not_the_seed():
    a = G.generate("few-points", 0, dim=3, seed=1, count="d+2", repeat=True)
    b = G.generate("few-points", 500, dim=3, seed=1, count="d+2", repeat=True)
    c = G.generate("few-points", 0, dim=3, seed=2, count="d+2", repeat=True)
    assert a.tobytes() == b.tobytes() != c.tobytes()
