"""JUnit XML for CI systems: one test case per algorithm config x family.

A test case fails when the algorithm failed in any of its calls (fail, error,
timeout, crash at stage ``algorithm``).  The ``<failure>`` element's message
counts the failures by check; its text carries, for each cause with a failure
of that config on that family, the minimal case (exact ``repr`` floats) and the
one-line reproduce command.  An internal error of the checker (stage
``check``) is an ``<error>`` of the test case, not a failure.  Failures of
the sphere method or eps set-up (stage ``preprocess``) are not the
algorithm's: they go to a suite of their own per config, named
``<config> (stage preprocess)``, present when the config ran preprocessing.
"""

from __future__ import annotations

import re
import xml.etree.ElementTree as ET
from collections.abc import Sequence
from pathlib import Path

import pandas as pd

from ..files import atomic_write_text, writable_folder
from ..io import points_text
from ..triage.signature import signature_of
from .failures import FailureRecord
from ..records import Sphere, Stage, Status
from .tables import failed_mask, stages

__all__ = ["junit_xml", "write_junit"]

# Characters XML 1.0 forbids even escaped (an exception message may hold any of them).
_NOT_XML = re.compile("[^\x09\x0a\x0d\x20-\ud7ff\ue000-\ufffd\U00010000-\U0010ffff]")


def _safe(text: str) -> str:
    return _NOT_XML.sub("\ufffd", text)


def _failure_text(records: Sequence[FailureRecord]) -> str:
    blocks = []
    for rec in records:
        pts = points_text(rec.points, indent="  ")
        blocks.append(
            f"{rec.cause.headline}: {rec.cause.failures} failures; "
            f"minimal case {rec.minimal_size} points (from {rec.original_size})\n"
            f"reason: {rec.reason}\n"
            f"reproduce: {rec.command}\n"
            f"folder: {rec.folder}\n"
            f"points ({rec.minimal_size}):\n{pts}"
        )
    return "\n\n".join(blocks)


def junit_xml(table: pd.DataFrame, records: Sequence[FailureRecord], *, suite: str = "hullstress") -> str:
    """The JUnit XML document for a results table and its failure records.

    Parameters
    ----------
    table : DataFrame
        A results table.
    records : sequence of FailureRecord
        Written causes (their minimal cases go into the failures).
    suite : str
        Name of the ``<testsuites>`` root.

    Returns
    -------
    str
        ``<testsuites>`` with one ``<testsuite>`` per config label and one
        ``<testcase classname=CONFIG name=FAMILY>`` per family it ran on.

    Examples
    --------
    >>> t = pd.DataFrame({"config": "a[sphere=off,eps=n/a]", "algorithm": "a", "sphere": "off", "eps": "n/a",
    ...                   "generator": ["dup", "dup"], "status": ["pass", "error"], "failed_checks": "",
    ...                   "reason": ["", "ZeroDivisionError"], "seconds": 0.0, "check_seconds": 0.0})
    >>> "failures=\\"1\\"" in junit_xml(t, [])
    True
    """
    root = ET.Element("testsuites", name=suite)
    totals = {"tests": 0, "failures": 0, "errors": 0, "time": 0.0}
    by_key: dict[tuple[str, ...], list[FailureRecord]] = {}
    for rec in records:
        for member in rec.cause.records:
            s = member.signature
            for family, _ in member.families:
                found = by_key.setdefault((s.algorithm, s.sphere, s.eps, family, s.stage), [])
                if not any(r is rec for r in found):
                    found.append(rec)
    if len(table):
        table = table.assign(stage=stages(table))
        for config, sub in table.groupby("config", sort=True, observed=True):
            _suite(root, str(config), sub, Stage.ALGORITHM, by_key, totals)
            if (sub["sphere"] == Sphere.ON.value).any() or (sub["stage"] == Stage.PREPROCESS.value).any():
                _suite(root, f"{config} (stage preprocess)", sub, Stage.PREPROCESS, by_key, totals)
    root.set("tests", str(totals["tests"]))
    root.set("failures", str(totals["failures"]))
    root.set("errors", str(totals["errors"]))
    root.set("time", f"{totals['time']:.3f}")
    ET.indent(root)
    return '<?xml version="1.0" encoding="UTF-8"?>\n' + ET.tostring(root, encoding="unicode") + "\n"


def _suite(root: ET.Element, name: str, sub: pd.DataFrame, stage: Stage,
           by_key: dict[tuple[str, ...], list[FailureRecord]], totals: dict[str, float]) -> None:
    """One ``<testsuite>``: a test case per family, failing on ``stage``'s failures."""
    ts = ET.SubElement(root, "testsuite", name=name)
    n_tests = n_fail = n_error = 0
    suite_time = 0.0
    for family, rows in sub.groupby("generator", sort=True, observed=True):
        seconds = float(rows["seconds"].fillna(0).sum() + rows["check_seconds"].fillna(0).sum())
        tc = ET.SubElement(ts, "testcase", classname=name, name=str(family), time=f"{seconds:.3f}")
        n_tests += 1
        suite_time += seconds
        failed = rows[failed_mask(rows, stage)]
        if len(failed):
            n_fail += 1
            first = rows.iloc[0]
            key = (str(first["algorithm"]), str(first["sphere"]), str(first["eps"]), str(family), stage.value)
            checks = pd.Series([signature_of(r).check for _, r in failed.iterrows()]).value_counts()
            message = (f"{len(failed)} of {len(rows)} calls failed: "
                       + ", ".join(f"{c} ({n})" for c, n in checks.items()))
            el = ET.SubElement(tc, "failure", message=_safe(message), type=str(checks.index[0]))
            recs = by_key.get(key, [])
            el.text = _safe(_failure_text(recs) if recs else "reasons: " + "; ".join(
                dict.fromkeys(str(r) for r in failed["reason"].fillna(""))))
        internal = rows[failed_mask(rows, Stage.CHECK)] if stage is Stage.ALGORITHM else rows.iloc[:0]
        if len(internal):
            n_error += 1
            el = ET.SubElement(tc, "error", message=_safe(f"{len(internal)} of {len(rows)} calls: internal error "
                                                          "of the checker"), type="internal")
            el.text = _safe("; ".join(dict.fromkeys(str(r) for r in internal["reason"].fillna(""))))
        rejected = int(((rows["status"] == Status.REJECTED.value) & (rows["stage"] == stage.value)).sum())
        if rejected:
            ET.SubElement(tc, "system-out").text = f"{rejected} of {len(rows)} calls rejected (degenerate input)"
    ts.set("tests", str(n_tests))
    ts.set("failures", str(n_fail))
    ts.set("errors", str(n_error))
    ts.set("skipped", "0")
    ts.set("time", f"{suite_time:.3f}")
    totals["tests"] += n_tests
    totals["failures"] += n_fail
    totals["errors"] += n_error
    totals["time"] += suite_time


def write_junit(path: str | Path, table: pd.DataFrame, records: Sequence[FailureRecord]) -> Path:
    """Write :func:`junit_xml` to ``path`` (parent folders created); returns the path."""
    path = Path(path)
    writable_folder(path.parent, "--junit")
    return atomic_write_text(path, junit_xml(table, records))
