"""Registries: decorator API, unknown names listing the valid ones, duplicates, eps detection."""

import numpy as np
import pytest

import hullstress
from hullstress import _registry as reg
from hullstress.errors import DuplicateNameError, UnknownNameError, UsageError


@pytest.fixture
def scratch_names():
    names = []
    yield names
    for n in names:
        reg.ALGORITHMS.remove(n)
        reg.GENERATORS.remove(n)


def test_register_algorithm_records_dim_eps_origin(scratch_names):
    @hullstress.register_algorithm("test-reg-eps", dim=3)
    def with_eps(points, /, *, eps=None):
        """Docstring summary line."""
        return np.zeros((0, 3), dtype=int)

    @hullstress.register_algorithm("test-reg-noeps", dim=2)
    def without_eps(points):
        return [0, 1, 2]

    scratch_names += ["test-reg-eps", "test-reg-noeps"]
    a = reg.get_algorithm("test-reg-eps")
    b = reg.get_algorithm("test-reg-noeps")
    assert (a.dim, a.takes_eps, a.origin, a.summary) == (3, True, "plugin", "Docstring summary line.")
    assert (b.dim, b.takes_eps) == (2, False)
    assert a in reg.algorithms(dim=3) and a not in reg.algorithms(dim=2)


def test_unknown_names_list_valid_ones():
    with pytest.raises(UnknownNameError) as info:
        reg.get_algorithm("no-such-hull")
    msg = str(info.value)
    assert "no-such-hull" in msg and "valid names:" in msg
    for name in reg.ALGORITHMS.names():
        assert name in msg
    with pytest.raises(UnknownNameError, match="unknown generator 'nope'"):
        reg.get_generator("nope")


def test_duplicate_name_with_other_function_is_rejected(scratch_names):
    @hullstress.register_algorithm("test-reg-dup", dim=2)
    def first(points):
        return [0, 1, 2]

    scratch_names.append("test-reg-dup")
    # Re-registering the same function (a plug-in imported twice) is fine.
    hullstress.register_algorithm("test-reg-dup", dim=2)(first)

    def second(points):
        return [0, 1, 2]

    with pytest.raises(DuplicateNameError, match="already registered"):
        hullstress.register_algorithm("test-reg-dup", dim=2)(second)


@pytest.mark.parametrize(
    "call, message",
    [
        (lambda: hullstress.register_algorithm("", dim=3), "non-empty string"),
        (lambda: hullstress.register_algorithm("x", dim=4), "dim must be 2 or 3, got 4"),
        (lambda: hullstress.register_generator("g", dims=(1,)), "dims must be"),
    ],
)
def test_bad_registrations(call, message):
    with pytest.raises(UsageError, match=message):
        call()


def test_generator_defaults_and_variants(scratch_names):
    @hullstress.register_generator("test-reg-gen", dims=(2,), variants=({}, {"k": 3}))
    def gen(rng, n, *, dim, k=1, scale=1.0):
        """A test family."""
        return rng.random((n, dim)) * scale * k

    scratch_names.append("test-reg-gen")
    spec = reg.get_generator("test-reg-gen")
    assert dict(spec.defaults) == {"k": 1, "scale": 1.0}
    assert [dict(v) for v in spec.variants] == [{}, {"k": 3}]
    with pytest.raises(UsageError, match="unknown parameters"):
        hullstress.register_generator("test-reg-bad", variants=({"nope": 1},))(gen)
