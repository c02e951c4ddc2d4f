"""hullstress: a robustness test harness and degeneracy fuzzer for convex hull algorithms.

Public surface (everything else lives in modules whose names start with ``_``
or is documented as internal):

>>> from hullstress import register_algorithm, check
"""

from ._registry import (
    AlgorithmSpec,
    GeneratorSpec,
    algorithms,
    generators,
    get_algorithm,
    get_generator,
    register_algorithm,
    register_generator,
)
from .case import Case
from .checker import check, qhull_reference
from .config import AlgorithmConfig, expand_configs
from .contract import FaceSet, normalize_output
from .errors import (
    AlgorithmStepLimit,
    ContractViolation,
    CorpusError,
    DuplicateNameError,
    HullstressError,
    InputFileError,
    UnknownNameError,
    UsageError,
)
from .evaluate import evaluate
from .results import ResultRow, to_frame
from .records import Stage
from .tolerance import EpsPolicy, tolerance
from .verdict import Verdict

__version__ = "0.1.0"

__all__ = [
    "AlgorithmConfig",
    "AlgorithmSpec",
    "AlgorithmStepLimit",
    "Case",
    "ContractViolation",
    "CorpusError",
    "DuplicateNameError",
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
    "register_generator",
    "to_frame",
    "tolerance",
]
