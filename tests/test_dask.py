"""The Dask backend on a real loopback cluster: the same table as a local run, crashes and hangs included."""

from __future__ import annotations

import json
import textwrap
from pathlib import Path

import pandas as pd
import pytest

from hullstress._registry import ALGORITHMS, GENERATORS
from hullstress.cli import main
from hullstress.results import TIMING_COLUMNS

distributed = pytest.importorskip("distributed", reason="the Dask backend needs the optional 'distributed' package")

P = "dask-test-"

PLUGIN = textwrap.dedent(
    '''
    """2D algorithms that pass, raise, return garbage, crash and hang: each must land the same way on Dask."""
    import ctypes

    from scipy.spatial import ConvexHull, QhullError

    from hullstress import register_algorithm, register_generator

    P = "dask-test-"


    @register_algorithm(P + "ok", dim=2)
    def ok(points):
        """Qhull's vertices (declines flat inputs with a reproducible message)."""
        try:
            return ConvexHull(points).vertices
        except QhullError:
            raise ValueError("Qhull declined a flat input") from None


    @register_algorithm(P + "raise", dim=2)
    def raises(points):
        """Declines every input."""
        raise RuntimeError("declined on purpose")


    @register_algorithm(P + "none", dim=2)
    def none(points):
        """Returns nothing."""
        return None


    @register_algorithm(P + "segfault", dim=2)
    def segfault(points):
        """Dereferences a null pointer."""
        return ctypes.string_at(0)


    @register_algorithm(P + "hang", dim=2)
    def hang(points):
        """Never returns."""
        while True:
            pass


    @register_generator(P + "cloud", dims=(2,), variants=({"spread": 1.0}, {"spread": 1e6}))
    def cloud(rng, n, *, dim, spread=1.0):
        """Uniform points in a square."""
        return rng.random((n, dim)) * spread
    '''
)


@pytest.fixture(scope="module")
def plugin(tmp_path_factory):
    path = tmp_path_factory.mktemp("dask_plugin") / "dask_misbehaving.py"
    path.write_text(PLUGIN)
    yield path
    for name in [n for n in ALGORITHMS.names() if n.startswith(P)]:
        ALGORITHMS.remove(name)
    GENERATORS.remove(P + "cloud")


@pytest.fixture(scope="module")
def scheduler():
    """A real scheduler and two single-threaded worker processes on 127.0.0.1."""
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, host="127.0.0.1",
                                  dashboard_address=None) as cluster:
        yield cluster.scheduler_address


def _run(plugin: Path, out: Path, capsys, *backend: str) -> Path:
    status = main(["run", "--plugin", str(plugin), "--generator", P + "cloud", "--sizes", "12,40",
                   "--sphere", "off", "--seed", "5", "--timeout", "1", "--quiet", "--out", str(out), *backend])
    captured = capsys.readouterr()
    assert status == 1, captured.err  # the misbehaving algorithms fail
    line = [x for x in captured.out.splitlines() if x.startswith("report: ")][-1]
    return Path(line.split("report: ", 1)[1])


def test_dask_table_equals_local_table(plugin, scheduler, tmp_path, capsys):
    local = _run(plugin, tmp_path / "local", capsys, "--workers", "2")
    dask = _run(plugin, tmp_path / "dask", capsys, "--scheduler", scheduler)

    left = pd.read_csv(local / "results.csv", keep_default_na=False).drop(columns=list(TIMING_COLUMNS))
    right = pd.read_csv(dask / "results.csv", keep_default_na=False).drop(columns=list(TIMING_COLUMNS))
    pd.testing.assert_frame_equal(left, right)

    # The table is not trivially equal: every kind of outcome is in it.
    assert set(left["status"]) == {"pass", "error", "fail", "crash", "timeout"}
    crash = left.loc[left["algorithm"] == P + "segfault", "reason"]
    assert set(crash) == {"killed by signal 11 (SIGSEGV)"}
    assert set(left.loc[left["algorithm"] == P + "hang", "reason"]) == {"exceeded 1.0 s"}

    meta = {name: json.loads((d / "run.json").read_text()) for name, d in (("local", local), ("dask", dask))}
    assert meta["local"]["runner"]["backend"] == "local"
    assert meta["dask"]["runner"]["backend"] == "dask"
    assert meta["dask"]["runner"]["workers"] == 2
    assert meta["dask"]["complete"] is True
