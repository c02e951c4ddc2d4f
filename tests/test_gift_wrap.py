"""Tests for hullstress.algorithms.gift_wrap (seed 000, Paul Nathan's 3D gift wrapping).

Two registered algorithms: ``gift-wrap-3d`` adds every triangle a pop finds,
as the seed writes it (a closed hull of ``F`` triangles takes ``3F/2`` pops and
comes back with ``F/2`` repeats), and ``gift-wrap-3d-dedup`` does not add a
triangle already in the array (the named improvement).  Three kinds of test:

* exactness: the vectorised search picks the same candidates as the seed's
  plain double loops (a pure-Python transcription below, ``reference_gift_wrap``);
* hull properties on general-position input, checked with an exact
  orientation predicate and against scipy's Qhull, under the seed's own
  premise that a candidate triangle's three vertices pass its test (the
  "Additional notes"); where rounding breaks that premise the algorithm
  can lose faces, and a test pins that weak spot down;
* the seed's particular behaviour: the eps formula, step 1's flattened point,
  step 2's first edge, the duplicate-edge check in both directions, the
  repeated triangles, and degenerate inputs.

Whether rounding keeps the premise is a property of one input's last bits,
so no test asserts it of a fixed input: tests that need it pick the first
inputs (in a fixed order) on which it holds, and tests on float-noisy input
accept the documented outcome set.
"""

from __future__ import annotations

import contextlib
import doctest
import itertools
import math
import time
from collections import Counter

import numpy as np
import pytest
from hypothesis import assume, given, note
from hypothesis import strategies as st
from scipy.spatial import ConvexHull

from hullstress import _registry
from hullstress.algorithms import gift_wrap
from hullstress.algorithms.gift_wrap import (
    DEDUP,
    LITERAL,
    _first_passing,
    _gift_wrap_trace,
    _screened_out,
    _rotation_key,
    gift_wrap_3d,
    gift_wrap_3d_dedup,
)
from hullstress.errors import AlgorithmStepLimit
from hullstress.tolerance import tolerance

from _hull_oracle import orient_sign, random_cloud

VARIANTS = {"gift-wrap-3d": gift_wrap_3d, "gift-wrap-3d-dedup": gift_wrap_3d_dedup}
TET = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]])
CUBE = np.array(list(itertools.product((0.0, 1.0), repeat=3)))


# --------------------------------------------------------------------------- helpers


def canonical(tri) -> tuple[int, int, int]:
    """A triangle rotated to start at its smallest index (same orientation)."""
    t = list(tri)
    k = t.index(min(t))
    return tuple(t[k:] + t[:k])


def assert_closed_outward_hull(points: np.ndarray, tri: np.ndarray) -> None:
    """Closed, consistently oriented, nothing outside, same extreme vertices as Qhull."""
    directed = Counter((int(t[i]), int(t[(i + 1) % 3])) for t in tri for i in range(3))
    assert max(directed.values()) == 1, "a directed edge is used twice"
    missing = [e for e in directed if (e[1], e[0]) not in directed]
    assert not missing, f"edges without a twin (surface not closed): {missing[:5]}"
    assert (orient_sign(points, tri) >= 0).all(), "a point lies outside a face"
    expected = set(ConvexHull(points).vertices.tolist())
    assert set(np.unique(tri).tolist()) == expected


def assert_stack_counts(points: np.ndarray, eps: float, n_vertices: int) -> None:
    """The seed's stack: ``pops == 3F/2``, ``F/2`` re-found triangles, added again only by the literal run.

    ``F = 2V - 4`` (Euler, every face a triangle in general position) with
    ``V`` from Qhull, so the expected counts do not come from the code.
    """
    f = 2 * n_vertices - 4
    literal = _gift_wrap_trace(points, eps, LITERAL)
    dedup = _gift_wrap_trace(points, eps, DEDUP)
    for tr in (literal, dedup):
        assert tr.pops == len(tr.edges) == 3 * f // 2  # each undirected edge pushed and popped once
        assert tr.refound == f // 2
    assert len(dedup.triangles) == f
    assert len(literal.triangles) == 3 * f // 2  # one triangle per pop
    # The literal array is the dedup array plus repeats (other rotations) of its triangles.
    assert {canonical(t) for t in literal.triangles.tolist()} == {canonical(t) for t in dedup.triangles.tolist()}
    kept = [t for t in literal.triangles.tolist() if canonical(t) in {canonical(u) for u in dedup.triangles.tolist()}]
    assert len(kept) == len(literal.triangles)
    np.testing.assert_array_equal(literal.triangles, gift_wrap_3d(points, eps=eps))
    np.testing.assert_array_equal(dedup.triangles, gift_wrap_3d_dedup(points, eps=eps))


def first_inputs_with_premise(count: int, n: int, kind: str, policies=("scaled", "fixed"), start: int = 0):
    """The first ``count`` seeds (from ``start``) whose cloud keeps the premise under every policy."""
    found = []
    for seed in itertools.count(start):
        pts = random_cloud(seed, n, kind)
        if all(nathan_premise(pts, tolerance(pts, p)) for p in policies):
            found.append((seed, pts))
            if len(found) == count:
                return found
        assert seed < start + 50 * count, f"the premise failed on 50 {kind} clouds in a row"


def nathan_premise(points: np.ndarray, eps: float) -> bool:
    """Whether every self-test the seed says "will always pass" does pass in floats.

    Step 2: each flattened candidate's own distance from its edge; step 4:
    the vertices of every true hull triangle (Qhull's, oriented outward, in
    all three rotations) against the triangle's own plane.  Computed with the
    seed's formulas in the same float operations as the code.
    """
    with np.errstate(divide="ignore", invalid="ignore"):
        first = int(np.argmax(points[:, 0] * points[:, 0] + points[:, 1] * points[:, 1]))
        e = points[:, :2] - points[first, :2]
        length = np.sqrt(e[:, 0] * e[:, 0] + e[:, 1] * e[:, 1])
        own = (e[:, 1] / length) * e[:, 0] + (-(e[:, 0] / length)) * e[:, 1]
        own[first] = -np.inf
        if (own > eps).any():
            return False
        hull = ConvexHull(points)
        s = hull.simplices.copy()
        a, b, c = (points[s[:, k]] for k in range(3))
        flip = np.einsum("ij,ij->i", np.cross(b - a, c - b), hull.equations[:, :3]) < 0
        s[flip] = s[flip][:, ::-1]
        for r in range(3):
            t = np.roll(s, r, axis=1)
            va, vb, vc = (points[t[:, k]] for k in range(3))
            e01, e12 = vb - va, vc - vb
            cx = e01[:, 1] * e12[:, 2] - e01[:, 2] * e12[:, 1]
            cy = e01[:, 2] * e12[:, 0] - e01[:, 0] * e12[:, 2]
            cz = e01[:, 0] * e12[:, 1] - e01[:, 1] * e12[:, 0]
            norm = np.sqrt(cx * cx + cy * cy + cz * cz)
            nx, ny, nz = cx / norm, cy / norm, cz / norm
            for v in (vb, vc):
                qv = v - va
                if ((qv[:, 0] * nx + qv[:, 1] * ny + qv[:, 2] * nz) > eps).any():
                    return False
    return True


def _div(a: float, b: float) -> float:
    """IEEE division for the reference: only 0/0 can occur (a zero norm has zero parts)."""
    return math.nan if b == 0.0 else a / b


def reference_gift_wrap(points: np.ndarray, eps: float, *, dedup: bool = False) -> list[tuple[int, int, int]]:
    """Nathan's steps 1-4 as the seed writes them: plain double loops over Python floats.

    With ``dedup`` (the variant), a triangle already in the array in any
    rotation (same cyclic order) is not appended again.
    """
    P = [tuple(float(v) for v in row) for row in points]
    n = len(P)
    first, best = 0, -math.inf
    for i, (x, y, _) in enumerate(P):
        if x * x + y * y > best:
            first, best = i, x * x + y * y
    v0x, v0y = P[first][0], P[first][1]
    second = -1
    for c in range(n):
        if c == first:
            continue
        ex, ey = P[c][0] - v0x, P[c][1] - v0y
        length = math.sqrt(ex * ex + ey * ey)
        nx, ny = _div(ey, length), -_div(ex, length)
        if not any(nx * (x - v0x) + ny * (y - v0y) > eps for x, y, _ in P):
            second = c
            break
    if second < 0:
        raise RuntimeError("no first edge")
    stack, seen, triangles = [(first, second)], {frozenset((first, second))}, []
    while stack:
        a, b = stack.pop()
        V0, V1 = P[a], P[b]
        e01 = [V1[k] - V0[k] for k in range(3)]
        for c in range(n):
            if c in (a, b):
                continue
            e12 = [P[c][k] - V1[k] for k in range(3)]
            cx = e01[1] * e12[2] - e01[2] * e12[1]
            cy = e01[2] * e12[0] - e01[0] * e12[2]
            cz = e01[0] * e12[1] - e01[1] * e12[0]
            norm = math.sqrt(cx * cx + cy * cy + cz * cz)
            nx, ny, nz = _div(cx, norm), _div(cy, norm), _div(cz, norm)
            if any(nx * (p[0] - V0[0]) + ny * (p[1] - V0[1]) + nz * (p[2] - V0[2]) > eps for p in P):
                continue
            for u, v in ((c, b), (a, c)):
                if frozenset((u, v)) not in seen:
                    seen.add(frozenset((u, v)))
                    stack.append((u, v))
            if not dedup or (a, b, c) not in triangles and (b, c, a) not in triangles and (c, a, b) not in triangles:
                triangles.append((a, b, c))
            break
    return triangles


# --------------------------------------------------------------------------- registration and contract


@pytest.mark.parametrize("name", sorted(VARIANTS))
def test_registered_in_house_with_eps(name):
    spec = _registry.get_algorithm(name)
    assert spec.func is VARIANTS[name]
    assert spec.dim == 3 and spec.takes_eps and spec.origin == "in-house"


@pytest.mark.parametrize("name", sorted(VARIANTS))
def test_returns_int64_triangles_and_leaves_input_alone(name):
    pts = random_cloud(1, 50, "ball")
    pts.setflags(write=False)
    before = pts.copy()
    out = VARIANTS[name](pts)
    assert out.dtype == np.int64 and out.ndim == 2 and out.shape[1] == 3
    np.testing.assert_array_equal(pts, before)


@pytest.mark.parametrize(
    ("points", "eps", "message"),
    [
        (np.zeros((5, 2)), None, r"points must have shape \(n, 3\), got \(5, 2\)"),
        (np.zeros(9), None, r"points must have shape \(n, 3\), got \(9,\)"),
        (np.zeros((4, 3, 1)), None, r"points must have shape \(n, 3\), got \(4, 3, 1\)"),
        (TET[:2], None, "points must hold at least 3 points, got 2"),
        (np.vstack([TET, [[np.nan, 0, 0]]]), None, r"points must be finite, got \[nan, 0.0, 0.0\] at row 4"),
        (np.vstack([TET, [[0, np.inf, 0]]]), None, "points must be finite"),
        (TET, -1.0, "eps must be a finite number >= 0 or None, got -1.0"),
        (TET, float("nan"), "eps must be a finite number >= 0 or None"),
    ],
)
@pytest.mark.parametrize("name", sorted(VARIANTS))
def test_bad_calls_raise_value_error(name, points, eps, message):
    with pytest.raises(ValueError, match=f"^{name}: {message}"):
        VARIANTS[name](points, eps=eps)


# --------------------------------------------------------------------------- exactness of the vectorised search


@given(
    n=st.integers(3, 28),
    seed=st.integers(0, 2**32 - 1),
    kind=st.sampled_from(["ball", "cube", "gauss", "int-grid", "flat", "duplicates"]),
    policy=st.sampled_from(["scaled", "fixed"]),
    dedup=st.booleans(),
    whole=st.booleans(),
)
def test_same_triangles_as_the_seeds_double_loops(n, seed, kind, policy, dedup, whole):
    rng = np.random.default_rng(seed)
    if kind == "int-grid":  # coplanar and collinear runs, repeated points
        pts = rng.integers(0, 3, size=(n, 3)).astype(float)
    elif kind == "flat":
        pts = np.c_[rng.random((n, 2)), np.full(n, 0.5)] @ np.linalg.qr(rng.standard_normal((3, 3)))[0]
    elif kind == "duplicates":
        base = random_cloud(seed, max(n // 2, 1), "ball")
        pts = base[rng.integers(0, len(base), size=n)]
    else:
        pts = random_cloud(seed, n, kind)
    eps = tolerance(pts, policy)
    func = gift_wrap_3d_dedup if dedup else gift_wrap_3d
    try:
        expected = reference_gift_wrap(pts, eps, dedup=dedup)
    except RuntimeError:
        with pytest.raises(RuntimeError, match="step 2 found no first edge"), _candidate_scan(whole):
            func(pts, eps=eps)
        return
    with _candidate_scan(whole):
        assert [tuple(t) for t in func(pts, eps=eps).tolist()] == expected


@given(
    n=st.integers(2, 700),
    seed=st.integers(0, 2**32 - 1),
    nan_rows=st.integers(0, 5),
    eps=st.sampled_from([0.0, 0.05, 0.3]),
    whole=st.booleans(),
)
def test_first_passing_matches_a_sequential_scan(n, seed, nan_rows, eps, whole):
    # Random planes, not geometry: most candidates fail, which drives the
    # block scan and the violator filter through every branch.
    rng = np.random.default_rng(seed)
    q = rng.standard_normal((n, 3))
    nrm = rng.standard_normal((n, 3))
    nrm /= np.linalg.norm(nrm, axis=1)[:, None]
    nrm[rng.integers(0, n, size=nan_rows)] = np.nan
    cand = rng.random(n) < 0.9
    expected = -1
    for c in np.flatnonzero(cand):
        d = q[:, 0] * nrm[c, 0] + q[:, 1] * nrm[c, 1] + q[:, 2] * nrm[c, 2]
        if not (d > eps).any():
            expected = int(c)
            break
    with _candidate_scan(whole, at_any_size=True):
        assert _first_passing(q, nrm, cand, eps) == expected


@contextlib.contextmanager
def _candidate_scan(whole: bool, *, at_any_size: bool = False, screen: bool | None = None):
    """Force one of _first_passing's two paths: every candidate in one block, or the pivoting scan.

    ``screen`` True or False screens the one block at every size or never
    (None keeps the size rule).
    """
    saved = gift_wrap._WHOLE_BUDGET, gift_wrap._SCREEN_FROM
    gift_wrap._WHOLE_BUDGET = (10**12 if at_any_size else saved[0]) if whole else 0
    if screen is not None:
        gift_wrap._SCREEN_FROM = 0 if screen else 10**12
    try:
        yield
    finally:
        gift_wrap._WHOLE_BUDGET, gift_wrap._SCREEN_FROM = saved


def _seed_distances(q: np.ndarray, nrm: np.ndarray) -> np.ndarray:
    """Row c: the seed's distances of every point to candidate c, summed x + y + z as its loop does.

    Elementwise float operations, each correctly rounded: the same bits as the
    scalar loop.
    """
    return q[None, :, 0] * nrm[:, None, 0] + q[None, :, 1] * nrm[:, None, 1] + q[None, :, 2] * nrm[:, None, 2]


@pytest.mark.parametrize("scale", [1.0, 1e-170, 2.0**-1000, 2.0**-1030, 2.0**-1045, 1e150, 1e300])
@pytest.mark.parametrize("layout", ["random", "in-plane"])
def test_screen_keeps_every_candidate_that_passes_with_no_margin(scale, layout):
    # eps is a candidate's own largest seed distance: it passes with no margin at all.
    # The matrix product differs from the seed's sums in the last bits on about a
    # third of the entries.  "random": each candidate in turn, its largest distance
    # far from zero (an eps-relative bound covers it).  "in-plane": every point on
    # candidate 0's plane, its distances rounding noise around zero, so only a bound
    # relative to the products (and, at 2**-1030 and below, the underflow term)
    # keeps it: without them, about 4 in 10 seeds reject it.
    for seed in range(200):
        rng = np.random.default_rng(seed)
        nrm = rng.standard_normal((20, 3))
        nrm /= np.linalg.norm(nrm, axis=1)[:, None]
        if layout == "in-plane":
            t1 = np.cross(nrm[0], [1.0, 0.0, 0.0])
            t1 /= np.linalg.norm(t1)
            q = rng.standard_normal((30, 2)) @ np.stack([t1, np.cross(nrm[0], t1)]) * scale
        else:
            q = rng.standard_normal((30, 3)) * scale
        with np.errstate(all="ignore"):
            seed_d = _seed_distances(q, nrm)
            for c, eps in enumerate(seed_d.max(axis=1)[: 1 if layout == "in-plane" else None]):
                if np.isfinite(eps) and eps >= 0:
                    assert not _screened_out(q, nrm, eps)[c], f"seed {seed}: candidate {c} rejected at eps={eps!r}"


@given(
    n=st.integers(1, 60),
    m=st.integers(1, 40),
    seed=st.integers(0, 2**32 - 1),
    scale=st.sampled_from([1.0, 2.0**-520, 2.0**-1000, 1e-170, 1e150, 1e300]),
    special=st.sampled_from(["none", "nan", "inf", "zero-row"]),
    eps_kind=st.sampled_from(["edge", "zero", "edge-plus-ulp"]),
)
def test_screen_rejects_only_what_the_seeds_sums_reject(n, m, seed, scale, special, eps_kind):
    # eps is set to one candidate's largest seed distance, so that candidate passes
    # with no margin at all; the matrix product differs from the seed's sums in the
    # last bits on about a third of the entries, so a screen with too small a bound
    # rejects it.
    rng = np.random.default_rng(seed)
    q = rng.standard_normal((n, 3)) * scale
    nrm = rng.standard_normal((m, 3))
    with np.errstate(all="ignore"):
        nrm /= np.linalg.norm(nrm, axis=1)[:, None]
        if special == "nan":
            nrm[rng.integers(0, m)] = np.nan
        elif special == "inf":
            nrm[rng.integers(0, m), 0] = np.inf
        elif special == "zero-row":
            q[rng.integers(0, n)] = 0.0
        seed_d = _seed_distances(q, nrm)
    edge = seed_d[rng.integers(0, m)].max()
    eps = {"edge": edge, "zero": 0.0, "edge-plus-ulp": np.nextafter(edge, np.inf)}[eps_kind]
    assume(np.isfinite(eps) and eps >= 0)
    with np.errstate(all="ignore"):
        rejected = _screened_out(q, nrm, eps)
    if special == "inf":
        assert rejected is None
        return
    assert rejected.shape == (m,)
    with np.errstate(invalid="ignore"):
        seed_rejects = (seed_d > eps).any(axis=1)
    assert not (rejected & ~seed_rejects).any(), "the screen rejected a candidate the seed's test passes"
    expected = next((c for c in range(m) if not seed_rejects[c]), -1)
    with _candidate_scan(True, at_any_size=True, screen=True), np.errstate(all="ignore"):
        assert _first_passing(q, nrm, np.ones(m, dtype=bool), eps) == expected


def test_screen_rejects_the_candidates_a_point_is_clearly_above():
    # Not a no-op: on random planes the screen rejects every candidate whose worst
    # point is above eps by more than a millionth, leaving few to the seed's sums.
    rng = np.random.default_rng(7)
    q = rng.standard_normal((100, 3))
    nrm = rng.standard_normal((98, 3))
    nrm /= np.linalg.norm(nrm, axis=1)[:, None]
    eps = 1e-3
    worst = _seed_distances(q, nrm).max(axis=1)
    rejected = _screened_out(q, nrm, eps)
    assert (worst > eps + 1e-6).sum() > 90
    np.testing.assert_array_equal(rejected, worst > eps + 1e-6)


# --------------------------------------------------------------------------- hull properties


@given(
    n=st.integers(4, 200),
    seed=st.integers(0, 2**32 - 1),
    kind=st.sampled_from(["ball", "cube", "gauss"]),
    policy=st.sampled_from(["scaled", "fixed"]),
)
def test_general_position_gives_the_hull(n, seed, kind, policy):
    pts = random_cloud(seed, n, kind)
    eps = tolerance(pts, policy)
    assume(nathan_premise(pts, eps))
    tri = gift_wrap_3d_dedup(pts, eps=eps)
    note(f"{len(tri)} triangles")
    assert_closed_outward_hull(pts, tri)
    assert_stack_counts(pts, eps, n_vertices=len(ConvexHull(pts).vertices))


@pytest.mark.parametrize("name", sorted(VARIANTS))
@pytest.mark.parametrize("scale_exp", [-30, -3, 7, 40])
def test_power_of_two_scaling_changes_nothing_under_the_scaled_policy(name, scale_exp):
    pts = random_cloud(5, 150, "gauss")
    np.testing.assert_array_equal(VARIANTS[name](pts), VARIANTS[name](pts * 2.0**scale_exp))


@pytest.mark.slow
@pytest.mark.parametrize("seed", [0, 1, 3])
@pytest.mark.parametrize("kind", ["ball", "gauss"])
def test_general_position_n2000(seed, kind):
    # The first cloud from this seed on that keeps the premise (rounding breaks
    # it on some 2000-point clouds: the seed's weak spot, tested elsewhere).
    ((_, pts),) = first_inputs_with_premise(1, 2000, kind, policies=("scaled",), start=1000 * seed)
    assert_closed_outward_hull(pts, gift_wrap_3d_dedup(pts))


def test_n1000_ball_runs_quickly():
    ((_, pts),) = first_inputs_with_premise(1, 1000, "ball", policies=("scaled",), start=3)
    start = time.perf_counter()
    tri = gift_wrap_3d(pts)
    elapsed = time.perf_counter() - start
    assert set(np.unique(tri).tolist()) == set(ConvexHull(pts).vertices.tolist())
    assert elapsed < 5.0, f"n=1000 took {elapsed:.2f} s"


# --------------------------------------------------------------------------- the seed's own rules


@pytest.mark.parametrize(
    "points",
    [
        [[0.0, 0.0, 0.0], [3.0, 4.0, 9.0], [1.0, 1.0, -2.0], [-2.0, 0.5, 1.0]],
        [[10.0, -3.0, 1.0], [7.5, 2.25, 0.0], [9.0, 9.0, 9.0], [8.0, -1.0, -30.0]],
        [[1.0, 0.0, 5.0], [0.0, 1.0, -5.0], [-1.0, 0.0, 0.0], [0.0, -1.0, 2.0]],
    ],
)
def test_scaled_eps_is_nathans_formula(points):
    flat = [(x, y, 0.0) for x, y, _ in points]
    dots = [x * x + y * y + z * z for x, y, z in flat]
    by_hand = 2.0**-52 * (math.sqrt(max(dots)) - math.sqrt(min(dots)))
    assert tolerance(np.array(points), "scaled") == pytest.approx(by_hand, rel=1e-15, abs=0)
    # eps=None means exactly that value.
    assert gift_wrap_3d(np.array(points)).tolist() == gift_wrap_3d(np.array(points), eps=by_hand).tolist()


def test_eps_is_the_threshold_on_signed_distance():
    # With eps larger than the whole cloud nothing is ever "outside", so every
    # popped edge takes the first candidate in index order: the seed's scan.
    pts = random_cloud(8, 30, "ball")
    tr = _gift_wrap_trace(pts, 10.0)
    for a, b, c in tr.triangles.tolist():
        assert c == min(set(range(30)) - {a, b})
    assert tr.first_edge == (tr.first_point, 0 if tr.first_point != 0 else 1)


def test_first_point_is_farthest_on_the_flattened_set():
    pts = np.array(
        [
            [0.0, 0.0, 100.0],  # farthest in 3D, at the origin once flattened
            [1.0, 0.0, 0.0],
            [0.0, -2.0, 1.0],  # farthest flattened: |(0, -2)| = 2
            [-2.0, 0.0, -1.0],  # ties with row 2: the lower index wins
            [0.5, 0.5, -3.0],
        ]
    )
    assert _gift_wrap_trace(pts, 0.0).first_point == 2


def test_first_edge_is_the_first_index_with_no_point_beyond_it():
    ((_, pts),) = first_inputs_with_premise(1, 40, "cube", policies=("scaled",), start=11)
    eps = tolerance(pts, "scaled")
    tr = _gift_wrap_trace(pts, eps)
    first = tr.first_point
    assert tr.first_edge[0] == first

    def outside(c):
        # The edge's own two points are on it (the premise says rounding keeps
        # them within eps); every other point is judged by the seed's formula.
        e = pts[c, :2] - pts[first, :2]
        normal = np.array([e[1], -e[0]]) / math.hypot(*e)  # E/|E| x z_hat
        rel = np.delete(pts[:, :2] - pts[first, :2], [first, c], axis=0)
        return (rel[:, 0] * normal[0] + rel[:, 1] * normal[1] > eps).any()

    passing = [c for c in range(40) if c != first and not outside(c)]
    assert tr.first_edge[1] == passing[0]
    # The edge runs counter-clockwise round the flattened hull: points on its left.
    assert len(passing) == 1


def test_duplicate_edge_check_in_both_directions_on_a_tetrahedron():
    tr = _gift_wrap_trace(TET, 0.0, LITERAL)
    undirected = [frozenset(e) for e in tr.edges]
    # Six hull edges, each recorded (and pushed) exactly once, in one direction only.
    assert len(tr.edges) == 6 and len(set(undirected)) == 6
    assert set(undirected) == {frozenset(p) for p in itertools.combinations(range(4), 2)}
    assert tr.pops == 6  # the first edge plus five pushes
    # Six pops find a triangle each; two of them are faces built already, and
    # the seed adds them again: six triangles, four distinct.
    assert tr.refound == 2 and len(tr.triangles) == 6
    assert len({canonical(t) for t in tr.triangles.tolist()}) == 4
    dedup = _gift_wrap_trace(TET, 0.0, DEDUP)
    assert dedup.pops == 6 and dedup.refound == 2 and len(dedup.triangles) == 4
    assert_closed_outward_hull(TET, dedup.triangles)


@pytest.mark.parametrize("policy", ["scaled", "fixed"])
def test_triangulated_cube_pops_three_halves_f_and_refinds_half(policy):
    # A cube with its corners moved by up to 1e-3: every quad splits into two
    # triangles along a definite diagonal, F = 12, 18 edges.  The first jitter
    # (in seed order) that keeps the premise.
    for seed in range(7, 57):
        pts = CUBE + np.random.default_rng(seed).uniform(-1e-3, 1e-3, CUBE.shape)
        eps = tolerance(pts, policy)
        if nathan_premise(pts, eps):
            break
    else:
        pytest.fail("the premise failed on 50 jittered cubes in a row")
    assert_closed_outward_hull(pts, gift_wrap_3d_dedup(pts, eps=eps))
    assert_stack_counts(pts, eps, n_vertices=8)


@pytest.mark.parametrize(("n", "kind"), [(30, "ball"), (100, "cube"), (300, "ball")])
def test_random_cloud_pops_three_halves_f_and_refinds_half(n, kind):
    # The first inputs where the seed's premise holds under both policies (on
    # Gaussian clouds the fixed eps usually breaks it; see the weak-spot tests).
    ((_, pts),) = first_inputs_with_premise(1, n, kind)
    for policy in ("scaled", "fixed"):
        assert_stack_counts(pts, tolerance(pts, policy), n_vertices=len(ConvexHull(pts).vertices))


def test_rotation_key_matches_rotations_not_reversals():
    keys = {_rotation_key(*t) for t in [(4, 1, 9), (1, 9, 4), (9, 4, 1)]}
    assert keys == {(1, 9, 4)}
    assert _rotation_key(4, 9, 1) == (1, 4, 9)  # the opposite orientation stays apart
    assert _rotation_key(3, 3, 0) == _rotation_key(3, 0, 3) == (0, 3, 3)  # repeated index


@pytest.mark.parametrize("variant", [LITERAL, DEDUP], ids=["literal", "dedup"])
def test_duplicate_edge_check_on_a_cube(variant):
    # The exact cube has four coplanar points per face: overlapping triangles
    # (see the coplanar test); the dedup variant adds each at most once.
    tr = _gift_wrap_trace(CUBE, tolerance(CUBE, "scaled"), variant)
    undirected = [frozenset(e) for e in tr.edges]
    distinct = len({canonical(t) for t in tr.triangles.tolist()})
    assert len(set(undirected)) == len(undirected) == tr.pops == distinct + tr.refound
    assert len(tr.triangles) == (distinct if variant.improved else tr.pops)
    # Every edge of every triangle was recorded once, whichever way it was met.
    tri_edges = {frozenset((t[i], t[(i + 1) % 3])) for t in tr.triangles.tolist() for i in range(3)}
    assert tri_edges == set(undirected)
    assert (orient_sign(CUBE, tr.triangles) >= 0).all()
    assert set(np.unique(tr.triangles).tolist()) == set(range(8))


def test_triangles_wind_counter_clockwise_from_outside():
    tri = gift_wrap_3d(TET)
    centroid = TET.mean(axis=0)
    for a, b, c in tri.tolist():
        normal = np.cross(TET[b] - TET[a], TET[c] - TET[b])  # the seed's E01 x E12
        assert normal @ (TET[a] - centroid) > 0


# --------------------------------------------------------------------------- weak spots and degenerate input


def test_self_test_rounding_can_lose_the_whole_hull():
    # Four points in general position.  The true triangle on the first edge
    # fails its own test: one of its vertices lands 2**-54 above its plane,
    # more than eps, although the seed says these "will always pass".
    pts = np.array(
        [
            [0.45720201095269336, 0.5678265506776123, -0.6368552587848431],
            [0.6437826032131759, -0.12486367229215553, -0.14082813651526624],
            [0.45189935499281675, -0.1761432141652837, -0.5160523153484281],
            [-0.1903480570903251, -0.48522648469094476, -0.7459284361288928],
        ]
    )
    assert not nathan_premise(pts, tolerance(pts, "scaled"))
    assert gift_wrap_3d(pts).shape == gift_wrap_3d_dedup(pts).shape == (0, 3)
    # A slightly larger eps finds all four faces.
    assert_closed_outward_hull(pts, gift_wrap_3d_dedup(pts, eps=1e-12))


def test_step_two_can_find_no_first_edge():
    pts = np.array(
        [
            [-0.5690262072791671, 0.3423510797942578, -0.054874480104524045],
            [-0.27731149769982105, -0.6277346827438616, -0.27409132534783814],
            [0.6092348169404991, -0.42045493288728186, 0.1422528092594389],
            [-0.2738697775291724, -0.11348269392344665, -0.5351295740119881],
        ]
    )
    with pytest.raises(RuntimeError, match="gift-wrap-3d: step 2 found no first edge"):
        gift_wrap_3d(pts)


def test_duplicate_points_give_zero_area_triangles():
    dup = np.vstack([TET[1:2], TET])  # rows 0 and 2 are the same point
    tri = gift_wrap_3d(dup)
    assert len(tri) > 0
    assert all(0 in t and 2 in t for t in tri.tolist())  # every triangle uses both copies


def test_a_reversed_triangle_is_not_a_repeat():
    # Worked by hand from the seed: rows 0 and 2 are (1, 0, 0), row 1 the
    # origin.  Step 1 takes row 0 (first of the farthest flattened points);
    # step 2 rejects c=1 (row 3 has y = 1 left of the edge) and takes c=2
    # (zero length: NaN normal).  Pop (0, 2): c=1 is zero-area, NaN, passes:
    # (0, 2, 1), pushing (1, 2) and (0, 1).  Pop (0, 1): c=2 is collinear,
    # passes: (0, 1, 2), the same points reversed, kept; both its new edges are
    # duplicates.  Pop (1, 2): c=0 gives (1, 2, 0), a rotation of (0, 1, 2),
    # found again and not added.
    dup = np.vstack([TET[1:2], TET])
    tr = _gift_wrap_trace(dup, tolerance(dup, "scaled"), DEDUP)
    assert tr.triangles.tolist() == [[0, 2, 1], [0, 1, 2]]
    assert tr.pops == 3 and tr.refound == 1
    literal = _gift_wrap_trace(dup, tolerance(dup, "scaled"), LITERAL)
    assert literal.triangles.tolist() == [[0, 2, 1], [0, 1, 2], [1, 2, 0]]


def test_coplanar_grid_gives_overlapping_triangles():
    grid = np.array(list(itertools.product(range(3), repeat=3)), dtype=float)
    tri = gift_wrap_3d(grid)
    distinct = {canonical(t) for t in tri.tolist()}
    assert (orient_sign(grid, np.array(sorted(distinct))) >= 0).all()
    directed = Counter((t[i], t[(i + 1) % 3]) for t in distinct for i in range(3))
    # Not a closed triangulation: some directed edge is used twice (overlap).
    assert max(directed.values()) > 1 or any((b, a) not in directed for a, b in directed)


# Exact inputs (no rounding in any test the seed makes: the triangles come
# back), and inputs whose rounding decides the self-tests (the seed's weak spot:
# triangles, possibly none, or no first edge at all).
EXACT_DEGENERATE = {
    "flat": lambda rng: np.c_[rng.integers(0, 1000, (200, 2)) / 1024.0, np.zeros(200)],
    "vertical-line": lambda rng: np.c_[np.zeros((20, 2)), rng.random(20)],
    "all-equal": lambda rng: np.ones((10, 3)),
    "three-points": lambda rng: TET[:3],
    "grid-10": lambda rng: np.array(list(itertools.product(range(10), repeat=3)), dtype=float),
}
NOISY_DEGENERATE = {
    "tilted-flat": lambda rng: np.c_[rng.random((200, 2)), np.zeros(200)] @ np.linalg.qr(rng.standard_normal((3, 3)))[0],
    "line": lambda rng: np.outer(rng.random(50), [1.0, 2.0, 3.0]),
    "duplicated-cloud": lambda rng: np.repeat(random_cloud(4, 40, "ball"), 3, axis=0),
}


@pytest.mark.parametrize("name", sorted(VARIANTS))
@pytest.mark.parametrize("case", sorted(EXACT_DEGENERATE) + sorted(NOISY_DEGENERATE))
def test_degenerate_input_ends_as_documented(case, name):
    points = {**EXACT_DEGENERATE, **NOISY_DEGENERATE}[case](np.random.default_rng(2))
    start = time.perf_counter()
    try:
        tri = VARIANTS[name](points)
    except RuntimeError as exc:
        assert case in NOISY_DEGENERATE, f"{case} is exact, yet: {exc}"
        assert str(exc).startswith(f"{name}: step 2 found no first edge")
        return
    finally:
        assert time.perf_counter() - start < 20.0
    assert tri.ndim == 2 and tri.shape[1] == 3
    assert len(tri) >= (1 if case in EXACT_DEGENERATE else 0)
    assert ((tri >= 0) & (tri < len(points))).all()
    if name == "gift-wrap-3d-dedup":
        assert len({canonical(t) for t in tri.tolist()}) == len(tri)  # no triangle twice in one orientation


@pytest.mark.parametrize("name", sorted(VARIANTS))
def test_main_loop_guard_names_the_step(monkeypatch, name):
    # The duplicate check bounds the pops by n(n-1)/2 + 1, far below the
    # guard; shrink the guard to check that it trips with a clear message.
    monkeypatch.setattr(gift_wrap, "_pop_limit", lambda n: 3)
    with pytest.raises(AlgorithmStepLimit, match=rf"^{name}: step 4 \(main loop\) exceeded 3 edge pops"):
        VARIANTS[name](TET)


@pytest.mark.parametrize("module", [gift_wrap], ids=lambda m: m.__name__.rsplit(".", 1)[-1])
def test_docstring_examples_run_as_printed(module):
    # The examples document the seed's behaviour, weak spots included.
    result = doctest.testmod(module, optionflags=doctest.ELLIPSIS, verbose=False)
    assert result.attempted > 0 and result.failed == 0
