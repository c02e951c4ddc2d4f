"""Triage a user can trust, end to end (issue 15): ``python -m hullstress run`` twice, then its folders.

* Two runs with the same seed, one with ``--workers 1`` and one with
  ``--workers 2``, give the same ``results.csv`` (timings aside) and
  byte-identical failure folders (the run folder's own path aside: it
  carries the start time).
* Every minimised case, re-run, fails with exactly the signature of the
  group it came from, and that is the signature the group's original case
  had in the sweep.
* Minimised cases are small, ``summary.md`` fits on a screen, the terminal
  ends with the top causes and where their folders are.

The fast tests use a few families and algorithms; the slow ones the whole
quick profile (``pytest -m slow``).
"""

from __future__ import annotations

import json
import statistics
import subprocess
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from hullstress.case import Case
from hullstress.results import TIMING_COLUMNS
from hullstress.triage import Signature, run_config, signature_of

PY = sys.executable

#: A subset that exercises every kind of signature (fail with checks, contract, error with a frame,
#: invalid input) in 2D and 3D, in-house and adapters, and keeps a run well under a minute on 2 cores.
SUBSET = ["--generator=kettner-classroom", "--generator=coplanar-grid", "--generator=bad-input",
          "--algorithm=monotone-chain", "--algorithm=jarvis-march", "--algorithm=gift-wrap-3d",
          "--algorithm=scipy-qhull-2d", "--algorithm=kenwright"]


def _run(tmp: Path, workers: int, extra: list[str]) -> tuple[subprocess.CompletedProcess, Path]:
    out = tmp / f"w{workers}"
    res = subprocess.run([PY, "-m", "hullstress", "run", "--seed", "3", "--out", str(out), "--workers", str(workers),
                          *extra], capture_output=True, text=True, timeout=1800)
    assert res.returncode in (0, 1), res.stderr[-3000:]
    line = [ln for ln in res.stdout.splitlines() if ln.startswith("report: ")][-1]
    return res, Path(line.split("report: ", 1)[1])


def _two_runs(tmp: Path, extra: list[str]):
    one = _run(tmp, 1, extra)
    two = _run(tmp, 2, extra)
    return one, two


@pytest.fixture(scope="module")
def subset_runs(tmp_path_factory):
    return _two_runs(tmp_path_factory.mktemp("triage-subset"), SUBSET)


@pytest.fixture(scope="module")
def quick_runs(tmp_path_factory):
    return _two_runs(tmp_path_factory.mktemp("triage-quick"), [])


def _table(run_dir: Path) -> pd.DataFrame:
    return pd.read_csv(run_dir / "results.csv", keep_default_na=False).drop(columns=list(TIMING_COLUMNS))


def _folder_files(run_dir: Path) -> dict[str, bytes]:
    """Every file under failures/, with the run folder's path (it holds the start time) replaced."""
    out = {}
    for path in sorted((run_dir / "failures").rglob("*")):
        if path.is_file():
            data = path.read_bytes()
            if path.suffix in (".json", ".txt", ".csv"):
                data = data.replace(str(run_dir.resolve()).encode(), b"<run>").replace(str(run_dir).encode(), b"<run>")
            out[path.relative_to(run_dir).as_posix()] = data
    return out


def _assert_same_table(runs) -> None:
    (_, a), (_, b) = runs
    pd.testing.assert_frame_equal(_table(a), _table(b))


def _assert_same_folders(runs) -> None:
    (_, a), (_, b) = runs
    files_a, files_b = _folder_files(a), _folder_files(b)
    assert sorted(files_a) == sorted(files_b)
    different = [name for name in files_a if files_a[name] != files_b[name]]
    assert not different, different[:10]
    assert any(name.endswith("picture.png") for name in files_a)
    meta = json.loads((a / "run.json").read_text())
    assert meta["triage"]["safety_net"] is False and meta["triage"]["stopped"] is False


def _members(run_dir: Path):
    """(folder, member entry, its points, the dim) for every failure group of the run."""
    for case_json in sorted((run_dir / "failures").glob("*/case.json")):
        folder = case_json.parent
        meta = json.loads(case_json.read_text())
        if meta["points_file"].endswith(".csv"):
            from hullstress.io import read_points

            points = read_points(folder / meta["points_file"])
        else:
            points = np.load(folder / meta["points_file"])
        for member in meta["members"]:
            own = points if member["points"] is None else np.asarray(member["points"], dtype=np.float64)
            yield folder, meta, member, own


def _assert_minimal_cases_keep_their_signature(run_dir: Path) -> None:
    table = pd.read_csv(run_dir / "results.csv", keep_default_na=False, na_values=[""],
                        dtype={"reason": "string", "failed_checks": "string", "error_frame": "string"})
    groups = pd.read_csv(run_dir / "groups.csv", keep_default_na=False, dtype=str).set_index("slug")
    checked = 0
    for folder, meta, member, points in _members(run_dir):
        recorded = Signature.from_dict(member["signature"])
        if recorded.dangerous and recorded.status == "timeout":
            continue  # a hang costs the whole timeout; its sweep row is checked below
        row = run_config(Case(points=points, dim=meta["dim"], family="file"), recorded.config,
                         timeout=float(meta["timeout"]), isolate=True)
        assert signature_of(row) == recorded, (folder.name, member["config"], row.get("reason"))
        # ... and the group's own smallest failing case failed that way in the sweep.
        smallest = groups.loc[member["slug"], "smallest_case_id"]
        origin = table[(table["case_id"] == smallest) & (table["config"] == member["config"])]
        assert len(origin) == 1 and signature_of(origin.iloc[0]) == recorded
        checked += 1
    assert checked >= 5


def _assert_small_and_on_a_screen(res: subprocess.CompletedProcess, run_dir: Path) -> None:
    groups = pd.read_csv(run_dir / "groups.csv", keep_default_na=False)
    causes = pd.read_csv(run_dir / "causes.csv")
    # Every group is triaged: in a cause with a folder; every one but the hangs is minimised (a hang's
    # every failing call lasts the whole timeout, and the quick profile spends none on them) ...
    assert set(groups["cause"]) == set(causes["slug"]) and "" not in set(groups["cause"])
    minimised = groups[groups["minimised"].astype(str) == "True"]
    assert set(groups.loc[groups["minimised"].astype(str) != "True", "status"]) <= {"timeout"}
    # ... and merged into fewer causes.
    assert len(causes) < len(groups)
    assert statistics.median(minimised["minimal_size"]) <= 10
    summary = (run_dir / "summary.md").read_text().splitlines()
    assert len(summary) < 200
    assert "## Top causes" in "\n".join(summary)
    out = res.stdout
    assert "short summary: top" in out and "CAUSE 1: " in out
    first_folder = out.split("CAUSE 1: ", 1)[1].splitlines()[1].strip()
    assert Path(first_folder).is_dir() and (Path(first_folder) / "reproduce.txt").is_file()
    assert "hullstress triage: " in res.stderr and "hullstress report: " in res.stderr  # progress in every phase


def test_same_seed_same_table_and_byte_identical_folders_with_1_and_2_workers(subset_runs):
    _assert_same_table(subset_runs)
    _assert_same_folders(subset_runs)


def test_every_minimised_case_fails_with_the_signature_it_came_from(subset_runs):
    _assert_minimal_cases_keep_their_signature(subset_runs[0][1])


def test_cases_are_small_every_group_is_triaged_and_the_summary_fits_on_a_screen(subset_runs):
    _assert_small_and_on_a_screen(*subset_runs[1])


@pytest.mark.slow
def test_quick_profile_same_seed_byte_identical_folders_with_1_and_2_workers(quick_runs):
    _assert_same_folders(quick_runs)


@pytest.mark.slow
def test_quick_profile_same_seed_same_table_with_1_and_2_workers(quick_runs):
    # Outputs are judged in canonical face order (evaluate.call_algorithm), so a library that
    # emits its faces in another order in another process (CGAL's 3D hull) gives the same row.
    _assert_same_table(quick_runs)


@pytest.mark.slow
def test_quick_profile_minimised_cases_keep_their_signature(quick_runs):
    _assert_minimal_cases_keep_their_signature(quick_runs[1][1])


@pytest.mark.slow
def test_quick_profile_cases_are_small_and_the_summary_fits_on_a_screen(quick_runs):
    _assert_small_and_on_a_screen(*quick_runs[1])
