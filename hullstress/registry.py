"""Registration without the heavy package: what plug-ins and generator families import.

Importing this module loads the standard library and hullstress's exception
tree only (no NumPy, SciPy or pandas), so a family module or a plug-in can
register itself cheaply, and a worker process starts fast.  The registries
themselves live in :mod:`hullstress._registry`; this module is their public face.

>>> from hullstress.registry import register_algorithm
>>> @register_algorithm("doc-registry-triangle", dim=2)
... def triangle(points):
...     '''The first three points, whatever the input (wrong on purpose).'''
...     return [0, 1, 2]
>>> from hullstress.registry import ALGORITHMS
>>> ALGORITHMS.remove("doc-registry-triangle")
"""

from ._registry import (
    ALGORITHMS,
    GENERATORS,
    AlgorithmSpec,
    GeneratorSpec,
    algorithms,
    generators,
    get_algorithm,
    get_generator,
    load_builtins,
    register_algorithm,
    register_executable,
    register_generator,
)

__all__ = [
    "ALGORITHMS",
    "GENERATORS",
    "AlgorithmSpec",
    "GeneratorSpec",
    "algorithms",
    "generators",
    "get_algorithm",
    "get_generator",
    "load_builtins",
    "register_algorithm",
    "register_executable",
    "register_generator",
]
