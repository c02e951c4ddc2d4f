"""The developer tools in ``tools/``: what they refuse before they touch anything."""

import shutil
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
BARE_PATH = "/usr/bin:/bin"


@pytest.mark.skipif(shutil.which("mutmut", path=BARE_PATH) is not None,
                    reason="mutmut is installed system-wide: there is no PATH without it to try")
def test_the_mutation_script_without_mutmut_exits_2_and_keeps_the_earlier_mutants(tmp_path):
    (tmp_path / "tools").mkdir()
    shutil.copy(ROOT / "tools" / "mutation.sh", tmp_path / "tools" / "mutation.sh")
    kept = tmp_path / "mutants" / "results.kept"
    kept.parent.mkdir()
    kept.write_text("earlier results")
    res = subprocess.run(["bash", str(tmp_path / "tools" / "mutation.sh")], capture_output=True, text=True,
                         env={"PATH": BARE_PATH}, timeout=60)
    assert res.returncode == 2
    assert "mutmut not found on PATH" in res.stderr
    assert kept.read_text() == "earlier results"
