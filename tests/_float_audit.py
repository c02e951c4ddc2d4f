"""A pytest plug-in that plays "another machine" for the in-house algorithm tests.

CI installs whatever numpy pip resolves that day, on whatever CPU it gets, and
some numpy operations take their last bits from CPU-specific code: LAPACK and
BLAS (``qr``, ``@``, ``dot``, ``matmul``), SIMD transcendental functions
(``cos``, ``sin``, ``power``, ``exp``, ``log``), and the reductions behind
``norm``.  A test whose outcome hinges on those bits passes here and fails
there.  This plug-in changes them on purpose::

    PYTHONPATH=tests HULLSTRESS_AUDIT_OPS_SEED=1 python -m pytest -p _float_audit tests/test_henckel.py
    PYTHONPATH=tests HULLSTRESS_AUDIT_EPS_ULPS=4 python -m pytest -p _float_audit tests/test_gift_wrap.py

* ``HULLSTRESS_AUDIT_OPS_SEED=S``: every result of the operations above gets
  random changes of up to 2 ulps (seeded by ``S``), in the tests and in the
  code under test alike.
* ``HULLSTRESS_AUDIT_EPS_ULPS=K``: every ``hullstress.tolerance.tolerance``
  result is multiplied by ``1 + K * 2**-52`` (its ``einsum`` is such a sum).

A test that passes unaudited and fails under either is asserting one float
trajectory; it should assert the documented outcome set instead.
"""

from __future__ import annotations

import importlib
import os
import sys

import numpy as np

_OPS = ("cos", "sin", "power", "exp", "log", "dot", "matmul")


def _jiggler(seed: int):
    rng = np.random.default_rng(seed)

    def jiggle(value):
        arr = np.asarray(value)
        if arr.dtype != np.float64 or arr.size == 0:
            return value
        out = arr.copy()
        steps = rng.integers(-2, 3, arr.shape)
        for _ in range(2):
            move = steps != 0
            out[move] = np.nextafter(out[move], np.where(steps[move] > 0, np.inf, -np.inf))
            steps = steps - np.sign(steps)
        return out if isinstance(value, np.ndarray) else float(out)

    return jiggle


def _patch_ops(seed: int) -> None:
    jiggle = _jiggler(seed)
    qr, norm = np.linalg.qr, np.linalg.norm

    def audited_qr(a, *args, **kwargs):
        result = qr(a, *args, **kwargs)
        return type(result)(*(jiggle(part) for part in result))

    np.linalg.qr = audited_qr
    np.linalg.norm = lambda *args, **kwargs: jiggle(norm(*args, **kwargs))
    for name in _OPS:
        func = getattr(np, name)
        setattr(np, name, lambda *args, _func=func, **kwargs: jiggle(_func(*args, **kwargs)))


def _patch_tolerance(ulps: int) -> None:
    importlib.import_module("hullstress.tolerance")
    original = sys.modules["hullstress.tolerance"].tolerance

    def audited(points, policy="scaled"):
        value = original(points, policy)
        return value * (1 + ulps * 2.0**-52) if np.isfinite(value) else value

    # Every module that imported the function by name, now and after collection.
    def rebind() -> None:
        for module in list(sys.modules.values()):
            if getattr(module, "tolerance", None) is original:
                module.tolerance = audited

    importlib.import_module("hullstress.algorithms")
    importlib.import_module("hullstress.sphere")
    rebind()
    _REBIND.append(rebind)


_REBIND: list = []


def pytest_configure(config) -> None:
    if "HULLSTRESS_AUDIT_OPS_SEED" in os.environ:
        _patch_ops(int(os.environ["HULLSTRESS_AUDIT_OPS_SEED"]))
    if "HULLSTRESS_AUDIT_EPS_ULPS" in os.environ:
        _patch_tolerance(int(os.environ["HULLSTRESS_AUDIT_EPS_ULPS"]))


def pytest_collection_modifyitems(session, config, items) -> None:
    for rebind in _REBIND:
        rebind()  # the test modules' own ``from hullstress.tolerance import tolerance``
