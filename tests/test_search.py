"""The search (hullstress.search): mutation operators, the exact degeneracy score, guidance, determinism, the CLI."""

from __future__ import annotations

import itertools
import subprocess
import sys
import textwrap
from fractions import Fraction
from pathlib import Path

import numpy as np
import pytest

from hullstress._registry import ALGORITHMS
from hullstress.case import Case
from hullstress.pipeline import RunOptions, run
from hullstress.results import TIMING_COLUMNS
from hullstress.search import MUTATIONS, Search, SearchOptions, degeneracy_score, mutations_for
from hullstress.search.guidance import Guidance, extreme_answer
from hullstress.search.score import floor_log2
from hullstress.sweep import SweepOptions

RNG = np.random.default_rng(20261125)
INPUTS = {
    "square-2d": np.array([[0.0, 0], [1, 0], [1, 1], [0, 1], [0.5, 0.5]]),
    "cloud-2d": RNG.random((30, 2)),
    "collinear-2d": np.array([[0.0, 0], [1, 1], [2, 2]]),
    "one-point-2d": np.array([[3.0, 4.0]]),
    "cloud-3d": RNG.random((40, 3)),
    "cube-3d": np.array(list(itertools.product([0.0, 1.0], repeat=3))),
    "flat-3d": np.column_stack([RNG.random((10, 2)), np.zeros(10)]),
    "huge-3d": RNG.random((12, 3)) * 1e300,
}


# -- mutation operators ---------------------------------------------------------------------------

@pytest.mark.parametrize("name", sorted(MUTATIONS))
@pytest.mark.parametrize("label", sorted(INPUTS))
def test_a_mutation_gives_finite_points_of_the_same_dimension_or_declines(name, label):
    points = INPUTS[label].copy()
    points.setflags(write=False)  # an operator must never write to its input
    other = INPUTS["cloud-2d"] if points.shape[1] == 2 else INPUTS["cloud-3d"]
    for seed in range(5):
        out = MUTATIONS[name](points, np.random.default_rng(seed), other=other)
        if out is None:
            continue
        assert out.dtype == np.float64 and out.flags.c_contiguous
        assert out.ndim == 2 and out.shape[1] == points.shape[1] and len(out) >= 1
        assert np.isfinite(out).all()
    # A pure function of the input and the generator's state.
    a = MUTATIONS[name](points, np.random.default_rng(7), other=other)
    b = MUTATIONS[name](points, np.random.default_rng(7), other=other)
    assert (a is None and b is None) or np.array_equal(a, b)


def test_operators_do_what_their_names_say():
    square = INPUTS["square-2d"]
    nudged = MUTATIONS["nudge-ulp"](square, np.random.default_rng(1))
    changed = np.argwhere(nudged != square)
    assert len(changed) == 1
    i, j = changed[0]
    assert 1 <= abs(int(np.float64(nudged[i, j]).view(np.int64)) - int(np.float64(square[i, j]).view(np.int64))) <= 4
    dup = MUTATIONS["duplicate-vertex"](square, np.random.default_rng(2))
    assert len(dup) == len(square) + 1 and any((dup[-1] == corner).all() for corner in square[:4])
    assert MUTATIONS["merge"](square, np.random.default_rng(0), other=None) is None
    assert len(MUTATIONS["merge"](square, np.random.default_rng(0), other=INPUTS["cloud-2d"])) == 35
    assert MUTATIONS["snap-edge"](INPUTS["collinear-2d"], np.random.default_rng(0)) is None  # no full hull
    assert MUTATIONS["snap-face"](square, np.random.default_rng(0)) is None  # 3D only
    assert "snap-face" not in mutations_for(2)


# -- the degeneracy score ---------------------------------------------------------------------------

def _brute_force_2d(points: np.ndarray) -> tuple[int | None, int]:
    """margin_bits and flat_tuples in rational arithmetic over all point pairs (small inputs only)."""
    q = [tuple(Fraction(float(x)) for x in p) for p in np.unique(points, axis=0)]

    def det(a, b, c):
        return (a[0] - c[0]) * (b[1] - c[1]) - (a[1] - c[1]) * (b[0] - c[0])

    margins, flat = [], 0
    for a, b in itertools.combinations(q, 2):
        values = [det(a, b, c) for c in q]
        if any(v > 0 for v in values) and any(v < 0 for v in values):
            continue  # not a supporting line
        on_line = [c for c, v in zip(q, values) if v == 0]
        if min(on_line) != min(a, b) or max(on_line) != max(a, b):
            continue  # a and b are not the ends of the hull edge on this line
        flat += len(on_line) - 2
        margins += [abs(v) for v in values if v]
    top = max(abs(x) for p in q for x in p)
    return (floor_log2(top**2 / min(margins)) if margins else None), flat


@pytest.mark.parametrize("seed", range(6))
def test_the_score_is_exact_against_a_rational_brute_force(seed):
    rng = np.random.default_rng(seed)
    # Small dyadic grids with jitter of a few ulps: many exact zeros and tiny margins.
    pts = rng.integers(0, 4, size=(9, 2)).astype(float)
    pts[rng.integers(9), rng.integers(2)] += np.spacing(4.0) * rng.integers(1, 4)
    score = degeneracy_score(pts)
    margin_bits, flat = _brute_force_2d(pts)
    assert (score.margin_bits, score.flat_tuples) == (margin_bits, flat)
    assert score.duplicates == len(pts) - len(np.unique(pts, axis=0))


def test_the_score_counts_flat_tuples_whatever_the_triangulation():
    grid = np.array(list(itertools.product(range(4), repeat=3)), dtype=float)
    # 6 square faces, each 2 triangles whose plane holds 16 points: 12 x 13.
    assert degeneracy_score(grid).flat_tuples == 156
    assert degeneracy_score(INPUTS["cube-3d"]).flat_tuples == 6 * 2 * 1


@pytest.mark.parametrize("label", ["cloud-2d", "square-2d", "cloud-3d", "cube-3d", "huge-3d"])
def test_the_score_ignores_row_order_and_power_of_two_scaling(label):
    points = INPUTS[label]
    score = degeneracy_score(points)
    assert degeneracy_score(points[::-1]) == score
    assert degeneracy_score(points[np.random.default_rng(3).permutation(len(points))]) == score
    assert degeneracy_score(points * 2.0**-40) == score
    assert degeneracy_score(np.vstack([points, points[:2]])).duplicates == score.duplicates + 2


def test_the_score_rises_as_an_input_nears_a_degenerate_decision():
    square = INPUTS["square-2d"]
    near = square.copy()
    near[4] = [0.5, np.nextafter(0.0, 1.0) * 2**40]  # a hair above the bottom edge
    assert degeneracy_score(near).margin_bits > degeneracy_score(square).margin_bits + 900
    on = square.copy()
    on[4] = [0.5, 0.0]
    assert degeneracy_score(on).flat_tuples == degeneracy_score(square).flat_tuples + 1
    assert degeneracy_score(square + 2.0**30).scale_bits == 30
    flat = degeneracy_score(INPUTS["flat-3d"])
    assert flat.margin_bits is None and flat.flat_tuples is None


@pytest.mark.parametrize("bad", [np.zeros((0, 2)), np.zeros((3, 4)), np.array([[0.0, np.nan], [1, 1]]),
                                 np.array([[0.0, np.inf], [1, 1], [2, 0]]), np.zeros(3)])
def test_the_score_refuses_what_is_not_a_finite_2d_or_3d_point_set(bad):
    with pytest.raises(ValueError, match="points must"):
        degeneracy_score(bad)


def test_guidance_keeps_new_signatures_raised_scores_and_differential_splits():
    guidance = Guidance()
    base = {"algorithm": "a", "sphere": "off", "eps": "n/a", "stage": "algorithm", "n_hull_vertices": 4}
    ok = {**base, "config": "a", "status": "pass", "n_missing_extreme": 0, "offending": "{}"}
    bad = {**base, "config": "b", "algorithm": "b", "status": "fail", "failed_checks": "containment",
           "severity": "gross", "n_missing_extreme": 1, "offending": '{"missing_extreme":[2]}'}
    square = Case.from_points(INPUTS["square-2d"])
    first = guidance.judge(square, [ok, bad])
    assert any(r.startswith("signature:") for r in first.reasons)
    assert "differential: a vs b" in first.reasons
    assert not guidance.judge(square, [ok, bad]).kept  # nothing new the second time
    nearer = INPUTS["square-2d"].copy()
    nearer[4] = [0.5, 2.0**-30]
    assert any(r.startswith("score: margin_bits") for r in guidance.judge(Case.from_points(nearer), [ok]).reasons)
    assert extreme_answer(bad) == (1, (2,))


# -- the search end to end --------------------------------------------------------------------------

PLANTED = textwrap.dedent(
    """
    import numpy as np
    from scipy.spatial import ConvexHull

    from hullstress import register_algorithm


    @register_algorithm("planted-duplicate-bug", dim=2)
    def planted(points):
        '''Qhull's hull, but a vertex goes missing when an input row repeats another exactly.'''
        hull = ConvexHull(points).vertices
        if len(np.unique(points, axis=0)) < len(points):
            return hull[1:]
        return hull
    """
)


@pytest.fixture
def planted(tmp_path):
    from hullstress.plugins import load_plugin

    path = tmp_path / "planted_search_plugin.py"
    path.write_text(PLANTED)
    load_plugin(str(path))
    yield path
    for name in [n for n in ALGORITHMS.names() if n.startswith("planted-")]:
        ALGORITHMS.remove(name)


def _search(tmp_path, *, evaluations, workers, name="run", **more):
    sweep = SweepOptions(algorithms=("planted-duplicate-bug",), generators=("uniform",), sizes=(12,), seed=5,
                         workers=workers, timeout=10.0)
    executor = Search(SearchOptions(evaluations=evaluations, seeds=2, generation=6, **more), sweep)
    return executor, run(RunOptions(sweep=sweep, out=str(tmp_path / name), shrink=False, pictures=False,
                                    executor=executor))


def test_a_planted_bug_the_seeds_miss_is_found_within_a_small_budget(tmp_path, planted):
    executor, the_run = _search(tmp_path, evaluations=30, workers=2)
    table = the_run.table
    seeds = table[table["generator"] == "uniform"]
    assert len(seeds) == 2 and (seeds["status"] == "pass").all()  # the seeds alone show nothing
    found = table[(table["generator"] == "search") & (table["status"] == "fail")]
    assert len(found), "the search found no input with a repeated row"
    assert the_run.exit_status == 1 and (the_run.run_dir / "results.csv").is_file()
    assert {c.case_id for c in the_run.plan.cases} == set(table["case_id"])
    assert len(table) == executor.evaluated == 30


def test_an_evaluation_budget_gives_identical_results_with_any_number_of_workers(tmp_path, planted):
    _, one = _search(tmp_path, evaluations=20, workers=1, name="one")
    _, two = _search(tmp_path, evaluations=20, workers=2, name="two")
    drop = [c for c in TIMING_COLUMNS if c in one.table.columns]
    assert one.table.drop(columns=drop).equals(two.table.drop(columns=drop))


def test_a_time_budget_cuts_the_search_short_and_says_so(tmp_path, planted):
    executor, the_run = _search(tmp_path, evaluations=10**6, workers=1, time_budget=1.0)
    assert the_run.stats.budget_exhausted and not the_run.complete
    assert 0 < executor.evaluated < 10**6


def test_an_interrupt_keeps_every_row_with_its_case(tmp_path, planted):
    sweep = SweepOptions(algorithms=("planted-duplicate-bug",), generators=("uniform",), sizes=(12,), workers=1)
    executor = Search(SearchOptions(evaluations=40, seeds=2, generation=4), sweep)
    seen = []

    def stop_after_ten(row):
        seen.append(row)
        if len(seen) == 10:
            raise KeyboardInterrupt

    the_run = run(RunOptions(sweep=sweep, out=str(tmp_path / "out"), shrink=False, pictures=False,
                             executor=executor), on_row=stop_after_ten)
    assert not the_run.complete and len(the_run.table) >= 9
    assert set(the_run.table["case_id"]) <= {c.case_id for c in the_run.plan.cases}


BAD_CALLS = [
    (["--evaluations", "0"], "--evaluations"),
    (["--evaluations", "many"], "--evaluations"),
    (["--time-budget", "-1"], "--time-budget"),
    (["--max-points", "2"], "--max-points"),
    (["--seeds", "0"], "--seeds"),
    (["--algorithm", "no-such-hull"], "no-such-hull"),
    (["--generator", "no-such-family"], "no-such-family"),
    (["--sizes", "ten"], "--sizes"),
]


@pytest.mark.parametrize("args,named", BAD_CALLS, ids=[" ".join(a) for a, _ in BAD_CALLS])
def test_bad_search_arguments_give_one_line_and_status_2(tmp_path, args, named):
    proc = subprocess.run([sys.executable, "-m", "hullstress", "search", "--out", str(tmp_path), *args],
                          capture_output=True, text=True, timeout=120)
    assert proc.returncode == 2, proc.stderr
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and named in lines[0], proc.stderr
    assert not list(Path(tmp_path).iterdir())  # nothing was run, no run folder left behind
