"""Failure folders a maintainer can act on without hullstress (issue 36).

* declared contracts: a strict plug-in keeping collinear boundary points fails, the same function lenient passes;
* every folder of a run holds a reproducer, ``certificate.json``, ``verify.py`` and ``bug-report.md``;
* reproducers and the verifier run in an interpreter that cannot import hullstress;
* the verifier accepts every certificate of the run and rejects corrupted ones.
"""

from __future__ import annotations

import copy
import json
import os
import shlex
import subprocess
import sys
import sysconfig
from pathlib import Path
from fractions import Fraction

import numpy as np
import pytest

from hullstress.case import Case
from hullstress.config import AlgorithmConfig
from hullstress.contract_verdict import apply_contract
from hullstress.errors import UsageError
from hullstress.evaluate import evaluate
from hullstress.hull_contract import LENIENT, STRICT, parse_contract
from hullstress.registry import ALGORITHMS, get_algorithm, register_algorithm
from hullstress.report.certificate_json import build_certificate
from hullstress.report.repro import write_reproducer

PY = sys.executable
HERE = Path(__file__).parent
PLUGIN = HERE / "keep_collinear_plugin.py"
PLANTED = HERE / "programs" / "planted_hull.py"
SITE = sysconfig.get_paths()["purelib"]


def run_without_hullstress(folder: Path, script: str) -> subprocess.CompletedProcess:
    """Run ``script`` in ``folder`` with no site processing: only the packages' directory on the path.

    ``-S`` skips the ``.pth`` files, among them the editable install's finder, so hullstress
    cannot be imported, while numpy, scipy, shapely and CGAL (plain directories there) can.
    """
    code = (f"import sys, runpy; sys.path[:0] = [{SITE!r}]; sys.argv = [{script!r}]; "
            f"runpy.run_path({script!r}, run_name='__main__')")
    return subprocess.run([PY, "-S", "-I", "-c", code], cwd=folder, capture_output=True, text=True, timeout=300,
                          env={"PATH": os.environ.get("PATH", "/usr/bin:/bin")})


def test_the_isolated_interpreter_cannot_import_hullstress(tmp_path):
    (tmp_path / "probe.py").write_text("import numpy\nimport hullstress\n")
    res = run_without_hullstress(tmp_path, "probe.py")
    assert res.returncode != 0 and "No module named 'hullstress'" in res.stderr


# ---- contracts ------------------------------------------------------------------------------------

def test_contract_spellings():
    assert parse_contract("strict") == STRICT and parse_contract("lenient") == LENIENT
    c = parse_contract("strict,faces=triangles,flat=raise")
    assert (c.vertices, c.faces, c.flat) == ("extreme", "triangles", "raise")
    assert parse_contract(c.label) == c
    for bad, word in [("strictest", "strictest"), ("faces=squares", "squares"), ("colour=red", "colour")]:
        with pytest.raises(UsageError, match=word):
            parse_contract(bad)


def test_builtin_adapters_declare_their_libraries_contracts():
    for name, label in [("shapely-convex-hull", "strict,flat=raise"), ("cgal-convex-hull-2d", "strict,flat=raise"),
                        ("cgal-convex-hull-3d", "strict,faces=triangles,flat=raise"),
                        ("scipy-qhull-3d", "lenient,faces=triangles"), ("monotone-chain", "lenient")]:
        if name in ALGORITHMS:
            assert get_algorithm(name).contract.label == label


@pytest.fixture
def keep_collinear_twice():
    """The plug-in's function registered twice: strict and lenient."""
    sys.path.insert(0, str(HERE))
    try:
        import keep_collinear_plugin as plugin
    finally:
        sys.path.remove(str(HERE))
    register_algorithm("keep-collinear-strict", dim=2, contract="strict")(plugin.keep_collinear)
    register_algorithm("keep-collinear-lenient", dim=2)(plugin.keep_collinear)
    yield
    ALGORITHMS.remove("keep-collinear-strict")
    ALGORITHMS.remove("keep-collinear-lenient")


def _row(name: str, points) -> dict:
    case = Case.from_points(np.asarray(points, dtype=np.float64), family="test")
    return evaluate(case, AlgorithmConfig(name, "off", "n/a")).values


def test_a_strict_plugin_keeping_collinear_boundary_points_fails_and_lenient_passes(keep_collinear_twice):
    square_with_midpoints = [[0, 0], [1, 0], [2, 0], [2, 2], [1, 2], [0, 2], [1, 1]]
    strict = _row("keep-collinear-strict", square_with_midpoints)
    lenient = _row("keep-collinear-lenient", square_with_midpoints)
    assert lenient["status"] == "pass" and lenient["contract"] == "lenient"
    assert strict["status"] == "fail" and strict["contract"] == "strict"
    assert "extreme_only" in strict["failed_checks"].split(",")
    assert strict["reason"].startswith("declared contract (strict): 2 hull vertices are not extreme")


def test_the_georust_collinear_middle_point_is_a_strict_failure():
    # georust/geo #905: the hull of (0,0), (1,1), (2,2) kept the middle point.
    def keeps_all(points):
        return [0, 1, 2]

    register_algorithm("doc-keeps-all-strict", dim=2, contract="strict")(keeps_all)
    register_algorithm("doc-keeps-all-lenient", dim=2)(keeps_all)
    try:
        collinear = [[0.0, 0.0], [1.0, 1.0], [2.0, 2.0]]
        lenient, strict = _row("doc-keeps-all-lenient", collinear), _row("doc-keeps-all-strict", collinear)
    finally:
        ALGORITHMS.remove("doc-keeps-all-strict")
        ALGORITHMS.remove("doc-keeps-all-lenient")
    assert strict["status"] == "fail" and "extreme_only" in strict["failed_checks"]
    assert lenient["status"] != "fail", lenient["reason"]


def test_a_kept_face_point_in_3d_is_a_strict_failure():
    # CGAL #3192: a 3D hull with a vertex that is not extreme (here the centre of the cube's top face).
    cube = [[x, y, z] for x in (0.0, 2.0) for y in (0.0, 2.0) for z in (0.0, 2.0)]
    points = np.asarray(cube + [[1.0, 1.0, 2.0]])
    from scipy.spatial import ConvexHull

    hull = ConvexHull(points, qhull_options="Qt Qc")
    faces = []
    for (a, b, c), eq in zip(hull.simplices.tolist(), hull.equations):
        n = np.cross(points[b] - points[a], points[c] - points[a])
        faces.append([a, b, c] if n @ eq[:3] > 0 else [a, c, b])
    top = [f for f in faces if all(points[v][2] == 2.0 for v in f)]
    rest = [f for f in faces if f not in top]
    corners = {1: [0.0, 0.0], 3: [0.0, 2.0], 7: [2.0, 2.0], 5: [2.0, 0.0]}  # the top face, counter-clockwise
    ring = [1, 5, 7, 3]
    assert all(points[v][2] == 2.0 for v in ring) and len(corners) == 4
    fan = [[8, ring[i], ring[(i + 1) % 4]] for i in range(4)]
    output = np.asarray(rest + fan)

    def with_face_centre(pts):
        return output

    register_algorithm("doc-face-centre-strict", dim=3, contract="strict")(with_face_centre)
    register_algorithm("doc-face-centre-lenient", dim=3)(with_face_centre)
    try:
        strict, lenient = _row("doc-face-centre-strict", points), _row("doc-face-centre-lenient", points)
    finally:
        ALGORITHMS.remove("doc-face-centre-strict")
        ALGORITHMS.remove("doc-face-centre-lenient")
    assert lenient["status"] == "pass", lenient["reason"]
    assert strict["status"] == "fail" and "extreme_only" in strict["failed_checks"]


def test_faces_and_flat_promises():
    from hullstress.contract import FaceSet
    from hullstress.results import ResultRow

    passed = ResultRow({"status": "pass", "failed_checks": "", "reason": "", "n_boundary_nonextreme": 0,
                        "invalid_input": "", "affine_rank": 1})
    quads = FaceSet.from_polygons([[0, 1, 2, 3], [0, 3, 2, 1]])
    assert apply_contract(passed, parse_contract("faces=triangles"), quads, degenerate=False)["failed_checks"] \
        == "face_shape"
    assert apply_contract(passed, LENIENT, quads, degenerate=False) is passed
    flat = apply_contract(passed, parse_contract("flat=raise"), [0, 1], degenerate=True)
    assert flat["status"] == "fail" and flat["failed_checks"] == "flat_input"
    rejected = ResultRow({"status": "rejected", "failed_checks": "", "reason": "ValueError: flat",
                          "invalid_input": ""})
    assert apply_contract(rejected, parse_contract("flat=lower-dim"), None, degenerate=True)["status"] == "fail"
    assert apply_contract(rejected, LENIENT, None, degenerate=True)["status"] == "rejected"


# ---- a run's folders ------------------------------------------------------------------------------

@pytest.fixture(scope="module")
def run_folder(tmp_path_factory) -> Path:
    """One quick sweep of a strict plug-in from a file, a program, shapely and scipy (QJ), with triage."""
    out = tmp_path_factory.mktemp("handover")
    planted = shlex.join([PY, str(PLANTED), "drop"])
    args = ["run", "--seed", "0", "--out", str(out), "--plugin", str(PLUGIN), "--contract", "keep-collinear=strict",
            "--exec", f"planted-drop[dim=2,output=Fx]={planted}"]
    for name in ("keep-collinear", "planted-drop", "shapely-convex-hull", "scipy-qhull-2d-QJ"):
        args += ["--algorithm", name]
    for family in ("collinear-edges", "mixed-magnitude", "near-collinear", "scaled", "few-points"):
        args += ["--generator", family]
    res = subprocess.run([PY, "-m", "hullstress", *args], capture_output=True, text=True, timeout=900)
    assert res.returncode == 1, res.stderr[-2000:]
    folders = [p for p in (out / "failures").iterdir() if p.is_dir()] if (out / "failures").is_dir() else []
    if not folders:  # --out names the run folder's parent
        folders = [p for p in out.glob("*/failures/*") if p.is_dir()]
    assert folders
    return folders[0].parent


def _folders(root: Path, prefix: str = "") -> list[Path]:
    return sorted(p for p in root.iterdir() if p.is_dir() and p.name.startswith(prefix))


def test_every_folder_has_the_maintainer_files(run_folder):
    for folder in _folders(run_folder):
        names = {p.name for p in folder.iterdir()}
        assert {"certificate.json", "verify.py", "bug-report.md"} <= names, folder.name
        assert "repro.py" in names or {"input.txt", "command.txt", "repro.sh"} <= names, folder.name
    strict = _folders(run_folder, "keep-collinear")
    assert strict and all("extreme_only" in f.name for f in strict)
    report = (strict[0] / "bug-report.md").read_text()
    assert "strict: only extreme points as vertices" in report and "python repro.py" in report
    assert json.loads((strict[0] / "case.json").read_text())["contract"] == "strict"
    html = next(run_folder.parent.glob("*.html")).read_text()
    assert "declared contract" in html and "<code>strict</code>" in html


def test_bad_contract_options_are_one_line_usage_errors(capsys):
    from hullstress.cli import main

    assert main(["run", "--contract", "monotone-chain=strictest"]) == 2
    assert main(["run", "--contract", "strict"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert err == ["hullstress: error: contract 'strictest': 'strictest' is not one of lenient, strict nor "
                   "KEY=VALUE (keys: vertices, orientation, faces, flat)",
                   "hullstress: error: --contract 'strict': expected NAME=CONTRACT (e.g. my-hull=strict)"]
    assert get_algorithm("monotone-chain").contract == LENIENT


def test_the_verifier_accepts_every_certificate_of_the_run(run_folder):
    geometric = 0
    for folder in _folders(run_folder):
        res = run_without_hullstress(folder, "verify.py")
        assert res.returncode == 0, (folder.name, res.stdout[-1500:])
        cert = json.loads((folder / "certificate.json").read_text())
        geometric += cert["geometric"]
        if cert["status"] == "fail":
            assert cert["geometric"] and cert["witnesses"], folder.name
            assert "VERIFIED" in res.stdout
    assert geometric >= 3


@pytest.mark.parametrize("prefix", ["keep-collinear", "shapely-convex-hull__sphere-off__eps-na__fail",
                                    "scipy-qhull-2d-QJ__sphere-off__eps-na__fail"])
def test_python_reproducers_show_the_failure_without_hullstress(run_folder, prefix):
    folders = _folders(run_folder, prefix)
    assert folders, prefix
    for folder in folders:
        res = run_without_hullstress(folder, "repro.py")
        assert res.returncode == 1, (folder.name, res.stdout[-800:], res.stderr[-800:])
        assert "wrong: " in res.stdout and "no failure found" not in res.stdout, folder.name


def test_the_plugin_reproducer_imports_the_plugin_file_by_path(run_folder):
    text = (_folders(run_folder, "keep-collinear")[0] / "repro.py").read_text()
    assert str(PLUGIN.resolve()) in text and "spec_from_file_location" in text and "import hullstress" not in text


def test_the_program_reproducer_is_its_input_and_command_line(run_folder):
    from hullstress.qhull_format import format_points, parse_hull
    from hullstress.io import read_points

    folder = _folders(run_folder, "planted-drop")[0]
    command = (folder / "command.txt").read_text().strip()
    assert command == shlex.join([PY, str(PLANTED), "drop"]) + " < input.txt"
    points = read_points(folder / "points.csv")
    assert (folder / "input.txt").read_text() == format_points(points)
    res = subprocess.run(["sh", str(folder / "repro.sh")], capture_output=True, text=True, timeout=60,
                         env={"PATH": "/usr/bin:/bin"})
    assert res.returncode == 0, res.stderr
    recorded = json.loads((folder / "faces.json").read_text())["faces"]
    from hullstress.contract import canonical_output, normalize_output

    got = canonical_output(normalize_output(parse_hull(res.stdout, "Fx", points), len(points), 2))
    assert got.tolist() == recorded  # the program, run by hand, returns the wrong hull again


def test_a_reproducer_of_a_passing_case_finds_nothing(tmp_path):
    pytest.importorskip("scipy")
    cube = np.array([[x, y, z] for x in (0.0, 1.0) for y in (0.0, 1.0) for z in (0.0, 1.5)] + [[0.5, 0.5, 0.5]])
    square = np.array([[0.0, 0.0], [3.0, 0.0], [3.0, 1.0], [0.0, 1.0], [1.0, 0.5]])
    for name, pts in [("scipy-qhull-3d", cube), ("scipy-qhull-2d", square), ("shapely-convex-hull", square)]:
        if name not in ALGORITHMS:
            continue
        folder = tmp_path / name
        folder.mkdir()
        spec = get_algorithm(name)
        assert write_reproducer(folder, spec, pts, eps_value=None, strict=spec.contract.vertices == "extreme",
                                header="a passing case") == "python"
        res = run_without_hullstress(folder, "repro.py")
        assert res.returncode == 0 and "no failure found" in res.stdout, (name, res.stdout, res.stderr)


# ---- corrupted certificates -----------------------------------------------------------------------

def _corruptions(cert: dict) -> list[tuple[str, dict]]:
    """Every way to break this certificate that the verifier must notice."""
    out = []
    for i, w in enumerate(cert["witnesses"]):
        for key in ("orient",):
            if key in w:
                bad = copy.deepcopy(cert)
                bad["witnesses"][i][key] = -w[key]
                out.append((f"flipped sign of witness {i}", bad))
        for key in ("face",):
            if key in w:
                bad = copy.deepcopy(cert)
                bad["witnesses"][i][key] = len(cert["faces"]) + 5 if cert["dim"] == 3 else 7
                out.append((f"a face not in the output (witness {i})", bad))
        if "point" in w:
            bad = copy.deepcopy(cert)
            other = (w["point"] + 1) % len(cert["points"])
            bad["witnesses"][i]["point"] = other if cert["points"][other] != cert["points"][w["point"]] else w["point"]
            if bad != cert:
                out.append((f"another point (witness {i})", bad))
        if "value" in w:
            bad = copy.deepcopy(cert)
            bad["witnesses"][i]["value"] = "1/3"
            out.append((f"a wrong measure (witness {i})", bad))
        if "direction" in w:
            bad = copy.deepcopy(cert)
            bad["witnesses"][i]["direction"] = [("-" + x).replace("--", "") for x in w["direction"]]
            out.append((f"a reversed direction (witness {i})", bad))
        if "combination" in w:
            bad = copy.deepcopy(cert)
            bad["witnesses"][i]["combination"][0][1] = "1/7"
            out.append((f"wrong weights (witness {i})", bad))
    bad = copy.deepcopy(cert)
    x = float.fromhex(bad["points"][0][0])
    bad["points"][0][0] = (x + 1.0 if x == 0 else x * 1.5).hex()
    out.append(("a moved coordinate", bad))
    bad = copy.deepcopy(cert)
    bad["witnesses"] = []
    out.append(("no witness", bad))
    return out


def test_the_verifier_rejects_corrupted_certificates(run_folder, tmp_path):
    checked = set()
    for folder in _folders(run_folder):
        cert = json.loads((folder / "certificate.json").read_text())
        if not cert.get("witnesses"):
            continue
        for what, bad in _corruptions(cert):
            work = tmp_path / f"{folder.name[:40]}-{len(checked)}"
            subprocess.run(["cp", "-r", str(folder), str(work)], check=True)
            (work / "certificate.json").write_text(json.dumps(bad))
            res = run_without_hullstress(work, "verify.py")
            assert res.returncode == 1, (folder.name, what, res.stdout[-600:])
            checked.add(what.split(" (")[0])
    assert {"flipped sign of witness 0", "a moved coordinate", "no witness"} <= checked | {
        w for w in checked if w.startswith("flipped")}
    assert any(c.startswith("a face not in the output") for c in checked)


def test_a_synthetic_3d_certificate_covers_each_surface_witness(tmp_path):
    """An open, inward, non-convex 3D output: the builder finds each kind and the verifier accepts them."""
    tet = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [0.2, 0.2, 0.2]])
    inward = [[0, 1, 2], [0, 3, 1], [0, 2, 3], [1, 3, 2]]  # every face clockwise seen from outside
    cert = build_certificate(tet, inward, dim=3, failed_checks=["convexity", "containment"],
                             points_file="given.json", faces_file="given.json")
    kinds = {w["kind"] for w in cert["witnesses"]}
    assert {"signed-volume", "outside"} <= kinds
    (tmp_path / "given.json").write_text(json.dumps({"points": cert["points"], "faces": inward}))
    (tmp_path / "certificate.json").write_text(json.dumps(cert))
    from hullstress.report import verify_certificate

    (tmp_path / "verify.py").write_text(Path(verify_certificate.__file__).read_text())
    res = run_without_hullstress(tmp_path, "verify.py")
    assert res.returncode == 0, res.stdout
    open_surface = inward[:3]
    cert = build_certificate(tet, open_surface, dim=3, failed_checks=["manifoldness"], points_file="given.json",
                             faces_file="given.json")
    assert "edge-count" in {w["kind"] for w in cert["witnesses"]}


@pytest.mark.parametrize("value", [Fraction(1, 2**1100), Fraction(-3, 2**1080), Fraction(5, 2**1074),
                                   Fraction(1, 2**1074), Fraction(-0.5), Fraction(2**60 + 1)])
def test_exact_text_reads_back_exactly_outside_the_double_range(value):
    """An exact area of 2**-1100 once printed as 0x0.0p+0: a zero witness that bug-report.md could not word."""
    from hullstress.report.certificate_json import exact_text

    text = exact_text(value)
    back = Fraction(float.fromhex(text)) if "/" not in text and "x" in text else Fraction(text)
    assert back == value, text
