"""Tests for hullstress.adapters: every registered adapter on general-position inputs,
the orientation of Qhull's triangles, degenerate inputs, and optional-library bookkeeping."""

from __future__ import annotations

import sys
import types
from collections import Counter
from fractions import Fraction

import numpy as np
import pytest
from scipy.spatial import ConvexHull, QhullError

import hullstress.adapters as adapters
from hullstress._registry import ALGORITHMS
from hullstress.adapters import scipy_qhull
from hullstress.contract import FaceSet, normalize_output

AVAILABLE = adapters.available_adapters()
ADAPTER_NAMES = sorted(name for names in AVAILABLE.values() for name in names)
SEEDS = (0, 1, 2)
SIZES = (10, 40, 500)
EXACT_UP_TO = 40  # exact Fraction predicates up to this many points, floats beyond


def _general_position(dim: int, n: int, seed: int) -> np.ndarray:
    """Random points in the unit square (2D) or the unit ball (3D), read-only like the harness's."""
    rng = np.random.default_rng(seed)
    if dim == 2:
        pts = rng.uniform(-1.0, 1.0, size=(n, 2))
    else:
        direction = rng.standard_normal((n, 3))
        direction /= np.linalg.norm(direction, axis=1, keepdims=True)
        pts = direction * rng.uniform(0.0, 1.0, size=(n, 1)) ** (1.0 / 3.0)
    pts = np.ascontiguousarray(pts, dtype=np.float64)
    pts.setflags(write=False)
    return pts


def _orient2d_exact(p: np.ndarray, q: np.ndarray, r: np.ndarray) -> Fraction:
    px, py = map(Fraction, p)
    qx, qy = map(Fraction, q)
    rx, ry = map(Fraction, r)
    return (qx - px) * (ry - py) - (qy - py) * (rx - px)


def _orient3d_exact(a: np.ndarray, b: np.ndarray, c: np.ndarray, d: np.ndarray) -> Fraction:
    """det[b-a, c-a, d-a]: negative when d is below the counter-clockwise triangle abc."""
    a_ = [Fraction(x) for x in a]
    u = [Fraction(x) - y for x, y in zip(b, a_)]
    v = [Fraction(x) - y for x, y in zip(c, a_)]
    w = [Fraction(x) - y for x, y in zip(d, a_)]
    return (
        u[0] * (v[1] * w[2] - v[2] * w[1])
        - u[1] * (v[0] * w[2] - v[2] * w[0])
        + u[2] * (v[0] * w[1] - v[1] * w[0])
    )


def _assert_closed_consistent(triangles: np.ndarray) -> None:
    """Every directed edge exactly once and its reverse exactly once."""
    directed = Counter()
    for a, b, c in triangles.tolist():
        directed.update([(a, b), (b, c), (c, a)])
    repeated = [e for e, k in directed.items() if k != 1]
    assert not repeated, f"directed edges used more than once: {repeated[:5]}"
    unmatched = [e for e in directed if (e[1], e[0]) not in directed]
    assert not unmatched, f"edges without an opposite: {unmatched[:5]}"


def _signed_volume(points: np.ndarray, triangles: np.ndarray) -> float:
    a, b, c = (points[triangles[:, k]] for k in range(3))
    return float(np.einsum("ij,ij->i", a, np.cross(b, c)).sum() / 6.0)


def _check_polygon(points: np.ndarray, verts: np.ndarray) -> None:
    assert len(set(verts.tolist())) == len(verts), f"repeated vertex in {verts.tolist()}"
    k = len(verts)
    assert k >= 3
    for i in range(k):
        p, q, r = points[verts[i]], points[verts[(i + 1) % k]], points[verts[(i + 2) % k]]
        if len(points) <= EXACT_UP_TO:
            turn = _orient2d_exact(p, q, r)
        else:
            turn = (q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0])
        assert turn > 0, f"not a strict counter-clockwise turn at {verts[(i + 1) % k]}: {float(turn)}"
    # Winding number one: the turning angles sum to 2*pi (rules out a polygon that winds twice).
    e = points[np.roll(verts, -1)] - points[verts]
    f = np.roll(e, -1, axis=0)
    angles = np.arctan2(e[:, 0] * f[:, 1] - e[:, 1] * f[:, 0], np.einsum("ij,ij->i", e, f))
    assert abs(angles.sum() - 2 * np.pi) < 1e-9


def _check_surface(points: np.ndarray, faces: FaceSet) -> None:
    assert faces.is_triangles, "the adapters return triangles on general-position input"
    tri = faces.triangles()
    _assert_closed_consistent(tri)
    n_vertices = len(faces.vertex_set())
    assert len(tri) == 2 * n_vertices - 4  # Euler, for a triangulated sphere
    centroid = points.mean(axis=0)
    if len(points) <= EXACT_UP_TO:
        for t in tri:
            s = _orient3d_exact(points[t[0]], points[t[1]], points[t[2]], centroid)
            assert s < 0, f"triangle {t.tolist()} is not counter-clockwise seen from outside"
    else:
        a, b, c = (points[tri[:, k]] for k in range(3))
        s = np.einsum("ij,ij->i", np.cross(b - a, c - a), centroid - a)
        assert (s < 0).all(), f"triangles not outward: {tri[s >= 0][:5].tolist()}"
    # Containment, in floats: no point clearly above any face's plane.
    a, b, c = (points[tri[:, k]] for k in range(3))
    normal = np.cross(b - a, c - a)
    normal /= np.linalg.norm(normal, axis=1, keepdims=True)
    height = (points @ normal.T) - np.einsum("ij,ij->i", normal, a)
    assert height.max() < 1e-12


@pytest.mark.parametrize("n", SIZES)
@pytest.mark.parametrize("seed", SEEDS)
@pytest.mark.parametrize("name", ADAPTER_NAMES)
def test_adapter_on_general_position(name: str, seed: int, n: int) -> None:
    spec = ALGORITHMS.get(name)
    points = _general_position(spec.dim, n, seed)
    raw = spec.func(points)
    out = normalize_output(raw, n, spec.dim)
    expected = sorted(ConvexHull(points).vertices.tolist())
    if spec.dim == 2:
        _check_polygon(points, out)
        assert sorted(out.tolist()) == expected
    else:
        _check_surface(points, out)
        assert out.vertex_set().tolist() == expected


def test_every_available_adapter_is_registered_with_its_dim() -> None:
    assert "scipy-qhull" in AVAILABLE  # scipy is a core dependency
    for family, names in AVAILABLE.items():
        assert names, family
        for name in names:
            spec = ALGORITHMS.get(name)
            assert spec.origin == "adapter"
            assert not spec.takes_eps  # the libraries bring their own tolerances
            assert spec.dim == (2 if "2d" in name or name == "shapely-convex-hull" else 3)
    assert set(AVAILABLE).isdisjoint(adapters.missing_adapters())


def test_scipy_qhull_options_table_matches_registry() -> None:
    assert set(scipy_qhull.QHULL_OPTIONS) <= set(ALGORITHMS.names())
    assert scipy_qhull.QHULL_OPTIONS["scipy-qhull-3d-QJ"] == "QJ"
    assert scipy_qhull.QHULL_OPTIONS["scipy-qhull-3d"] is None


# --- Qhull's orientation on inputs where Qt produces coplanar and degenerate triangles ---


def _grid(k: int) -> np.ndarray:
    g = np.linspace(0.0, 1.0, k)
    return np.array([[x, y, z] for x in g for y in g for z in g])


def _jittered_grid(k: int, seed: int, scale: float) -> np.ndarray:
    rng = np.random.default_rng(seed)
    pts = _grid(k)
    return pts + rng.uniform(-scale, scale, size=pts.shape)


@pytest.mark.parametrize("name", [n for n in scipy_qhull.ALGORITHM_NAMES if "3d" in n])
@pytest.mark.parametrize(
    "points",
    [_grid(4), _jittered_grid(4, 0, 1e-13), _jittered_grid(5, 1, 1e-9)],
    ids=["grid", "jitter-1e-13", "jitter-1e-9"],
)
def test_qhull_3d_orientation_on_near_coplanar_input(name: str, points: np.ndarray) -> None:
    out = normalize_output(ALGORITHMS.get(name).func(points), len(points), 3)
    tri = out.triangles()
    _assert_closed_consistent(tri)
    volume = _signed_volume(points, tri)
    assert volume == pytest.approx(1.0, rel=1e-6)  # outward: positive, and the whole cube


def _neighbors(tri: np.ndarray) -> np.ndarray:
    """Qhull's convention: neighbors[i, k] shares the edge opposite vertex k of triangle i."""
    owner: dict[frozenset, list[int]] = {}
    for i, t in enumerate(tri.tolist()):
        for k in range(3):
            owner.setdefault(frozenset(t[:k] + t[k + 1 :]), []).append(i)
    nbr = np.full(tri.shape, -1, dtype=np.int64)
    for i, t in enumerate(tri.tolist()):
        for k in range(3):
            pair = owner[frozenset(t[:k] + t[k + 1 :])]
            nbr[i, k] = pair[0] if pair[1] == i else pair[1]
    return nbr


def test_orient_simplices_fixes_a_zero_area_triangle() -> None:
    # A square pyramid whose base holds a zero-area triangle (0, 4, 1), 4 being the
    # midpoint of the base edge 0-1: its own normal has no sign; propagation gives it one.
    points = np.array(
        [[0, 0, 0], [2, 0, 0], [2, 2, 0], [0, 2, 0], [1, 0, 0], [1, 1, 2]], dtype=np.float64
    )
    outward = np.array(
        [[0, 1, 4], [0, 2, 1], [0, 3, 2], [5, 0, 4], [5, 4, 1], [5, 1, 2], [5, 2, 3], [5, 3, 0]]
    )
    rng = np.random.default_rng(7)
    for _ in range(10):
        flip = rng.random(len(outward)) < 0.5
        scrambled = outward.copy()
        scrambled[flip, 1], scrambled[flip, 2] = outward[flip, 2], outward[flip, 1]
        a, b, c = (points[outward[:, k]] for k in range(3))
        normals = np.cross(b - a, c - a)
        normals[0] = [0.0, 0.0, -1.0]  # Qhull reports the merged base facet's normal
        result = scipy_qhull.orient_simplices(points, scrambled, _neighbors(scrambled), normals)
        assert sorted(map(sorted, result.tolist())) == sorted(map(sorted, outward.tolist()))
        _assert_closed_consistent(result)
        assert _signed_volume(points, result) == pytest.approx(8.0 / 3.0)
        assert result[0].tolist() in ([0, 1, 4], [1, 4, 0], [4, 0, 1])


def test_orient_simplices_empty() -> None:
    empty = np.zeros((0, 3), dtype=np.int64)
    assert scipy_qhull.orient_simplices(np.zeros((0, 3)), empty, empty, np.zeros((0, 3))).shape == (0, 3)


# --- degenerate inputs: declines are exceptions, never half-hulls ---


def _coplanar(n: int = 30, seed: int = 0) -> np.ndarray:
    rng = np.random.default_rng(seed)
    return np.c_[rng.uniform(-1, 1, (n, 2)), np.zeros(n)]


def _collinear(n: int = 12, seed: int = 0) -> np.ndarray:
    t = np.random.default_rng(seed).uniform(-1, 1, n)
    return np.c_[t, 2.0 * t]


@pytest.mark.parametrize(
    ("name", "points"),
    [("scipy-qhull-3d", _coplanar()), ("scipy-qhull-2d", _collinear())],
)
def test_qhull_error_propagates_on_flat_input(name: str, points: np.ndarray) -> None:
    with pytest.raises(QhullError, match="flat"):
        ALGORITHMS.get(name).func(points)


@pytest.mark.parametrize(
    ("name", "points"),
    [("scipy-qhull-3d-QJ", _coplanar()), ("scipy-qhull-2d-QJ", _collinear())],
)
def test_qhull_joggle_returns_a_hull_on_flat_input(name: str, points: np.ndarray) -> None:
    dim = points.shape[1]
    out = normalize_output(ALGORITHMS.get(name).func(points), len(points), dim)
    if dim == 3:
        assert out.n_faces >= 4
        _assert_closed_consistent(out.triangles())
    else:
        assert len(out) >= 3


def _requires(family: str) -> pytest.MarkDecorator:
    return pytest.mark.skipif(
        family not in AVAILABLE, reason=adapters.missing_adapters().get(family, family)
    )


@_requires("shapely-geos")
@pytest.mark.parametrize(
    ("points", "kind"),
    [(_collinear(), "LineString"), (np.ones((5, 2)), "Point"), (np.zeros((0, 2)), "GeometryCollection")],
)
def test_shapely_declines_degenerate_input(points: np.ndarray, kind: str) -> None:
    with pytest.raises(ValueError, match=f"shapely returned an? {kind}"):
        ALGORITHMS.get("shapely-convex-hull").func(points)


@_requires("cgal")
@pytest.mark.parametrize(
    "points", [_coplanar(), np.c_[_collinear(), np.zeros(12)], np.ones((3, 3)), np.zeros((0, 3))]
)
def test_cgal_3d_declines_flat_input(points: np.ndarray) -> None:
    with pytest.raises(ValueError, match="CGAL returned (an open surface|no facets)"):
        ALGORITHMS.get("cgal-convex-hull-3d").func(points)


@_requires("cgal")
@pytest.mark.parametrize("name", ["cgal-convex-hull-2d", "cgal-graham-andrew-2d", "cgal-jarvis-2d"])
def test_cgal_2d_declines_collinear_input(name: str) -> None:
    with pytest.raises(ValueError, match=r"returned 2 hull point\(s\)"):
        ALGORITHMS.get(name).func(_collinear())


# The adapters that map returned coordinates back to indices (GEOS, CGAL).
COORDINATE_ADAPTERS = [n for n in ADAPTER_NAMES if not n.startswith("scipy-")]


@pytest.mark.parametrize("name", COORDINATE_ADAPTERS)
def test_duplicates_map_to_the_lowest_index(name: str) -> None:
    spec = ALGORITHMS.get(name)
    base = _general_position(spec.dim, 30, 3)
    # Rows 30..59 repeat rows 0..29; rows 60.. are a reversed copy.
    points = np.ascontiguousarray(np.vstack([base, base, base[::-1]]))
    out = normalize_output(spec.func(points), len(points), spec.dim)
    used = out.tolist() if spec.dim == 2 else out.vertex_set().tolist()
    assert max(used) < 30
    assert sorted(set(used)) == sorted(ConvexHull(base).vertices.tolist())


# --- bookkeeping of optional libraries ---


class _Uninstalled:
    """A meta-path finder that makes one top-level package look uninstalled."""

    def __init__(self, package: str) -> None:
        self.package = package

    def find_spec(self, fullname: str, path: object = None, target: object = None) -> None:
        if fullname == self.package or fullname.startswith(self.package + "."):
            raise ModuleNotFoundError(f"No module named {fullname!r}", name=fullname)
        return None


def test_probe_reports_a_missing_library(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.delitem(sys.modules, "hullstress.adapters.shapely_geos", raising=False)
    for key in [k for k in sys.modules if k == "shapely" or k.startswith("shapely.")]:
        monkeypatch.delitem(sys.modules, key)
    monkeypatch.setattr(sys, "meta_path", [_Uninstalled("shapely"), *sys.meta_path])
    probe = adapters._probe(adapters._Adapter("shapely-geos", "shapely_geos", "shapely", "pip install shapely"))
    assert probe == ((), "shapely not installed (pip install shapely)")


def test_probe_reports_a_broken_library(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.delitem(sys.modules, "hullstress.adapters.shapely_geos", raising=False)
    monkeypatch.setitem(sys.modules, "shapely.geometry", types.ModuleType("shapely.geometry"))
    names, reason = adapters._probe(adapters._Adapter("shapely-geos", "shapely_geos", "shapely", "x"))
    assert names == ()
    assert reason is not None and reason.startswith("shapely failed to import: ImportError: cannot import name")


def test_probe_does_not_hide_a_hullstress_bug() -> None:
    with pytest.raises(ModuleNotFoundError, match="hullstress.adapters.no_such_adapter"):
        adapters._probe(adapters._Adapter("x", "no_such_adapter", "numpy", "x"))
