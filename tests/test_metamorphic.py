"""Metamorphic chains and the answer comparison: a transform never changes the hull vertex set.

Qhull on generic 3D inputs and an exact (Fraction) 2D extreme-point oracle on
degenerate inputs (collinear runs, duplicates, closed rings) show that every
transform keeps the exact vertex set, through ``source_rows``; and
``vertex_set_change`` is shown to report the wrong answers it exists for.
"""

from __future__ import annotations

from fractions import Fraction

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from scipy.spatial import ConvexHull

import generators as G
from generators.metamorphic import apply_transforms, vertex_set_change
from generators.transforms import TRANSFORMS, duplicate_all, reverse_rows
from hullstress.strategies import point_sets, seeds

any_points = st.sampled_from([2, 3]).flatmap(lambda d: point_sets(dim=d, min_size=1, max_size=30))


ROW_PRESERVING = ["permute-rows", "reverse-rows", "duplicate-all"]  # coordinates untouched, rows moved


@given(any_points, seeds(), st.lists(st.sampled_from(ROW_PRESERVING), min_size=1, max_size=4))
def test_apply_transforms_composes_the_row_maps(points, seed, chain):
    t = apply_transforms(points, chain, seed=seed)
    assert t.name == "+".join(chain)
    assert t.points.tobytes() == points[t.source_rows].tobytes()
    assert [step["name"] for step in t.params["steps"]] == chain


def test_apply_transforms_keeps_added_rows_and_orientation_parity():
    pts = G.generate("uniform", 30, dim=3, seed=2, shape="ball")
    t = apply_transforms(pts, ["add-interior", "permute-rows", "reflect", "reflect"], seed=4)
    kept = t.source_rows >= 0
    assert np.count_nonzero(~kept) == 30 // 4
    assert t.orientation_preserved  # two reflections
    assert t.witness is None  # the chain moved the rows a witness would name
    single = apply_transforms(pts, "add-interior", seed=4)
    assert single.witness is not None and len(single.witness) == 30 // 4


def hull_2d_exact(points: np.ndarray) -> list[int]:
    """Indices of the strictly extreme points of a 2D set (monotone chain, exact Fraction turns)."""
    fr = [tuple(Fraction(float(x)) for x in row) for row in points]
    order = sorted(range(len(fr)), key=lambda i: fr[i])
    uniq = []
    for i in order:
        if not uniq or fr[uniq[-1]] != fr[i]:
            uniq.append(i)

    def turn(a, b, c):
        return (fr[b][0] - fr[a][0]) * (fr[c][1] - fr[a][1]) - (fr[b][1] - fr[a][1]) * (fr[c][0] - fr[a][0])

    def chain(seq):
        out = []
        for i in seq:
            while len(out) >= 2 and turn(out[-2], out[-1], i) <= 0:  # drops collinear points: extreme only
                out.pop()
            out.append(i)
        return out

    if len(uniq) < 3:
        return uniq
    return chain(uniq)[:-1] + chain(uniq[::-1])[:-1]


GENERIC_3D = [("uniform", {"shape": "ball"}), ("sphere", {}), ("uniform", {"shape": "gaussian"})]


@pytest.mark.parametrize("name", sorted(TRANSFORMS))
@pytest.mark.parametrize("family, params", GENERIC_3D, ids=[f[0] + "-" + "-".join(map(str, f[1].values())) for f in GENERIC_3D])
def test_every_transform_keeps_the_qhull_vertex_set_in_3d(name, family, params):
    for seed in range(3):
        pts = G.generate(family, 40, dim=3, seed=seed, **params)
        t = apply_transforms(pts, name, seed=seed)
        assert vertex_set_change(pts, ConvexHull(pts).vertices, t, ConvexHull(t.points).vertices) is None


DEGENERATE_2D = [
    ("collinear-edges", {}),
    ("duplicates", {"mode": "every-point"}),
    ("equal-x-columns", {"columns": 3}),
    ("regular-polygon", {}),
    ("closed-ring", {"shape": "rectangle"}),
    ("few-points", {"count": "d+2", "repeat": True}),
]


@pytest.mark.parametrize("name", sorted(TRANSFORMS))
@pytest.mark.parametrize("family, params", DEGENERATE_2D, ids=[f[0] for f in DEGENERATE_2D])
def test_every_transform_keeps_the_exact_extreme_set_on_degenerate_2d_input(name, family, params):
    """Collinear runs, duplicates, equal x, a closed ring: the exact extreme points do not move."""
    pts = G.generate(family, 24, dim=2, seed=1, **params)
    try:
        t = apply_transforms(pts, name, seed=1)
    except ValueError:
        assert name in ("add-interior", "scale-pow2")  # may decline a degenerate or extreme input
        return
    assert vertex_set_change(pts, hull_2d_exact(pts), t, hull_2d_exact(t.points)) is None


def test_vertex_set_change_reports_what_differs():
    pts = G.generate("uniform", 30, dim=2, seed=3, shape="ball")
    before = hull_2d_exact(pts)
    t = apply_transforms(pts, "permute-rows", seed=0)
    after = hull_2d_exact(t.points)
    back = {int(t.source_rows[j]): j for j in after}
    dropped = after[:-1]  # an answer that misses one vertex
    msg = vertex_set_change(pts, before, t, dropped)
    assert msg == f"permute-rows changed the hull vertex set: lost input row {int(t.source_rows[after[-1]])}"
    interior = next(i for i in range(30) if i not in before)
    msg = vertex_set_change(pts, before, t, after + [int(np.flatnonzero(t.source_rows == interior)[0])])
    assert msg == f"permute-rows changed the hull vertex set: gained input row {interior}"
    assert set(back) == set(before)
    added = apply_transforms(pts, "add-interior", seed=0)
    new_row = len(pts)
    msg = vertex_set_change(pts, before, added, before + [new_row])
    assert msg == f"add-interior changed the hull vertex set: reported added interior row {new_row}"


def test_vertex_set_change_counts_a_duplicate_copy_as_the_same_point():
    pts = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [0.2, 0.2]])
    t = duplicate_all(pts)
    assert vertex_set_change(pts, [0, 1, 2], t, [4, 5, 6]) is None  # the second copies
    assert vertex_set_change(pts, [0, 1, 2], t, [0, 5, 2]) is None
    twin = np.array([[0.0, 0.0], [0.0, 0.0], [1.0, 0.0], [0.0, 1.0]])
    assert vertex_set_change(twin, [0, 2, 3], reverse_rows(twin), [0, 1, 2]) is None  # row 1 or 0: the same point
