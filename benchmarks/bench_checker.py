"""Benchmark: the exact checker against scipy's ConvexHull on the same points, small and large.

Part 1, the sizes the sweep runs (``--sizes``, default 24, 100, 1000; 2D and
3D): many clouds uniform in a ball, each checked once per round; per call:

* ``ConvexHull``: scipy's Qhull build (default options), the yardstick;
* ``ConvexHull + orienting``: the build plus turning its triangles outward
  (the README's ``my_quickhull`` plug-in, the algorithm issue 19 timed);
* ``check``: :func:`hullstress.checker.check` of Qhull's hull with default
  settings, i.e. building and certifying the Qhull reference itself;
* ``check, reference given``: what the sweep pays per algorithm output (the
  case's reference is built once per case);
* ``check --no-qhull``: the exact checks alone.

Part 2, ``--n`` points (default 100,000) in a 3D ball, best of ``--repeat``:

* ``check`` (reference built inside), ``check`` with the reference given,
  ``check --no-qhull``, ``qhull_reference`` (Qhull's hull plus its exact
  certification), and ``qconvex`` / ``qconvex Tv`` when Qhull's program is
  installed (includes parsing the text input, the same for both);
* optionally (``--brute``) plain float numpy, every point against every facet.

Part 3, ``--adversarial``: the inputs of issue 33, each judged in a fresh
process so that its peak memory (``ru_maxrss``) is its own, and scipy's
``ConvexHull`` timed on the same points in another fresh process.  ``check``
is timed twice: with its default Qhull reference (it runs Qhull on the points
and certifies Qhull's hull with the same exact checks, then compares the
answer's extreme vertices and volume with it) and with ``qhull=False`` (the
exact checks of the answer alone, what the checker itself costs):

* a 2D circle of ``--wrong-n`` points given clockwise (a wrong answer);
* a 3D sphere of ``--wrong-n`` points with every face reversed (a wrong answer);
* ``--mixed-n`` Gaussian points times 1e300 plus the point (1e-300, 0, 0), with
  their correct hull (mixed magnitudes: no exact scaling brings them into range);
* ``--sphere-n`` points on a sphere, every one extreme, with their correct hull.

The figures go to ``docs/figures/bench_checker.md`` (``--figures FILE`` elsewhere, ``none``
for no file), under the header of ``benchmarks/_figures.py``; docs/checker.md includes it.

Every figure is the best of ``--repeat`` rounds, and every ratio is taken
against ConvexHull measured in the same run, interleaved, so that the ratios
survive a shared, loaded machine.  ``--clock cpu`` measures process CPU time
instead of wall time (steadier when other processes compete for the cores).

Run: ``python benchmarks/bench_checker.py [--sizes 24,100,1000] [--n 100000] [--repeat 5]``,
or ``python benchmarks/bench_checker.py --adversarial [--sphere-n 1000000]`` for part 3 alone.
Prints Markdown tables.
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
from scipy.spatial import ConvexHull

from _figures import add_figures_option, recorded  # a sibling: benchmarks run as scripts
from hullstress.adapters.executable import locate_program
from hullstress.checker import check, qhull_reference
from hullstress.io import write_points


def ball(rng: np.random.Generator, n: int, dim: int) -> np.ndarray:
    """n points uniform in the unit ball."""
    v = rng.normal(size=(n, dim))
    v /= np.linalg.norm(v, axis=1)[:, None]
    return v * rng.random(n)[:, None] ** (1.0 / dim)


def best_per_call(fns: dict, args: list, repeat: int, clock) -> dict:
    """Best over ``repeat`` rounds of the mean time per call of each function over ``args``, interleaved."""
    best = {name: float("inf") for name in fns}
    for _ in range(repeat):
        for name, fn in fns.items():
            start = clock()
            for a in args:
                fn(*a)
            best[name] = min(best[name], (clock() - start) / len(args))
    return best


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
    exe = locate_program("qconvex")  # PATH, or where cmeel-qhull (the `all` extra) puts it
    if exe is None:
        return None
    with tempfile.TemporaryDirectory() as tmp:
        path = write_points(Path(tmp) / "points.txt", points, "qhull")
        data = path.read_bytes()

        def run(opts):
            subprocess.run([exe, *opts], input=data, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, check=True)

        def best(opts):
            times = []
            for _ in range(repeat):
                t = time.perf_counter()
                run(opts)
                times.append(time.perf_counter() - t)
            return min(times)

        return best([]), best(["Tv"])


def oriented_hull(points: np.ndarray) -> np.ndarray:
    """scipy's hull as an algorithm returns it: 2D vertex cycle, or 3D triangles turned outward."""
    hull = ConvexHull(points)
    if points.shape[1] == 2:
        return hull.vertices
    tri = hull.simplices.copy()
    a, b, c = (points[tri[:, k]] for k in range(3))
    inward = np.einsum("ij,ij->i", np.cross(b - a, c - a), hull.equations[:, :3]) < 0
    tri[inward] = tri[inward][:, ::-1]
    return tri


def small_sizes(sizes: list[int], repeat: int, seed: int, clock) -> list[str]:
    lines = [
        "| dim | n | clouds | ConvexHull ms | check ms | check / ConvexHull | check / (ConvexHull + orienting) "
        "| reference given | --no-qhull |",
        "| ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |",
    ]
    for dim in (3, 2):
        for n in sizes:
            clouds = max(3, min(50, 2000 // n))  # short rounds: the best of many resists a loaded machine
            rng = np.random.default_rng(seed)
            cases = []
            for _ in range(clouds):
                pts = ball(rng, n, dim)
                ref = qhull_reference(pts)
                faces = oriented_hull(pts)
                verdict = check(pts, faces)
                if not verdict.ok:
                    raise SystemExit(f"unexpected verdict on Qhull's hull (n={n}, dim={dim}): {verdict.detail}")
                cases.append((pts, faces, ref))
            t = best_per_call(
                {
                    "hull": lambda p, f, r: ConvexHull(p),
                    "oriented": lambda p, f, r: oriented_hull(p),
                    "check": lambda p, f, r: check(p, f),
                    "given": lambda p, f, r: check(p, f, reference=r),
                    "exact": lambda p, f, r: check(p, f, qhull=False),
                },
                cases,
                repeat,
                clock,
            )
            h = t["hull"]
            lines.append(
                f"| {dim} | {n} | {clouds} | {h * 1e3:.3f} | {t['check'] * 1e3:.3f} | {t['check'] / h:.1f}x "
                f"| {t['check'] / t['oriented']:.1f}x | {t['given'] / h:.2f}x | {t['exact'] / h:.1f}x |"
            )
    return lines


def large(n: int, repeat: int, seed: int, brute: bool, clock) -> list[str]:
    points = ball(np.random.default_rng(seed), n, 3)
    hull = ConvexHull(points)
    ref = qhull_reference(points)
    faces = oriented_hull(points)
    verdict = check(points, faces, reference=ref)
    if not verdict.ok:
        raise SystemExit(f"unexpected verdict on Qhull's hull: {verdict.detail}")
    t = best_per_call(
        {
            "hull": lambda: ConvexHull(points),
            "check": lambda: check(points, faces),
            "given": lambda: check(points, faces, reference=ref),
            "exact": lambda: check(points, faces, qhull=False),
            "reference": lambda: qhull_reference(points),
        },
        [()],
        repeat,
        clock,
    )
    rows = [
        ("scipy ConvexHull", t["hull"]),
        ("check (default: builds and certifies the Qhull reference)", t["check"]),
        ("check, reference given (what the sweep pays per output)", t["given"]),
        ("check --no-qhull (exact checks only)", t["exact"]),
        ("qhull_reference (Qhull's hull + its exact certification)", t["reference"]),
    ]
    q = qconvex_times(points, repeat)
    if q is not None:
        rows += [("qconvex", q[0]), ("qconvex Tv (Qhull's own, tolerance-based verification)", q[1])]
    if brute:
        rows.append(("plain numpy, all points x all facets (float, not exact)", brute_numpy(points, hull.equations)))
    lines = [
        f"n = {n}, dim = 3, uniform in a ball, seed {seed}: {len(hull.vertices)} hull vertices, "
        f"{len(hull.simplices)} facets; best of {repeat}",
        "",
        "| what | seconds | / ConvexHull |",
        "| --- | ---: | ---: |",
    ]
    lines += [f"| {name} | {s:.4f} | {s / t['hull']:.2f}x |" for name, s in rows]
    return lines


# --------------------------------------------------------------------------- part 3: adversarial inputs

def _outward(points: np.ndarray, hull: ConvexHull) -> np.ndarray:
    tri = hull.simplices.copy()
    a, b, c = (points[tri[:, k]] for k in range(3))
    inward = np.einsum("ij,ij->i", np.cross(b - a, c - a), hull.equations[:, :3]) < 0
    tri[inward] = tri[inward][:, ::-1]
    return tri


def adversarial_input(kind: str, n: int, seed: int) -> tuple[np.ndarray, np.ndarray]:
    """The points and the answer of one part-3 input."""
    rng = np.random.default_rng(seed)
    if kind == "circle-clockwise":
        t = np.sort(rng.uniform(0.0, 2.0 * np.pi, n))
        return np.c_[np.cos(t), np.sin(t)], np.arange(n)[::-1].copy()
    if kind in ("sphere-reversed", "sphere"):
        p = rng.standard_normal((n, 3))
        p /= np.linalg.norm(p, axis=1)[:, None]
        faces = _outward(p, ConvexHull(p))
        return p, (faces[:, ::-1].copy() if kind == "sphere-reversed" else faces)
    if kind == "mixed":
        p = np.vstack([rng.standard_normal((n - 1, 3)) * 1e300, [[1e-300, 0.0, 0.0]]])
        scaled = p * 2.0**-1000  # Qhull overflows at 1e300; the scaled copy has the same faces
        return p, _outward(scaled, ConvexHull(scaled))
    raise SystemExit(f"unknown adversarial input {kind!r}")


def _measure_one(task: str, path: str) -> None:
    """Child process: time ``check`` (or ``ConvexHull``) on a saved input; print seconds and peak MB as JSON."""
    data = np.load(path)
    points, faces = data["points"], data["faces"]
    start = time.perf_counter()
    if task in ("check", "check-no-qhull"):
        verdict = check(points, faces, qhull=task == "check")
        extra = {"ok": verdict.ok, "detail": verdict.detail[:120]}
    else:
        with np.errstate(all="ignore"):
            try:
                ConvexHull(points)
                extra = {"ok": True}
            except Exception as exc:  # Qhull's own overflow at 1e300: report it, it is only the yardstick
                extra = {"ok": False, "detail": f"{type(exc).__name__}"}
    seconds = time.perf_counter() - start
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0  # KiB on Linux
    print(json.dumps({"seconds": seconds, "peak_mb": peak, **extra}))


def _child(task: str, path: str) -> dict:
    out = subprocess.run([sys.executable, __file__, "--measure", task, path], capture_output=True, text=True, check=False)
    if out.returncode:
        raise SystemExit(f"measuring {task} failed: {out.stderr.strip().splitlines()[-1] if out.stderr else out.returncode}")
    return json.loads(out.stdout.strip().splitlines()[-1])


def adversarial(sizes: dict[str, int], repeat: int, seed: int) -> list[str]:
    """Part 3: every input in fresh processes, best time of ``repeat`` rounds, the largest peak."""
    targets = {
        "circle-clockwise": "<= 2 s",
        "sphere-reversed": "<= 5 s",
        "mixed": "<= 1 s, <= 500 MB",
        "sphere": "<= 1.5x ConvexHull, <= 2048 MB",
    }
    what = {
        "circle-clockwise": "2D circle given clockwise (wrong)",
        "sphere-reversed": "3D sphere, every face reversed (wrong)",
        "mixed": "Gaussian x 1e300 plus (1e-300, 0, 0) (right)",
        "sphere": "sphere, every point extreme (right)",
    }
    lines = [
        "| input | n | check s | check peak MB | check --no-qhull s | --no-qhull peak MB | ConvexHull s "
        "| check / ConvexHull | --no-qhull / ConvexHull | verdict | target |",
        "| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | --- | --- |",
    ]
    with tempfile.TemporaryDirectory() as tmp:
        for kind, n in sizes.items():
            if not n:
                continue
            points, faces = adversarial_input(kind, n, seed)
            path = os.path.join(tmp, f"{kind}.npz")
            np.savez(path, points=points, faces=faces)
            del points, faces
            checks, alone, hulls = [], [], []
            for _ in range(repeat):  # interleaved, so the ratios survive a loaded machine
                checks.append(_child("check", path))
                alone.append(_child("check-no-qhull", path))
                hulls.append(_child("hull", path))
            c = min(checks, key=lambda r: r["seconds"])
            a = min(alone, key=lambda r: r["seconds"])
            h = min(hulls, key=lambda r: r["seconds"])
            if a["ok"] != c["ok"]:
                raise SystemExit(f"{kind}: check and check --no-qhull disagree ({c['detail']!r} / {a['detail']!r})")
            peak, peak_alone = max(r["peak_mb"] for r in checks), max(r["peak_mb"] for r in alone)
            hull_note = f"{h['seconds']:.3f}" if h["ok"] else f"fails ({h.get('detail', '')})"
            ratio = f"{c['seconds'] / h['seconds']:.2f}x" if h["ok"] else "-"
            ratio_alone = f"{a['seconds'] / h['seconds']:.2f}x" if h["ok"] else "-"
            verdict = "valid" if c["ok"] else "invalid"
            lines.append(f"| {what[kind]} | {n} | {c['seconds']:.3f} | {peak:.0f} | {a['seconds']:.3f} | {peak_alone:.0f} "
                         f"| {hull_note} | {ratio} | {ratio_alone} | {verdict} | {targets[kind]} |")
    return lines


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", default="24,100,1000", help="comma-separated small sizes (part 1)")
    parser.add_argument("--n", type=int, default=100_000, help="the large size (part 2); 0 skips it")
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--clock", choices=("wall", "cpu"), default="wall")
    parser.add_argument("--brute", action="store_true", help="also time plain numpy all points x all facets")
    parser.add_argument("--adversarial", action="store_true",
                        help="run part 3 (issue 33's inputs) alone and write its figures")
    parser.add_argument("--wrong-n", type=int, default=100_000, help="points of the wrong 2D and 3D answers")
    parser.add_argument("--mixed-n", type=int, default=200_000, help="points of the mixed-magnitude input")
    parser.add_argument("--sphere-n", type=int, default=1_000_000, help="points of the all-extreme sphere")
    add_figures_option(parser, "bench_checker")  # part 3 only
    parser.add_argument("--measure", nargs=2, metavar=("TASK", "NPZ"), help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    clock = time.perf_counter if args.clock == "wall" else time.process_time
    if args.measure:
        _measure_one(*args.measure)
        return 0
    if args.adversarial:
        sizes = {"circle-clockwise": args.wrong_n, "sphere-reversed": args.wrong_n, "mixed": args.mixed_n,
                 "sphere": args.sphere_n}
        reference = "scipy's ConvexHull on the same points, each run in a fresh process, interleaved with check's"
        with recorded(args.figures, "bench_checker", reference):
            lines = adversarial(sizes, args.repeat, args.seed)
            load = ", ".join(f"{x:.2f}" for x in os.getloadavg())
            print(f"Issue 33's inputs, seed {args.seed}, best of {args.repeat} fresh processes each "
                  f"(wall clock; load average {load} (1, 5, 15 min) on {os.cpu_count()} CPUs at the end)\n")
            print("\n".join(lines))
        return 0

    sizes = [int(s) for s in args.sizes.split(",") if s.strip()]
    if sizes:
        print(f"Per call, best of {args.repeat} rounds ({args.clock} clock), uniform in a ball:")
        print()
        print("\n".join(small_sizes(sizes, args.repeat, args.seed, clock)))
    if args.n:
        print()
        print("\n".join(large(args.n, args.repeat, args.seed, args.brute, clock)))
        if locate_program("qconvex"):
            print("\n(qconvex includes parsing its text input.)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
