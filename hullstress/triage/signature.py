"""Failure signatures: how two failing calls are judged to be "the same failure".

A signature is (algorithm, sphere, eps, failed check, family, stage).  The
stage (:class:`~hullstress.records.Stage`) keeps a failure of the sphere
method or of the checker apart from the algorithm's own.  The *failed
check* is

* for status ``fail``: ``contract`` when the output broke the output contract
  (the row's reason starts with ``output contract:``), else the first failed
  check in :data:`hullstress.verdict.CHECKS` order, else ``collapsed`` (the
  sphere method left too little of the input to map back: stage
  ``preprocess``), else ``invalid-input`` (tables from before non-finite
  input had its own rule: a hull returned for it);
* for ``error``, ``timeout`` and ``crash``: the status itself.

``pass`` and ``rejected`` rows have no signature.
"""

from __future__ import annotations

import hashlib
import re
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

from ..config import AlgorithmConfig
from ..records import CONTRACT_REASON, METHOD_REASON, Stage
from ..verdict import CHECKS

__all__ = ["Signature", "failed_check", "signature_of", "stage_of", "FAILED_STATUSES", "FAILED_CHECKS"]

#: Statuses that are failures of the code under test (``rejected`` is acceptable behaviour).
FAILED_STATUSES = ("fail", "error", "timeout", "crash")

#: Every value the "failed check" part of a signature can take (``shrink --check`` accepts these).
FAILED_CHECKS = ("contract",) + tuple(CHECKS) + ("invalid-input", "error", "timeout", "crash")

_UNSAFE = re.compile(r"[^A-Za-z0-9._-]+")


def _text(value: Any) -> str:
    # Table cells may be pandas' NA / NaN; those read as "no text".
    if value is None or (isinstance(value, float) and value != value):
        return ""
    try:
        import pandas as pd

        if value is pd.NA:
            return ""
    except ImportError:  # pragma: no cover - pandas is a dependency
        pass
    return str(value)


def failed_check(status: str, reason: Any = "", failed_checks: Any = "") -> str | None:
    """The "failed check" part of a signature, or None for pass/rejected.

    Parameters
    ----------
    status : str
        The row's status.
    reason : str
        The row's one-line reason.
    failed_checks : str
        The row's comma-joined failed checks.

    Examples
    --------
    >>> failed_check("fail", "", "containment,qhull_agreement")
    'containment'
    >>> failed_check("fail", "output contract: index 7 out of range", "")
    'contract'
    >>> failed_check("crash"), failed_check("rejected", "ValueError: coplanar")
    ('crash', None)
    """
    if status not in FAILED_STATUSES:
        return None
    if status != "fail":
        return status
    if _text(reason).startswith(CONTRACT_REASON):
        return "contract"
    checks = [c for c in _text(failed_checks).split(",") if c]
    if checks:
        # The first in report order, whatever order the cell lists them in.
        known = [c for c in CHECKS if c in checks]
        return known[0] if known else checks[0]
    if _text(reason).startswith(METHOD_REASON):
        return "collapsed"
    return "invalid-input"


@dataclass(frozen=True, order=True)
class Signature:
    """What makes two failures the same: algorithm config, failed check and family.

    Attributes
    ----------
    algorithm, sphere, eps : str
        The algorithm config (``eps`` is ``n/a`` for algorithms without eps).
    check : str
        See :func:`failed_check`.
    family : str
        The generator family (``file`` for points files).
    stage : str
        The stage that failed (``algorithm``, ``preprocess`` or ``check``).

    Examples
    --------
    >>> s = Signature("gift-wrap", "on", "fixed", "containment", "coplanar-grid")
    >>> s.slug
    'gift-wrap__sphere-on__eps-fixed__containment__coplanar-grid'
    >>> Signature("gift-wrap", "on", "fixed", "containment", "coplanar-grid", "preprocess").slug
    'gift-wrap__sphere-on__eps-fixed__preprocess-containment__coplanar-grid'
    """

    algorithm: str
    sphere: str
    eps: str
    check: str
    family: str
    stage: str = Stage.ALGORITHM.value

    @property
    def config(self) -> AlgorithmConfig:
        """The algorithm config this signature is about."""
        return AlgorithmConfig(self.algorithm, self.sphere, self.eps)

    @property
    def status(self) -> str:
        """The row status this signature implies (``fail`` for check and contract failures)."""
        return self.check if self.check in ("error", "timeout", "crash") else "fail"

    @property
    def slug(self) -> str:
        """A filesystem-safe folder name, unique per signature.

        Characters outside ``[A-Za-z0-9._-]`` become ``-``; when that changed
        anything (so two signatures could collide) a short hash is appended.
        """
        # "n/a" is the one standard value with an unsafe character: spell it "na" up front.
        eps = "na" if self.eps == "n/a" else self.eps
        check = self.check if self.stage == Stage.ALGORITHM else f"{self.stage}-{self.check}"
        parts = (self.algorithm, f"sphere-{self.sphere}", f"eps-{eps}", check, self.family)
        clean = [_UNSAFE.sub("-", p).strip("-.") or "x" for p in parts]
        slug = "__".join(clean)
        raw = "__".join(parts)
        if slug != raw or len(slug) > 150:
            digest = hashlib.sha256(raw.encode()).hexdigest()[:8]
            slug = f"{slug[:140]}__{digest}"
        return slug

    @property
    def label(self) -> str:
        """``alg[sphere=on,eps=fixed] containment on coplanar-grid``: for reports (the stage when not the algorithm)."""
        stage = "" if self.stage == Stage.ALGORITHM else f" (stage {self.stage})"
        return f"{self.config.label} {self.check} on {self.family}{stage}"

    def as_dict(self) -> dict[str, str]:
        return {"algorithm": self.algorithm, "sphere": self.sphere, "eps": self.eps,
                "check": self.check, "family": self.family, "stage": self.stage}


def signature_of(row: Mapping[str, Any] | Any) -> Signature | None:
    """The signature of one result row (a ResultRow, a dict or a DataFrame row), or None.

    Examples
    --------
    >>> signature_of({"algorithm": "a", "sphere": "off", "eps": "n/a", "generator": "dup",
    ...               "status": "error", "reason": "ZeroDivisionError", "failed_checks": ""}).check
    'error'
    >>> signature_of({"algorithm": "a", "sphere": "off", "eps": "n/a", "generator": "dup",
    ...               "status": "pass", "reason": "", "failed_checks": ""}) is None
    True
    """
    get = row.get
    check = failed_check(str(get("status")), get("reason", ""), get("failed_checks", ""))
    if check is None:
        return None
    return Signature(str(get("algorithm")), str(get("sphere")), str(get("eps")), check, str(get("generator")),
                     stage_of(get("stage", "")))


def stage_of(value: Any) -> str:
    """A row's stage cell as a string; ``algorithm`` when missing (tables from before the stage column).

    Examples
    --------
    >>> stage_of("preprocess"), stage_of(None), stage_of(float("nan"))
    ('preprocess', 'algorithm', 'algorithm')
    """
    return _text(value) or Stage.ALGORITHM.value
