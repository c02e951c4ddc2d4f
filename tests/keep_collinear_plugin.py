"""A test plug-in: an exact 2D hull that keeps the points lying on its edges, registered as ``keep-collinear``.

Andrew's monotone chain in rationals, popping only on a strict clockwise turn,
so every input point on the hull's boundary is a vertex (counter-clockwise).
That is a correct hull under the lenient contract and a failure under the
strict one (only extreme points as vertices): the georust/geo #905 behaviour.
It raises ``ValueError`` on collinear input and on fewer than three distinct points.
"""

from __future__ import annotations

from fractions import Fraction

import numpy as np

from hullstress import register_algorithm


def _turn(o, a, b):
    return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])


@register_algorithm("keep-collinear", dim=2)
def keep_collinear(points: np.ndarray, /) -> list[int]:
    """Exact monotone chain keeping boundary points: every point on an edge is a vertex (a test plug-in)."""
    pts = np.asarray(points, dtype=np.float64)
    if pts.ndim != 2 or pts.shape[1] != 2 or not np.isfinite(pts).all():
        raise ValueError(f"need finite (n, 2) points, got shape {pts.shape}")
    first: dict[tuple[Fraction, Fraction], int] = {}
    for i, (x, y) in enumerate(pts.tolist()):
        first.setdefault((Fraction(x), Fraction(y)), i)
    keys = sorted(first)
    if len(keys) < 3 or all(_turn(keys[0], keys[1], k) == 0 for k in keys[2:]):
        raise ValueError("collinear input: no polygon")

    def chain(seq):
        out = []
        for k in seq:
            while len(out) >= 2 and _turn(out[-2], out[-1], k) < 0:
                out.pop()
            out.append(k)
        return out

    ring = chain(keys)[:-1] + chain(keys[::-1])[:-1]
    return [first[k] for k in ring]
