"""Imported once by the multiprocessing fork server, so that workers start with everything loaded.

Every worker is forked from the fork server, so whatever this module imports
is already in memory when a worker starts: replacing a worker after a crash
costs a fork (milliseconds), not a fresh interpreter importing NumPy and
SciPy (about half a second).  Nothing here may raise: an exception would kill
the fork server, and with it every worker start.
"""

from __future__ import annotations

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
