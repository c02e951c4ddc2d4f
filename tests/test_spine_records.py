"""Case ids, configs and the eps policy."""

import math

import numpy as np
import pytest

from hullstress.case import Case
from hullstress.config import AlgorithmConfig, expand_configs
from hullstress.errors import UsageError
from hullstress.tolerance import MACHINE_EPSILON, tolerance
from hullstress._registry import AlgorithmSpec


def test_case_id_depends_on_exact_bytes_and_provenance():
    pts = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]])
    a = Case(points=pts, dim=2, family="f", params={"k": 1}, seed=3)
    b = Case(points=pts.copy(), dim=2, family="f", params={"k": 1}, seed=3)
    assert a.case_id == b.case_id and len(a.case_id) == 16
    bumped = pts.copy()
    bumped[1, 0] = math.nextafter(1.0, 2.0)
    assert Case(points=bumped, dim=2, family="f", params={"k": 1}, seed=3).case_id != a.case_id
    assert Case(points=pts, dim=2, family="f", params={"k": 2}, seed=3).case_id != a.case_id
    assert a.content_hash == Case(points=pts, dim=2, family="g").content_hash
    # -0.0 and 0.0 are different bytes, hence different cases.
    neg = pts.copy()
    neg[0, 0] = -0.0
    assert Case(points=neg, dim=2, family="f", params={"k": 1}, seed=3).case_id != a.case_id


def test_case_points_are_frozen_copies():
    src = np.array([[0.0, 0.0, 0.0]])
    c = Case.from_points(src)
    src[0, 0] = 5.0
    assert c.points[0, 0] == 0.0 and not c.points.flags.writeable and c.points.flags.c_contiguous
    assert c.dim == 3


def test_tolerance_matches_nathans_formula():
    pts = np.array([[3.0, 4.0, 100.0], [0.0, 1.0, -7.0], [6.0, 8.0, 0.0]])
    # sqrt(max P'.P') - sqrt(min P'.P') on the X-Y flattened points: 10 - 1
    assert tolerance(pts, "scaled") == MACHINE_EPSILON * 9.0
    assert tolerance(pts, "fixed") == MACHINE_EPSILON == 2.0**-52
    assert tolerance(np.array([[1.0, 0.0], [0.0, -1.0]]), "scaled") == 0.0  # the seed's quirk
    with pytest.raises(UsageError, match="eps policy must be one of"):
        tolerance(pts, "loose")


def _spec(name, dim, takes_eps):
    return AlgorithmSpec(name=name, func=lambda p: None, dim=dim, takes_eps=takes_eps, origin="plugin", summary="")


def test_expand_configs_applies_eps_only_where_taken():
    configs = expand_configs([_spec("a", 2, True), _spec("b", 3, False)], sphere="both", eps="both")
    labels = [c.label for c in configs]
    assert labels == [
        "a[sphere=off,eps=fixed]", "a[sphere=off,eps=scaled]", "a[sphere=on,eps=fixed]",
        "a[sphere=on,eps=scaled]", "b[sphere=off,eps=n/a]", "b[sphere=on,eps=n/a]",
    ]
    only = expand_configs([_spec("a", 2, True)], sphere="on", eps="fixed")
    assert only == [AlgorithmConfig("a", "on", "fixed")]
    with pytest.raises(UsageError, match="--sphere must be one of off, on, both, got 'maybe'"):
        expand_configs([], sphere="maybe")
    with pytest.raises(UsageError, match="sphere must be 'off' or 'on'"):
        AlgorithmConfig("a", "both")
