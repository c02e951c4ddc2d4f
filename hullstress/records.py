"""The vocabulary of result records: one home for the enums every stage shares.

A value of these enums is what the results table stores (their ``value``
strings: ``"preprocess"``, ``"in-house"``), and because they subclass
``str`` they compare equal to those strings, so code reading an old table or
a plain dict needs no conversion.

Every word a row's ``status``, ``stage``, ``severity``, ``sphere``, ``eps``
and ``origin`` columns can hold is a member here; code elsewhere names the
member, never the string (``tests/test_vocabulary.py`` enforces it).
``str()`` and ``format()`` of a member give its value, so f-strings and CSV
files read ``fail``, not ``Status.FAIL``.
"""

from __future__ import annotations

from enum import Enum

__all__ = ["Status", "FAILED_STATUSES", "Severity", "Sphere", "EpsPolicy", "NO_EPS", "Stage", "Origin",
           "SphereStructure", "CONTRACT_REASON", "METHOD_REASON"]

#: How the reason of a row that broke the output contract begins.
CONTRACT_REASON = "output contract:"
#: How the reason of a failure of the sphere method (stage preprocess) begins.
METHOD_REASON = "sphere method:"


class _Word(str, Enum):
    """A member that prints as its value (``f"{Status.FAIL}"`` is ``fail`` on every Python)."""

    def __str__(self) -> str:
        return str(self.value)

    def __format__(self, spec: str) -> str:
        return format(str(self.value), spec)

    # Enum hashes the member's name; a word must hash as its value so ``"fail" in {Status.FAIL}`` holds.
    __hash__ = str.__hash__


class Status(_Word):
    """How one call ended; every row has exactly one (docs/design.md, "Statuses and stages").

    Attributes
    ----------
    PASS
        A hull that passed every check (or a correct answer for degenerate or invalid input).
    FAIL
        A hull that failed a check, or output that broke the contract.
    REJECTED
        The algorithm declined input it may decline (degenerate or invalid): fine.
    ERROR
        The algorithm (or a harness stage, see :class:`Stage`) raised.
    TIMEOUT
        The call exceeded its time limit and was killed.
    CRASH
        The process running the call died (a signal, a memory limit).

    Examples
    --------
    >>> Status("fail") is Status.FAIL, f"{Status.CRASH}", "error" in FAILED_STATUSES
    (True, 'crash', True)
    """

    PASS = "pass"
    FAIL = "fail"
    REJECTED = "rejected"
    ERROR = "error"
    TIMEOUT = "timeout"
    CRASH = "crash"


#: The statuses that count as failures (everything but pass and rejected), in table order; members equal
#: their strings, so ``"fail" in FAILED_STATUSES`` and ``column.isin(FAILED_STATUSES)`` both work.
FAILED_STATUSES = (Status.FAIL, Status.ERROR, Status.TIMEOUT, Status.CRASH)


class Severity(_Word):
    """How far a failed hull is from a correct one (:mod:`hullstress.checker.severity`).

    Attributes
    ----------
    NONE
        Nothing failed.
    ROUNDOFF
        Every violation within a small multiple of Qhull's DISTround.
    GROSS
        A larger violation, or a topological defect.
    """

    NONE = "none"
    ROUNDOFF = "roundoff"
    GROSS = "gross"


class Sphere(_Word):
    """Whether a config runs the algorithm on the sphere projection of its input."""

    OFF = "off"
    ON = "on"


class EpsPolicy(_Word):
    """How an algorithm's comparison tolerance is derived from its input (:mod:`hullstress.tolerance`)."""

    SCALED = "scaled"
    FIXED = "fixed"


#: The ``eps`` column's value for algorithms that take no eps.
NO_EPS = "n/a"


class Stage(_Word):
    """The part of one call that produced a row's verdict.

    Attributes
    ----------
    PREPROCESS
        The harness's preprocessing of the variant: the sphere method
        (duplicate removal, support mapping, projection, and mapping the
        algorithm's hull back) and the eps set-up.  Its failures are findings
        about that method, never charged to the algorithm.
    ALGORITHM
        The algorithm itself, judged on the points it was given.
    CHECK
        The harness's own judging: case facts, the exact checker.  A row with
        this stage is an internal error of hullstress.

    Examples
    --------
    >>> Stage("preprocess") is Stage.PREPROCESS, Stage.CHECK == "check"
    (True, True)
    """

    PREPROCESS = "preprocess"
    ALGORITHM = "algorithm"
    CHECK = "check"


class Origin(_Word):
    """Where a registered algorithm comes from; decides its default variants.

    Attributes
    ----------
    IN_HOUSE
        An implementation of a seed document (``hullstress.algorithms``).
    ADAPTER
        A wrapped library (``hullstress.adapters``).
    PLUGIN
        Registered by user code or a ``--plugin`` module.
    EXECUTABLE
        A program run through the executable adapter.
    """

    IN_HOUSE = "in-house"
    ADAPTER = "adapter"
    PLUGIN = "plugin"
    EXECUTABLE = "executable"


class SphereStructure(_Word):
    """Whether the exact hull of a sphere projection, mapped back, is the input's hull.

    The column ``sphere_structure`` (:mod:`hullstress.sphere_causes`); empty
    when no projection was made.

    Attributes
    ----------
    SAME
        The certified hull of the projected points, mapped back, is the input's hull.
    CHANGED
        It is not (a vertex was lost, or the faces differ).
    UNKNOWN
        The projected points have no certified hull to map back.
    ERROR
        The checker raised on the mapped-back hull (a bug of hullstress).
    """

    SAME = "same"
    CHANGED = "changed"
    UNKNOWN = "unknown"
    ERROR = "error"
