"""Does a case still fail the same way?  One judged call, isolated when possible.

Shrinking and fuzzing call the code under test hundreds of times on point
sets nobody has tried before, so a segfault or a hang is likely.  When the
runner offers ``hullstress.runner.run_one`` (one call in a worker process with
a timeout) every call goes through it.  Without it, calls run in this process
through :func:`hullstress.evaluate.evaluate`, which is only safe for failures
that return or raise (``fail`` and ``error``); reproducing a ``timeout`` or a
``crash`` then raises :class:`IsolationUnavailable` instead of hanging or
killing the caller.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from ..case import Case
from ..config import AlgorithmConfig
from ..errors import HullstressError
from ..options import DEFAULTS
from ..results import ResultRow
from .signature import Signature, signature_of

__all__ = ["IsolationUnavailable", "isolated_runner", "run_config", "fails_same_way", "same_failure",
           "DEFAULT_TIMEOUT"]

#: Per-call timeout (seconds) for isolated calls when the caller gives none.
DEFAULT_TIMEOUT = DEFAULTS.call_timeout


class IsolationUnavailable(HullstressError):
    """A timeout or crash cannot be reproduced safely: no isolated runner (``run_one``) is available."""


def isolated_runner() -> Callable[..., ResultRow] | None:
    """``hullstress.runner.run_one`` when the runner provides it, else None.

    Looked up on every call rather than once at import, so that a runner
    loaded later (or patched in a test) is picked up.
    """
    from .. import runner

    return getattr(runner, "run_one", None)


def run_config(
    case: Case,
    config: AlgorithmConfig,
    *,
    timeout: float | None = None,
    isolate: bool | None = None,
    dangerous: bool = False,
    qhull: bool = True,
    qhull_options: str | None = None,
) -> ResultRow:
    """Run and judge ``config`` on ``case`` once.

    Parameters
    ----------
    case : Case
    config : AlgorithmConfig
    timeout : float, optional
        Per-call timeout for the isolated call (default :data:`DEFAULT_TIMEOUT`).
    isolate : bool, optional
        ``None`` (default): isolated when ``run_one`` exists, else in-process.
        ``True``: isolated or :class:`IsolationUnavailable`.  ``False``: in-process.
    dangerous : bool
        The call is expected to hang or crash (a timeout/crash signature): it
        is never run in-process.
    qhull : bool
        Compute the Qhull reference (the ``qhull_agreement`` check needs it).
    qhull_options : str, optional
        Qhull options tried first for the reference (the run's ``--qhull-options``).

    Returns
    -------
    ResultRow
    """
    run_one = isolated_runner() if isolate is not False else None
    if run_one is not None:
        return run_one(case, config, timeout=timeout if timeout is not None else DEFAULT_TIMEOUT, qhull=qhull,
                       qhull_options=qhull_options)
    if isolate or dangerous:
        raise IsolationUnavailable(
            f"reproducing {config.label} safely needs hullstress.runner.run_one "
            f"(an isolated worker), which this installation does not provide"
        )
    from ..evaluate import evaluate

    return evaluate(case, config, qhull=qhull, qhull_options=qhull_options)


def fails_same_way(
    case: Case,
    config: AlgorithmConfig,
    signature: Signature,
    *,
    timeout: float | None = None,
    isolate: bool | None = None,
    qhull_options: str | None = None,
) -> bool:
    """True when running ``config`` on ``case`` fails with exactly ``signature``.

    The family is provenance, not behaviour, and is not part of a signature:
    a shrunk or file-loaded copy of a case fails "the same way" when its row
    has the same signature (config, stage, status, failed checks and
    severity, exception type and frame).

    Parameters
    ----------
    case : Case
    config : AlgorithmConfig
    signature : Signature
    timeout, isolate, qhull_options
        As in :func:`run_config`.

    Examples
    --------
    A config that passes on a plain triangle does not fail "the same way" as
    any signature:

    >>> import hullstress  # doctest: +SKIP
    >>> fails_same_way(Case.from_points([[0, 0], [1, 0], [0, 1]]), config, sig)  # doctest: +SKIP
    False
    """
    row = run_config(case, config, timeout=timeout, isolate=isolate, dangerous=signature.dangerous,
                     qhull_options=qhull_options)
    return same_failure(row, signature)


def same_failure(row: ResultRow | Any, signature: Signature) -> bool:
    """True when ``row``'s signature is exactly ``signature``."""
    return signature_of(row) == signature
