"""The judge under attack: Hypothesis draws hulls and wrong answers at every magnitude, and an
independent brute-force oracle in exact rationals (``tests/_brute_oracle.py``) says what the
verdict must be.  ``check`` (the exact checks, and with Qhull) and ``assert_valid_hull`` must
agree with it on every pair; malformed output of any shape must be a contract violation.

Fast form: the Hypothesis profile's example count (``ci``: 30 per test).  Slow form (``-m
slow``, nightly with ``HYPOTHESIS_PROFILE=nightly``): more points per input and more examples.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

from _brute_oracle import affine_rank, hull_facets_3d, hull_polygon_2d, rationals, triangulated, valid
from hullstress.checker import check
from hullstress.contract import FaceSet
from hullstress.errors import ContractViolation
from hullstress.testing import assert_valid_hull

#: Magnitude regimes: how the small integer lattice below becomes doubles.
MAGNITUDES = ("unit", "subnormal", "huge", "tiny", "mixed", "top", "ulp", "jitter")


def _scale_points(lattice: np.ndarray, regime: str, draw) -> np.ndarray:
    """Small integer coordinates -> doubles at one magnitude regime (degeneracies survive exact scalings)."""
    x = lattice.astype(np.float64)
    n = len(x)
    if regime == "subnormal":
        return x * 5e-324 * draw(st.sampled_from([1.0, 3.0, 2.0**20]))  # exact: integers times the least subnormal
    if regime == "huge":
        return x * draw(st.sampled_from([1e300, 2.0**1000, 1e200]))
    if regime == "tiny":
        return x * draw(st.sampled_from([1e-300, 2.0**-1000, 1e-200]))
    if regime == "top":
        # Near the top of the range, with a coordinate so small that no exact power-of-two
        # scaling brings the set into range (F3: the checker then works unscaled).
        out = x * (1.7e308 / max(1.0, float(np.abs(x).max())))
        i, j = draw(st.integers(0, n - 1)), draw(st.integers(0, x.shape[1] - 1))
        out[i, j] = draw(st.sampled_from([0.1, -0.1, 1e-300, 0.0]))
        return out
    if regime == "mixed":
        scales = np.array(draw(st.lists(st.sampled_from([1e-200, 1e200, 1.0, 1e-100]), min_size=n, max_size=n)))
        return x * scales[:, None]
    if regime == "ulp":
        # One-ulp nudges of some coordinates: coplanar and collinear sets made barely not so.
        out = x.copy()
        for i, j, up in draw(st.lists(st.tuples(st.integers(0, n - 1), st.integers(0, x.shape[1] - 1),
                                                st.booleans()), max_size=3)):
            out[i, j] = math.nextafter(out[i, j], math.inf if up else -math.inf)
        return out
    if regime == "jitter":
        seed = draw(st.integers(0, 2**32 - 1))
        return x + np.random.default_rng(seed).uniform(-1e-12, 1e-12, x.shape)
    return x


@st.composite
def point_sets(draw, dim: int, max_points: int):
    """A full-rank point set of a few points on a small lattice, at a drawn magnitude (with its name)."""
    n = draw(st.integers(dim + 1, max_points))
    coords = st.integers(-3, 3)
    lattice = np.array(draw(st.lists(st.lists(coords, min_size=dim, max_size=dim), min_size=n, max_size=n)))
    regime = draw(st.sampled_from(MAGNITUDES))
    pts = _scale_points(lattice, regime, draw)
    if not np.isfinite(pts).all() or affine_rank(rationals(pts)) < dim:
        pts = np.vstack([pts, np.eye(dim + 1, dim) * (2.0 if regime != "subnormal" else 5e-324)])
        if affine_rank(rationals(pts)) < dim:  # e.g. a mixed set whose big points swamp the simplex
            pts = np.vstack([pts, np.eye(dim) * 1e200, np.eye(dim) * -1e200])
    return pts, regime


# --------------------------------------------------------------------------- answers


def _mutate_polygon(draw, pts: np.ndarray, poly: list[int]) -> list[int]:
    kind = draw(st.sampled_from(["none", "reverse", "rotate", "drop", "insert", "repeat", "swap", "replace"]))
    n, k = len(pts), len(poly)
    if kind == "reverse":
        return poly[::-1]
    if kind == "rotate":
        r = draw(st.integers(0, k - 1))
        return poly[r:] + poly[:r]
    if kind == "drop":
        return poly[: (i := draw(st.integers(0, k - 1)))] + poly[i + 1 :]
    if kind == "insert":
        i = draw(st.integers(0, k))
        return poly[:i] + [draw(st.integers(0, n - 1))] + poly[i:]
    if kind == "repeat":
        return poly + poly  # winds twice
    if kind == "swap" and k >= 2:
        i, j = draw(st.integers(0, k - 1)), draw(st.integers(0, k - 1))
        out = list(poly)
        out[i], out[j] = out[j], out[i]
        return out
    if kind == "replace":
        out = list(poly)
        out[draw(st.integers(0, k - 1))] = draw(st.integers(0, n - 1))
        return out
    return poly


def _mutate_faces(draw, pts: np.ndarray, faces: list[list[int]]) -> list[list[int]]:
    kinds = ["none", "reverse-one", "reverse-all", "double-face", "double-cover", "drop", "pinch",
             "replace", "t-junction", "split-edge", "rotate-face", "swap-in-face"]
    kind = draw(st.sampled_from(kinds))
    n, m = len(pts), len(faces)
    faces = [list(f) for f in faces]
    f = draw(st.integers(0, m - 1))
    if kind == "reverse-one":
        faces[f] = faces[f][::-1]
    elif kind == "reverse-all":
        faces = [g[::-1] for g in faces]
    elif kind == "double-face":
        faces.append(list(faces[f]))
    elif kind == "double-cover":
        faces = faces + [list(g) for g in faces]
    elif kind == "drop" and m > 1:
        del faces[f]
    elif kind == "pinch":  # two vertices made one everywhere
        a, b = draw(st.integers(0, n - 1)), draw(st.integers(0, n - 1))
        faces = [[a if v == b else v for v in g] for g in faces]
    elif kind == "replace":
        g = faces[f]
        g[draw(st.integers(0, len(g) - 1))] = draw(st.integers(0, n - 1))
    elif kind in ("t-junction", "split-edge"):
        # Split face f's first edge at a drawn point: t-junction leaves the neighbour as it is,
        # split-edge also inserts the point into the neighbour across that edge (edge to edge).
        g = faces[f]
        p = draw(st.integers(0, n - 1))
        a, b = g[0], g[1]
        faces[f] = [a, p] + g[1:]
        if kind == "split-edge":
            for h in faces:
                for t in range(len(h)):
                    if h[t] == b and h[(t + 1) % len(h)] == a and h is not faces[f]:
                        h.insert(t + 1, p)
                        break
    elif kind == "rotate-face":
        g = faces[f]
        faces[f] = g[1:] + g[:1]
    elif kind == "swap-in-face" and len(faces[f]) >= 2:
        g = faces[f]
        g[0], g[-1] = g[-1], g[0]
    return faces


@st.composite
def cases_2d(draw, max_points: int = 8):
    pts, regime = draw(point_sets(2, max_points))
    poly = hull_polygon_2d(rationals(pts))
    if draw(st.booleans()):  # boundary points on the edges, in order, are allowed: add one when there is one
        poly = _with_boundary_point_2d(pts, poly)
    return pts, _mutate_polygon(draw, pts, poly), regime


def _with_boundary_point_2d(pts: np.ndarray, poly: list[int]) -> list[int]:
    r = rationals(pts)
    for t, (a, b) in enumerate(zip(poly, poly[1:] + poly[:1])):
        for q in range(len(pts)):
            if r[q] in (r[a], r[b]):
                continue
            ab = (r[b][0] - r[a][0], r[b][1] - r[a][1])
            aq = (r[q][0] - r[a][0], r[q][1] - r[a][1])
            if ab[0] * aq[1] - ab[1] * aq[0] == 0 and 0 < ab[0] * aq[0] + ab[1] * aq[1] < ab[0] ** 2 + ab[1] ** 2:
                return poly[: t + 1] + [q] + poly[t + 1 :]
    return poly


@st.composite
def cases_3d(draw, max_points: int = 8):
    pts, regime = draw(point_sets(3, max_points))
    facets = hull_facets_3d(rationals(pts))
    faces = facets if draw(st.booleans()) else triangulated(facets)
    return pts, _mutate_faces(draw, pts, faces), regime


def _verdicts(pts: np.ndarray, faces, with_qhull: bool) -> tuple[bool, bool, bool | None]:
    """``check`` without Qhull, ``assert_valid_hull`` without Qhull, and ``check`` with Qhull (or None)."""
    exact = check(pts, faces, qhull=False).ok
    try:
        assert_valid_hull(pts, faces, qhull=False)
        asserted = True
    except AssertionError:
        asserted = False
    with_q = check(pts, faces).ok if with_qhull else None
    return exact, asserted, with_q


def _agree(pts, faces, regime, with_qhull: bool = True) -> None:
    truth = valid(pts, faces)
    exact, asserted, with_q = _verdicts(pts, faces, with_qhull)
    where = f"regime {regime}\npoints = {pts.tolist()!r}\nfaces = {faces!r}"
    assert exact == truth, f"check says {exact}, the oracle {truth}\n{where}"
    assert asserted == truth, f"assert_valid_hull says {asserted}, the oracle {truth}\n{where}"
    # A valid answer agrees with a Qhull hull that passes the exact checks (or Qhull is no
    # reference there); an invalid one fails whatever Qhull says.
    if with_q is not None:
        assert with_q == truth, f"check with Qhull says {with_q}, the oracle {truth}\n{where}"


# --------------------------------------------------------------------------- the issue's reproducers


F1 = ([[0.0, 0.0, 0.0], [1e200, 0.0, 1e199], [0.0, 1e200, 1e199], [-1e200, -1e200, -1e200], [-1e-100, -1e-100, -1e-110]],
      [[0, 1, 2], [0, 2, 3], [0, 3, 1], [1, 3, 2]])
F2 = ([[1.955092598286932e-201, 3.869709716411563e-202, -9.799380919182126e-201],
       [2.5906931933836857e199, 6.638108710689908e199, 7.015969036620544e199],
       [2.9884504958895646e-39, -5.139695464984047e-38, 3.860320782111019e-38],
       [1.6204941788923908e195, -1.820292608493031e195, -4.2848160586590746e195],
       [-1.2745944568263834e-127, 7.229227930773337e-127, 6.17357715342725e-127]],
      [[2, 0, 3], [4, 0, 2], [0, 4, 3], [1, 2, 3], [1, 4, 2], [3, 4, 1]])
F3 = ([[1.7e308, 3.4000000000000003e307], [3.4000000000000003e307, 1.7e308], [-1.7e308, 8.5e307],
       [-1.7e308, -1.7e308], [1.7e308, -1.7e308], [0.1, -1.7e308]], [0, 1, 2, 3, 5, 4])
F4 = ([[-1.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 1.0], [0.0, -1.0, 1.0], [-1e-170, 0.0, 0.0], [0.0, 0.0, 0.0],
       [1e-170, 0.0, 0.0]], [[2, 1, 6, 5, 4, 0], [0, 4, 5, 6, 1, 3], [3, 2, 0], [1, 2, 3]])
F8 = ([[0.03125, 1.0, -1.0], [0.03125, 1.0, -1.0], [0.0, 0.0, 0.0], [1.0, 0.015625, 0.0625], [1.0, 0.015625, 0.0625],
       [0.0, 0.0, 1.0], [1.0, -1.0, 0.0]],
      [[6, 3, 4], [6, 4, 3], [4, 3, 0], [4, 0, 1], [4, 1, 0], [1, 0, 2], [1, 2, 0], [2, 0, 1], [0, 3, 1], [1, 3, 0]])


#: Found by the nightly profile: polygon faces whose coordinate differences overflow (warnings, then errors).
TOP_FLAT = [[0.1, 0.0, 0.0], [0.0, 1.7e308, 0.0], [1.7e308, 0.0, 0.0], [-1.7e308, 1.7e308, 0.0], [2.0, 0.0, 0.0],
            [0.0, 2.0, 0.0], [0.0, 0.0, 2.0], [0.0, 0.0, 0.0]]


@pytest.mark.parametrize("case", [F1, F2, F3, F4, F8], ids=["F1", "F2", "F3", "F4", "F8"])
def test_issue_reproducers_get_the_oracles_verdict(case):
    pts, faces = np.array(case[0]), case[1]
    _agree(pts, faces, "reproducer")


def test_f2_variant_with_the_point_strictly_inside_passes():
    pts = np.array(F1[0])
    pts[4] = [1e-100, 1e-100, 1e-110]
    assert valid(pts, F1[1])
    _agree(pts, F1[1], "reproducer")


# --------------------------------------------------------------------------- the fast form (CI)


@given(cases_2d())
def test_2d_answers_agree_with_the_oracle(case):
    pts, poly, regime = case
    _agree(pts, poly, regime)


@given(cases_3d())
@example((np.array(F1[0]), F1[1], "reproducer"))
@example((np.array(F4[0]), F4[1], "reproducer"))
@example((np.array(TOP_FLAT), [[2, 0, 7, 3], [2, 3, 1], [2, 6, 7], [1, 6, 2], [1, 3, 6], [7, 6, 3]], "top"))
@example((np.array(TOP_FLAT), [[3, 0, 2, 1], [1, 2, 6], [6, 3, 1], [2, 3, 6]], "top"))
def test_3d_answers_agree_with_the_oracle(case):
    pts, faces, regime = case
    _agree(pts, faces, regime)


_garbage_leaf = st.one_of(
    st.integers(-3, 10), st.integers(-(2**70), 2**70), st.floats(allow_nan=True), st.none(), st.booleans(),
    st.text(max_size=3), st.just(np.int32(1)), st.just(np.float64(2.0)),
)
_garbage = st.recursive(_garbage_leaf, lambda inner: st.lists(inner, max_size=5) | st.tuples(inner, inner), max_leaves=20)


@st.composite
def _garbage_face_sets(draw):
    dtype = draw(st.sampled_from([np.int64, np.int32, np.float64, np.uint8, bool]))
    idx = np.array(draw(st.lists(st.integers(-2, 6), max_size=12)), dtype=np.int64).astype(dtype)
    off = np.array(draw(st.lists(st.integers(-1, 14), max_size=6)), dtype=draw(st.sampled_from([np.int64, np.float64])))
    return FaceSet(idx, off)


@given(st.one_of(_garbage, _garbage_face_sets(), st.builds(np.array, st.lists(st.integers(-1, 5), max_size=9))))
@example([[0, 2, 1, [3]], [0, 1, 3], [0, 3, 2], [1, 2, 3]])
@example(FaceSet(np.array([0.0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3]), np.arange(0, 13, 3)))
@example(FaceSet(np.array([0, 2, 1]), np.zeros(0, dtype=np.int64)))
def test_malformed_output_is_a_contract_violation_never_an_internal_error(garbage):
    tetra = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]])
    square = tetra[:, :2]
    for pts in (tetra, square):
        try:
            check(pts, garbage, qhull=False)
        except ContractViolation:
            pass
        try:
            assert_valid_hull(pts, garbage, qhull=False)
        except AssertionError:
            pass


# --------------------------------------------------------------------------- the slow form (nightly)

#: At least 300 examples of larger inputs; the nightly profile's 1000 when it is loaded.
_SLOW_EXAMPLES = max(300, settings.default.max_examples)


@pytest.mark.slow
@settings(max_examples=_SLOW_EXAMPLES)
@given(cases_2d(max_points=14))
def test_2d_answers_agree_with_the_oracle_at_length(case):
    pts, poly, regime = case
    _agree(pts, poly, regime)


@pytest.mark.slow
@settings(max_examples=_SLOW_EXAMPLES)
@given(cases_3d(max_points=12))
def test_3d_answers_agree_with_the_oracle_at_length(case):
    pts, faces, regime = case
    _agree(pts, faces, regime)
