"""The checker against the independent exact verdict on random small hulls with one random defect.

Qhull's hull of a few lattice points (many coplanar and collinear), at unit,
~1e-300 or ~1e300 scale, with one corruption drawn by Hypothesis: a face
removed, turned over, duplicated or given a wrong vertex, a vertex moved one
ulp, a 2D vertex dropped or an index inserted.  The failed checks, the
severity and the counts must be what ``tests/_exact_verdict.py`` computes in
integers.  The negative corpus pins chosen defects; this explores the rest.
"""

from __future__ import annotations

import numpy as np
from hypothesis import assume, given
from hypothesis import strategies as st
from scipy.spatial import ConvexHull, QhullError

from _exact_verdict import dot, exact_verdict, normal, sub, to_integers
from hullstress.checker import check

SCALES = (1.0, 2.0**-1000, 2.0**990)
OPS = ("none", "drop", "flip", "duplicate", "ulp", "wrong-vertex", "insert")


def _outward_triangles(points: np.ndarray, simplices) -> list[list[int]]:
    ints, _ = to_integers(points.tolist())
    distinct = sorted(set(ints))
    total = tuple(sum(p[i] for p in distinct) for i in range(3))
    faces = []
    for a, b, c in simplices:
        up = dot(normal(ints[a], ints[b], ints[c]), sub(total, tuple(len(distinct) * x for x in ints[a]))) > 0
        faces.append([a, c, b] if up else [a, b, c])
    return faces


@given(
    dim=st.sampled_from([2, 3]),
    ints=st.lists(st.lists(st.integers(-4, 4), min_size=3, max_size=3), min_size=5, max_size=10),
    scale=st.sampled_from(SCALES),
    op=st.sampled_from(OPS),
    where=st.integers(0, 2**16),
    toward=st.sampled_from([np.inf, -np.inf]),
)
def test_checker_matches_the_exact_verdict(dim, ints, scale, op, where, toward):
    pts = np.array(ints, dtype=np.float64)[:, :dim]
    try:
        hull = ConvexHull(pts)  # on the small integers: Qhull is exact there
    except QhullError:
        assume(False)
    pts = pts * scale
    n = len(pts)
    if dim == 2:
        faces = [int(i) for i in hull.vertices]
    else:
        faces = _outward_triangles(pts, hull.simplices.tolist())
    k = where % len(faces)
    if op == "drop" and (dim == 3 or len(faces) > 3):
        faces.pop(k)
    elif op == "flip":
        faces = faces[::-1] if dim == 2 else faces[:k] + [faces[k][::-1]] + faces[k + 1:]
    elif op == "duplicate":
        faces.append(faces[k])
    elif op == "ulp":
        v = faces[k] if dim == 2 else faces[k][0]
        # A subnormal beside ~1e300 coordinates crashes Qhull inside the checker: pinned by
        # the xfail corpus entry huge-with-subnormal-coordinate, kept out of this process.
        assume(not (scale > 1 and pts[v, where % dim] == 0))
        pts[v, where % dim] = np.nextafter(pts[v, where % dim], toward)
    elif op == "wrong-vertex" and dim == 3:
        faces[k] = [faces[k][0], faces[k][1], where % n]
    elif op == "insert" and dim == 2:
        faces.insert(k, where % n)
    exact = exact_verdict(pts.tolist(), faces)
    assume(not any("factor 2" in note for note in exact.notes))  # too close to a threshold to call
    v = check(pts, faces)
    assert v.qhull_ok == exact.qhull_ok, v.detail
    failed = list(v.failed_checks)
    if exact.convexity is None:  # a face plane cuts the surface: the checker's interior point decides
        failed = [c for c in failed if c != "convexity"]
    assert failed == exact.failed, f"{v.detail} | exact: {exact.notes}"
    if exact.severity != "unknown":
        assert v.severity == exact.severity, f"{v.detail} | exact: {exact.magnitudes}"
    assert v.n_outside == exact.counts["n_outside"]
    assert v.affine_rank == exact.counts["affine_rank"]
    assert v.n_hull_vertices == exact.counts["n_hull_vertices"]
    if v.n_extreme is not None:
        assert v.n_extreme == exact.counts["n_extreme"]
        assert v.n_missing_extreme == exact.counts["n_missing_extreme"]
