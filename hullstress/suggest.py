""""Did you mean ...?" for every name a user types: one helper, used wherever a name is looked up.

Algorithms, generators, executables, profiles, checks, transforms and the
command line's fixed choices all report an unknown name the same way: the
closest valid names first (:mod:`difflib`), then every valid name.
"""

from __future__ import annotations

import difflib
from collections.abc import Iterable

__all__ = ["close_names", "did_you_mean", "unknown_name"]

#: How alike two names must be to be suggested (difflib's ratio; 0.6 is its default).
CUTOFF = 0.6
#: At most this many suggestions.
MAX_SUGGESTIONS = 3


def close_names(name: object, valid: Iterable[str]) -> list[str]:
    """The valid names closest to ``name``, best first (empty when none is close).

    Examples
    --------
    >>> close_names("monotone-chian", ["jarvis-march", "monotone-chain", "quickhull-2d"])
    ['monotone-chain']
    """
    if not isinstance(name, str):
        return []
    choices = sorted(set(valid))
    found = difflib.get_close_matches(name, choices, n=MAX_SUGGESTIONS, cutoff=CUTOFF)
    if not found:  # a different case or a prefix ("Quick", "mono"): compare case-insensitively
        lowered = {c.lower(): c for c in choices}
        found = [lowered[c] for c in difflib.get_close_matches(name.lower(), list(lowered), n=MAX_SUGGESTIONS,
                                                                cutoff=CUTOFF)]
        found += [c for c in choices if c.lower().startswith(name.lower()) and name and c not in found]
    return found[:MAX_SUGGESTIONS]


def did_you_mean(name: object, valid: Iterable[str]) -> str:
    """``" (did you mean 'x'?)"`` (or ``'x' or 'y'``), or ``""`` when no valid name is close.

    Examples
    --------
    >>> did_you_mean("quik", ["quick", "nightly"])
    " (did you mean 'quick'?)"
    >>> did_you_mean("zzz", ["quick", "nightly"])
    ''
    """
    found = close_names(name, valid)
    if not found:
        return ""
    return " (did you mean " + " or ".join(repr(f) for f in found) + "?)"


def unknown_name(kind: str, name: object, valid: Iterable[str], *, listing: str = "valid names") -> str:
    """The one-line message for an unknown name: the suggestion first, then every valid name.

    Examples
    --------
    >>> unknown_name("algorithm", "monotone-chian", ["jarvis-march", "monotone-chain"])
    "unknown algorithm 'monotone-chian' (did you mean 'monotone-chain'?); valid names: jarvis-march, monotone-chain"
    """
    names = sorted(set(valid))
    listed = ", ".join(names) or "(none registered)"
    return f"unknown {kind} {name!r}{did_you_mean(name, names)}; {listing}: {listed}"
