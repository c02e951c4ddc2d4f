"""Float literals read exactly as written: decimal (correctly rounded) and C99 hexadecimal.

One home for the token parser every points and hull format shares
(:mod:`hullstress.io`, :mod:`hullstress.qhull_format`).
"""

from __future__ import annotations

import math
import re

__all__ = ["parse_float"]

_HEX_RE = re.compile(r"^[+-]?0[xX]")


def parse_float(token: str) -> float:
    """Parse one decimal or hexadecimal float literal exactly.

    Parameters
    ----------
    token : str
        ``"0.1"``, ``"-1e-300"``, ``"4.9e-324"``, ``"0x1.8p-3"``, ``"-0x0p+0"``.

    Returns
    -------
    float
        The correctly rounded double (decimal) or the exact double (hex); a
        literal beyond the largest double is ±inf in both notations.

    Raises
    ------
    ValueError
        When ``token`` is not a float literal.

    Examples
    --------
    >>> parse_float("0x1.8p-3"), parse_float("1e-320") > 0
    (0.1875, True)
    """
    if _HEX_RE.match(token):
        try:
            return float.fromhex(token)
        except OverflowError:  # as float("1e999") does: too large is infinite (then refused as non-finite)
            return -math.inf if token.startswith("-") else math.inf
    return float(token)
