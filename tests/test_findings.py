"""The findings: each claim's numbers on small hand-made tables, a tiny real run, and the command.

The hand-made tables are results tables with only the rows each claim needs;
every expected number below is counted by hand from those rows.
"""

from __future__ import annotations

import json
from pathlib import Path

import pandas as pd
import pytest

from hullstress.cli import main
from hullstress.report.findings import compute_findings, findings_frame, findings_markdown
from hullstress.results import ResultRow, read_frame, to_frame

UNIFORM_BALL = json.dumps({"add": "none", "scale": 1.0, "shape": "ball"})
UNIFORM_CUBE = json.dumps({"add": "cube", "scale": 1.0, "shape": "cube"})


def _row(**values) -> ResultRow:
    base = {"generator": "uniform", "params": UNIFORM_BALL, "dim": 3, "size": 16, "n_points": 16,
            "algorithm": "alg", "sphere": "off", "eps": "scaled", "status": "pass", "stage": "algorithm",
            "sphere_method": "", "sphere_structure": "", "sphere_kept_structure": "", "reason": "",
            "failed_checks": "", "case_id": "c"}
    base.update(values)
    return ResultRow(base)


def _table(rows: list[ResultRow]) -> pd.DataFrame:
    return to_frame(rows)


def _projection(case, *, extreme, lost, structure, kept, dim=3, eps="scaled", status=None, **kw):
    """A sphere-on row of ``case`` whose method verdict follows from its structure."""
    method = "pass" if structure == "same" else "fail"
    status = status or method
    return _row(case_id=case, dim=dim, sphere="on", eps=eps, status=status,
                stage="algorithm" if method == "pass" else "preprocess", sphere_method=method,
                sphere_extreme=extreme, sphere_lost_extreme=lost, sphere_structure=structure,
                sphere_kept_structure=kept, **kw)


# -- the sphere method -------------------------------------------------------------------------


def _sphere_table() -> pd.DataFrame:
    rows = [
        # A: 2 of 10 vertices lost; its fixed-eps row says otherwise and must not be the one counted.
        _projection("A", extreme=10, lost=2, structure="changed", kept="changed"),
        _projection("A", extreme=10, lost=5, structure="changed", kept="changed", eps="fixed"),
        _projection("A", extreme=10, lost=2, structure="changed", kept="changed", algorithm="other"),
        # B: nothing lost, the faces changed anyway.
        _projection("B", extreme=8, lost=0, structure="changed", kept="changed"),
        # C: the hull kept; the algorithm failed on the projected points (its own failure, not the method's).
        _projection("C", extreme=6, lost=0, structure="same", kept="same"),
        _row(case_id="C", sphere="on", status="fail", stage="algorithm", sphere_extreme=6, sphere_lost_extreme=0,
             sphere_structure="same", sphere_kept_structure="same", algorithm="other"),
        # D: the projection raised: no projection, a method error.
        _row(case_id="D", sphere="on", status="error", stage="preprocess", sphere_method="error"),
        # E: 2D, one vertex of five lost; the kept projection would have been right.
        _projection("E", extreme=5, lost=1, structure="changed", kept="same", dim=2),
        # A sphere-off row never counts.
        _row(case_id="A", status="fail"),
    ]
    return _table(rows)


def test_sphere_claim_counts_each_cause_once_per_projection():
    claim = compute_findings(_sphere_table()).claim("sphere-method")
    detail = claim.detail.set_index("dim")
    three = detail.loc[3]
    assert three["projections"] == 4 and three["no_projection"] == 1
    assert (three["vertex_lost"], three["extreme_known"]) == (1, 3)
    assert (three["lost_sum"], three["extreme_sum"]) == (2, 24)  # A's scaled row: 2, not the fixed row's 5
    assert (three["faces_change"], three["kept_known"]) == (2, 3)
    assert (three["changed_none_lost"], three["none_lost"]) == (1, 2)
    assert (three["hull_kept"], three["observed_known"]) == (1, 3)
    # Rows: A x3, B, C x2, D with sphere on; method failures A x3, B, D; the algorithm's own: C's second row.
    assert (three["rows"], three["method_failed"], three["algorithm_failed"]) == (7, 5, 1)
    two = detail.loc[2]
    assert (two["vertex_lost"], two["lost_sum"], two["extreme_sum"], two["faces_change"]) == (1, 1, 5, 0)
    text = " ".join(claim.reading + claim.why)
    assert "3D: the sphere method failed (stage preprocess) in 5/7 sphere-on rows" in text
    assert "(a) vertex loss: the support mapping dropped a true vertex in 1/3 (33%), 2 of 24 true vertices" in text
    assert "different hull in 2/3 (67%); where the method itself lost no vertex, its hull still changed in 1/2" in text


def test_sphere_claim_without_sphere_rows_says_untested():
    claim = compute_findings(_table([_row()])).claim("sphere-method")
    assert claim.detail.empty and "untested" in claim.reading[0]


# -- eps policies ------------------------------------------------------------------------------


def _eps_table() -> pd.DataFrame:
    scaled = {s: json.dumps({"base": "ball", "scale": s}) for s in (1e3, 1e6)}
    offset = {o: json.dumps({"base": "ball", "offset": o}) for o in (1e6, 1e8)}
    rows = []
    for eps, value in (("fixed", 2.0 ** -52), ("scaled", 2.0 ** -52 * 2e6)):
        for k in range(2):
            rows.append(_row(case_id=f"s{k}", generator="scaled", params=scaled[1e6], eps=eps, eps_value=value,
                             status="fail" if eps == "fixed" else "pass"))
            rows.append(_row(case_id=f"u{k}", eps=eps, eps_value=2.0 ** -52 * 2))
        rows.append(_row(case_id="t", generator="scaled", params=scaled[1e3], eps=eps))
        for o in (1e6, 1e8):
            rows.append(_row(case_id=f"o{o}", generator="offset", params=offset[o], eps=eps, status="fail",
                             eps_value=2e-16))
        # Neither a sphere-on row nor a failure of the eps set-up is the algorithm's: no call of it.
        rows.append(_row(case_id="s0", generator="scaled", params=scaled[1e6], eps=eps, sphere="on", status="fail"))
        rows.append(_row(case_id="u0", eps=eps, status="error", stage="preprocess"))
    # A family at one placement (and not the control) is not on the scale axis.
    rows.append(_row(case_id="g", generator="coplanar-grid", params="{}", eps="fixed", status="fail"))
    return _table(rows)


def test_eps_claim_pairs_the_policies_per_placement():
    claim = compute_findings(_eps_table()).claim("eps-policy")
    detail = claim.detail.set_index("placement")
    cols = ["fixed_failed", "fixed_calls", "scaled_failed", "scaled_calls"]
    assert detail.loc["x1e6", cols].tolist() == [2, 2, 0, 2]
    assert detail.loc["x1e3", cols].tolist() == [0, 1, 0, 1]
    assert detail.loc["x1", cols].tolist() == [0, 2, 0, 2]
    assert detail.loc["x1", ["fixed_unjudged", "scaled_unjudged"]].tolist() == [1, 1]
    assert detail.loc["+1e6", ["fixed_failed", "scaled_failed"]].tolist() == [1, 1]
    assert set(claim.detail["family"]) == {"uniform", "scaled", "offset"}
    moderate = dict(claim.tables)["Moderate scales (x1 to x1e12)"].set_index("family")
    assert moderate.loc["scaled", ["x1", "x1e3", "x1e6"]].tolist() == ["-", "0/1 vs 0/1", "2/2 vs 0/2"]
    assert moderate.loc["uniform", "x1"] == "0/2 vs 0/2"
    assert dict(claim.tables)["Offsets"].iloc[0][["+1e6", "+1e8"]].tolist() == ["1/1 vs 1/1", "1/1 vs 1/1"]
    assert claim.reading == ("alg (3D): the policies differ in 1 cell (fixed vs scaled): scaled x1e6 2/2 vs 0/2.",)
    # The cause, from eps_value: the fixed eps is 2.2e-22 of coordinates of size 1e6, the scaled one 4.4e-16.
    assert "x1e6: fixed 2.2e-22, scaled 4.4e-16" in claim.why[0]


# -- uniform clouds by variant and size --------------------------------------------------------


def test_uniform_claim_splits_by_variant_size_and_eps():
    rows = []
    for n in (16, 64):
        for eps in ("fixed", "scaled"):
            rows.append(_row(case_id=f"cube{n}", params=UNIFORM_CUBE, size=n, eps=eps, algorithm="gw", status="fail",
                             failed_checks="manifoldness", n_faces=10))
            plain_fails = n == 64 and eps == "fixed"
            rows.append(_row(case_id=f"ball{n}", size=n, eps=eps, algorithm="gw",
                             status="fail" if plain_fails else "pass", n_faces=0 if plain_fails else 20))
            rows.append(_row(case_id=f"ball{n}", size=n, eps=eps, algorithm="good"))
    rows.append(_row(case_id="ball16", algorithm="gw", sphere="on", status="fail", stage="preprocess"))
    claim = compute_findings(_table(rows)).claim("uniform-variants")
    table = dict(claim.tables)["Sphere off, algorithms with a failure"].set_index("variant")
    assert table.loc["add=cube shape=cube", "n=16"] == "fixed 1/1 · scaled 1/1"
    assert table.loc["add=none shape=ball", "n=16"] == "fixed 0/1 · scaled 0/1"
    assert table.loc["add=none shape=ball", "n=64"] == "fixed 1/1 · scaled 0/1"
    assert claim.reading[0].startswith("gw (3D), sphere off: 5/8 (62%) failed; by variant: add=cube shape=cube "
                                       "fixed 2/2 · scaled 2/2; add=none shape=ball fixed 1/2 · scaled 0/2; by size: "
                                       "n=16 fixed 1/2 · scaled 1/2; n=64 fixed 2/2 · scaled 1/2.")
    assert claim.reading[1] == "No failure with sphere off (4 calls): good."
    assert claim.why == ("gw: manifoldness 4, no faces 1 (failed checks, or error type, of the failing calls).",)


# -- degenerate families against the control ---------------------------------------------------


def test_degenerate_claim_counts_only_the_algorithms_own_failures():
    rows = []
    for k in range(4):
        rows.append(_row(case_id=f"g{k}", generator="coplanar-grid", params="{}",
                         status="fail" if k < 3 else "pass", failed_checks="containment"))
        # Sphere on: the algorithm fails on the projected points once; twice its hull was right and the
        # method lost it (the method's failure, yet a call the algorithm passed).
        on_status, on_stage = [("fail", "algorithm"), ("fail", "preprocess"), ("fail", "preprocess"), ("pass", "algorithm")][k]
        rows.append(_row(case_id=f"g{k}", generator="coplanar-grid", params="{}", sphere="on", status=on_status,
                         stage=on_stage, sphere_method="fail" if on_stage == "preprocess" else ""))
        rows.append(_row(case_id=f"g{k}", generator="coplanar-grid", params="{}", algorithm="lib", eps="n/a",
                         status="rejected"))
    for k in range(2):
        rows.append(_row(case_id=f"u{k}"))
    # The projection raised before the call: no call of the algorithm at all.
    rows.append(_row(case_id="u0", sphere="on", status="error", stage="preprocess", sphere_method="error"))
    claim = compute_findings(_table(rows)).claim("degenerate-vs-control")
    summary = claim.tables[0][1]
    alg = summary.set_index("algorithm").loc["alg"]
    assert alg["degenerate, sphere off"] == "3/4 (75%)"
    assert alg["degenerate, sphere on"] == "1/4 (25%)"  # the two preprocess failures are the method's
    assert alg["degenerate, sphere on, end to end"] == "3/4 (75%)"  # ... and count end to end
    assert alg["uniform, sphere off"] == "0/2 (0%)"
    assert alg["uniform, sphere on"] == "-"
    assert alg["uniform, sphere on, end to end"] == "1/1 (100%)"  # the projection raised
    assert claim.detail.query("kind == 'uniform' and sphere == 'on'")["unjudged"].tolist() == [1]
    assert summary.set_index("algorithm").loc["lib", "degenerate, sphere off"] == "0/4 (0%)"  # rejected is fine
    assert claim.reading[0].startswith("3D, sphere off, degenerate vs uniform: alg 3/4 (75%) vs 0/2 (0%)")
    assert claim.why == ("alg on degenerate families, sphere off: containment 3.",)


def test_markdown_and_csv_hold_every_claim():
    table = pd.concat([_sphere_table(), _eps_table()], ignore_index=True)
    findings = compute_findings(table, source="run `x`")
    text = findings_markdown(findings)
    for claim in findings.claims:
        assert f"### {claim.title}" in text
    frame = findings_frame(findings)
    assert set(frame["claim"]) == {c.key for c in findings.claims if len(c.detail)}
    assert "From run `x` (" in text


# -- the command -------------------------------------------------------------------------------


def _one_error_line(capsys) -> str:
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1, err
    return err[0]


def test_findings_command_bad_inputs(tmp_path, capsys):
    assert main(["findings", str(tmp_path / "missing")]) == 2
    assert "no such file or directory" in _one_error_line(capsys)
    assert main(["findings", str(tmp_path)]) == 2
    assert "no results table in this folder (expected results.parquet or results.csv)" in _one_error_line(capsys)
    (tmp_path / "results.csv").write_text("not,a,table\n1,2,3\n")
    assert main(["findings", str(tmp_path)]) == 2
    line = _one_error_line(capsys)
    assert "cannot read the results table" in line and "missing columns" in line
    (tmp_path / "results.parquet").write_bytes(b"\x00garbage")
    assert main(["findings", str(tmp_path)]) == 2
    assert "results.parquet" in _one_error_line(capsys)


def test_findings_command_unwritable_out(tmp_path, capsys):
    _sphere_table().to_csv(tmp_path / "results.csv", index=False)
    blocker = tmp_path / "file"
    blocker.write_text("")
    assert main(["findings", str(tmp_path), "--out", str(blocker / "sub")]) == 2
    assert "--out" in _one_error_line(capsys)


def test_a_table_read_back_gives_the_same_findings(tmp_path, capsys):
    table = pd.concat([_sphere_table(), _eps_table()], ignore_index=True)
    table.to_csv(tmp_path / "results.csv", index=False)
    assert main(["findings", str(tmp_path / "results.csv"), "--quiet"]) == 0
    assert capsys.readouterr().out.startswith("findings: ")
    again = pd.read_csv(tmp_path / "findings.csv")
    direct = findings_frame(compute_findings(read_frame(tmp_path / "results.csv")))
    pd.testing.assert_frame_equal(again, pd.read_csv(pd.io.common.StringIO(direct.to_csv(index=False))))


def test_findings_computed_beside_the_report_are_the_findings_of_the_table(monkeypatch):
    # With workers to spare the findings are computed in a process of their own from the moment the
    # table is final (while triage runs); the same function of the same table, so the same claims, and
    # here when that process cannot start or is closed before it is asked.
    from hullstress.report import stage
    from hullstress.runner import start_method

    start_method()  # the run's fork server, with its imports (as in a run), not a bare one started here
    table = pd.concat([_sphere_table(), _eps_table()], ignore_index=True)
    want = findings_markdown(compute_findings(table, source="run `x`"))
    with stage.FindingsBeside(table, 2) as beside:
        assert beside.helped  # a helper computes them
        assert findings_markdown(beside.result("run `x`")) == want
    assert findings_markdown(stage.FindingsBeside(table, 1).result("run `x`")) == want
    early = stage.FindingsBeside(table, 2)
    early.close()  # e.g. the run stopped before its report: asked anyway, they are computed here
    assert findings_markdown(early.result("run `x`")) == want

    def refused(*args, **kwargs):
        raise OSError("no process for you")

    monkeypatch.setattr(stage.multiprocessing, "get_context", refused)
    refused_helper = stage.FindingsBeside(table, 2)
    assert not refused_helper.helped
    assert findings_markdown(refused_helper.result("run `x`")) == want


@pytest.fixture(scope="module")
def tiny_run(tmp_path_factory) -> Path:
    """A real run: two algorithms, three families, one small size, in this process."""
    out = tmp_path_factory.mktemp("runs")
    status = main(["run", "--generator", "uniform", "--generator", "cube-faces",
                   "--algorithm", "monotone-chain", "--algorithm", "kenwright", "--sizes", "12",
                   "--workers", "0", "--no-shrink", "--out", str(out), "--quiet"])
    assert status in (0, 1)
    (run_dir,) = [p for p in out.iterdir() if p.is_dir()]
    return run_dir


def test_the_run_report_and_the_command_compute_the_same_findings(tiny_run, tmp_path, capsys):
    written = (tiny_run / "findings.md").read_text()
    assert main(["findings", str(tiny_run), "--out", str(tmp_path)]) == 0
    printed = capsys.readouterr().out
    assert (tmp_path / "findings.md").read_text() == written
    assert (tmp_path / "findings.csv").read_text() == (tiny_run / "findings.csv").read_text()
    assert printed.startswith(written)  # the command prints the same Markdown
    assert "## Findings" in (tiny_run / "summary.md").read_text()
    assert "The sphere method, per dimension" in (tiny_run / "report.html").read_text()


def test_the_real_runs_causes_obey_their_invariants(tiny_run):
    table = read_frame(tiny_run / "results.parquet" if (tiny_run / "results.parquet").exists()
                       else tiny_run / "results.csv")
    on = table[table["sphere"] == "on"]
    projected = on[on["sphere_structure"] != ""]
    assert len(projected) and (table.loc[table["sphere"] == "off", "sphere_structure"] == "").all()
    # A lost vertex always changes the hull; a method that passed lost nothing and kept the structure.
    lost = projected["sphere_lost_extreme"].fillna(0) > 0
    assert (projected.loc[lost, "sphere_structure"] == "changed").all()
    passed = projected["sphere_method"] == "pass"
    assert (projected.loc[passed, "sphere_lost_extreme"] == 0).all()
    assert (projected.loc[passed, "sphere_structure"] == "same").all()
    # On uniform clouds every projection is certified: each cause is known.
    clouds = projected[projected["generator"] == "uniform"]
    assert clouds["sphere_structure"].isin(["same", "changed"]).all()
    assert clouds["sphere_kept_structure"].isin(["same", "changed"]).all()
    claim = compute_findings(table).claim("sphere-method")
    assert int(claim.detail["projections"].sum()) == on["case_id"].nunique()
