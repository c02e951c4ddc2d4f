"""Generator specs as text: ``near-coplanar:surface=plane,delta=1e-12`` <-> (name, params).

What ``run --generator`` and :func:`generators.compose.compose`'s ``base``
accept.  Grammar::

    spec   := NAME | NAME ":" params | NAME "(" params ")"
    params := item ("," item)*          commas inside parentheses belong to the value
    item   := KEY "=" VALUE

Each value is converted to the type of the parameter's declared default
(``true``/``false`` for bools; integers, also written ``1e6`` when exact;
floats in decimal or hex, ``0x1p-40``; strings as written).  A parameter whose
default is ``None`` takes the first of int, float, bool that parses, else the
text.  :func:`parse_spec` then calls the family once per dimension at its
smallest size, so a value the family refuses (``surface=oblique``) is reported
when the spec is read, with the family's own one-line message, which names
the parameter and its valid values.

Every error is a :class:`~hullstress.errors.UsageError` (exit status 2 on the
command line) whose message quotes the spec and names the offending key or
value and the valid ones.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

import numpy as np

from hullstress.registry import GeneratorSpec, get_generator
from hullstress.errors import GeneratorValueError, UnknownNameError, UsageError
from hullstress.suggest import did_you_mean

__all__ = ["parse_spec", "format_spec", "convert_value", "check_params"]

_TRUE = ("true", "yes", "on", "1")
_FALSE = ("false", "no", "off", "0")


def _split_top_level(text: str, spec_text: str) -> list[str]:
    """Split on commas that are not inside parentheses."""
    items, depth, start = [], 0, 0
    for i, ch in enumerate(text):
        if ch == "(":
            depth += 1
        elif ch == ")":
            depth -= 1
            if depth < 0:
                break
        elif ch == "," and depth == 0:
            items.append(text[start:i])
            start = i + 1
    if depth != 0:
        raise UsageError(f"generator spec {spec_text!r}: unbalanced parentheses")
    items.append(text[start:])
    return items


def _parse_float(text: str) -> float:
    t = text.strip()
    return float.fromhex(t) if t.lower().lstrip("+-").startswith("0x") else float(t)


def convert_value(family: str, key: str, text: str, default: Any) -> Any:
    """Convert ``text`` to the type of ``default`` (the parameter's declared default).

    Raises
    ------
    GeneratorValueError
        Naming ``key``, the text and the expected form.

    Examples
    --------
    >>> convert_value("near-coplanar", "delta", "1e-12", 1e-13)
    1e-12
    >>> convert_value("few-points", "repeat", "True", False)
    True
    >>> convert_value("near-collinear", "ulps", "1e3", 1)
    1000
    """
    t = text.strip()

    def bad(expected: str) -> GeneratorValueError:
        return GeneratorValueError(f"{family}: {key} must be {expected}, got {t!r}")

    if isinstance(default, (bool, np.bool_)):
        if t.lower() in _TRUE:
            return True
        if t.lower() in _FALSE:
            return False
        raise bad("true or false")
    if isinstance(default, (int, np.integer)):
        try:
            return int(t, 0)
        except ValueError:
            pass
        try:
            x = _parse_float(t)
        except ValueError:
            raise bad("an integer") from None
        if math.isfinite(x) and x == int(x) and abs(x) <= 2**53:
            return int(x)
        raise bad("an integer")
    if isinstance(default, (float, np.floating)):
        try:
            x = _parse_float(t)
        except ValueError:
            raise bad("a float (e.g. 1e-12 or 0x1p-40)") from None
        if not math.isfinite(x):
            raise bad("a finite float")
        return x
    if default is None:
        for kind in (0, 0.0, False):
            try:
                return convert_value(family, key, t, kind)
            except GeneratorValueError:
                pass
    if not t:
        raise bad("a non-empty value")
    return t


def _format_value(value: Any) -> str:
    if isinstance(value, (bool, np.bool_)):
        return "true" if value else "false"
    if isinstance(value, (float, np.floating)):
        return repr(float(value))
    return str(value)


def format_spec(name: str, params: Mapping[str, Any], *, nested: bool = False) -> str:
    """The text form of (name, params), keys sorted: ``parse_spec(format_spec(n, p)) == (n, p)``.

    ``nested=True`` writes ``name(k=v,...)``, the form used inside another
    spec (``compose:base=near-coplanar(surface=plane)``).

    Examples
    --------
    >>> format_spec("near-coplanar", {"surface": "plane", "delta": 1e-12})
    'near-coplanar:delta=1e-12,surface=plane'
    >>> format_spec("duplicates", {"mode": "every-point"}, nested=True)
    'duplicates(mode=every-point)'
    """
    body = ",".join(f"{k}={_format_value(params[k])}" for k in sorted(params))
    if not body:
        return name
    return f"{name}({body})" if nested else f"{name}:{body}"


def _split_name(text: str) -> tuple[str, str | None]:
    colon, paren = text.find(":"), text.find("(")
    if paren >= 0 and (colon < 0 or paren < colon):
        if not text.endswith(")"):
            raise UsageError(f"generator spec {text!r}: expected NAME(key=value,...) with a closing ')'")
        return text[:paren].strip(), text[paren + 1 : -1]
    if colon >= 0:
        return text[:colon].strip(), text[colon + 1 :]
    return text.strip(), None


def check_params(spec: GeneratorSpec, params: Mapping[str, Any], spec_text: str | None = None) -> None:
    """Call the family once per dimension at its smallest size; raise if every dimension refuses.

    A value valid in one dimension only (a 3D-only option) passes: the sweep
    skips the other dimension with the family's reason.
    """
    from . import generate, min_size  # the package imports this module first

    errors: list[str] = []
    for dim in spec.dims:
        try:
            n = min_size(spec.name, dim=dim, **params)
            generate(spec.name, n, dim=dim, seed=0, **params)
        except (UsageError, ValueError) as exc:
            errors.append(str(exc))
        else:
            return
    where = f"generator spec {spec_text!r}: " if spec_text is not None else ""
    raise GeneratorValueError(f"{where}{errors[0]}")


def parse_spec(text: str, *, validate: bool = True) -> tuple[str, dict[str, Any]]:
    """Parse ``NAME[:key=value,...]`` (or ``NAME(key=value,...)``) into (name, params).

    Parameters
    ----------
    text : str
        The spec, e.g. ``"near-coplanar:surface=plane,delta=1e-12"``.
    validate : bool
        Also run the family once per dimension at its smallest size, so a
        value it refuses is reported now (see :func:`check_params`).

    Returns
    -------
    name : str
        A registered family.
    params : dict
        Only the keys given, converted to their declared types.

    Raises
    ------
    hullstress.errors.UsageError
        One line quoting the spec: an unknown family (with the valid names),
        an unknown or repeated key (with the valid keys), a malformed item, a
        value of the wrong type, or a value the family refuses.

    Examples
    --------
    >>> parse_spec("near-coplanar:surface=plane,delta=1e-12")
    ('near-coplanar', {'surface': 'plane', 'delta': 1e-12})
    >>> parse_spec("near-coplanar:jitter=1e-12")
    Traceback (most recent call last):
    ...
    hullstress.errors.GeneratorValueError: generator spec 'near-coplanar:jitter=1e-12': unknown parameter 'jitter'; valid parameters of near-coplanar: delta, rotate, surface, ulps
    """
    if not isinstance(text, str) or not text.strip():
        raise UsageError(f"generator spec must be NAME or NAME:key=value,..., got {text!r}")
    name, body = _split_name(text.strip())
    try:
        spec = get_generator(name)
    except UnknownNameError as exc:
        raise UnknownNameError(f"generator spec {text!r}: {exc}") from None
    valid = ", ".join(sorted(spec.defaults)) or "(none)"
    params: dict[str, Any] = {}
    for item in _split_top_level(body, text) if body is not None and body.strip() else []:
        key, eq, value = item.partition("=")
        key = key.strip()
        if not eq or not key:
            raise GeneratorValueError(
                f"generator spec {text!r}: {item.strip()!r} is not key=value; valid parameters of {name}: {valid}"
            )
        if key not in spec.defaults:
            raise GeneratorValueError(
                f"generator spec {text!r}: unknown parameter {key!r}{did_you_mean(key, spec.defaults)}; "
                f"valid parameters of {name}: {valid}"
            )
        if key in params:
            raise GeneratorValueError(f"generator spec {text!r}: parameter {key!r} given twice")
        try:
            params[key] = convert_value(name, key, value, spec.defaults[key])
        except GeneratorValueError as exc:
            raise GeneratorValueError(f"generator spec {text!r}: {exc}") from None
    if validate:
        check_params(spec, params, text)
    return name, params
