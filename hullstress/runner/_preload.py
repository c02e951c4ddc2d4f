"""Imported once by the multiprocessing fork server, so that workers start with everything loaded.

Every worker is forked from the fork server, so whatever this module imports
is already in memory when a worker starts: replacing a worker after a crash
costs a fork (milliseconds), not a fresh interpreter importing NumPy and
SciPy (about half a second).  Nothing here may raise: an exception would kill
the fork server, and with it every worker start.
"""

from __future__ import annotations

import gc
import os

from ._worker import THREAD_ENV

# The fork server inherits the parent's environment when it starts; make the
# numerical libraries it loads single-threaded before they read it.
for _key, _value in THREAD_ENV.items():
    os.environ.setdefault(_key, _value)

try:
    import numpy  # noqa: F401
    import scipy.spatial  # noqa: F401

    from .. import contract, evaluate, results, sphere, tolerance  # noqa: F401
    from .._registry import load_builtins
    from . import _protocol  # noqa: F401

    load_builtins()
except Exception:  # a broken optional piece must not take the fork server down; workers re-import
    pass

try:
    from .. import checker  # noqa: F401
except Exception:
    pass


def _judge_one_case_per_dimension() -> None:
    """Judge one small case in 2D and in 3D (Qhull's own output): the set-ups a first job would pay."""
    import numpy as np

    from ..case import Case
    from ..config import AlgorithmConfig
    from ..evaluate import call_algorithm, case_facts, judge

    rng = np.random.default_rng(0)
    for dim, name in ((2, "scipy-qhull-2d"), (3, "scipy-qhull-3d")):
        case = Case.from_points(rng.random((12, dim)))
        config = AlgorithmConfig(name)
        judge(case, config, call_algorithm(case, config), case_facts(case))


# A worker's first job pays for whatever its process touches for the first time (lazy set-ups in
# NumPy, SciPy's Qhull and the checker; memory copied on write after the fork).  Triage runs each
# candidate of a crash's shrink in a fresh worker, about a hundred per quick run: do those set-ups
# once, here, before any fork (about 3 ms).
try:
    _judge_one_case_per_dimension()
except Exception:
    pass

# Everything loaded so far lives as long as any worker: keep it out of the collector's sweeps, which
# in each worker would touch (and so copy) every page of it.
gc.freeze()
