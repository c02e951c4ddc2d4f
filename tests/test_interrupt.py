"""SIGINT and SIGTERM in every phase of a run: a prompt stop, the partial report, the right exit status.

``tests/programs/phase_holder.py`` holds one phase (a 10 s call in the sweep,
a 10 s call in the shrinker, a slow picture in the report) and touches a
marker file when it starts holding; the test then signals the run and
expects, within 2 s: exit status 130 (SIGINT) or 143 (SIGTERM), a message on
stderr, every finished row in ``results.csv``, ``report.html`` and
``summary.md`` written, and ``run.json`` marked interrupted with the signal.
The two signals of a phase run side by side to keep the test short.
"""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pandas as pd
import pytest

PY = sys.executable
HOLDER = Path(__file__).resolve().parent / "programs" / "phase_holder.py"
#: Seconds from the signal to the process's exit, as promised.
STOP_WITHIN = 2.0

PHASES = {
    # phase: sizes swept (the holder's HOLD_SIZE is 12), families, more options
    "sweep": ("8,16", ["uniform"], []),
    "triage": ("12", ["uniform"], []),
    # One worker: the run draws its pictures itself, where the holder slows them down (with more, a
    # helper process draws them: tests/test_picture_helper.py interrupts the wait for one).
    "report": ("12", ["uniform", "sphere", "regular-polygon", "duplicates", "kettner-classroom"],
               ["--no-shrink", "--workers", "1"]),
}
EXPECTED = {signal.SIGINT: (130, "SIGINT"), signal.SIGTERM: (143, "SIGTERM")}


def _start(tmp_path: Path, phase: str, signum: int) -> tuple[subprocess.Popen, Path, Path]:
    sizes, families, more = PHASES[phase]
    folder = tmp_path / signal.Signals(signum).name
    folder.mkdir()
    mark = folder / "holding"
    args = [PY, "-m", "hullstress", "run", "--plugin", str(HOLDER), "--algorithm", "phase-holder",
            "--sphere", "off", "--sizes", sizes, "--workers", "2", "--timeout", "30", "--no-qhull",
            "--out", str(folder / "out"), *more] + [f"--generator={f}" for f in families]
    stderr = open(folder / "stderr.txt", "w")
    proc = subprocess.Popen(args, stdout=subprocess.DEVNULL, stderr=stderr, cwd=folder,
                            env={**os.environ, "HOLD_PHASE": phase, "HOLD_MARK": str(mark)})
    stderr.close()
    return proc, mark, folder


@pytest.mark.parametrize("phase", list(PHASES))
def test_a_signal_in_any_phase_stops_the_run_within_2_s_with_its_partial_report(tmp_path, phase):
    runs = {signum: _start(tmp_path, phase, signum) for signum in EXPECTED}
    sent: dict[int, float] = {}
    ended: dict[int, float] = {}
    try:
        deadline = time.monotonic() + 240
        while len(ended) < len(runs):
            assert time.monotonic() < deadline, f"the {phase} phase was not held, or the run did not stop"
            for signum, (proc, mark, folder) in runs.items():
                if signum in ended:
                    continue
                if proc.poll() is not None:
                    assert signum in sent, (folder / "stderr.txt").read_text()
                    ended[signum] = time.monotonic()
                elif signum not in sent and mark.exists():
                    time.sleep(0.2)  # well inside the held step
                    proc.send_signal(signum)
                    sent[signum] = time.monotonic()
            time.sleep(0.01)
    finally:
        for proc, _, _ in runs.values():
            proc.kill()
            proc.wait()
    for signum, (proc, mark, folder) in runs.items():
        status, name = EXPECTED[signum]
        err = (folder / "stderr.txt").read_text()
        assert proc.returncode == status, err
        took = ended[signum] - sent[signum]
        assert took < STOP_WITHIN, f"{phase}/{name}: stopped {took:.2f} s after the signal"
        assert f"interrupted ({name})" in err and "Traceback" not in err
        run_dir = next((folder / "out").iterdir())
        meta = json.loads((run_dir / "run.json").read_text())
        assert (meta["state"], meta["interrupted"], meta["signal"], meta["complete"]) == ("interrupted", True,
                                                                                           name, False)
        assert (run_dir / "report.html").is_file() and (run_dir / "summary.md").is_file()
        table = pd.read_csv(run_dir / "results.csv")
        assert meta["calls"] == len(table)
        if phase == "sweep":
            # The small cases finished (and are kept); the large ones were cut off mid-call.
            assert 1 <= len(table) < meta["calls_planned"]
            assert set(table["n_points"]) == {8}
        else:
            # Every call finished; the chain without its last vertex fails wherever a hull has a corner
            # (a degenerate family's correct lower-dimensional answer may pass).
            assert len(table) == meta["calls_planned"] and "fail" in set(table["status"])
        if phase == "report":
            assert len(list((run_dir / "failures").iterdir())) >= 3  # the folders, some without pictures
