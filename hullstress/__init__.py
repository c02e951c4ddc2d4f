"""hullstress: a robustness test harness and degeneracy fuzzer for convex hull algorithms.

Public surface (everything else lives in modules whose names start with ``_``
or is documented as internal):

>>> from hullstress import register_algorithm, check

Importing the package is cheap: the registry and the exception tree load at
once, everything that needs NumPy, SciPy or pandas (the checker, the results
table, the runner) on first use of its name.  Plug-ins and generator families
register through the light :mod:`hullstress.registry`.
"""

from __future__ import annotations

from importlib import import_module
from typing import TYPE_CHECKING, Any

from ._registry import (
    AlgorithmSpec,
    GeneratorSpec,
    algorithms,
    generators,
    get_algorithm,
    get_generator,
    register_algorithm,
    register_executable,
    register_generator,
)
from .errors import (
    AlgorithmStepLimit,
    ContractViolation,
    CorpusError,
    DuplicateNameError,
    EnvironmentFailure,
    HullstressError,
    InputFileError,
    UnknownNameError,
    UsageError,
)

__version__ = "0.1.0"

#: Public names loaded on first use, with the module that defines each.
_LAZY = {
    "AlgorithmConfig": "config",
    "expand_configs": "config",
    "Case": "case",
    "check": "checker",
    "qhull_reference": "checker",
    "FaceSet": "contract",
    "normalize_output": "contract",
    "evaluate": "evaluate",
    "ResultRow": "results",
    "to_frame": "results",
    "EpsPolicy": "tolerance",
    "Stage": "records",
    "tolerance": "tolerance",
    "Verdict": "verdict",
}

if TYPE_CHECKING:  # static analysers see the eager imports
    from .case import Case
    from .checker import check, qhull_reference
    from .config import AlgorithmConfig, expand_configs
    from .contract import FaceSet, normalize_output
    from .evaluate import evaluate
    from .records import Stage
    from .results import ResultRow, to_frame
    from .tolerance import EpsPolicy, tolerance
    from .verdict import Verdict


def __getattr__(name: str) -> Any:
    home = _LAZY.get(name)
    if home is None:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    value = getattr(import_module(f"{__name__}.{home}"), name)
    globals()[name] = value  # later lookups skip this function
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(_LAZY))


__all__ = [
    "AlgorithmConfig",
    "AlgorithmSpec",
    "AlgorithmStepLimit",
    "Case",
    "ContractViolation",
    "CorpusError",
    "DuplicateNameError",
    "EnvironmentFailure",
    "EpsPolicy",
    "FaceSet",
    "GeneratorSpec",
    "HullstressError",
    "InputFileError",
    "ResultRow",
    "Stage",
    "UnknownNameError",
    "UsageError",
    "Verdict",
    "algorithms",
    "check",
    "evaluate",
    "expand_configs",
    "generators",
    "get_algorithm",
    "get_generator",
    "normalize_output",
    "qhull_reference",
    "register_algorithm",
    "register_executable",
    "register_generator",
    "to_frame",
    "tolerance",
]
