"""The vocabulary of result records: one home for the enums every stage shares.

A value of these enums is what the results table stores (their ``value``
strings: ``"preprocess"``, ``"in-house"``), and because they subclass
``str`` they compare equal to those strings, so code reading an old table or
a plain dict needs no conversion.

Only :class:`Stage`, :class:`Origin` and :class:`SphereStructure` live here so far; ``Status``,
``Severity``, ``Sphere`` and ``EpsPolicy`` are meant to move here too (see
DESIGN.md, "Layout").
"""

from __future__ import annotations

from enum import Enum

__all__ = ["Stage", "Origin", "SphereStructure", "CONTRACT_REASON", "METHOD_REASON"]

#: How the reason of a row that broke the output contract begins.
CONTRACT_REASON = "output contract:"
#: How the reason of a failure of the sphere method (stage preprocess) begins.
METHOD_REASON = "sphere method:"


class Stage(str, Enum):
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


class Origin(str, Enum):
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


class SphereStructure(str, Enum):
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
