"""Failure signatures: what makes two failing calls "the same bug".

A :class:`Signature` is everything a row says about *how* a call failed,
and nothing about the input that made it fail:

* the algorithm config (algorithm, sphere, eps);
* the stage that produced the verdict (``preprocess``, ``algorithm`` or
  ``check``; rows written before the stage column existed read as
  ``algorithm``);
* the status (``fail``, ``error``, ``timeout``, ``crash``);
* for ``fail``: every failed check (in :data:`hullstress.verdict.CHECKS`
  order) and the severity of the worst violation, or ``contract`` when the
  output broke the output contract, or ``invalid-input`` when a hull came
  back for an input that should have been rejected;
* for ``error``: the exception's type and the innermost frame of the code
  under test that raised it (the ``error_frame`` column), the way Hypothesis
  tells failures apart by exception type and location; ``internal`` for
  hullstress's own errors;
* for ``crash``: how the worker died (the signal's name or the exit code).

The generator family is *not* part of it: one bug shows up in many families,
and the report lists the families a failure group covers instead.  Failure
groups are signatures (:mod:`.grouping`), and the shrinker keeps a group's
signature exactly (:mod:`.shrink`).  ``pass`` and ``rejected`` rows have no
signature.

The identity of "the same failure"
----------------------------------
This module is the only home of that identity.  Triage groups by it, the
report names groups by it, the regression corpus keeps one entry per
signature (:attr:`Signature.group_id` names the entry's file), ``run
--baseline`` compares a run's signatures with a baseline's, ``replay``
compares each call's :func:`verdict_of` with the one recorded, and ``run
--last-failed`` / ``--failed-first`` take the calls that have a signature.
Every field is a function of the row alone, so the same code and seed give
the same signatures whatever ``--workers`` says.  An error's frame is kept
as module and function without its line number: an edit elsewhere in a
module (a docstring, a new function above) must not turn a known failure
into a "new" one and its old self into a "fixed" one in a nightly loop.
Two raises of the same exception type in one function are therefore one
group.  What can still move a signature: renaming the function that raises,
and a call that runs close to its timeout on a loaded machine (``timeout``
is a status of its own).
"""

from __future__ import annotations

import hashlib
import re
from collections.abc import Mapping
from dataclasses import asdict, dataclass
from typing import Any

from ..config import AlgorithmConfig
from ..records import CONTRACT_REASON, FAILED_STATUSES, METHOD_REASON, NO_EPS, Stage, Status
from ..verdict import CHECKS, FAILED_CHECKS

__all__ = ["Signature", "failed_check", "failed_checks_of", "signature_of", "stage_of", "verdict_of",
           "is_failure_verdict", "FAILED_STATUSES", "FAILED_CHECKS", "DEFAULT_STAGE"]

#: The stage of a row that does not say (tables written before the ``stage`` column).
DEFAULT_STAGE = Stage.ALGORITHM.value


_CONTRACT_PREFIX = CONTRACT_REASON
_INTERNAL_PREFIX = "internal:"
_UNSAFE = re.compile(r"[^A-Za-z0-9._-]+")
_SIGNAL = re.compile(r"\((SIG[A-Z0-9]+)\)")
_EXIT = re.compile(r"exited with code (-?\d+)")
#: A plug-in file's module name (hullstress.plugins): its stem plus a hash of the file's absolute path.
_PLUGIN_MODULE = re.compile(r"\bhullstress_plugin_(\w+?)_[0-9a-f]{12}\b")
#: ``module:line in function`` (the ``error_frame`` column): the line number's place.
_FRAME_LINE = re.compile(r"^([^:\s]+):\d+ in ")


def _frame(value: Any) -> str:
    """The frame as the identity keeps it: ``module in function``, a plug-in's module by its file's stem.

    The line number is left out, so that an edit elsewhere in the module does
    not move the group; a plug-in's module is named by its file's stem, not
    by the hash of where the file lives, so that a corpus committed from CI
    names the same groups on a laptop where the checkout is somewhere else.
    The ``error_frame`` column keeps the line for the reader.

    Examples
    --------
    >>> _frame("hullstress_plugin_myhull_0123456789ab:12 in hull")
    'myhull in hull'
    >>> _frame("hullstress.adapters.scipy_qhull:149 in qhull_3d")
    'hullstress.adapters.scipy_qhull in qhull_3d'
    """
    return _FRAME_LINE.sub(r"\1 in ", _PLUGIN_MODULE.sub(r"\1", _text(value)))


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


def stage_of(value: Any) -> str:
    """A row's stage cell as a string; ``algorithm`` when missing (tables from before the stage column).

    Examples
    --------
    >>> stage_of("preprocess"), stage_of(None), stage_of(float("nan"))
    ('preprocess', 'algorithm', 'algorithm')
    """
    return _text(value) or DEFAULT_STAGE


def failed_checks_of(status: str, reason: Any = "", failed_checks: Any = "") -> str:
    """The ``checks`` part of a signature: what a ``fail`` failed, ``""`` for other statuses.

    Examples
    --------
    >>> failed_checks_of("fail", "", "qhull_agreement,containment")
    'containment,qhull_agreement'
    >>> failed_checks_of("fail", "output contract: index 7 out of range", "")
    'contract'
    >>> failed_checks_of("error", "ValueError: x", "")
    ''
    """
    if status != Status.FAIL:
        return ""
    if _text(reason).startswith(_CONTRACT_PREFIX):
        return "contract"
    checks = [c for c in _text(failed_checks).split(",") if c]
    if checks:
        # Report order, whatever order the cell lists them in; unknown names (a newer checker) after.
        return ",".join([c for c in CHECKS if c in checks] + sorted(c for c in set(checks) if c not in CHECKS))
    if _text(reason).startswith(METHOD_REASON):
        return "collapsed"  # the sphere method left too little of the input to map back (stage preprocess)
    return "invalid-input"


def failed_check(status: str, reason: Any = "", failed_checks: Any = "") -> str | None:
    """One word for how a row failed: its first failed check, or its status; None for pass/rejected.

    A short word for display only: the identity of a failure (what the
    corpus, ``--baseline`` and ``replay`` compare) is the whole
    :class:`Signature`, which keeps every failed check.

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
    if status != Status.FAIL:
        return status
    return failed_checks_of(status, reason, failed_checks).split(",")[0]


def _error_kind(status: str, reason: str) -> str:
    if status == Status.ERROR:
        if reason.startswith(_INTERNAL_PREFIX):
            return "internal"
        return reason.split(":", 1)[0].strip()
    if status == Status.CRASH:
        signal = _SIGNAL.search(reason)
        if signal:
            return signal.group(1)
        code = _EXIT.search(reason)
        return f"exit {code.group(1)}" if code else (reason.split(":", 1)[0].strip() or "crash")
    return ""


@dataclass(frozen=True, order=True)
class Signature:
    """How a call failed: the identity of a failure group.

    Attributes
    ----------
    algorithm, sphere, eps : str
        The algorithm config (``eps`` is ``n/a`` for algorithms without eps).
    stage : {"preprocess", "algorithm", "check"}
        The part of the call that produced the verdict.
    status : {"fail", "error", "timeout", "crash"}
    checks : str
        For ``fail``: the failed checks, comma-joined in report order, or
        ``contract`` or ``invalid-input``; ``""`` otherwise.
    severity : str
        For ``fail`` with failed checks: ``none``, ``roundoff`` or ``gross``; ``""`` otherwise.
    error : str
        For ``error``: the exception type (``internal`` for hullstress's own);
        for ``crash``: the signal (``SIGSEGV``) or ``exit N``; ``""`` otherwise.
    frame : str
        For ``error``: ``module in function``, the innermost frame of the
        code under test without its line number; ``""`` otherwise or when unknown.

    Examples
    --------
    >>> s = Signature("gift-wrap-3d", "on", "fixed", checks="containment", severity="gross")
    >>> s.slug
    'gift-wrap-3d__sphere-on__eps-fixed__fail__containment__gross'
    >>> s.label
    'gift-wrap-3d[sphere=on,eps=fixed] fail containment (gross)'
    """

    algorithm: str
    sphere: str
    eps: str
    stage: str = DEFAULT_STAGE
    status: str = Status.FAIL.value
    checks: str = ""
    severity: str = ""
    error: str = ""
    frame: str = ""

    @property
    def config(self) -> AlgorithmConfig:
        """The algorithm config this signature is about."""
        return AlgorithmConfig(self.algorithm, self.sphere, self.eps)

    @property
    def check(self) -> str:
        """One word: the first failed check for ``fail`` (``contract``, ``invalid-input``), else the status."""
        return self.checks.split(",")[0] if self.status == Status.FAIL and self.checks else self.status

    @property
    def dangerous(self) -> bool:
        """Reproducing it hangs or kills the process: only ever run in an isolated worker."""
        return self.status in (Status.TIMEOUT, Status.CRASH)

    @property
    def what(self) -> str:
        """How it failed, without the config: ``fail containment,qhull_agreement (gross)``.

        Examples
        --------
        >>> Signature("a", "off", "n/a", status="error", error="ZeroDivisionError", frame="m in f").what
        'error ZeroDivisionError at m in f'
        """
        parts = [self.status]
        if self.stage != DEFAULT_STAGE:
            parts[0] = f"{self.status} in {self.stage}"
        if self.checks:
            parts.append(self.checks)
        if self.severity:
            parts.append(f"({self.severity})")
        if self.error:
            parts.append(self.error)
        if self.frame:
            parts.append(f"at {self.frame}")
        return " ".join(parts)

    @property
    def label(self) -> str:
        """``alg[sphere=on,eps=fixed] fail containment (gross)``: for reports."""
        return f"{self.config.label} {self.what}"

    @property
    def slug(self) -> str:
        """A filesystem-safe folder name, unique per signature.

        Characters outside ``[A-Za-z0-9._-]`` become ``-``; the frame is not
        spelled out.  A short hash of the whole signature is appended when
        the frame is set, when sanitising changed anything (two signatures
        could then collide) or when the name would be long.
        """
        # "n/a" is the one standard value with an unsafe character: spell it "na" up front.
        eps = "na" if self.eps == NO_EPS else self.eps
        parts = [self.algorithm, f"sphere-{self.sphere}", f"eps-{eps}"]
        if self.stage != DEFAULT_STAGE:
            parts.append(self.stage)
        parts.append(self.status)
        parts += [p for p in (self.checks, self.severity, self.error) if p]
        clean = [_UNSAFE.sub("-", p.replace(",", "-")).strip("-.") or "x" for p in parts]
        slug = "__".join(clean)
        raw = "__".join(p.replace(",", "-") for p in parts)
        if self.frame or slug != raw or len(slug) > 150:
            digest = hashlib.sha256(repr(self.key).encode()).hexdigest()[:8]
            slug = f"{slug[:140]}__{digest}"
        return slug

    @property
    def group_id(self) -> str:
        """16 hex digits naming the failure group: a hash of :attr:`key`, stable across runs and machines.

        The regression corpus names an entry's file after it, so one group has one entry.

        Examples
        --------
        >>> Signature("a", "off", "n/a", status="crash", error="SIGSEGV").group_id
        '38b07233d42ddd4e'
        """
        return hashlib.sha256("\x1f".join(self.key).encode()).hexdigest()[:16]

    @property
    def key(self) -> tuple[str, ...]:
        """The fields as a tuple (stable order; what the slug's hash covers)."""
        return (self.algorithm, self.sphere, self.eps, self.stage, self.status, self.checks, self.severity,
                self.error, self.frame)

    def as_dict(self) -> dict[str, str]:
        return asdict(self)

    @classmethod
    def from_dict(cls, values: Mapping[str, Any]) -> "Signature":
        """The inverse of :meth:`as_dict` (unknown keys ignored, missing ones defaulted)."""
        fields = cls.__dataclass_fields__
        return cls(**{k: str(v) for k, v in values.items() if k in fields and v is not None})


def signature_of(row: Mapping[str, Any] | Any) -> Signature | None:
    """The signature of one result row (a ResultRow, a dict or a DataFrame row), or None.

    Examples
    --------
    >>> signature_of({"algorithm": "a", "sphere": "off", "eps": "n/a", "status": "error",
    ...               "reason": "ZeroDivisionError: division by zero", "error_frame": "m:3 in f"}).error
    'ZeroDivisionError'
    >>> signature_of({"algorithm": "a", "sphere": "off", "eps": "n/a", "status": "crash",
    ...               "reason": "killed by signal 11 (SIGSEGV)"}).error
    'SIGSEGV'
    >>> signature_of({"algorithm": "a", "sphere": "off", "eps": "n/a", "status": "pass"}) is None
    True
    """
    get = row.get
    status = _text(get("status"))
    if status not in FAILED_STATUSES:
        return None
    reason = _text(get("reason"))
    checks = failed_checks_of(status, reason, get("failed_checks"))
    severity = _text(get("severity")) if status == Status.FAIL and checks not in ("contract", "invalid-input") else ""
    return Signature(
        algorithm=_text(get("algorithm")), sphere=_text(get("sphere")), eps=_text(get("eps")),
        stage=stage_of(get("stage")), status=status, checks=checks, severity=severity,
        error=_error_kind(status, reason), frame=_frame(get("error_frame")) if status == Status.ERROR else "",
    )


#: Verdicts of calls that did not fail (a ``fail`` verdict is its :attr:`Signature.what`).
PASSING_VERDICTS = (Status.PASS.value, Status.REJECTED.value)


def verdict_of(row: Mapping[str, Any] | Any) -> str:
    """One call's verdict as the corpus records it: ``pass``, ``rejected``, or its signature's :attr:`~Signature.what`.

    The config is left out (an expectation is keyed by the config's label), so
    two calls of one config have the same verdict exactly when they have the
    same :class:`Signature`.

    Examples
    --------
    >>> verdict_of({"algorithm": "a", "sphere": "off", "eps": "n/a", "status": "pass"})
    'pass'
    >>> verdict_of({"algorithm": "a", "sphere": "off", "eps": "n/a", "status": "fail",
    ...             "failed_checks": "containment", "severity": "gross"})
    'fail containment (gross)'
    """
    sig = signature_of(row)
    return sig.what if sig is not None else _text(row.get("status"))


def is_failure_verdict(verdict: str | None) -> bool:
    """True for a recorded verdict that is a failure (anything but ``pass``, ``rejected`` or nothing).

    Examples
    --------
    >>> is_failure_verdict("fail containment (gross)"), is_failure_verdict("rejected"), is_failure_verdict(None)
    (True, False, False)
    """
    return bool(verdict) and verdict not in PASSING_VERDICTS
