"""``check`` without a reference builds Qhull's once and lets it settle the rank, with unchanged verdicts.

The default call used to test full rank first (a certificate of its own)
and then build the reference; now the reference comes first and its exact
witness simplex answers the rank question.  A lower-dimensional input must
still get the verdict it got before: no Qhull reference is attached to it
unless the caller gave one.
"""

from __future__ import annotations

import numpy as np

import hullstress.checker.api as api
import hullstress.checker.lowdim as lowdim
from hullstress.checker import check, qhull_reference


def _counting(monkeypatch, module, name):
    calls = []
    real = getattr(module, name)

    def wrapper(*args, **kwargs):
        calls.append(name)
        return real(*args, **kwargs)

    monkeypatch.setattr(module, name, wrapper)
    return calls


def test_a_full_dimensional_check_builds_one_reference_and_no_rank_certificate(monkeypatch):
    rng = np.random.default_rng(11)
    pts = rng.normal(size=(24, 3))
    faces = qhull_reference(pts).faces.indices.reshape(-1, 3)
    built = _counting(monkeypatch, api, "qhull_reference")
    ranked = _counting(monkeypatch, lowdim, "full_dimensional")
    verdict = check(pts, faces)
    assert verdict.ok and verdict.qhull_agreement == "agree"
    assert built == ["qhull_reference"] and ranked == []
    assert verdict == check(pts, faces, reference=qhull_reference(pts))


def test_a_flat_input_gets_no_qhull_witness_unless_given_one():
    pts = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0], [0.5, 0.5, 0]])
    faces = [[0, 1, 3], [0, 3, 2]]
    verdict = check(pts, faces)
    assert verdict == check(pts, faces, qhull=False)
    assert verdict.qhull_options is None and verdict.affine_rank == 2
    given = check(pts, faces, reference=qhull_reference(pts))
    assert given.qhull_options is not None  # a reference the caller gives is used


def test_a_segment_and_a_point_in_2d_are_judged_as_before():
    collinear = np.array([[0.0, 0], [1, 1], [2, 2], [3, 3]])
    same = np.array([[1.0, 2], [1, 2], [1, 2]])
    for pts, hull in ((collinear, [0, 3]), (same, [0])):
        assert check(pts, hull) == check(pts, hull, qhull=False)
