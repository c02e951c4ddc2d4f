"""Tests for fuzz mode: hullstress.triage.fuzzing and the ``fuzz`` subcommand."""

from __future__ import annotations

import argparse
import json
import textwrap
from pathlib import Path

import numpy as np
import pytest

from hullstress.plugins import load_plugin
from hullstress.triage.fuzzing import case_strategy, fuzz

PLUGIN = textwrap.dedent(
    '''
    """Throw-away plug-ins for tests/test_fuzz.py."""
    import numpy as np
    from scipy.spatial import ConvexHull

    from hullstress import register_algorithm, register_generator


    @register_generator("test-fuzz-disc", dims=(2,), variants=({}, {"radius": 1e6}))
    def disc(rng, n, *, dim, radius=1.0):
        """Uniform points in a disc."""
        r = radius * np.sqrt(rng.uniform(0, 1, n))
        t = rng.uniform(0, 2 * np.pi, n)
        return np.column_stack([r * np.cos(t), r * np.sin(t)])


    @register_algorithm("test-fuzz-count", dim=2)
    def count(points):
        """Qhull's polygon, but raises from 10 points on."""
        if len(points) >= 10:
            raise OverflowError("too many points")
        return [int(i) for i in ConvexHull(points).vertices]


    @register_algorithm("test-fuzz-dropper", dim=2)
    def dropper(points):
        """Qhull's polygon minus its first vertex from 6 points on."""
        hull = [int(i) for i in ConvexHull(points).vertices]
        return hull[1:] if len(points) >= 6 else hull


    @register_algorithm("test-fuzz-good", dim=2)
    def good(points):
        """Qhull's polygon."""
        return [int(i) for i in ConvexHull(points).vertices]
    '''
)


@pytest.fixture(scope="module")
def plugin(tmp_path_factory) -> Path:
    path = tmp_path_factory.mktemp("fuzz-plugin") / "fuzz_plugins.py"
    path.write_text(PLUGIN)
    load_plugin(str(path))
    return path


def _cli(argv: list[str]) -> int:
    from hullstress.cli import _fuzz

    parser = argparse.ArgumentParser(prog="hullstress")
    _fuzz.add_parser(parser.add_subparsers())
    args = parser.parse_args(argv)
    return args.handler(args)


def test_fuzz_finds_the_threshold_and_hypothesis_shrinks_to_it(plugin, tmp_path):
    db = tmp_path / "db"
    # Unseeded: Hypothesis saves what it finds to the database.
    result = fuzz("test-fuzz-count", families=["test-fuzz-disc"], max_examples=40, database=db,
                  max_findings=2, shrink_budget_seconds=5)
    assert [f.signature.check for f in result.findings] == ["error"]
    finding = result.findings[0]
    # Hypothesis shrinks the drawn size to the smallest failing one, and the family's first variant.
    assert finding.case.n_points == 10
    assert "radius" not in finding.case.params and "transform" not in finding.case.params  # first variant
    assert finding.shrunk is not None and finding.shrunk.minimal_size == 10
    assert "OverflowError" in finding.row.get("reason")
    assert any(db.rglob("*")), "the example database stores the failure"
    # Replayed from the database first (also by a seeded run): found again at once.
    for seed in (None, 2):
        again = fuzz("test-fuzz-count", families=["test-fuzz-disc"], max_examples=40, database=db, seed=seed,
                     max_findings=1, shrink_budget_seconds=0)
        assert again.findings and again.findings[0].case.n_points == 10
        assert again.examples <= 5, again.examples


def test_a_seeded_search_is_reproducible(plugin):
    runs = [fuzz("test-fuzz-count", families=["test-fuzz-disc"], max_examples=30, seed=11, max_findings=1,
                 shrink_budget_seconds=0) for _ in range(2)]
    assert runs[0].examples == runs[1].examples
    assert runs[0].findings[0].case.case_id == runs[1].findings[0].case.case_id


def test_fuzz_targets_the_violation_magnitude(plugin, monkeypatch):
    import hypothesis

    labels = []
    real = hypothesis.target

    def spy(value, *, label=""):
        labels.append((label, value))
        return real(value, label=label)

    monkeypatch.setattr(hypothesis, "target", spy)
    result = fuzz("test-fuzz-dropper", families=["test-fuzz-disc"], max_examples=20, seed=0, max_findings=1,
                  shrink_budget_seconds=0)
    assert result.findings and result.findings[0].signature.check in ("containment", "qhull_agreement")
    assert labels and all(label.startswith("max_violation") for label, _ in labels)
    assert max(v for _, v in labels) > 0


def test_case_strategy_draws_cases_of_the_families(plugin):
    from hypothesis import given, settings

    seen = set()

    @settings(max_examples=25, database=None)
    @given(case_strategy(2, ["test-fuzz-disc"], min_size=4, max_size=9))
    def check(case):
        assert case.family == "test-fuzz-disc" and case.dim == 2
        assert case.points.shape[1] == 2 and 4 <= case.n_points
        bits = case.params.get("fuzz_bits")
        if bits is not None:
            from hullstress.triage.simplify import mantissa_bits

            assert mantissa_bits(case.points).max() <= bits
        seen.add(case.params.get("radius", 1.0))  # only the variant's own parameters are recorded

    check()
    assert seen == {1.0, 1e6}


def test_fuzz_command_writes_failure_folders_and_exits_1(plugin, tmp_path):
    out = tmp_path / "out"
    code = _cli(["fuzz", "--algorithm", "test-fuzz-count", "--generator", "test-fuzz-disc", "--max-examples", "30",
                 "--seed", "3", "--database", "none", "--max-findings", "1", "--shrink-budget", "3",
                 "--plugin", str(plugin), "--out", str(out)])
    assert code == 1
    (run,) = list(out.iterdir())
    summary = json.loads((run / "fuzz.json").read_text())
    assert summary["seed"] == 3 and len(summary["findings"]) == 1
    folder = Path(summary["findings"][0]["folder"])
    assert (folder / "reproduce.txt").read_text().strip() == summary["findings"][0]["reproduce"]
    assert len(np.load(folder / "points.npy")) == 10


def test_fuzz_command_exits_0_when_nothing_fails(plugin, tmp_path):
    code = _cli(["fuzz", "--algorithm", "test-fuzz-good", "--generator", "test-fuzz-disc", "--max-examples", "10",
                 "--seed", "0", "--database", "none", "--out", str(tmp_path / "out")])
    assert code == 0
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize(
    "argv, message",
    [
        (["--max-examples", "0"], "argument --max-examples: must be at least 1, got '0'"),
        (["--max-size", "2"], "argument --max-size: must be at least 4, got '2'"),
        (["--generator", "no-such-family"], "unknown generator 'no-such-family'"),
    ],
)
def test_fuzz_command_bad_arguments(plugin, argv, message, capsys):
    from hullstress.cli import main

    assert main(["fuzz", "--algorithm", "test-fuzz-good", "--database", "none"] + argv) == 2
    assert message in capsys.readouterr().err


def test_a_seeded_search_with_an_empty_or_stale_database(plugin, tmp_path):
    db = tmp_path / "db"
    result = fuzz("test-fuzz-good", families=["test-fuzz-disc"], max_examples=10, database=db, seed=4)
    assert result.findings == [] and result.examples >= 10
