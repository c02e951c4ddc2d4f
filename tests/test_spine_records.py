"""Case ids, configs and the eps policy."""

import math

import numpy as np
import pytest

from hullstress.case import Case
from hullstress.config import AlgorithmConfig, expand_configs, single_config
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


def _origin_spec(name, origin, takes_eps, dim=2):
    return AlgorithmSpec(name=name, func=lambda p: None, dim=dim, takes_eps=takes_eps, origin=origin, summary="")


def test_default_variants_depend_on_origin():
    specs = [_origin_spec("seed", "in-house", True), _origin_spec("lib", "adapter", False),
             _origin_spec("mine", "plugin", True), _origin_spec("exe", "executable", False)]
    labels = [c.label for c in expand_configs(specs)]
    assert labels == [
        "exe[sphere=off,eps=n/a]", "lib[sphere=off,eps=n/a]", "mine[sphere=off,eps=n/a]",
        "seed[sphere=off,eps=fixed]", "seed[sphere=off,eps=scaled]", "seed[sphere=on,eps=fixed]",
        "seed[sphere=on,eps=scaled]",
    ]
    # Given explicitly, --sphere and --eps apply to everyone: `--sphere both` opts a library in.
    opted = [c.label for c in expand_configs(specs[1:3], sphere="both")]
    assert opted == ["lib[sphere=off,eps=n/a]", "lib[sphere=on,eps=n/a]",
                     "mine[sphere=off,eps=n/a]", "mine[sphere=on,eps=n/a]"]
    assert [c.label for c in expand_configs(specs[2:3], eps="fixed")] == ["mine[sphere=off,eps=fixed]"]
    assert [c.label for c in expand_configs(specs[:1], sphere="off")] == [
        "seed[sphere=off,eps=fixed]", "seed[sphere=off,eps=scaled]"]


def test_single_config_defaults_follow_the_origin():
    assert single_config(_origin_spec("seed", "in-house", True)).eps == "scaled"
    assert single_config(_origin_spec("mine", "plugin", True)).eps == "n/a"
    assert single_config(_origin_spec("mine", "plugin", True), "on", "fixed").label == "mine[sphere=on,eps=fixed]"
    assert single_config(_origin_spec("lib", "adapter", False), eps="fixed").eps == "n/a"


SCALES = [5e-324, 1e-310, 1e-300, 1e-160, 1e-150, 1e150, 1e154, 1e155, 1e200, 1e300, 1.7976931348623157e308]


@pytest.mark.parametrize("scale", SCALES)
def test_scaled_tolerance_is_finite_at_every_finite_scale(scale):
    # Issue 13: P'.P' overflowed above ~1e154 and the tolerance became inf (then NaN downstream).
    pts = np.array([[0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [0.0, -1.0, 0.0], [-1.0, 1.0, 0.5]]) * scale
    eps = tolerance(pts, "scaled")
    assert np.isfinite(eps) and eps >= 0.0
    # Nathan's formula in exact arithmetic: 2**-52 * (sqrt(2) - 0) * scale, up to rounding.
    exact = MACHINE_EPSILON * math.sqrt(2.0) * scale
    assert exact == 0.0 or abs(eps - exact) <= 4 * 2.0**-52 * exact or eps < 1e-300


def test_scaled_tolerance_is_the_literal_formula_where_that_is_finite():
    rng = np.random.default_rng(7)
    for exponent in range(-140, 141, 7):
        pts = rng.normal(size=(30, 3)) * 10.0**exponent
        flat = pts[:, :2]
        r2 = np.einsum("ij,ij->i", flat, flat)
        assert tolerance(pts, "scaled") == MACHINE_EPSILON * (np.sqrt(r2.max()) - np.sqrt(r2.min()))


@pytest.mark.parametrize("power", [-900, -500, -1, 1, 500, 900])
def test_scaled_tolerance_scales_exactly_with_a_power_of_two(power):
    pts = np.random.default_rng(3).normal(size=(20, 2))
    assert tolerance(np.ldexp(pts, power), "scaled") == np.ldexp(tolerance(pts, "scaled"), power)


def test_non_finite_input_gives_a_non_finite_tolerance_as_the_seed_would():
    assert math.isnan(tolerance(np.array([[np.nan, 0.0], [1.0, 1.0]])))
    assert math.isinf(tolerance(np.array([[np.inf, 0.0], [1.0, 1.0]])))
