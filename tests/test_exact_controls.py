"""Exactly-correct implementations are positive controls: a sweep must find nothing wrong with them.

The done criterion of issue 13: a quick run at default settings of CGAL's
``cgal-convex-hull-3d`` and ``cgal-graham-andrew-2d`` and of an exact-rational
plug-in (``tests/exact_hull_plugin.py``) has no ``fail`` or ``error`` row on
any family, bad input included; and ``--workers 1`` and ``--workers 2`` give
the same table in every column but the timing ones.
"""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import pandas as pd
import pytest

from hullstress import generators
from hullstress._registry import ALGORITHMS
from hullstress.plugins import load_plugin
from hullstress.results import TIMING_COLUMNS
from hullstress.sweep import SweepOptions, run_sweep

pytest.importorskip("CGAL", reason="the cgal bindings (PyPI 'cgal') are not installed: no CGAL controls")

PLUGIN = Path(__file__).with_name("exact_hull_plugin.py")
CONTROLS = ("cgal-convex-hull-3d", "cgal-graham-andrew-2d", "exact-rational-2d")
#: Families where CGAL 3D sees every kind of face ordering: with sphere on (opt-in for an adapter).
SPHERE_FAMILIES = ("uniform", "sphere", "minkowski-cubes", "regular-polyhedron", "cube-faces", "coplanar-grid")


@pytest.fixture(scope="module")
def default_runs() -> Iterator[dict[int, pd.DataFrame]]:
    load_plugin(str(PLUGIN))
    try:
        yield {w: run_sweep(SweepOptions(algorithms=CONTROLS, workers=w)).table for w in (1, 2)}
    finally:
        ALGORITHMS.remove("exact-rational-2d")


def _without_timing(table: pd.DataFrame) -> pd.DataFrame:
    return table.drop(columns=list(TIMING_COLUMNS)).reset_index(drop=True)


def test_exact_controls_have_no_fail_or_error_rows_on_any_family(default_runs):
    table = default_runs[2]
    bad = table[table["status"].isin(["fail", "error"])]
    assert bad.empty, "\n" + bad[["config", "generator", "params", "status", "stage", "reason"]].to_string()
    # Every family ran, bad input included, in the defaults of a library: sphere off, its own tolerance.
    assert set(table["generator"]) == {g.name for g in generators()}
    assert set(table["sphere"]) == {"off"} and set(table["eps"]) == {"n/a"}
    # CGAL 3D dies on NaN / inf (SIGFPE): a crash is recorded, never passed off; only invalid input may do that.
    odd = table[table["status"].isin(["crash", "timeout"])]
    assert (odd["invalid_input"].astype(str) != "").all(), odd[["config", "generator", "params", "status"]]


def test_lower_dimensional_answers_of_the_rational_plugin_pass(default_runs):
    table = default_runs[2]
    mine = table[(table["algorithm"] == "exact-rational-2d") & table["degenerate"].fillna(False).astype(bool)
                 & (table["invalid_input"].astype(str) == "")]
    assert len(mine) > 0 and set(mine["status"]) == {"pass"}
    assert set(mine["affine_rank"].astype(int)) == {0, 1}


def test_workers_1_and_2_give_identical_tables(default_runs):
    pd.testing.assert_frame_equal(_without_timing(default_runs[1]), _without_timing(default_runs[2]))


def test_cgal_3d_with_sphere_on_is_identical_across_workers():
    # CGAL emits a Polyhedron_3's facets in an order that differs between processes; the
    # canonical output makes the rows independent of it.
    opts = dict(algorithms=("cgal-convex-hull-3d",), generators=SPHERE_FAMILIES, sphere="both")
    one = run_sweep(SweepOptions(workers=1, **opts)).table
    two = run_sweep(SweepOptions(workers=2, **opts)).table
    assert set(one["sphere"]) == {"off", "on"}
    pd.testing.assert_frame_equal(_without_timing(one), _without_timing(two))
