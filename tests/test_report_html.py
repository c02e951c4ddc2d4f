"""Tests for the run's report: report.html, failure folders, reproduce commands, findings, summary.

A small sweep of throw-away plug-in algorithms (correct hulls from Qhull with
bugs planted) over a plug-in generator, then the triage and report stages (:func:`_finalize`).
"""

from __future__ import annotations

import base64
import io
import json
import os
import shlex
import shutil
import subprocess
import sys
import textwrap
from html.parser import HTMLParser
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from hullstress.io import read_points
from hullstress.plugins import load_plugin
from hullstress.options import PROFILES, TriageBudget
from hullstress.report.pictures import PNG_SIGNATURE
from hullstress.report.stage import write_run_report
from hullstress.report.writer import run_metadata, write_report
from hullstress.triage.stage import triage_failures

PLUGIN = textwrap.dedent(
    '''
    """Throw-away plug-ins for tests/test_report_html.py."""
    import numpy as np
    from scipy.spatial import ConvexHull

    from hullstress import register_algorithm, register_generator


    @register_generator("test-report-cloud", dims=(2, 3))
    def cloud(rng, n, *, dim, spread=10.0):
        """Uniform points in a box."""
        return rng.uniform(-spread, spread, size=(n, dim))


    def _outward(points, hull):
        faces = []
        centre = points[hull.vertices].mean(axis=0)
        for tri in hull.simplices:
            a, b, c = points[tri]
            if np.dot(np.cross(b - a, c - a), a - centre) < 0:
                tri = tri[[0, 2, 1]]
            faces.append([int(i) for i in tri])
        return faces


    @register_algorithm("test-report-dropper", dim=2)
    def dropper(points):
        """Qhull's polygon minus its first vertex."""
        return [int(i) for i in ConvexHull(points).vertices][1:]


    @register_algorithm("test-report-raiser", dim=2)
    def raiser(points, *, eps=None):
        """Qhull's polygon, but raises when a point has x < 0."""
        if float(points[:, 0].min()) < 0.0:
            raise ZeroDivisionError("planted")
        return [int(i) for i in ConvexHull(points).vertices]


    @register_algorithm("test-report-holey", dim=3)
    def holey(points):
        """Qhull's triangles, outward, minus the first one (an open surface)."""
        return _outward(points, ConvexHull(points))[1:]


    @register_algorithm("test-report-good", dim=2)
    def good(points):
        """Qhull's polygon."""
        return [int(i) for i in ConvexHull(points).vertices]
    '''
)


@pytest.fixture(scope="module")
def plugin(tmp_path_factory) -> Path:
    path = tmp_path_factory.mktemp("report-plugin") / "report_plugins.py"
    path.write_text(PLUGIN)
    load_plugin(str(path))
    return path


def _sweep(tmp_path: Path, plugin: Path, algorithms: tuple[str, ...], *, sphere: str = "off"):
    from hullstress.sweep import SweepOptions, run_sweep

    options = SweepOptions(profile="quick", algorithms=algorithms, generators=("test-report-cloud",),
                           sphere=sphere, eps="both", sizes=(12,), seed=5, workers=0)
    result = run_sweep(options)
    run_dir = tmp_path / "run"
    run_dir.mkdir()
    meta = run_metadata(run_id="test-run", arguments={"profile": "quick", "seed": 5, "plugin": [str(plugin)]},
                        df=result.table, wall_seconds=1.0, complete=True, skipped=[])
    write_report(run_dir, result.table, meta)
    return run_dir, result, meta


def _finalize(run_dir, table, cases, meta, *, budget: TriageBudget | None = None, shrink: bool = True,
              junit_path=None, plugins=(), pictures: bool = True) -> dict:
    """The triage stage, then the report stage, as the pipeline runs them."""
    budget = budget or PROFILES["quick"].triage
    triage = triage_failures(table, cases, budget=budget, shrink=shrink, workers=2)
    files = write_run_report(run_dir, table, meta, triage, pictures=budget.pictures if pictures else 0,
                             plugins=plugins, junit_path=junit_path)
    return {"groups": triage.groups, "records": files.records, "notes": files.notes, "html": files.html,
            "findings_md": files.findings_md, "findings_csv": files.findings_csv, "findings": files.findings,
            "junit": files.junit, "triage": triage}


class _Structure(HTMLParser):
    """Checks nesting and collects images, links and section ids."""

    VOID = {"meta", "img", "br", "hr", "link", "input", "col", "source", "wbr"}

    def __init__(self) -> None:
        super().__init__(convert_charrefs=True)
        self.stack: list[str] = []
        self.errors: list[str] = []
        self.images: list[dict[str, str]] = []
        self.refs: list[str] = []
        self.ids: list[str] = []
        self.tags: list[str] = []
        self.text: list[str] = []

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        self.tags.append(tag)
        if tag == "img":
            self.images.append(a)
        for key in ("href", "src"):
            if key in a and tag != "img":
                self.refs.append(a[key])
        if "id" in a:
            self.ids.append(a["id"])
        if tag not in self.VOID:
            self.stack.append(tag)

    def handle_startendtag(self, tag, attrs):
        self.handle_starttag(tag, attrs)
        if tag not in self.VOID:
            self.stack.pop()

    def handle_endtag(self, tag):
        if tag in self.VOID:
            return
        if not self.stack or self.stack[-1] != tag:
            self.errors.append(f"</{tag}> closes <{self.stack[-1] if self.stack else None}>")
            return
        self.stack.pop()

    def handle_data(self, data):
        self.text.append(data)


def _check_html(path: Path) -> _Structure:
    text = path.read_text(encoding="utf-8")
    assert text.startswith("<!DOCTYPE html>")
    parser = _Structure()
    parser.feed(text)
    parser.close()
    assert not parser.errors, parser.errors[:5]
    assert parser.stack == [], parser.stack
    for tag in ("html", "head", "title", "style", "body", "h1", "table"):
        assert tag in parser.tags, tag
    assert "script" not in parser.tags and "link" not in parser.tags  # nothing external
    assert all(ref.startswith("#") for ref in parser.refs), parser.refs
    assert len(parser.ids) == len(set(parser.ids)), "duplicate ids"
    for img in parser.images:
        src = img["src"]
        assert src.startswith("data:image/png;base64,"), src[:40]
        png = base64.b64decode(src.split(",", 1)[1], validate=True)
        assert png[:8] == PNG_SIGNATURE
        from PIL import Image

        with Image.open(io.BytesIO(png)) as im:
            im.verify()
        with Image.open(io.BytesIO(png)) as im:
            assert im.size[0] > 100 and im.size[1] > 100
        assert img.get("alt")
    return parser


@pytest.fixture(scope="module")
def failing_run(tmp_path_factory, plugin):
    tmp = tmp_path_factory.mktemp("report-run")
    run_dir, result, meta = _sweep(tmp, plugin, ("test-report-dropper", "test-report-raiser",
                                                 "test-report-holey", "test-report-good"))
    budget = TriageBudget(calls=5000, group_calls=400, hang_calls=0, pictures=60, safety_seconds=600.0)
    (tmp / "ci").mkdir()
    out = _finalize(run_dir, result.table, result.cases, meta, budget=budget, junit_path=tmp / "ci" / "junit.xml",
                    plugins=[str(plugin)])
    return run_dir, result, out


def test_report_html_is_self_contained_and_every_picture_decodes(failing_run):
    run_dir, result, out = failing_run
    parser = _check_html(out["html"])
    records = out["records"]
    assert len(records) >= 3
    # One section per cause, each with its picture.
    for rec in records:
        assert rec.cause.slug in parser.ids
    assert len(parser.images) == len(records)
    text = " ".join(parser.text)
    for rec in records:
        assert rec.command in text
    assert "Findings" in text and "Failure rates by algorithm x variant x family" in text
    assert "of 5000 evaluations used (400 per group at most)" in text
    for g in out["groups"]:
        assert g.signature.label in text  # every group listed, linked to its cause


def test_every_cause_has_a_complete_failure_folder(failing_run):
    run_dir, result, out = failing_run
    table = result.table
    folders = sorted(p.name for p in (run_dir / "failures").iterdir() if p.is_dir())
    assert folders == sorted(r.cause.slug for r in out["records"])
    expected_groups = {(r.algorithm, r.sphere, r.eps) for r in table[table["status"] != "pass"].itertuples()}
    assert {(g.signature.algorithm, g.signature.sphere, g.signature.eps) for g in out["groups"]} == expected_groups
    assert not any(g.signature.algorithm == "test-report-good" for g in out["groups"])
    # Every group is in exactly one cause.
    members = [m.signature.slug for r in out["records"] for m in r.cause.records]
    assert sorted(members) == sorted(g.slug for g in out["groups"])
    for rec in out["records"]:
        folder = rec.folder
        for name in ("points.npy", "points.csv", "case.json", "faces.json", "verdict.json", "picture.png",
                     "reproduce.txt"):
            assert (folder / name).is_file(), (folder, name)
        npy = np.load(folder / "points.npy")
        assert np.array_equal(read_points(folder / "points.csv"), npy)  # exact round trip
        assert np.array_equal(npy, rec.points)
        meta = json.loads((folder / "case.json").read_text())
        assert meta["minimal_size"] == len(npy) <= meta["original_size"] == 12
        assert meta["signature"] == rec.signature.as_dict()
        assert meta["verified"] is True
        assert [m["config"] for m in meta["members"]] == list(rec.cause.configs)
        assert "seconds" not in json.dumps(meta)  # nothing that depends on the machine's speed
        assert (folder / "reproduce.txt").read_text().strip() == rec.command
        verdict = json.loads((folder / "verdict.json").read_text())
        faces = json.loads((folder / "faces.json").read_text())
        if rec.signature.status == "error":
            assert verdict["status"] == "error" and faces["faces"] is None
            # The identity names a plug-in file's module by the file's stem and leaves the line out; the row
            # keeps the module's own name and the line.
            module, line_and_function = verdict["error_frame"].split(":", 1)
            line, function = line_and_function.split(" in ", 1)
            assert line.isdigit() and module.startswith("hullstress_plugin_report_plugins_")
            assert rec.signature.frame == f"report_plugins in {function}" == "report_plugins in raiser"
        else:
            assert verdict["status"] == "fail" and verdict["failed_checks"] == rec.signature.checks
            assert faces["faces"]
        assert (folder / "picture.png").read_bytes()[:8] == PNG_SIGNATURE


def test_planted_failures_shrink_small(failing_run):
    _, _, out = failing_run
    sizes = {m.signature.algorithm: m.shrink.minimal_size for r in out["records"] for m in r.cause.records}
    assert sizes["test-report-raiser"] == 3  # one far-left point plus two to make it non-degenerate
    assert sizes["test-report-dropper"] <= 4
    assert sizes["test-report-holey"] <= 5


def test_every_reproduce_command_exits_1_as_printed(failing_run, tmp_path):
    _, _, out = failing_run
    commands = [r.command for r in out["records"]]
    assert all(shlex.split(c)[:4] == [sys.executable, "-m", "hullstress", "reproduce"] for c in commands)
    # From an unrelated directory: the commands must not depend on the cwd.
    procs = [subprocess.Popen(cmd, shell=True, cwd=tmp_path, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                              text=True) for cmd in commands]
    for cmd, proc in zip(commands, procs):
        stdout, stderr = proc.communicate(timeout=180)
        assert proc.returncode == 1, (cmd, stdout[-2000:], stderr[-2000:])
        assert "the same failure as recorded" in stdout


def test_summary_findings_and_junit(failing_run):
    import xml.etree.ElementTree as ET

    run_dir, result, out = failing_run
    summary = (run_dir / "summary.md").read_text()
    assert summary.startswith("# hullstress run")
    assert f"{len(out['groups'])} failure groups" in summary and "## Top causes" in summary
    assert "## Findings" in summary
    for rec in out["records"]:
        assert f"]({rec.folder.relative_to(run_dir).as_posix()}/)" in summary  # a link to each folder
    causes = pd.read_csv(run_dir / "causes.csv")
    assert list(causes["slug"]) == [r.cause.slug for r in out["records"]]
    groups = pd.read_csv(run_dir / "groups.csv")
    assert sorted(groups["slug"]) == sorted(g.slug for g in out["groups"])
    # The report's findings are the findings command's: the same computation, the same files.
    from hullstress.report.findings import compute_findings, findings_frame, findings_markdown, run_source

    findings = compute_findings(result.table, source=run_source(json.loads((run_dir / "run.json").read_text())))
    assert out["findings_md"].read_text() == findings_markdown(findings, level=1)
    assert out["findings_csv"].read_text() == findings_frame(findings).to_csv(index=False)
    # This run has one plug-in family, no sphere and no placed family: those claims say so.
    assert "untested here" in " ".join(out["findings"].claim("sphere-method").reading)
    assert "untested here" in " ".join(out["findings"].claim("eps-policy").reading)
    doc = ET.parse(out["junit"]).getroot()
    failing = {(c.get("classname"), c.get("name")) for c in doc.iter("testcase") if c.find("failure") is not None}
    assert failing == {(g.signature.config.label, f) for g in out["groups"] for f in g.family_names}
    for case in doc.iter("testcase"):
        if case.find("failure") is not None:
            assert "reproduce: " in case.find("failure").text
    index = json.loads((run_dir / "failures" / "index.json").read_text())
    assert len(index["folders"]) == len(out["records"])


def test_a_clean_run_reports_no_failures(tmp_path, plugin):
    run_dir, result, meta = _sweep(tmp_path, plugin, ("test-report-good",))
    out = _finalize(run_dir, result.table, result.cases, meta, junit_path=tmp_path / "junit.xml")
    parser = _check_html(out["html"])
    assert out["records"] == [] and parser.images == []
    assert "No failures." in " ".join(parser.text)
    assert not (run_dir / "failures").exists() or not any(p.is_dir() for p in (run_dir / "failures").iterdir())


def test_no_shrink_keeps_the_smallest_case(tmp_path, plugin):
    run_dir, result, meta = _sweep(tmp_path, plugin, ("test-report-raiser",))
    out = _finalize(run_dir, result.table, result.cases, meta, shrink=False, pictures=False)
    assert out["records"] and all(r.minimal_size == r.original_size == 12 for r in out["records"])
    assert all(not r.shrunk and "--no-shrink" in r.note for r in out["records"])
    assert len(out["records"]) == len(out["groups"])  # nothing was minimised, so nothing merges
    assert "Shrinking was turned off" in out["html"].read_text()


@pytest.mark.skipif(shutil.which("chromium") is None and not os.path.exists("/usr/bin/chromium"),
                    reason="no chromium on this machine: the report's structure and pictures are validated "
                    "by the other tests instead")
def test_report_renders_in_headless_chromium(failing_run, tmp_path):
    _, _, out = failing_run
    exe = shutil.which("chromium") or "/usr/bin/chromium"
    shot = tmp_path / "shot.png"
    cmd = [exe, "--headless", "--disable-gpu", "--no-sandbox", f"--screenshot={shot}", "--window-size=1200,3000",
           out["html"].resolve().as_uri()]
    proc = subprocess.run(cmd, capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, (shlex.join(cmd), proc.stderr[-2000:])
    assert shot.read_bytes()[:8] == PNG_SIGNATURE


def test_evaluation_budgets_leave_groups_unshrunk_and_pictures_to_the_top_causes(tmp_path, plugin):
    run_dir, result, meta = _sweep(tmp_path, plugin, ("test-report-raiser", "test-report-dropper"))
    none = TriageBudget(calls=0, group_calls=100, hang_calls=0, pictures=1, safety_seconds=600.0)
    out = _finalize(run_dir, result.table, result.cases, meta, budget=none)
    assert len(out["records"]) == len(out["groups"]) == 3  # every group still gets a folder, unshrunk
    assert all(not r.shrunk and "evaluation budget was spent" in r.note for r in out["records"])
    assert sum(r.picture is not None for r in out["records"]) == 1
    assert all((r.folder / "picture.png").exists() == (r.picture is not None) for r in out["records"])
    assert any("Pictures are drawn for the top 1 causes" in n for n in out["notes"])
    assert any("3 groups keep their smallest failing case unshrunk" in n for n in out["notes"])

    tight = TriageBudget(calls=5000, group_calls=3, hang_calls=0, pictures=0, safety_seconds=600.0)
    run2 = tmp_path / "run2"
    run2.mkdir()
    out = _finalize(run2, result.table, result.cases, meta, budget=tight)
    assert all(r.shrunk and r.shrink_calls <= 3 for r in out["records"])
    assert any("ran out of evaluations" in n for n in out["notes"])
    assert all(r.picture is None for r in out["records"])


PICTURE_INPUTS = [
    # points, faces, dim, offending
    (np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]]), [0, 2], 2, {"containment": [1]}),  # collinear
    (np.array([[1e300, 0.0], [-1e300, 1e300], [0.0, -1e300]]), [0, 1, 2], 2, {"flipped_edges": [0]}),
    (np.array([[0.0, 0.0], [np.nan, 1.0], [1.0, 1.0], [1.0, 0.0]]), [0, 2, 3], 2, {}),
    (np.zeros((0, 2)), None, 2, {}),
    (np.ones((4, 3)), [[0, 1, 2], [0, 2, 1]], 3, {"degenerate_faces": [0, 1]}),  # one point, repeated
    (np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1.0]]), [[0, 2, 1], [0, 1, 3], [1, 2, 3]], 3,
     {"manifold_faces": [2], "containment": [3], "missing_extreme": [9]}),  # out-of-range index ignored
]


@pytest.mark.parametrize("points, faces, dim, offending", PICTURE_INPUTS)
def test_pictures_of_degenerate_and_extreme_inputs_decode(points, faces, dim, offending):
    from PIL import Image

    from hullstress.report.pictures import failure_picture

    png = failure_picture(points, faces, dim=dim, offending=offending, title="t")
    assert png[:8] == PNG_SIGNATURE
    with Image.open(io.BytesIO(png)) as im:
        assert im.size[0] > 100


def test_split_offending_sorts_keys_into_points_faces_and_edges():
    from hullstress.report.pictures import split_offending

    pts, faces, edges = split_offending({"containment": [4], "missing_extreme": [1], "reflex_vertices": [2],
                                         "manifold_faces": [0, 3], "degenerate_edges": [5]})
    assert (pts, faces, edges) == ({1, 2, 4}, {0, 3}, {5})


