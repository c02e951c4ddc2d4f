"""Search against sweep in the same wall-clock time, on bugs planted where the quick sweep does not look.

This file is also the plug-in that plants them (``--plugin benchmarks/bench_search.py``).
Each planted algorithm is Qhull's hull (scipy), correct except under one trigger, and
only on inputs where some row repeats another exactly (a hazard the quick sweep's
``duplicates`` family has, but never together with the trigger):

=============================  ==================================================================
algorithm                      wrong when
=============================  ==================================================================
``planted-size-threshold``     the input has more than 150 rows (2D)
``planted-ulp-pair``           two points differ by exactly one ulp in one coordinate and agree
                               in the others (3D)
``planted-near-degenerate``    some point lies within 2**-40 of the hull's extent from a hull edge
                               without being exactly on it (2D)
``planted-offset``             the smallest coordinate is above 2**20 times the input's extent
                               (2D)
=============================  ==================================================================

Under its trigger each raises its own exception (``PlantedBug: size-threshold``), so a
planted bug counts as found only when that signature appears, never for Qhull's own
errors on degenerate inputs.

One run of ``python benchmarks/bench_search.py [--seconds S]`` runs the quick
sweep with the planted algorithms under ``--time-budget S`` (its first round
over every family always runs, so it may take longer: the time it took is
the search's budget), then the search for the same wall-clock time, and
prints a Markdown table: distinct failure signatures (of the planted
algorithms) each found, and how many of the four planted bugs.
"""

from __future__ import annotations

import argparse
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
from scipy.spatial import ConvexHull

from hullstress import register_algorithm
from hullstress.adapters.scipy_qhull import qhull_3d

PLANTED = ("planted-size-threshold", "planted-ulp-pair", "planted-near-degenerate", "planted-offset")


def _hull(points: np.ndarray) -> np.ndarray:
    return ConvexHull(points).vertices


def _repeats(points: np.ndarray) -> bool:
    return len(np.unique(points, axis=0)) < len(points)


def size_threshold(points):
    """Qhull's hull; drops a vertex on inputs of more than 150 points."""
    hull = _hull(points)
    if len(points) > 150 and _repeats(points):
        raise PlantedBug("size-threshold")
    return hull


class PlantedBug(RuntimeError):
    """Raised by a planted algorithm under its trigger (the message names the bug)."""


def ulp_pair(points):
    """Qhull's 3D hull, outward; raises when two points are one ulp apart in one coordinate, equal in the others."""
    distinct = np.unique(points, axis=0)
    for axis in range(3):
        others = [k for k in range(3) if k != axis]
        order = np.lexsort([distinct[:, axis]] + [distinct[:, k] for k in others[::-1]])
        s = distinct[order]
        same = (s[1:, others] == s[:-1, others]).all(axis=1)
        if (same & (np.nextafter(s[:-1, axis], np.inf) == s[1:, axis])).any() and _repeats(points):
            raise PlantedBug("ulp-pair")
    return qhull_3d(points, None)  # the scipy adapter's outward triangles


def near_degenerate(points):
    """Qhull's hull; drops a vertex when a point is within 2**-40 of the extent from a hull edge, but not on it."""
    hull = _hull(points)
    p = points - points.min(axis=0)
    extent = float(np.ptp(points, axis=0).max()) or 1.0
    ring = p[hull]
    edge = np.roll(ring, -1, axis=0) - ring
    length = np.hypot(edge[:, 0], edge[:, 1])
    rel = p[None, :, :] - ring[:, None, :]
    dist = np.abs(edge[:, None, 0] * rel[:, :, 1] - edge[:, None, 1] * rel[:, :, 0]) / length[:, None]
    if ((dist > 0) & (dist < extent * 2.0**-40)).any() and _repeats(points):
        raise PlantedBug("near-degenerate")
    return hull


def far_offset(points):
    """Qhull's hull, clockwise when the input sits more than 2**20 extents away from the origin."""
    hull = _hull(points)
    extent = float(np.ptp(points, axis=0).max()) or 1.0
    if float(np.abs(points).min()) > extent * 2.0**20 and _repeats(points):
        raise PlantedBug("offset")
    return hull


if __name__ != "__main__":  # registered when imported as a plug-in (main() does that), never twice
    for _name, _dim, _func in (("planted-size-threshold", 2, size_threshold), ("planted-ulp-pair", 3, ulp_pair),
                               ("planted-near-degenerate", 2, near_degenerate), ("planted-offset", 2, far_offset)):
        register_algorithm(_name, dim=_dim)(_func)


def _signatures(table) -> set:
    from hullstress.triage.signature import signature_of

    return {s for s in (signature_of(r) for _, r in table.iterrows()) if s is not None and s.algorithm in PLANTED}


def main(argv: list[str] | None = None) -> int:
    # Imported here, not at the top: worker processes import this file as a plug-in, without
    # benchmarks/ on their path.
    from _figures import add_figures_option, recorded

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seconds", type=float, default=60.0, help="the sweep's --time-budget (default 60)")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--workers", type=int, default=None)
    add_figures_option(parser, "bench_search")
    args = parser.parse_args(argv)
    with recorded(args.figures, "bench_search", "the quick sweep with the planted algorithms, given the same wall-clock time as the search", argv):

        from hullstress.pipeline import RunOptions, run
        from hullstress.plugins import load_plugin
        from hullstress.search import Search, SearchOptions
        from hullstress.sweep import SweepOptions

        load_plugin(str(Path(__file__).resolve()))  # registered under the name worker processes import it by
        out = tempfile.mkdtemp(prefix="bench-search-")
        common = dict(algorithms=PLANTED, seed=args.seed, workers=args.workers, timeout=10.0)

        t0 = time.perf_counter()
        sweep = run(RunOptions(sweep=SweepOptions(time_budget=args.seconds, **common), out=out, shrink=False,
                               pictures=False))
        sweep_seconds = time.perf_counter() - t0

        t0 = time.perf_counter()
        searcher = Search(SearchOptions(evaluations=10**9, time_budget=sweep_seconds, seeds=40), SweepOptions(**common))
        searched = run(RunOptions(sweep=SweepOptions(**common), out=out, shrink=False, pictures=False,
                                  executor=searcher))
        search_seconds = time.perf_counter() - t0

        rows = []
        for name, the_run, seconds in (("quick sweep", sweep, sweep_seconds), ("search", searched, search_seconds)):
            sigs = _signatures(the_run.table)
            bugs = sorted({s.algorithm for s in sigs if s.error == "PlantedBug"})
            rows.append(f"| {name} | {seconds:.0f} | {the_run.table['case_id'].nunique()} | {len(the_run.table)} | "
                        f"{len(sigs)} | {len(bugs)} of {len(PLANTED)} ({', '.join(b.removeprefix('planted-') for b in bugs) or '-'}) |")
        print(f"Planted bugs, seed {args.seed}, same wall-clock time (machine shared; {sys.platform}):\n")
        print("| execute stage | seconds | inputs | calls | distinct failure signatures | planted bugs found |")
        print("| --- | ---: | ---: | ---: | ---: | --- |")
        print("\n".join(rows))
        print(f"run folders under {out}", file=sys.stderr)  # a temporary path: not a figure
        return 0


if __name__ == "__main__":
    sys.exit(main())
