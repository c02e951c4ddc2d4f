"""One registered form of an in-house algorithm: its seed as written, or a named improvement.

Where a seed's text has a weakness that an implementation could quietly fix,
the algorithm is registered twice from one module: under its own name, as the
seed writes it, and under a suffixed name with the fix (``henckel`` and
``henckel-normalised``).  A run carries its :class:`SeedVariant`, so the code
branches on one flag and every message names the registry entry that ran.
"""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["SeedVariant"]


@dataclass(frozen=True)
class SeedVariant:
    """Which form of an algorithm runs.

    Attributes
    ----------
    name : str
        The registry name, used as the prefix of every error message.
    improved : bool
        False: the seed as written, weak spots included.  True: the module's
        one named improvement (its docstring says which).
    """

    name: str
    improved: bool
