"""Benchmark: the full exact check of Qhull's hull of n points uniform in a ball.

Measures, in one process and on the same points:

* ``ConvexHull``: scipy's Qhull (default options), the yardstick;
* ``check``: :func:`hullstress.checker.check` of Qhull's hull with the Qhull
  reference already computed (what the sweep pays per algorithm output);
* ``check --no-qhull``: the exact checks alone;
* ``qhull_reference``: Qhull's hull plus its own exact certification (paid
  once per case);
* ``qconvex`` / ``qconvex Tv``: Qhull's program without and with its own
  (tolerance-based) verification, when the program is installed (includes
  parsing the text input, the same for both);
* optionally (``--brute``) a plain numpy test of every point against every facet.

Run: ``python benchmarks/bench_checker.py [--n 100000] [--dim 3] [--repeat 5] [--brute]``.
Prints a Markdown table; each figure is the best of ``--repeat`` runs.
"""

from __future__ import annotations

import argparse
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
from scipy.spatial import ConvexHull

from hullstress.checker import check, qhull_reference
from hullstress.io import write_points


def ball(rng: np.random.Generator, n: int, dim: int) -> np.ndarray:
    """n points uniform in the unit ball."""
    v = rng.normal(size=(n, dim))
    v /= np.linalg.norm(v, axis=1)[:, None]
    return v * rng.random(n)[:, None] ** (1.0 / dim)


def best_of(fn, repeat: int) -> float:
    times = []
    for _ in range(repeat):
        t = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t)
    return min(times)


def brute_numpy(points: np.ndarray, equations: np.ndarray) -> float:
    """Every point against every facet plane in plain float numpy (chunked); returns seconds."""
    t = time.perf_counter()
    chunk = max(1, 2_000_000 // len(equations))
    worst = -np.inf
    for s in range(0, len(points), chunk):
        d = points[s : s + chunk] @ equations[:, :-1].T + equations[:, -1]
        worst = max(worst, float(d.max()))
    return time.perf_counter() - t


def qconvex_times(points: np.ndarray, repeat: int) -> tuple[float, float] | None:
    exe = shutil.which("qconvex")
    if exe is None:
        return None
    with tempfile.TemporaryDirectory() as tmp:
        path = write_points(Path(tmp) / "points.txt", points, "qhull")
        data = path.read_bytes()

        def run(opts):
            subprocess.run([exe, *opts], input=data, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, check=True)

        return best_of(lambda: run([]), repeat), best_of(lambda: run(["Tv"]), repeat)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, default=100_000)
    parser.add_argument("--dim", type=int, choices=(2, 3), default=3)
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--brute", action="store_true", help="also time plain numpy all points x all facets")
    args = parser.parse_args(argv)

    points = ball(np.random.default_rng(args.seed), args.n, args.dim)
    hull = ConvexHull(points)
    ref = qhull_reference(points)
    verdict = check(points, ref.faces, reference=ref)
    if not verdict.ok:
        print(f"unexpected verdict on Qhull's hull: {verdict.detail}", file=sys.stderr)
        return 1

    t_hull = best_of(lambda: ConvexHull(points), args.repeat)
    t_check = best_of(lambda: check(points, ref.faces, reference=ref), args.repeat)
    t_exact = best_of(lambda: check(points, ref.faces, qhull=False), args.repeat)
    t_ref = best_of(lambda: qhull_reference(points), args.repeat)
    rows = [
        ("scipy ConvexHull", t_hull),
        ("check (reference given)", t_check),
        ("check --no-qhull", t_exact),
        ("qhull_reference (hull + its certification)", t_ref),
    ]
    q = qconvex_times(points, args.repeat)
    if q is not None:
        rows += [("qconvex", q[0]), ("qconvex Tv", q[1])]
    if args.brute:
        rows.append(("plain numpy, all points x all facets (float, not exact)", brute_numpy(points, hull.equations)))

    print(f"n = {args.n}, dim = {args.dim}, uniform in a ball, seed {args.seed}: "
          f"{len(hull.vertices)} hull vertices, {len(hull.simplices)} facets; best of {args.repeat}")
    print()
    print("| what | seconds | / ConvexHull |")
    print("| --- | ---: | ---: |")
    for name, t in rows:
        print(f"| {name} | {t:.4f} | {t / t_hull:.2f}x |")
    if q is not None:
        print(f"\nqconvex Tv / qconvex: {q[1] / q[0]:.1f}x")
    return 0


if __name__ == "__main__":
    sys.exit(main())
