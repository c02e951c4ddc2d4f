"""Generator specs from text (``near-coplanar:surface=plane,delta=1e-12``): parsing, round trips, errors."""

from __future__ import annotations

import pytest

import generators as G
from generators.spec import convert_value, format_spec, parse_spec
from hullstress._registry import generators as registered
from hullstress.errors import UnknownNameError, UsageError


GOOD = [
    ("near-coplanar", ("near-coplanar", {})),
    ("  near-coplanar  ", ("near-coplanar", {})),
    ("near-coplanar:surface=plane,delta=1e-12", ("near-coplanar", {"surface": "plane", "delta": 1e-12})),
    ("near-coplanar: surface = plane , delta = 0x1p-40", ("near-coplanar", {"surface": "plane", "delta": 2.0**-40})),
    ("near-collinear:ulps=16,apex=true", ("near-collinear", {"ulps": 16, "apex": True})),
    ("near-collinear:ulps=1e3", ("near-collinear", {"ulps": 1000})),
    ("few-points:count=d+2,repeat=yes", ("few-points", {"count": "d+2", "repeat": True})),
    ("duplicates(mode=every-point,copies=3)", ("duplicates", {"mode": "every-point", "copies": 3})),
    ("offset:offset=1e9", ("offset", {"offset": 1e9})),
    (
        "compose:base=near-coplanar(surface=plane,ulps=2),offset=1e8,float32=false",
        ("compose", {"base": "near-coplanar(surface=plane,ulps=2)", "offset": 1e8, "float32": False}),
    ),
    ("compose:base=prism", ("compose", {"base": "prism"})),  # valid in 3D only: accepted, 2D is skipped
]


@pytest.mark.parametrize("text, expected", GOOD, ids=[g[0].strip() for g in GOOD])
def test_parse_good_specs(text, expected):
    name, params = parse_spec(text)
    assert (name, params) == expected
    for key, value in params.items():
        assert type(value) is type(expected[1][key])  # ints stay ints, bools bools


def _variant_ids():
    return [(s.name, dict(v)) for s in registered() for v in s.variants]


@pytest.mark.parametrize("name, variant", _variant_ids(), ids=[f"{n}-{i}" for i, (n, _) in enumerate(_variant_ids())])
def test_every_registered_variant_round_trips_through_text(name, variant):
    text = format_spec(name, variant)
    got_name, got = parse_spec(text, validate=False)
    assert got_name == name and got == variant
    assert {k: type(v) for k, v in got.items()} == {k: type(v) for k, v in variant.items()}
    nested = format_spec(name, variant, nested=True)
    assert parse_spec(nested, validate=False) == (name, variant)


def test_parse_then_generate_gives_the_variant_case():
    name, params = parse_spec("near-coplanar:surface=plane,ulps=2")
    a = G.generate(name, 20, dim=3, seed=1, **params)
    b = G.generate("near-coplanar", 20, dim=3, seed=1, surface="plane", ulps=2)
    assert a.tobytes() == b.tobytes()


BAD = [
    ("", ["generator spec must be NAME"]),
    ("no-such-family:x=1", ["'no-such-family:x=1'", "unknown generator 'no-such-family'", "valid names:", "uniform"]),
    (
        "near-coplanar:jitter=1e-12,plane=oblique",
        ["unknown parameter 'jitter'", "valid parameters of near-coplanar: delta, rotate, surface, ulps"],
    ),
    ("near-coplanar:surface=oblique", ["surface must be one of 'cube', 'plane', 'sphere'", "got 'oblique'"]),
    ("near-coplanar:delta=abc", ["delta must be a float", "'abc'"]),
    ("near-coplanar:delta=nan", ["delta must be a finite float", "'nan'"]),
    ("near-coplanar:delta=-1", ["delta", "-1"]),
    ("few-points:repeat=maybe", ["repeat must be true or false", "'maybe'"]),
    ("near-collinear:ulps=1.5", ["ulps must be an integer", "'1.5'"]),
    ("near-coplanar:delta", ["'delta' is not key=value", "valid parameters of near-coplanar"]),
    ("near-coplanar:delta=1e-9,delta=1e-8", ["parameter 'delta' given twice"]),
    ("near-coplanar:=1", ["'=1' is not key=value"]),
    ("duplicates(mode=some", ["closing ')'"]),
    ("compose:base=near-coplanar(surface=plane", ["unbalanced parentheses"]),
    ("compose:base=kettner-classroom", ["base must be a family that takes n", "'kettner-classroom'"]),
    ("compose:base=near-coplanar(jitter=1)", ["unknown parameter 'jitter'"]),
    ("compose:base=uniform,repeat=1.5", ["repeat must be a float in [0, 1)", "1.5"]),
    ("prism:layers=1", ["layers must be an integer in [2, 64]", "got 1"]),
    ("sliver-tetrahedron:kind=cube", ["kind must be one of", "'cube'"]),
]


@pytest.mark.parametrize("text, words", BAD, ids=[b[0] or "empty" for b in BAD])
def test_bad_specs_raise_one_line_usage_errors(text, words):
    with pytest.raises(UsageError) as info:
        parse_spec(text)
    message = str(info.value)
    assert "\n" not in message
    for word in words:
        assert word in message, message
    if text:
        assert repr(text.strip()) in message  # the offending spec is quoted


def test_unknown_family_is_an_unknown_name_error():
    with pytest.raises(UnknownNameError):
        parse_spec("nope")


def test_validate_false_skips_the_families_own_checks():
    assert parse_spec("near-coplanar:surface=oblique", validate=False) == ("near-coplanar", {"surface": "oblique"})
    with pytest.raises(UsageError, match="unknown parameter"):
        parse_spec("near-coplanar:oblique=1", validate=False)  # names and types are always checked


CONVERSIONS = [
    ("1e-12", 0.5, 1e-12),
    ("-0x1.8p1", 0.5, -3.0),
    ("7", 0.5, 7.0),
    ("0x10", 3, 16),
    ("2e3", 3, 2000),
    ("FALSE", True, False),
    ("on", False, True),
    ("plane", "cube", "plane"),
    ("12", None, 12),
    ("1.5", None, 1.5),
    ("true", None, True),
    ("text", None, "text"),
]


@pytest.mark.parametrize("text, default, expected", CONVERSIONS)
def test_values_take_the_type_of_the_declared_default(text, default, expected):
    got = convert_value("fam", "key", text, default)
    assert got == expected and type(got) is type(expected)


def test_format_spec_is_canonical():
    assert format_spec("near-coplanar", {"surface": "plane", "delta": 1e-12}) == "near-coplanar:delta=1e-12,surface=plane"
    assert format_spec("uniform", {}) == "uniform"
    assert format_spec("few-points", {"repeat": True}, nested=True) == "few-points(repeat=true)"
