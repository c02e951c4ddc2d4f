"""Time every registered in-house hull algorithm next to scipy's Qhull.

A script, not a test::

    python benchmarks/bench_algorithms.py
    python benchmarks/bench_algorithms.py --sizes 100,1000 --repeat 5 --max-seconds 5
    python benchmarks/bench_algorithms.py --algorithm kenwright --sphere

Inputs are uniform in the unit square (2D algorithms) or the unit ball (3D),
drawn from ``numpy.random.default_rng(--seed)``, the same points for the
algorithm and for ``scipy.spatial.ConvexHull``.  Each time is the best of
``--repeat`` calls (``time.perf_counter``).  Sizes grow in the order given; a
size is skipped when the previous size took more than ``--max-seconds`` or
when the growth seen so far predicts more than that (so an O(n^3) method
never gets a call that would run for hours).  The output is two Markdown
tables: the timings, and per algorithm the fitted growth exponent (least
squares slope of log time against log n over the sizes measured).
"""

from __future__ import annotations

import argparse
import importlib
import math
import sys
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np
from scipy.spatial import ConvexHull

# The in-house modules; each registers its algorithm on import.  A module not
# written yet is skipped with a note rather than stopping the benchmark.
MODULES = (
    "hullstress.algorithms.naive2d",
    "hullstress.algorithms.monotone_chain",
    "hullstress.algorithms.jarvis",
    "hullstress.algorithms.gift_wrap",
    "hullstress.algorithms.henckel",
    "hullstress.algorithms.kenwright",
)

# Assumed growth exponent when only one size has been measured.
_DEFAULT_EXPONENT = 2.0


@dataclass(frozen=True)
class Row:
    """One timing: ``seconds`` is None when the size was skipped or failed."""

    algorithm: str
    dim: int
    n: int
    seconds: float | None
    scipy_seconds: float | None
    note: str = ""


def import_modules(modules: Sequence[str] = MODULES) -> None:
    """Import the in-house algorithm modules, printing a note for missing ones."""
    for name in modules:
        try:
            importlib.import_module(name)
        except ImportError as exc:
            print(f"note: skipping {name}: {exc}", file=sys.stderr)


def make_points(rng: np.random.Generator, n: int, dim: int) -> np.ndarray:
    """Uniform points: the unit square in 2D, the unit ball in 3D.

    Returns a read-only, C-contiguous ``(n, dim)`` float64 array, as the
    harness hands it to an algorithm.
    """
    if dim == 2:
        pts = rng.random((n, 2))
    else:
        v = rng.standard_normal((n, 3))
        pts = v / np.linalg.norm(v, axis=1)[:, None] * rng.random((n, 1)) ** (1.0 / 3.0)
    pts = np.ascontiguousarray(pts, dtype=np.float64)
    pts.setflags(write=False)
    return pts


def best_time(call: Callable[[], object], repeat: int, max_seconds: float) -> float:
    """Best of ``repeat`` calls; stops repeating once a call exceeds ``max_seconds``."""
    best = math.inf
    for _ in range(repeat):
        start = time.perf_counter()
        call()
        elapsed = time.perf_counter() - start
        best = min(best, elapsed)
        if elapsed > max_seconds:
            break
    return best


def growth_exponent(sizes: Sequence[int], seconds: Sequence[float]) -> float | None:
    """Least-squares slope of log(seconds) against log(n); None below two sizes."""
    pairs = [(n, t) for n, t in zip(sizes, seconds) if t is not None and t > 0]
    if len(pairs) < 2:
        return None
    x = np.log([p[0] for p in pairs])
    y = np.log([p[1] for p in pairs])
    return float(np.polyfit(x, y, 1)[0])


def bench_one(
    spec,
    sizes: Sequence[int],
    *,
    repeat: int,
    max_seconds: float,
    seed: int,
    sphere: bool,
) -> list[Row]:
    """Time ``spec`` (an AlgorithmSpec) and scipy over ``sizes``."""
    from hullstress.sphere import map_back, sphere_project

    def run(points: np.ndarray) -> object:
        if not sphere:
            return spec.func(points)
        projected, original = sphere_project(points)
        projected.setflags(write=False)
        return map_back(spec.func(projected), original)

    rows: list[Row] = []
    done_n: list[int] = []
    done_t: list[float] = []
    stop = ""
    for n in sizes:
        if stop:
            rows.append(Row(spec.name, spec.dim, n, None, None, stop))
            continue
        if done_t:
            exponent = growth_exponent(done_n, done_t) or _DEFAULT_EXPONENT
            predicted = done_t[-1] * (n / done_n[-1]) ** max(exponent, 1.0)
            if predicted > max_seconds:
                stop = f"skipped: predicted {predicted:.3g} s > {max_seconds:g} s"
                rows.append(Row(spec.name, spec.dim, n, None, None, stop))
                continue
        points = make_points(np.random.default_rng(seed), n, spec.dim)
        try:
            seconds = best_time(lambda: run(points), repeat, max_seconds)
        except Exception as exc:  # a benchmark reports a broken call and goes on
            reason = str(exc).splitlines()[0] if str(exc) else ""
            rows.append(Row(spec.name, spec.dim, n, None, None, f"error: {type(exc).__name__}: {reason}"))
            continue
        scipy_seconds = best_time(lambda: ConvexHull(points), repeat, max_seconds)
        rows.append(Row(spec.name, spec.dim, n, seconds, scipy_seconds))
        done_n.append(n)
        done_t.append(seconds)
        if seconds > max_seconds:
            stop = f"skipped: n={n} took {seconds:.3g} s > {max_seconds:g} s"
    return rows


def _fmt(value: float | None) -> str:
    return "" if value is None else f"{value:.4g}"


def markdown(rows: Sequence[Row]) -> str:
    """The timing table and the growth table, in Markdown."""
    out = [
        "| algorithm | dim | n | seconds | scipy seconds | ratio | note |",
        "| --- | ---: | ---: | ---: | ---: | ---: | --- |",
    ]
    for r in rows:
        ratio = r.seconds / r.scipy_seconds if r.seconds is not None and r.scipy_seconds else None
        out.append(
            f"| {r.algorithm} | {r.dim} | {r.n} | {_fmt(r.seconds)} | {_fmt(r.scipy_seconds)} "
            f"| {_fmt(ratio)} | {r.note} |"
        )
    out += ["", "| algorithm | growth exponent | scipy growth exponent |", "| --- | ---: | ---: |"]
    for name in dict.fromkeys(r.algorithm for r in rows):
        mine = [r for r in rows if r.algorithm == name and r.seconds is not None]
        k = growth_exponent([r.n for r in mine], [r.seconds for r in mine])
        q = growth_exponent([r.n for r in mine], [r.scipy_seconds for r in mine])
        out.append(f"| {name} | {_fmt(k)} | {_fmt(q)} |")
    return "\n".join(out)


def _sizes(text: str) -> list[int]:
    try:
        sizes = [int(s) for s in text.split(",") if s.strip()]
    except ValueError:
        raise argparse.ArgumentTypeError(f"--sizes must be comma-separated integers, got {text!r}") from None
    if not sizes or min(sizes) < 4:
        raise argparse.ArgumentTypeError(f"--sizes must be integers >= 4, got {text!r}")
    return sizes


def _positive(kind: type) -> Callable[[str], float]:
    def parse(text: str):
        try:
            value = kind(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"expected a positive {kind.__name__}, got {text!r}") from None
        if value <= 0:
            raise argparse.ArgumentTypeError(f"expected a positive {kind.__name__}, got {text!r}")
        return value

    return parse


def main(argv: Sequence[str] | None = None) -> int:
    """Parse options, run the benchmark, print the Markdown tables; return 0."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=_sizes, default=[100, 1000, 10000], help="comma-separated n (default 100,1000,10000)")
    parser.add_argument("--repeat", type=_positive(int), default=3, help="best of this many calls (default 3)")
    parser.add_argument("--max-seconds", type=_positive(float), default=20.0, help="per-call limit for growing n (default 20)")
    parser.add_argument("--seed", type=int, default=0, help="random seed for the inputs (default 0)")
    parser.add_argument("--algorithm", action="append", help="only this algorithm (repeatable)")
    parser.add_argument("--sphere", action="store_true", help="apply the sphere variant (sphere_project) inside each timed call")
    args = parser.parse_args(argv)

    import_modules()
    from hullstress._registry import algorithms

    specs = [s for s in algorithms() if s.origin == "in-house"]
    if args.algorithm:
        known = {s.name for s in specs}
        unknown = sorted(set(args.algorithm) - known)
        if unknown:
            parser.error(f"--algorithm must be one of {', '.join(sorted(known))}, got {', '.join(unknown)}")
        specs = [s for s in specs if s.name in args.algorithm]
    rows: list[Row] = []
    for spec in specs:
        print(f"timing {spec.name} ...", file=sys.stderr, flush=True)
        rows += bench_one(
            spec,
            sorted(args.sizes),
            repeat=args.repeat,
            max_seconds=args.max_seconds,
            seed=args.seed,
            sphere=args.sphere,
        )
    print(f"seed={args.seed} repeat={args.repeat} max-seconds={args.max_seconds:g} sphere={'on' if args.sphere else 'off'}")
    print()
    print(markdown(rows))
    return 0


if __name__ == "__main__":
    sys.exit(main())
