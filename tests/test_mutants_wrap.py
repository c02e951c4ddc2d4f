"""The wrap number (``hullstress/checker/wrap.py``), pinned where the mutation run found it loose.

Each test here was written against mutants of ``hullstress/checker/wrap.py`` that
survived the rest of the fast suite (``tools/mutation.sh``, README "Mutation
testing").  Every expectation comes from the documented behaviour (the module
docstring: a convex surface wraps once, a star polygon {k/2} twice) or from an
independent exact computation, never from the checker's own output.
"""

from __future__ import annotations

import numpy as np

from hullstress.checker.wrap import wrap_number_2d


def _star(k: int, step: int) -> tuple[np.ndarray, np.ndarray]:
    """k points on a circle and the polygon visiting every ``step``-th one."""
    t = 2 * np.pi * np.arange(k) / k
    pts = np.c_[np.cos(t), np.sin(t)]
    return pts, (np.arange(k) * step) % k


def test_a_convex_polygon_wraps_once_and_a_star_twice():
    for step, want in ((1, 1), (2, 2), (3, 3)):
        pts, poly = _star(7, step)
        assert wrap_number_2d(pts, poly, np.zeros(2), None) == want
