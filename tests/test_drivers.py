"""The drivers shipped in drivers/: each builds with its documented command, passes on
general-position input (so a failure in a sweep is the library's, not the driver's), and is
fuzzed by the quick profile in persistent mode.

A driver whose toolchain is missing is skipped, with the command that installs it
(.ci/run installs them all on CI).
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pandas as pd
import pytest

PY = sys.executable
REPO = Path(__file__).resolve().parent.parent
DRIVERS = REPO / "drivers"


def run_cli(*args, timeout=600):
    return subprocess.run([PY, "-m", "hullstress", *args], capture_output=True, text=True, cwd=REPO,
                          env=dict(os.environ), timeout=timeout)


def _run_dir(stdout: str) -> Path:
    return Path([line for line in stdout.splitlines() if line.startswith("report: ")][-1].split("report: ", 1)[1])


def _make(target: str, build: Path, header: str, package: str) -> str:
    if shutil.which("make") is None or shutil.which(os.environ.get("CC", "cc")) is None:
        pytest.skip("needs make and a C/C++ compiler: apt-get install build-essential")
    if not Path("/usr/include", header).exists():
        pytest.skip(f"needs {header}: apt-get install {package}")
    res = subprocess.run(["make", "-C", str(DRIVERS), target, f"BUILD={build}"], capture_output=True, text=True,
                         timeout=900)
    assert res.returncode == 0, res.stdout + res.stderr
    return str(build)


@pytest.fixture(scope="module")
def build(tmp_path_factory) -> Path:
    return tmp_path_factory.mktemp("drivers")


@pytest.fixture(scope="module")
def qhull_driver(build) -> str:
    return _make("qhull", build, "libqhull_r/libqhull_r.h", "libqhull-dev") + "/qhull_r_driver"


@pytest.fixture(scope="module")
def cgal_driver(build) -> str:
    return _make("cgal", build, "CGAL/convex_hull_3.h", "libcgal-dev") + "/cgal_hull3_driver"


@pytest.fixture(scope="module")
def quickhull3d_driver() -> str:
    if shutil.which("node") is None or shutil.which("npm") is None:
        pytest.skip("needs Node.js 20 and npm: apt-get install nodejs npm")
    if not (DRIVERS / "js" / "node_modules" / "quickhull3d").is_dir():
        res = subprocess.run(["npm", "install", "--prefix", str(DRIVERS / "js"), "--no-audit", "--no-fund"],
                             capture_output=True, text=True, timeout=600)
        if res.returncode != 0:
            pytest.skip(f"`npm install --prefix drivers/js` failed (no network?): {res.stderr.strip()[-200:]}")
    return f"node {DRIVERS / 'js' / 'quickhull3d_driver.mjs'}"


DRIVER_FIXTURES = {"qhull": "qhull_driver", "cgal": "cgal_driver", "quickhull3d": "quickhull3d_driver"}
LIBRARIES = {"qhull": "libqhull_r 2020", "cgal": "CGAL 5", "quickhull3d": "quickhull3d 3"}


@pytest.mark.parametrize("driver", sorted(DRIVER_FIXTURES))
def test_driver_passes_on_general_position_input(request, tmp_path, driver):
    command = request.getfixturevalue(DRIVER_FIXTURES[driver])
    res = run_cli("run", "--exec", f"{driver}[mode=persistent]={command}", "--algorithm", driver,
                  "--generator", "uniform:shape=ball", "--generator", "uniform:shape=gaussian",
                  "--sizes", "8,50,400", "--seed", "3", "--no-shrink", "--quiet", "--out", str(tmp_path))
    assert res.returncode == 0, res.stdout + res.stderr
    run_dir = _run_dir(res.stdout)
    table = pd.read_csv(run_dir / "results.csv", keep_default_na=False)
    assert len(table) >= 6 and set(table["status"]) == {"pass"}, table[["n_points", "status", "reason"]]
    said = json.loads((run_dir / "run.json").read_text())["executables"][driver]
    assert said["mode"] == "persistent" and said["library"].startswith(LIBRARIES[driver]), said


@pytest.mark.parametrize("driver", sorted(DRIVER_FIXTURES))
def test_driver_is_fuzzed_by_the_quick_profile(request, tmp_path, driver):
    command = request.getfixturevalue(DRIVER_FIXTURES[driver])
    res = run_cli("run", "--exec", f"{driver}[mode=persistent]={command}", "--algorithm", driver,
                  "--no-shrink", "--quiet", "--out", str(tmp_path))
    # 1: the sweep found failures (these libraries have some; docs/executables.md lists them).
    assert res.returncode in (0, 1), res.stdout + res.stderr
    table = pd.read_csv(_run_dir(res.stdout) / "results.csv", keep_default_na=False)
    assert len(table) >= 100
    # Every row is a verdict on the library, never the harness losing track of the driver.
    assert not table["reason"].str.contains("internal:|out of step|handshake").any()
    assert (table["status"] == "pass").mean() > 0.5
