"""The negative corpus: minimally wrong hulls, one defect each, and their minimally right twins.

``tests/data/negative/<kind>.json`` (written by ``tools/make_negative_corpus.py``)
holds, per check of docs/design.md's verdict semantics, hulls with exactly one
defect (a point one ulp outside a face, a polygon face one ulp out of plane,
a repeated face, two indices with the same coordinates, a surface wrapping
twice, ...) and the same constructions one ulp on the allowed side: over 2D
and 3D, triangles and 4-, 5-, 6- and 8-gon faces, axis-aligned and oblique
planes, at unit, ~1e-300 and ~1e300 scales.  Each entry records the verdict
(failed checks, severity, key words of the reason, counts).

Two tests per entry: the checker must give the recorded verdict, and the
recorded verdict must be what an independent exact computation gives
(``tests/_exact_verdict.py``, integers and Fractions, no checker code), so
neither the checker nor the data can drift without a failure.  An entry that
shows a checker bug carries ``"xfail": "checker bug: ..."`` and is expected
to fail (strictly) until the checker is fixed.
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from _exact_verdict import exact_verdict
from hullstress.checker import check

DATA = Path(__file__).parent / "data" / "negative"
KINDS = ("containment", "convexity", "manifoldness", "polygon2d", "qhull_agreement", "affine_rank")


def _load() -> list[dict]:
    entries = []
    for kind in KINDS:
        for entry in json.loads((DATA / f"{kind}.json").read_text()):
            entries.append(dict(entry, kind=kind))
    return entries


ENTRIES = _load()


def _params(entries) -> list:
    return [
        pytest.param(e, id=e["id"], marks=[pytest.mark.xfail(strict=True, reason=e["xfail"])] if e.get("xfail") else [])
        for e in entries
    ]


def test_every_check_has_wrong_and_right_entries():
    # Every check of docs/design.md fails in some entry; every kind has minimally right twins
    # (the manifoldness defects are combinatorial: their twins are the valid shapes of the
    # other kinds).
    failed = {c for e in ENTRIES for c in e["expect"]["failed"]}
    assert failed == {"convexity", "containment", "manifoldness", "qhull_agreement"}
    for kind in KINDS:
        mine = [e for e in ENTRIES if e["kind"] == kind]
        assert any(e["expect"]["failed"] for e in mine), kind
        assert kind == "manifoldness" or any(not e["expect"]["failed"] for e in mine), kind
    assert len({e["id"] for e in ENTRIES}) == len(ENTRIES)
    sizes = {len(f) for e in ENTRIES if e["dim"] == 3 for f in e["faces"]}
    assert {3, 4, 5, 6, 8} <= sizes


_ISOLATED = """
import json, sys
import numpy as np
from hullstress.checker import check
entry = json.load(sys.stdin)
v = check(np.array(entry["points"], dtype=np.float64), entry["faces"], qhull=entry.get("qhull", True))
print(json.dumps(dict(v.as_row(), detail=v.detail, failed=list(v.failed_checks))))
"""


class _Row:
    """A verdict read back from a subprocess, with the attributes the test asks for."""

    def __init__(self, row: dict):
        self.__dict__.update(row)
        self.failed_checks = tuple(row["failed"])


def _check(entry):
    if not entry.get("isolate"):
        return check(np.array(entry["points"], dtype=np.float64), entry["faces"], qhull=entry.get("qhull", True))
    # An input that kills the checker's process: judge it in a child, and report how it died.
    proc = subprocess.run([sys.executable, "-c", _ISOLATED], input=json.dumps(entry), capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, f"the checker died (exit status {proc.returncode}): {proc.stderr.strip()[-300:]}"
    return _Row(json.loads(proc.stdout))


@pytest.mark.parametrize("entry", _params(ENTRIES))
def test_checker_gives_the_recorded_verdict(entry):
    expect = entry["expect"]
    v = _check(entry)
    context = f"{entry['about']}: {v.detail}"
    undecided = expect.get("undecided", [])  # the checker's interior point decides these
    assert [c for c in v.failed_checks if c not in undecided] == expect["failed"], context
    assert v.severity == expect["severity"], context
    for word in expect["reason"]:
        assert word in v.detail, f"{word!r} not in the reason: {context}"
    got = {key: getattr(v, key) for key in expect["counts"]}
    assert got == expect["counts"], context
    if expect["qhull_ok"] is not None:
        assert v.qhull_ok is expect["qhull_ok"], context


@pytest.mark.parametrize("entry", _params([e for e in ENTRIES if not e.get("xfail")]))
def test_recorded_verdict_is_exact(entry):
    expect = entry["expect"]
    e = exact_verdict(entry["points"], entry["faces"], qhull=entry.get("qhull", True))
    assert e.failed == expect["failed"], e.notes
    assert (e.convexity is None) == ("convexity" in expect.get("undecided", []))
    assert e.severity == expect["severity"], e.magnitudes
    assert {k: e.counts[k] for k in expect["counts"]} == expect["counts"]
    assert e.qhull_ok == expect["qhull_ok"]
