"""Tests for hullstress.report.junit: one test case per config x family, failures carry the minimal case."""

from __future__ import annotations

import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pandas as pd

from hullstress.case import Case
from hullstress.report.failures import FailureRecord
from hullstress.report.junit import junit_xml, write_junit
from hullstress.triage import Cause, ShrinkResult, TriageRecord, group_failures


def _table() -> pd.DataFrame:
    rows = []
    for config, alg, sphere in (("a[sphere=off,eps=n/a]", "a", "off"), ("a[sphere=on,eps=n/a]", "a", "on")):
        for family, statuses in (("grid", ["pass", "fail", "fail"]), ("dup", ["pass", "rejected", "error"])):
            for i, status in enumerate(statuses):
                rows.append({
                    "case_id": f"{family}{i}", "config": config, "algorithm": alg, "sphere": sphere, "eps": "n/a",
                    "generator": family, "status": status, "n_points": 10 + i,
                    "failed_checks": "containment" if status == "fail" else "",
                    "reason": {"fail": "1 point outside", "error": "KeyError: 3\x00\x07"}.get(status, ""),
                    "seconds": 0.01, "check_seconds": 0.02,
                })
    return pd.DataFrame(rows)


def _record(group, points) -> FailureRecord:
    sig = group.signature
    case = Case.from_points(points, family="grid")
    shrunk = ShrinkResult(case=case, original=case, signature=sig, original_size=12, minimal_size=len(points),
                          calls=40, seconds=0.5, reproduced=True)
    triaged = TriageRecord(signature=sig, config=sig.config, group=group, shrink=shrunk, faces=None, faces_note="",
                           storage="csv", verified=True)
    cause = Cause(key="k", records=(triaged,))
    return FailureRecord(cause=cause, folder=Path("/tmp/x") / sig.slug,
                         command=f"/usr/bin/python3 -m hullstress reproduce /tmp/x/{sig.slug}", points=np.asarray(points))


def test_one_testcase_per_config_and_family_with_failure_counts():
    table = _table()
    doc = ET.fromstring(junit_xml(table, []).split("\n", 1)[1])
    assert doc.tag == "testsuites"
    suites = doc.findall("testsuite")
    # The sphere-on config also gets the suite of its preprocessing (the sphere method), all passing here.
    assert sorted(s.get("name") for s in suites) == [
        "a[sphere=off,eps=n/a]", "a[sphere=on,eps=n/a]", "a[sphere=on,eps=n/a] (stage preprocess)"]
    cases = [c for c in doc.findall("testsuite/testcase") if "preprocess" not in c.get("classname")]
    assert len(cases) == 4
    assert {(c.get("classname"), c.get("name")) for c in cases} == {
        (cfg, fam) for cfg in ("a[sphere=off,eps=n/a]", "a[sphere=on,eps=n/a]") for fam in ("grid", "dup")}
    assert doc.get("tests") == "6" and doc.get("failures") == "4"
    grid = [c for c in cases if c.get("name") == "grid"][0]
    failure = grid.find("failure")
    assert failure.get("message") == "2 of 3 calls failed: containment (2)"
    assert failure.get("type") == "containment"
    dup = [c for c in cases if c.get("name") == "dup"][0]
    assert dup.find("failure").get("type") == "error"
    assert "1 of 3 calls rejected" in dup.find("system-out").text
    # Characters XML forbids were replaced, so the document parsed at all.
    assert "\x00" not in dup.find("failure").text
    assert abs(float(grid.get("time")) - 0.09) < 1e-6


def test_failures_carry_the_minimal_case_exactly_and_the_command(tmp_path):
    table = _table()
    groups = {(g.signature.sphere, g.signature.status): g for g in group_failures(table)}
    points = np.array([[0.1, 1e-300], [-3.0000000000000004, 2.0], [5e-324, -0.0]])
    g = groups[("off", "fail")]
    rec = _record(g, points)
    path = write_junit(tmp_path / "sub" / "junit.xml", table, [rec])
    doc = ET.parse(path).getroot()
    case = [c for c in doc.iter("testcase") if c.get("classname") == "a[sphere=off,eps=n/a]" and c.get("name") == "grid"][0]
    text = case.find("failure").text
    assert rec.command in text
    lines = text.split("points (3):\n", 1)[1].splitlines()
    back = np.array([[float(v) for v in line.split(",")] for line in lines])
    assert np.array_equal(back, points) and np.signbit(back[2, 1])
    # The other config's grid failure has no record: it lists reasons instead.
    other = [c for c in doc.iter("testcase") if c.get("classname") == "a[sphere=on,eps=n/a]" and c.get("name") == "grid"][0]
    assert other.find("failure").text.startswith("reasons: 1 point outside")


def test_a_clean_table_has_no_failures():
    table = _table()
    table["status"] = "pass"
    doc = ET.fromstring(junit_xml(table, []).split("\n", 1)[1])
    assert doc.get("failures") == "0" and not doc.findall(".//failure")
    empty = ET.fromstring(junit_xml(table.iloc[0:0], []).split("\n", 1)[1])
    assert empty.get("tests") == "0"


def test_stages_are_kept_apart():
    """A failure of the sphere method is not the algorithm's; a checker error is an <error>, not a failure."""
    table = _table()
    table["stage"] = "algorithm"
    on_grid = (table["sphere"] == "on") & (table["generator"] == "grid") & (table["status"] == "fail")
    table.loc[on_grid, "stage"] = "preprocess"
    off_dup_error = (table["sphere"] == "off") & (table["status"] == "error")
    table.loc[off_dup_error, "stage"] = "check"
    doc = ET.fromstring(junit_xml(table, []).split("\n", 1)[1])

    def case(classname, name):
        return [c for c in doc.iter("testcase") if c.get("classname") == classname and c.get("name") == name][0]

    assert case("a[sphere=on,eps=n/a]", "grid").find("failure") is None
    method = case("a[sphere=on,eps=n/a] (stage preprocess)", "grid").find("failure")
    assert method.get("message") == "2 of 3 calls failed: containment (2)"
    dup = case("a[sphere=off,eps=n/a]", "dup")
    assert dup.find("failure") is None and dup.find("error").get("type") == "internal"
    assert doc.get("errors") == "1"
