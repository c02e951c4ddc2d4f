"""What a sweep plans: sizes per profile, generator specs, metamorphic copies, the schedule, size caps."""

from __future__ import annotations

import json
from collections import Counter

import pandas as pd
import pytest

from hullstress.cli import main
from hullstress.options import PROFILES
from hullstress.registry import generators
from hullstress.sweep import SweepOptions, build_cases, build_tasks


@pytest.fixture(scope="module")
def quick_plan():
    return build_tasks(SweepOptions(profile="quick"))


def test_quick_profile_has_three_sizes_per_dimension_and_every_family(quick_plan):
    tasks, cases, _, skipped = quick_plan
    for dim in (2, 3):
        sizes = {c.size for c in cases if c.dim == dim and c.size is not None}
        assert len(sizes) >= 3, (dim, sizes)
        assert min(sizes) <= 10 and max(sizes) >= 100
    families = {spec.name for spec in generators()}
    assert {c.family for c in cases} == families
    assert skipped == []  # a variant too large or small for its rotated size falls back to another size


def test_nightly_profile_reaches_thousands_and_caps_the_slow_seeds():
    profile = PROFILES["nightly"]
    assert max(profile.sizes[2]) >= 4096 and max(profile.sizes[3]) >= 4096
    tasks, cases, _, skipped = build_tasks(SweepOptions(profile="nightly", generators=("uniform",)))
    big = [t for t in tasks if t.case.n_points > 1024]
    assert big and all(c.algorithm not in profile.max_points for t in big for c in t.configs)
    assert any(c.algorithm == "naive-2d" for t in tasks if t.case.n_points <= 1024 for c in t.configs)
    assert any(line.startswith("naive-2d:") and "cap of 1024 points" in line for line in skipped)


def test_schedule_is_round_robin_over_families_smallest_first(quick_plan):
    tasks, cases, _, _ = quick_plan
    families = {c.family for c in cases}
    first = [t.case.family for t in tasks[: len(families)]]
    assert sorted(first) == sorted(families)  # any budget that runs len(families) tasks touches every family
    for family in families:
        sizes = [t.case.n_points for t in tasks if t.case.family == family]
        assert sizes == sorted(sizes), family
    # The table order is the build order, independent of the schedule.
    assert [c.case_id for c in cases] != [t.case.case_id for t in tasks]
    assert sorted(c.case_id for c in cases) == sorted(t.case.case_id for t in tasks)


def test_a_generator_spec_runs_exactly_that_variant():
    cases, _ = build_cases(SweepOptions(generators=("near-coplanar:surface=plane,delta=1e-9",), sizes=(12,)))
    assert cases and {c.family for c in cases} == {"near-coplanar"}
    assert {(c.params["surface"], c.params["delta"]) for c in cases} == {("plane", 1e-9)}
    every, _ = build_cases(SweepOptions(generators=("near-coplanar",), sizes=(12,)))
    assert len({c.params_json for c in every}) > 1


@pytest.mark.parametrize("spec, words", [
    ("near-coplanar:jitter=1e-12", ["unknown parameter 'jitter'", "delta"]),
    ("no-such-family", ["no-such-family"]),
])
def test_bad_generator_specs_are_one_line_usage_errors(spec, words, capsys):
    assert main(["run", "--generator", spec, "--workers", "0"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and all(w in err for w in words), err


def test_metamorphic_copies_keep_provenance_and_have_the_same_points_as_a_set():
    cases, _ = build_cases(SweepOptions(generators=("uniform:shape=ball",), sizes=(10,),
                                        transforms=("permute-rows", "scale-pow2")))
    base = [c for c in cases if "transform" not in c.params]
    copies = Counter(c.params["transform"] for c in cases if "transform" in c.params)
    assert copies == {"permute-rows": len(base), "scale-pow2": len(base)}
    for c in cases:
        if c.params.get("transform") == "permute-rows":
            original = next(b for b in base if b.dim == c.dim and b.seed == c.seed)
            assert sorted(map(tuple, c.points.tolist())) == sorted(map(tuple, original.points.tolist()))


def test_bad_transform_is_a_usage_error(capsys):
    assert main(["run", "--transform", "rotate-wildly", "--workers", "0"]) == 2
    err = capsys.readouterr().err
    assert "permute-rows" in err and "rotate-wildly" in err


def test_a_short_time_budget_still_touches_every_family(tmp_path):
    out = tmp_path / "out"
    # Any budget shorter than the first round: the first round runs whole, nothing after it.
    status = main(["run", "--time-budget", "0.01", "--algorithm", "monotone-chain", "--algorithm", "scipy-qhull-3d",
                   "--no-shrink", "--quiet", "--out", str(out), "--workers", "2"])
    assert status in (0, 1)
    run_dir = next(out.iterdir())
    table = pd.read_csv(run_dir / "results.csv")
    assert set(table["generator"]) == {spec.name for spec in generators()}
    meta = json.loads((run_dir / "run.json").read_text())
    assert meta["budget_exhausted"] is True and meta["complete"] is False
    assert sum(meta["not_reached"].values()) == meta["calls_planned"] - len(table) > 0
    assert table["case_id"].nunique() == table["generator"].nunique()  # one case per family: the first round


def test_transformed_copies_are_compared_with_their_originals(tmp_path):
    out = tmp_path / "out"
    status = main(["run", "--generator", "collinear-edges", "--algorithm", "jarvis-march", "--transform",
                   "permute-rows", "--sizes", "24", "--no-shrink", "--quiet", "--out", str(out), "--workers", "0"])
    assert status in (0, 1)
    run_dir = next(out.iterdir())
    table = pd.read_csv(run_dir / "results.csv", keep_default_na=False)
    assert (table["transform"] == "permute-rows").sum() == (table["transform"] == "").sum() > 0
    changes = pd.read_csv(run_dir / "metamorphic.csv")
    assert set(changes.columns) >= {"transform", "base_status", "status", "base_case_id"}
    assert "Metamorphic copies:" in (run_dir / "summary.md").read_text()


@pytest.mark.parametrize("profile, seconds", [("quick", 2.0), ("nightly", 30.0)])
def test_the_per_call_timeout_is_the_profiles_unless_given(profile, seconds):
    # docs/commands.md: `--timeout SECONDS` (per call; the profile's by default: 2 s quick, 30 s nightly).
    assert PROFILES[profile].timeout == seconds
    assert SweepOptions(profile=profile).runner_options().timeout == seconds
    assert SweepOptions(profile=profile, timeout=0.5).runner_options().timeout == 0.5
