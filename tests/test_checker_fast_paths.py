"""The checker's shortcuts change no verdict: every case of the quick profile, both ways.

Two shortcuts serve the common case (issue 19): the batched certificate of a
closed convex triangle mesh or polygon (:mod:`hullstress.checker.closed_mesh`),
and the reuse of a certified Qhull reference's certificate when the output is
the same face set.  Both only ever conclude "certified", deferring to the
general checks otherwise.  Here every case of the quick profile (degenerate,
extreme-scale and bad-input families included) is checked with the outputs of
the in-house algorithms and of scipy's Qhull, once with the shortcuts and once
with the general checks alone (reference included), and the verdicts must be
identical, field for field and bit for bit.
"""

from __future__ import annotations

import numpy as np
import pytest

from hullstress._registry import algorithms, load_builtins
from hullstress.checker import certify as certify_module
from hullstress.checker import check, qhull_reference
from hullstress.config import AlgorithmConfig
from hullstress.evaluate import call_algorithm, input_problem
from hullstress.sweep import SweepOptions, build_cases

# Qhull may die with SIGSEGV on raw points near the ends of the double range (the
# reference itself rescales them); the scipy adapters run on the raw points.
_SAFE = (2.0**-400, 2.0**400)


def _configs(dim: int, points: np.ndarray) -> list[AlgorithmConfig]:
    configs = []
    for spec in algorithms(dim):
        if spec.origin == "in-house":
            configs.append(AlgorithmConfig(spec.name, "off", "fixed" if spec.takes_eps else "n/a"))
        elif spec.name in ("scipy-qhull-2d", "scipy-qhull-3d"):
            top = float(np.abs(points).max()) if points.size else 0.0
            if _SAFE[0] <= top <= _SAFE[1]:
                configs.append(AlgorithmConfig(spec.name, "off", "n/a"))
    return configs


def _outputs():
    load_builtins()
    cases, _ = build_cases(SweepOptions(profile="quick"))
    out = []
    for case in cases:
        if input_problem(case.points, case.dim) is not None:
            continue
        for config in _configs(case.dim, case.points):
            outcome = call_algorithm(case, config)
            if outcome.kind == "ok":
                out.append((case, config.label, outcome.faces))
    return out


@pytest.fixture(scope="module")
def outputs():
    return _outputs()


def test_the_shortcuts_give_the_verdicts_of_the_general_checks(outputs, monkeypatch):
    assert len(outputs) > 500
    references = {}
    shortcut = {}
    for case, label, faces in outputs:
        if case.case_id not in references:
            references[case.case_id] = qhull_reference(case.points)
        shortcut[(case.case_id, label)] = check(case.points, faces, reference=references[case.case_id])
    # The general checks alone: no batched certificate (for the reference either), no reuse.
    monkeypatch.setattr(certify_module, "certify_closed_mesh", lambda *a, **k: None)
    monkeypatch.setattr(certify_module, "certify_convex_polygon", lambda *a, **k: None)
    full_references = {}
    reused = differ = 0
    for case, label, faces in outputs:
        if case.case_id not in full_references:
            full_references[case.case_id] = qhull_reference(case.points)
        full = check(case.points, faces, reference=full_references[case.case_id], reuse_reference=False)
        fast = shortcut[(case.case_id, label)]
        if fast != full:
            differ += 1
            print(case.family, case.params, label, "\n  fast:", fast, "\n  full:", full)
        reused += references[case.case_id].qhull_ok is True and references[case.case_id].same_faces(faces)
    assert differ == 0
    assert reused > 100  # the reuse shortcut was exercised, not just the batched certificate
