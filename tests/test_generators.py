"""Tests for the generator families: contract, determinism, and the promised degeneracies.

Every registered built-in family is covered by the generic tests through the
registry (a new family is picked up automatically); the degeneracy checks are
a table keyed by family name, and a test insists every family has an entry.
The checks are exact where the family promises exactness (Fraction
determinants, math.nextafter walks) and use stated tolerances otherwise.
"""

from __future__ import annotations

import doctest
import hashlib
import importlib
import json
import math
import os
import random
import re
import subprocess
import sys
from fractions import Fraction
from itertools import combinations

import numpy as np
import pytest
from scipy.spatial import ConvexHull

import generators as G
from generators import kettner as K
from generators._common import orient_exact, orient_sign, random_rotation, ulp_distance, ulp_shift
from _exact import affine_rank, frac_rows, nextafter_steps, orient_frac
from hullstress._registry import get_generator
from hullstress.errors import UnknownNameError, UsageError
from test_generators_reach import REACH_BAD_CALLS, REACH_CHECKS

EPS = 2.0**-52
FAMILIES = G.family_names(builtin_only=True)


def _cases() -> list[tuple[str, int, int, dict]]:
    out = []
    for name in FAMILIES:
        spec = get_generator(name)
        for dim in spec.dims:
            for i, v in enumerate(spec.variants):
                out.append((name, dim, i, dict(v)))
    return out


CASES = _cases()
CASE_IDS = [f"{name}-{dim}d-v{i}" for name, dim, i, _ in CASES]


def _n_for(name: str, dim: int, params: dict, n: int = 12) -> int:
    return max(n, G.min_size(name, dim=dim, **params))


# ---------------------------------------------------------------------------
# exact helpers (independent of generators._common)


def within_ulps(a: float, b: float, k: int) -> bool:
    """True when b is reached from a in at most k math.nextafter steps."""
    return nextafter_steps(a, b, k) is not None


def thickness(points: np.ndarray) -> float:
    """Smallest singular value of the centred points over the largest (0 for exactly flat)."""
    c = points - points.mean(axis=0)
    s = np.linalg.svd(c, compute_uv=False)
    return float(s[-1] / s[0]) if s[0] > 0 else 0.0


# ---------------------------------------------------------------------------
# generic tests over the registry


@pytest.mark.parametrize("name,dim,vi,params", CASES, ids=CASE_IDS)
def test_contract_shape_dtype(name, dim, vi, params):
    spec = get_generator(name)
    for n in sorted({G.min_size(name, dim=dim, **params), _n_for(name, dim, params, 7), _n_for(name, dim, params, 40)}):
        pts = G.generate(name, n, dim=dim, seed=3, **params)
        assert isinstance(pts, np.ndarray) and pts.dtype == np.float64
        if name == "bad-input":
            continue  # checked per kind in its degeneracy check
        assert pts.flags.c_contiguous
        assert pts.ndim == 2 and pts.shape[1] == dim
        if not spec.fixed_size:
            assert pts.shape[0] == n
        assert np.all(np.isfinite(pts)), "only bad-input may return non-finite values"


#: (family, variant) pairs whose output does not depend on the seed, by design.
SEED_FREE = {("bad-input", (("kind", "all-nan"),)), ("bad-input", (("kind", "empty"),))}
#: Families of published fixed cases (fixed-size families like few-points still draw from the seed).
SEED_FREE_FAMILIES = {"kettner-classroom"}


@pytest.mark.parametrize("name,dim,vi,params", CASES, ids=CASE_IDS)
def test_deterministic_bytes_and_seed_matters(name, dim, vi, params):
    spec = get_generator(name)
    n = _n_for(name, dim, params, 30)
    a = G.generate(name, n, dim=dim, seed=20240607, **params)
    b = G.generate(name, n, dim=dim, seed=20240607, **params)
    assert a.tobytes() == b.tobytes() and a.shape == b.shape
    # The raw function with a fresh generator gives the same bytes as generate().
    c = spec.func(np.random.default_rng(20240607), n, dim=dim, **params)
    assert c.tobytes() == a.tobytes()
    other = G.generate(name, n, dim=dim, seed=20240608, **params)
    if name in SEED_FREE_FAMILIES or (name, tuple(sorted(params.items()))) in SEED_FREE:
        assert other.tobytes() == a.tobytes()
    else:
        assert other.tobytes() != a.tobytes(), "a different seed should give a different case"


@pytest.mark.parametrize("name", FAMILIES)
def test_no_global_random_state(name):
    spec = get_generator(name)
    np_state = np.random.get_state()
    py_state = random.getstate()
    for dim in spec.dims:
        for v in spec.variants:
            G.generate(name, _n_for(name, dim, dict(v), 20), dim=dim, seed=1, **v)
    after = np.random.get_state()
    assert all(np.array_equal(x, y) if isinstance(x, np.ndarray) else x == y for x, y in zip(np_state, after))
    assert random.getstate() == py_state


def _digest_all() -> str:
    h = hashlib.sha256()
    for name, dim, _, params in CASES:
        pts = G.generate(name, _n_for(name, dim, params, 25), dim=dim, seed=77, **params)
        h.update(f"{name}{dim}{sorted(params.items())}{pts.shape}".encode())
        h.update(np.ascontiguousarray(pts).tobytes())
    return h.hexdigest()


def test_identical_bytes_in_a_fresh_process_with_another_hash_seed():
    code = "import sys; sys.path.insert(0, 'tests'); import test_generators as t; print(t._digest_all())"
    # Another hash seed (set and dict order) and single-threaded BLAS: the bytes must not move.
    env = dict(os.environ, PYTHONHASHSEED="12345", OPENBLAS_NUM_THREADS="1", OMP_NUM_THREADS="1", MKL_NUM_THREADS="1")
    out = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, env=env, check=True,
        cwd=os.path.dirname(os.path.dirname(os.path.abspath(__file__))),
    )
    assert out.stdout.strip() == _digest_all()


@pytest.mark.parametrize("name", FAMILIES)
def test_every_family_documents_what_it_stresses(name):
    spec = get_generator(name)
    doc = spec.func.__doc__ or ""
    assert spec.summary and len(spec.summary) > 20
    for section in ("Parameters", "Returns", "Notes", "Examples"):
        assert section in doc, f"{name}: docstring lacks {section}"
    mod_doc = sys.modules[spec.func.__module__].__doc__ or ""
    assert len(mod_doc) > 200, f"{spec.func.__module__}: module docstring should say what the family breaks and why"
    assert spec.variants, f"{name} has no variants for the sweep profiles"


@pytest.mark.parametrize("name", FAMILIES)
def test_too_small_n_and_bad_dim_raise(name):
    spec = get_generator(name)
    for dim in spec.dims:
        params = dict(spec.variants[0])
        lo = G.min_size(name, dim=dim, **params)
        if not spec.fixed_size:
            with pytest.raises(ValueError, match=r"\bn\b"):
                G.generate(name, lo - 1, dim=dim, seed=0, **params)
    bad_dim = 4
    with pytest.raises(ValueError, match="dim"):
        G.generate(name, 10, dim=bad_dim, seed=0)
    with pytest.raises(ValueError, match="dim"):
        spec.func(np.random.default_rng(0), 10, dim=bad_dim)


BAD_CALLS = [
    ("duplicates", {"mode": "nope"}, "mode"),
    ("duplicates", {"fraction": 1.5}, "fraction"),
    ("duplicates", {"mode": "ulp-near", "ulps": 0}, "ulps"),
    ("coplanar-grid", {"lattice": "hex"}, "lattice"),
    ("coplanar-grid", {"scale": -1.0}, "scale"),
    ("cube-faces", {"layout": "spiral"}, "layout"),
    ("lattice-block", {"a": 1.5}, "a"),
    ("grid-apex", {"height": -1.0}, "height"),
    ("collinear-line", {"scale": 0.0}, "scale"),
    ("collinear-edges", {"interior": 1.0}, "interior"),
    ("near-collinear", {"ulps": -1}, "ulps"),
    ("equal-x-columns", {"columns": 0}, "columns"),
    ("sliver-triangle", {"kind": "sliver"}, "kind"),
    ("sliver-tetrahedron", {"thinness": 2.0}, "thinness"),
    ("narrow-cone", {"gap": 0.0}, "gap"),
    ("narrow-lens", {"radius": 0.5}, "radius"),
    ("minkowski-cubes", {"rotation": "twist"}, "rotation"),
    ("near-coplanar", {"delta": float("nan")}, "delta"),
    ("pinched", {"copies": 0}, "copies"),
    ("uniform", {"shape": "torus"}, "shape"),
    ("sphere", {"mode": "rational"}, "mode"),
    ("paraboloid-lift", {"offset": 2**26}, "offset"),
    ("regular-polygon", {"center": float("inf")}, "center"),
    ("regular-polyhedron", {"solid": "prism"}, "solid"),
    ("spiral", {"order": "zigzag"}, "order"),
    ("simplex-points", {"width": 0.0}, "width"),
    ("kettner-classroom", {"case": "Z9"}, "case"),
    ("kettner-ulp-grid", {"grid": 3}, "grid"),
    ("scaled", {"scale": 0.0}, "scale"),
    ("offset", {"offset": -1.0}, "offset"),
    ("mixed-magnitude", {"span": 400}, "span"),
    ("subnormal", {"units": 2**52}, "units"),
    ("bad-input", {"kind": "sideways"}, "kind"),
    *REACH_BAD_CALLS,
]


@pytest.mark.parametrize("name,params,word", BAD_CALLS, ids=[f"{c[0]}-{c[2]}" for c in BAD_CALLS])
def test_bad_parameters_raise_one_line_errors(name, params, word):
    dim = get_generator(name).dims[-1]
    with pytest.raises(ValueError, match=word) as info:
        G.generate(name, 30, dim=dim, seed=0, **params)
    assert "\n" not in str(info.value)
    assert isinstance(info.value, UsageError)


def test_bad_calls_is_a_full_table():
    assert {c[0] for c in BAD_CALLS} == set(FAMILIES)


def test_generate_rejects_unknown_names_params_and_seeds():
    with pytest.raises(UnknownNameError, match="valid names"):
        G.generate("no-such-family", 5, dim=2, seed=0)
    with pytest.raises(ValueError, match="unknown parameters"):
        G.generate("duplicates", 5, dim=2, seed=0, colour="red")
    with pytest.raises(ValueError, match="seed"):
        G.generate("duplicates", 5, dim=2, seed=-1)
    with pytest.raises(ValueError, match="transform"):
        G.generate("duplicates", 5, dim=2, seed=0, transform="spin")


def test_catalogue_lists_dims_params_and_variants():
    rows = {r["name"]: r for r in G.catalogue()}
    assert set(FAMILIES) <= set(rows)
    assert rows["duplicates"]["dims"] == (2, 3)
    assert list(rows["duplicates"]["params"]) == ["mode", "fraction", "copies", "ulps", "scale"]
    assert {"mode": "all-identical"} in rows["duplicates"]["variants"]
    assert rows["sliver-tetrahedron"]["min_size"] == {3: 4}
    assert rows["kettner-classroom"]["fixed_size"] is True
    assert len(rows["kettner-classroom"]["variants"]) == 6
    assert G.catalogue(dim=2) and all(2 in r["dims"] for r in G.catalogue(dim=2))


@pytest.mark.slow
@pytest.mark.parametrize("name,dim,vi,params", CASES, ids=CASE_IDS)
def test_fast_at_100000_points(name, dim, vi, params):
    import time

    G.generate(name, 100000, dim=dim, seed=5, **params)  # warm caches (lattice spheres)
    t = time.perf_counter()
    pts = G.generate(name, 100000, dim=dim, seed=6, **params)
    assert time.perf_counter() - t < 2.0
    if not get_generator(name).fixed_size and name != "bad-input":
        assert pts.shape == (100000, dim)


# ---------------------------------------------------------------------------
# family-specific degeneracy checks: check(points, dim, params, n)


def _modes(params, **defaults):
    out = dict(defaults)
    out.update(params)
    return out


def check_duplicates(pts, dim, params, n):
    p = _modes(params, mode="some", fraction=0.5, copies=2, ulps=1)
    uniq, counts = np.unique(pts, axis=0, return_counts=True)
    mode = p["mode"]
    if mode == "some":
        assert len(uniq) == n - max(1, int(n * p["fraction"]))
    elif mode == "every-point":
        assert len(uniq) == -(-n // p["copies"])
        assert np.count_nonzero(counts != p["copies"]) <= 1
    elif mode == "one-point":
        top = uniq[np.argmax(counts)]
        assert counts.max() == n // 2 + 1
        assert top[0] == pts[:, 0].max()  # a true extreme point
    elif mode == "all-identical":
        assert len(uniq) == 1
    else:
        k = p["ulps"]
        twins = 0
        for i in range(n):
            for j in range(n):
                if i != j and not np.array_equal(pts[i], pts[j]) and all(
                    within_ulps(a, b, k) for a, b in zip(pts[i], pts[j])
                ):
                    twins += 1
                    break
        assert twins >= n - (n + 1) // 2


def check_coplanar_grid(pts, dim, params, n):
    p = _modes(params, lattice="integer", plane="axis", rotate=False, scale=1.0)
    if dim == 2:
        if not p["rotate"] and p["lattice"] != "random":
            assert len(np.unique(pts[:, 0])) < n  # lattice columns: exact collinear runs
            assert affine_rank(pts[pts[:, 0] == pts[0, 0]]) <= 1
        if p["rotate"]:
            assert len(np.unique(pts[:, 0])) == n  # no exactly aligned columns survive
        return
    exact = not p["rotate"] and (p["plane"] == "axis" or p["lattice"] == "integer")
    if exact:
        assert affine_rank(pts) == 2
    else:
        assert thickness(pts) < 1e-13
        if p["rotate"]:
            assert affine_rank(pts) == 3  # rotation made coplanarity inexact


def check_cube_faces(pts, dim, params, n):
    p = _modes(params, layout="random", rotate=False)
    if p["rotate"]:
        # Points of a cube's surface are between half-side and half-side * sqrt(dim)
        # from its centre; the grid layout includes the corners (n >= 2**dim here).
        norms = np.linalg.norm(pts, axis=1)
        half = 1.0 if p["layout"] == "random" else norms.max() / math.sqrt(dim)
        assert np.all(norms >= half * (1 - 1e-12)) and np.all(norms <= half * math.sqrt(dim) * (1 + 1e-12))
        assert affine_rank(pts) == dim
        return
    h = np.abs(pts).max()
    on_face = np.any(np.abs(pts) == h, axis=1)
    assert np.all(on_face)
    for axis in range(dim):
        face = pts[pts[:, axis] == h]
        if len(face) >= dim + 1:
            assert affine_rank(face) == dim - 1
    if p["layout"] == "grid" and n >= 2**dim:
        corners = pts[np.all(np.abs(pts) == h, axis=1)]
        assert len(np.unique(corners, axis=0)) == 2**dim


def check_lattice_block(pts, dim, params, n):
    p = _modes(params, a=3, b=4, c=5, order="rbox", rotate=False)
    if p["rotate"]:
        assert affine_rank(pts) == min(dim, n - 1)
        return
    assert np.array_equal(pts, np.round(pts))
    s = 1
    while s**dim < n:
        s += 1
    if p["order"] == "rbox":
        assert affine_rank(pts[: min(n, s)]) <= 1  # the first points are collinear (flat initial simplex)
    if dim == 3 and p["c"] == 0:
        assert len(np.unique(pts[:, 2])) == 1
        if n > s * s:
            assert len(np.unique(pts, axis=0)) < n


def check_grid_apex(pts, dim, params, n):
    p = _modes(params, rotate=False, height=1.0)
    if p["rotate"]:
        assert affine_rank(pts) == dim
        return
    off = pts[:, -1] != 0.0
    assert np.count_nonzero(off) == 1
    base = pts[~off]
    assert affine_rank(base) == dim - 1
    assert affine_rank(pts) == dim


def check_collinear_line(pts, dim, params, n):
    p = _modes(params, exact=True, distinct=True)
    if p["exact"]:
        assert affine_rank(pts) == 1
        if not p["distinct"]:
            assert len(np.unique(pts, axis=0)) < n
        else:
            assert len(np.unique(pts, axis=0)) == n
    else:
        assert thickness(pts) < 1e-14


def check_collinear_edges(pts, dim, params, n):
    p = _modes(params, shape="box", interior=0.0, rotate=False)
    n_in = int(n * p["interior"])
    if p["rotate"]:
        assert affine_rank(pts) == dim
        return
    fr = frac_rows(pts)
    interior = 0
    for row in fr:
        if p["shape"] == "box":
            on = sum(1 for x in row if x in (0, 1))
            if on >= dim - 1:
                continue
            assert all(0 < x < 1 for x in row)
        else:
            zeros = sum(1 for x in row if x == 0)
            nonzero = [x for x in row if x != 0]
            if zeros >= dim - 1 or (zeros == dim - 2 and sum(nonzero) == 1):
                continue  # on an axis edge, or exactly on the edge between e_i and e_j
            assert all(x > 0 for x in row) and sum(row) < 1
        interior += 1
    assert interior == n_in


def check_near_collinear(pts, dim, params, n):
    p = _modes(params, ulps=1, direction="integer", apex=False)
    if p["direction"] == "integer":
        r = np.round(pts)
        ints = [[int(x) for x in row] for row in r]

        def on_line(a, b, c):
            u = [b[j] - a[j] for j in range(dim)]
            v = [c[j] - a[j] for j in range(dim)]
            return all(u[i] * v[j] == u[j] * v[i] for i, j in combinations(range(dim), 2))

        # Among the first dim + 2 rows at least two lie on the line: take the
        # pair whose line holds the most rows (exact integer arithmetic).
        best = max(
            ([on_line(ints[i], ints[j], c) for c in ints] for i, j in combinations(range(dim + 2), 2)
             if ints[i] != ints[j]),
            key=sum,
        )
        line = np.array(best)
        assert np.count_nonzero(~line) == (dim - 1 if p["apex"] else 0)
        assert affine_rank(r[line]) == 1  # the unperturbed points are exactly collinear
        for a, b in zip(pts[line].ravel(), r[line].ravel()):
            assert within_ulps(a, b, p["ulps"])
        if p["ulps"] and np.count_nonzero(line) >= 3:
            assert not np.array_equal(pts[line], r[line])
    else:
        line_pts = pts
        if p["apex"]:
            # the apexes are the rows farthest from the line through the rest
            far = np.argsort(-np.abs(pts - pts.mean(axis=0)).sum(axis=1))[: dim - 1]
            line_pts = np.delete(pts, far, axis=0)
            assert affine_rank(pts) == dim
        assert thickness(line_pts) < 1e-14 or len(line_pts) < 3


def check_equal_x_columns(pts, dim, params, n):
    p = _modes(params, columns=3, spacing="random")
    key = pts[:, : dim - 1]
    cols = np.unique(key, axis=0)
    assert len(cols) == p["columns"]
    for c in cols:
        assert affine_rank(pts[np.all(key == c, axis=1)]) <= 1
    if p["spacing"] == "integer":
        assert np.array_equal(pts[:, -1], np.round(pts[:, -1]))


def check_sliver(pts, dim, params, n):
    p = _modes(params, thinness=1e-12, rotate=True)
    verts = frac_rows(pts[: dim + 1])
    det = abs(orient_frac(verts))
    diam = max(max(abs(float(a - b)) for a, b in zip(u, v)) for u, v in combinations(verts, 2))
    assert float(det) / diam**dim <= 10 * p["thinness"]
    if not p["rotate"]:
        assert det > 0


def check_narrow_cone(pts, dim, params, n):
    p = _modes(params, radius=1.0, gap=1e-13)
    apex = np.zeros(dim)
    apex[-1] = -1.0
    assert np.array_equal(pts[0], apex)
    base = pts[1:]
    if len(base):
        assert np.all(np.abs(np.linalg.norm(base, axis=1) - 1.0) <= 4 * EPS)
        r = p["radius"]
        assert np.ptp(base[:, -1]) <= r * r / (1 + (r * (1 - p["gap"])) ** 2) ** 1.5 * p["gap"] * 1.01 + 4 * EPS


def check_narrow_lens(pts, dim, params, n):
    p = _modes(params, radius=1e5, gap=1.0)
    R = p["radius"]
    lb = R * math.cos(math.asin(1.0 / R))
    assert np.all(np.abs(pts[:, -1]) <= (R - lb) + 8 * np.spacing(lb))
    centre = np.zeros(dim)
    for row in pts:
        centre[-1] = -lb if row[-1] >= 0 else lb
        assert abs(np.linalg.norm(row - centre) - R) <= 1e-9 * R


def check_minkowski(pts, dim, params, n):
    p = _modes(params, rotation="random")
    if p["rotation"] == "none":
        assert set(np.unique(pts[:64]).tolist()) <= {-2.0, 0.0, 2.0} or n > 4**dim
    if p["rotation"] == "pythagorean":
        assert np.array_equal(pts, np.round(pts)) or n > 4**dim
    if p["rotation"] == "axis" and dim == 3 and n == 64:
        assert np.count_nonzero(pts[:, 2] == 2.0) == 16
        assert np.count_nonzero(pts[:, 2] == -2.0) == 16
    half = 5.0 if p["rotation"] == "pythagorean" else 1.0
    assert np.all(np.linalg.norm(pts, axis=1) <= 2 * half * math.sqrt(dim) * (1 + 1e-12))


def check_near_coplanar(pts, dim, params, n):
    p = _modes(params, surface="cube", delta=1e-13, ulps=0, rotate=False)
    if p["rotate"]:
        assert thickness(pts) < 1e-12
        return
    k, delta = p["ulps"], p["delta"]
    if p["surface"] == "cube":
        for row in pts:
            if k:
                assert any(within_ulps(x, math.copysign(1.0, x), k) for x in row)
            else:
                assert np.min(np.abs(np.abs(row) - 1.0)) <= delta + EPS
    elif p["surface"] == "plane":
        for x in pts[:, -1]:
            assert within_ulps(x, 1.0, k) if k else abs(x - 1.0) <= delta
    else:
        assert np.all(np.abs(np.linalg.norm(pts, axis=1) - 1.0) <= delta + 4 * EPS)


def check_pinched(pts, dim, params, n):
    p = _modes(params, copies=1, radius=2e-13)
    g = p["copies"] + 1
    for start in range(0, n, g):
        group = pts[start : start + g]
        dev = np.abs(group - group[0])
        assert np.all(dev <= p["radius"] + np.spacing(np.abs(group[0]) + p["radius"]))
        if p["radius"] == 0.0:
            assert np.all(dev == 0)


def check_uniform(pts, dim, params, n):
    p = _modes(params, shape="cube", add="none")
    if p["shape"] == "cube":
        assert np.all(np.abs(pts) <= 1.0)
    if p["shape"] == "ball":
        assert np.all(np.linalg.norm(pts, axis=1) <= 1.0 + 4 * EPS)
    if p["add"] == "cube":
        corners = pts[np.all(np.abs(pts) == 1.0, axis=1)]
        assert len(np.unique(corners, axis=0)) == 2**dim
        face = pts[pts[:, 0] == 1.0]
        assert affine_rank(face) == dim - 1  # the hull's faces are exactly coplanar corner sets
    if p["add"] == "diamond":
        for axis in range(dim):
            e = np.zeros(dim)
            e[axis] = 1.0
            assert any(np.array_equal(r, e) for r in pts) and any(np.array_equal(r, -e) for r in pts)


def check_sphere(pts, dim, params, n):
    p = _modes(params, mode="float")
    if p["mode"] == "float":
        assert np.all(np.abs(np.linalg.norm(pts, axis=1) - p.get("scale", 1.0)) <= 4 * EPS * p.get("scale", 1.0))
        return
    r2 = {sum(x * x for x in row) for row in frac_rows(pts)}
    assert len(r2) == 1  # exactly cospherical
    assert len(np.unique(pts, axis=0)) == n


def check_paraboloid(pts, dim, params, n):
    p = _modes(params, lattice="integer", offset=0)
    lifted = pts[:, -1]
    if p["lattice"] == "random":
        exact = np.sum(pts[:, :-1] ** 2, axis=1)
        assert np.all(np.abs(lifted - exact) <= 2 * EPS * exact)
        return
    ints = [[int(x) for x in row] for row in pts]
    assert all(row[-1] == sum(v * v for v in row[:-1]) for row in ints)
    assert all(float(v) == x for row, frow in zip(ints, pts) for v, x in zip(row, frow))
    if dim == 3:
        have = {tuple(r[:2]) for r in ints}
        squares = [(x, y) for x, y in have if {(x + 1, y), (x, y + 1), (x + 1, y + 1)} <= have]
        assert squares, "a grid cell is expected"
        x, y = squares[0]
        quad = [r for r in pts if (int(r[0]), int(r[1])) in {(x, y), (x + 1, y), (x, y + 1), (x + 1, y + 1)}]
        assert orient_frac(frac_rows(np.array(quad))) == 0  # co-circular -> coplanar on the lift
    else:
        assert all(orient_frac(frac_rows(np.array(t))) != 0 for t in combinations(pts[:6], 3))


def check_regular_polygon(pts, dim, params, n):
    p = _modes(params, radius=1.0, center=0.0)
    c, r = p["center"], p["radius"]
    d = np.linalg.norm(pts - c, axis=1)
    assert np.all(np.abs(d - r) <= 8 * EPS * (r + abs(c)))
    assert len(np.unique(pts, axis=0)) == n


def check_regular_polyhedron(pts, dim, params, n):
    p = _modes(params, solid="cube", extra="faces", rotate=False)
    size = {"tetrahedron": 4, "cube": 8, "octahedron": 6, "icosahedron": 12, "dodecahedron": 20}[p["solid"]]
    hull = ConvexHull(pts)
    assert len(hull.vertices) == size
    dist = pts @ hull.equations[:, :3].T + hull.equations[:, 3]
    if p["extra"] == "faces":
        assert np.all(dist.max(axis=1) >= -1e-12)  # every point on the boundary
    else:
        assert np.count_nonzero(dist.max(axis=1) < -0.1) == n - size
    if p["solid"] in ("tetrahedron", "cube", "octahedron") and not p["rotate"]:
        verts = pts[hull.vertices]
        assert np.array_equal(verts, np.round(verts))  # exact integer vertices


def check_spiral(pts, dim, params, n):
    assert np.all(np.abs(np.hypot(pts[:, 0], pts[:, 1]) - 1.0) <= 4 * EPS)
    expected = sorted(2.0 * i / (n - 1) - 1.0 for i in range(n))
    assert sorted(pts[:, 2].tolist()) == expected


def check_simplex_points(pts, dim, params, n):
    p = _modes(params, width=1.0, vertices=True)
    verts = np.concatenate([np.eye(dim), -np.ones((1, dim))])
    if p["vertices"]:
        assert np.array_equal(pts[: dim + 1], verts)
    rest = pts[dim + 1 :] if p["vertices"] else pts
    # barycentric coordinates w.r.t. e_1..e_d, (-1,..,-1)
    lam_last = -np.ones(len(rest))
    m = np.vstack([np.concatenate([np.eye(dim), -np.ones((dim, 1))], axis=1), np.ones((1, dim + 1))])
    lam = np.linalg.solve(m, np.vstack([rest.T, np.ones(len(rest))])).T
    del lam_last
    assert np.all(lam >= -1e-12)
    if p["width"] < 1e-6:
        assert np.all(lam.min(axis=1) <= 1e4 * p["width"])


def check_kettner_classroom(pts, dim, params, n):
    case = params.get("case", K.kettner_case_names()[0])
    literals = _literal_points()[case]
    assert pts.tolist() == [[float(x) for x in row] for row in literals]


def check_kettner_ulp_grid(pts, dim, params, n):
    g = K.kettner_data()["orientation_grids"]["grids"][params.get("grid", 0)]
    assert pts[0].tolist() == [float(x) for x in g["q"]] and pts[1].tolist() == [float(x) for x in g["r"]]
    pv = [Fraction(float(x)) for x in g["p"]]
    u = Fraction(1, 2**53)
    seen = set()
    for row in pts[2:]:
        steps = [(Fraction(float(x)) - b) / u for x, b in zip(row, pv)]
        assert all(s.denominator == 1 and 0 <= s < 2**16 for s in steps)
        seen.add(tuple(steps))
    assert len(seen) == n - 2
    # the grid really is made of consecutive doubles: one step is one nextafter
    assert math.nextafter(float(pv[0]), 1.0) - float(pv[0]) == float(u)


def check_scaled(pts, dim, params, n):
    p = _modes(params, base="ball", scale=1e300)
    assert np.all(np.abs(pts) <= p["scale"])
    assert np.abs(pts).max() > 0
    if p["base"] == "cube-faces":
        h = np.abs(pts).max()
        assert np.all(np.any(np.abs(pts) == h, axis=1))
    if p["base"] == "grid":
        s = 1
        while s**dim < n:
            s += 1
        assert all(len(np.unique(pts[:, j])) <= s for j in range(dim))


def check_offset(pts, dim, params, n):
    p = _modes(params, base="ball", offset=1e8)
    off = p["offset"]
    assert np.all(np.abs(pts - off) <= 1.0 + np.spacing(off))
    if off >= 2**49:  # spacing >= 1/8: the shape is quantised
        assert np.array_equal(pts * 8, np.round(pts * 8))


def check_mixed_magnitude(pts, dim, params, n):
    p = _modes(params, mode="radial", span=30)
    if p["mode"] == "radial":
        size = np.abs(pts).max(axis=1)  # not the 2-norm: squares of 1e300 overflow
        assert math.log10(size.max()) - math.log10(size.min()) >= 2 * p["span"] - 1
    else:
        half = 10.0 ** (p["span"] * np.arange(dim) / (dim - 1))
        assert np.all(np.abs(pts) <= half)
        assert np.abs(pts[:, -1]).max() > 10.0 ** (p["span"] - 3) or n < 10


def check_subnormal(pts, dim, params, n):
    p = _modes(params, mode="all", units=1000)
    tiny = np.finfo(np.float64).tiny
    sub = np.all(np.abs(pts) < tiny, axis=1)
    assert np.count_nonzero(sub) == (n if p["mode"] == "all" else n // 2)
    k = np.ldexp(pts[sub], 1074)
    assert np.array_equal(k, np.round(k)) and np.all(np.abs(k) <= p["units"])
    assert np.any(pts[sub] != 0)


def check_bad_input(pts, dim, params, n):
    kind = params.get("kind", "nan")
    expected = {
        "empty": (0, dim),
        "one-point": (1, dim),
        "two-points": (2, dim),
        "two-identical": (2, dim),
        "wrong-columns": (n, dim + 1),
        "one-dimensional": (n * dim,),
        "extra-axis": (n, dim, 1),
    }.get(kind, (n, dim))
    assert pts.shape == expected
    if kind == "nan":
        assert np.count_nonzero(np.isnan(pts)) == 1 and np.count_nonzero(np.isinf(pts)) == 0
    elif kind == "inf":
        assert np.count_nonzero(pts == np.inf) == 1 and not np.isnan(pts).any()
    elif kind == "neg-inf":
        assert np.count_nonzero(pts == -np.inf) == 1 and not np.isnan(pts).any()
    elif kind == "all-nan":
        assert np.all(np.isnan(pts))
    elif kind == "two-points":
        assert not np.array_equal(pts[0], pts[1])
    elif kind == "two-identical":
        assert np.array_equal(pts[0], pts[1])
    if kind not in ("nan", "inf", "neg-inf", "all-nan"):
        assert np.all(np.isfinite(pts))


DEGENERACY_CHECKS = {
    "duplicates": check_duplicates,
    "coplanar-grid": check_coplanar_grid,
    "cube-faces": check_cube_faces,
    "lattice-block": check_lattice_block,
    "grid-apex": check_grid_apex,
    "collinear-line": check_collinear_line,
    "collinear-edges": check_collinear_edges,
    "near-collinear": check_near_collinear,
    "equal-x-columns": check_equal_x_columns,
    "sliver-triangle": check_sliver,
    "sliver-tetrahedron": check_sliver,
    "narrow-cone": check_narrow_cone,
    "narrow-lens": check_narrow_lens,
    "minkowski-cubes": check_minkowski,
    "near-coplanar": check_near_coplanar,
    "pinched": check_pinched,
    "uniform": check_uniform,
    "sphere": check_sphere,
    "paraboloid-lift": check_paraboloid,
    "regular-polygon": check_regular_polygon,
    "regular-polyhedron": check_regular_polyhedron,
    "spiral": check_spiral,
    "simplex-points": check_simplex_points,
    "kettner-classroom": check_kettner_classroom,
    "kettner-ulp-grid": check_kettner_ulp_grid,
    "scaled": check_scaled,
    "offset": check_offset,
    "mixed-magnitude": check_mixed_magnitude,
    "subnormal": check_subnormal,
    "bad-input": check_bad_input,
    **REACH_CHECKS,
}


def test_every_family_has_a_degeneracy_check():
    assert set(FAMILIES) == set(DEGENERACY_CHECKS)


@pytest.mark.parametrize("name,dim,vi,params", CASES, ids=CASE_IDS)
@pytest.mark.parametrize("size", [12, 64])
def test_family_produces_its_degeneracy(name, dim, vi, params, size):
    n = _n_for(name, dim, params, size)
    for seed in (0, 1):
        pts = G.generate(name, n, dim=dim, seed=seed, **params)
        if get_generator(name).fixed_size:
            n = len(pts)
        DEGENERACY_CHECKS[name](pts, dim, params, n)


def test_degeneracy_checks_can_fail():
    """The checks are not tautologies: a generic cloud fails the exact ones."""
    cloud = G.generate("uniform", 12, dim=3, seed=0)
    with pytest.raises(AssertionError):
        check_coplanar_grid(cloud, 3, {}, 12)
    with pytest.raises(AssertionError):
        check_collinear_line(cloud, 3, {}, 12)
    with pytest.raises(AssertionError):
        check_duplicates(cloud, 3, {"mode": "all-identical"}, 12)
    with pytest.raises(AssertionError):
        check_sphere(cloud, 3, {"mode": "lattice"}, 12)
    with pytest.raises(AssertionError):
        check_near_coplanar(cloud, 3, {"surface": "plane"}, 12)


# ---------------------------------------------------------------------------
# the Kettner data: every literal parsed exactly as written


def _literal_text() -> str:
    from importlib import resources

    return resources.files("generators").joinpath("data", "kettner_classroom.json").read_text(encoding="utf-8")


def _literal_points() -> dict[str, list[list[str]]]:
    """Point literals per case, as strings cut from the raw JSON text (no float parsing)."""
    text = _literal_text()
    out = {}
    for m in re.finditer(r'"name":\s*"([^"]+)",\s*"points":\s*\[(.*?)\]\s*,\s*"effect"', text, re.S):
        pairs = re.findall(r"\[\s*([-0-9.eE+]+)\s*,\s*([-0-9.eE+]+)\s*\]", m.group(2))
        out[m.group(1)] = [list(p) for p in pairs]
    return out


def test_kettner_data_is_a_verbatim_copy_shipped_in_the_package():
    shared = os.path.join(os.path.dirname(__file__), "..", "..", "shared", "data", "kettner_classroom.json")
    if os.path.exists(shared):  # only in the development tree; never read at run time
        with open(shared, encoding="utf-8") as fh:
            assert fh.read() == _literal_text()
    assert len(_literal_points()) == 6


def test_kettner_literals_parse_exactly():
    data = K.kettner_data()
    lit = _literal_points()
    assert [c["name"] for c in data["cases"]] == list(lit)
    for case in data["cases"]:
        pts = G.generate("kettner-classroom", 0, dim=2, seed=0, case=case["name"])
        for row, lrow in zip(pts, lit[case["name"]]):
            for x, s in zip(row, lrow):
                assert x == float(s)
                # float() is correctly rounded: the literal is within half an ulp of x
                assert abs(Fraction(s) - Fraction(float(x))) <= Fraction(math.ulp(x)) / 2
    far = G.generate("kettner-classroom", 0, dim=2, seed=0, case="global_unbounded_area_error")[3, 0]
    assert far == float("1.267650600228229e30")
    assert far != 1.267650600228229 * 1e30


def test_kettner_grid_literal_rounds_to_nearest_double():
    grids = K.kettner_data()["orientation_grids"]["grids"]
    x = grids[1]["r"][1]
    s = "24.0000000000000517765"
    assert s in _literal_text()
    assert x == float(s)
    exact = Fraction(s)
    below, above = math.nextafter(x, 0.0), math.nextafter(x, 100.0)
    assert abs(Fraction(x) - exact) < abs(Fraction(below) - exact)
    assert abs(Fraction(x) - exact) <= abs(Fraction(above) - exact)


def test_kettner_parse_uses_float_on_the_original_text():
    raw = json.loads(_literal_text())  # the stdlib default is also float(literal)
    assert raw == K.kettner_data()


# ---------------------------------------------------------------------------
# shared helpers in generators._common


def test_ulp_shift_matches_nextafter():
    xs = np.array([0.0, -0.0, 5e-324, -5e-324, 1.0, -1.0, 0.1, 1e300, -2.2250738585072014e-308])
    for k in (-5, -1, 0, 1, 5):
        got = ulp_shift(xs, k)
        for x, g in zip(xs, got):
            y = float(x)
            for _ in range(abs(k)):
                y = math.nextafter(y, math.copysign(math.inf, k))
            assert g == y
            if k == 0:
                assert math.copysign(1.0, g) == math.copysign(1.0, x)
        assert np.all(ulp_distance(xs, got) == k) or k == 0 or np.any(xs == 0)
    with pytest.raises(ValueError):
        ulp_shift(np.array([np.finfo(np.float64).max]), 1)
    with pytest.raises(ValueError):
        ulp_shift(np.array([np.nan]), 1)


def test_orient_sign_agrees_with_fractions():
    rng = np.random.default_rng(0)
    for d in (2, 3):
        sets = [rng.uniform(-1, 1, (200, d + 1, d))]
        base = rng.uniform(-1, 1, (200, 1, d))
        line = rng.uniform(-1, 1, (200, 1, d))
        t = rng.integers(-3, 4, (200, d + 1, 1)).astype(float)
        sets.append(base + t * line)  # exactly degenerate (integer multiples)
        sets.append(np.round(rng.uniform(-4, 4, (200, d + 1, d))) * 2.0**-1070)  # subnormal: products underflow
        sets.append(rng.uniform(-1, 1, (50, d + 1, d)) * 1e300)  # overflow
        for s in sets:
            got = orient_sign(s)
            want = [int(np.sign(orient_frac(frac_rows(x)))) for x in s]
            assert got.tolist() == want
            assert all(orient_exact(x) == w for x, w in zip(s[:20], want[:20]))


def test_random_rotation_is_a_proper_rotation():
    for dim in (2, 3):
        for seed in range(20):
            r = random_rotation(np.random.default_rng(seed), dim)
            assert np.allclose(r @ r.T, np.eye(dim), atol=4 * EPS)
            assert abs(np.linalg.det(r) - 1.0) <= 8 * EPS


DOC_MODULES = [m.__name__ for m in G.FAMILY_MODULES] + [
    "generators._common", "generators.transforms", "generators.metamorphic", "generators.spec", "generators",
]


@pytest.mark.parametrize("module", DOC_MODULES)
def test_docstring_examples_run(module):
    mod = importlib.import_module(module)
    result = doctest.testmod(mod, extraglobs={"np": np, "math": math}, optionflags=doctest.ELLIPSIS, verbose=False)
    assert result.failed == 0 and result.attempted > 0
