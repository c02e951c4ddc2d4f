"""The exception tree of hullstress.

Every error the harness raises on purpose derives from :class:`HullstressError`.
The command line maps :class:`UsageError` (and its subclasses) to exit status 2
with the message on one line; anything else escaping is an internal error
(exit status 3).
"""

from __future__ import annotations

import re

__all__ = [
    "HullstressError",
    "UsageError",
    "UnknownNameError",
    "DuplicateNameError",
    "InputFileError",
    "ContractViolation",
    "AlgorithmStepLimit",
    "CorpusError",
    "GeneratorValueError",
    "one_line",
]


class HullstressError(Exception):
    """Root of every error raised by hullstress itself."""


class UsageError(HullstressError):
    """A bad argument or option value given by the user (exit status 2)."""


class UnknownNameError(UsageError, KeyError):
    """A registry lookup for a name that is not registered."""

    def __str__(self) -> str:  # KeyError would quote the message
        return str(self.args[0]) if self.args else ""


class DuplicateNameError(HullstressError):
    """A second, different object registered under a name already taken."""


class InputFileError(UsageError):
    """A points or faces file that is missing, unreadable or malformed."""


class ContractViolation(HullstressError):
    """An algorithm's output breaks the output contract of DESIGN.md."""


class AlgorithmStepLimit(HullstressError):
    """An in-house algorithm hit its iteration guard (it would loop forever)."""


class CorpusError(HullstressError):
    """A regression-corpus file that cannot be read or written."""


class GeneratorValueError(UsageError, ValueError):
    """A generator argument out of range, e.g. too few points for the family (also a ValueError)."""


def one_line(exc: BaseException) -> str:
    """``TypeName: message`` on one line: the form of every ``reason`` in a results table.

    Qhull appends "While executing: ... run-id <random>" to its errors; that
    tail differs between runs and would make identical runs' tables differ, so
    it is cut.

    Examples
    --------
    >>> one_line(ValueError("need\\n3 points"))
    'ValueError: need 3 points'
    """
    text = re.split(r"\s+While executing:", str(exc), maxsplit=1)[0]
    text = " ".join(text.split())
    return f"{type(exc).__name__}: {text}" if text else type(exc).__name__
