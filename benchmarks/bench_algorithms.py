"""Time every registered in-house hull algorithm next to scipy's Qhull, on random and worst-case input.

A script, not a test::

    python benchmarks/bench_algorithms.py
    python benchmarks/bench_algorithms.py --input worst --algorithm naive-2d --max-seconds 30
    python benchmarks/bench_algorithms.py --sizes 256,1024,4096 --repeat 5 --sphere

Two inputs per algorithm, the same points for the algorithm and for
``scipy.spatial.ConvexHull`` in the same run (so the ratio survives a loaded
machine):

* ``random``: uniform in the unit square (2D) or the unit ball (3D), where
  the hull has few vertices and most algorithms finish early;
* ``worst``: an input on which the algorithm cannot finish early, chosen per
  algorithm from what its seed's cost depends on (:data:`WORST_CASE`), e.g.
  for naive-2d, whose seed claims O(n^3), points in convex position on a
  flat arc, in arc order.

Each time is the best of ``--repeat`` calls, in CPU seconds of this process
(``time.process_time``) by default: on a shared machine, other processes
stretch wall time far more than the process's own CPU time (every algorithm
here, and scipy's Qhull, runs on one thread); ``--clock wall`` uses
``time.perf_counter`` instead.  Sizes
grow in the order given; a size is skipped when the previous size took more
than ``--max-seconds`` or when the growth seen so far predicts more than
that, so an O(n^3) method never gets a call that would run for hours.  A call
that raises (e.g. ``henckel``'s literal sort key ending at its step limit) is
reported with its exception, not timed, and ends that series.

The output is two Markdown tables: every timing, and per (algorithm, input)
the growth exponent, the least-squares slope of log time against log n over
the three largest sizes measured (the smaller ones are dominated by fixed
costs), beside scipy's over the same sizes, and the time ratio at the largest
size.
"""

from __future__ import annotations

import os

# One thread for BLAS and OpenMP, before numpy loads: the timed calls then
# use one core each, and CPU time measures their work, not a thread pool's.
for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import argparse  # noqa: E402
import importlib  # noqa: E402
import math  # noqa: E402
import platform  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
from collections.abc import Callable, Sequence  # noqa: E402
from dataclasses import dataclass  # noqa: E402

import numpy as np  # noqa: E402
from _figures import add_figures_option, recorded  # noqa: E402  (a sibling: benchmarks run as scripts)
from scipy.spatial import ConvexHull  # noqa: E402

# The in-house modules; each registers its algorithms on import.  A module not
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
# Sizes the growth exponent is fitted over: the largest this many measured.
_FIT_SIZES = 3
INPUTS = ("random", "worst")


def _frozen(pts: np.ndarray) -> np.ndarray:
    """A read-only, C-contiguous float64 copy, as the harness hands points to an algorithm."""
    pts = np.ascontiguousarray(pts, dtype=np.float64)
    pts.setflags(write=False)
    return pts


def random_points(rng: np.random.Generator, n: int, dim: int) -> np.ndarray:
    """Uniform points: the unit square in 2D, the unit ball in 3D."""
    if dim == 2:
        return _frozen(rng.random((n, 2)))
    v = rng.standard_normal((n, 3))
    return _frozen(v / np.linalg.norm(v, axis=1)[:, None] * rng.random((n, 1)) ** (1.0 / 3.0))


def flat_arc(rng: np.random.Generator, n: int) -> np.ndarray:
    """n points on a 0.04-radian arc of the unit circle, in arc order: all in convex position.

    naive-2d's probe directions (8 and 64 evenly spaced) find only the arc's
    ends and middle, so about n^2/4 ordered pairs reach the full O(n) test;
    and in arc order the seed's own loop ("go to 2" at the first point on the
    left, in index order) tries about min(i, j) points for the pair (i, j)
    before it can stop.  Either way the work is cubic.
    """
    t = np.linspace(-0.02, 0.02, n)
    return _frozen(np.c_[np.sin(t), np.cos(t)])


def circle(rng: np.random.Generator, n: int, *, shuffled: bool = True) -> np.ndarray:
    """n points on the unit circle (every point a hull vertex), shuffled or in angular order."""
    t = np.arange(n) * (2.0 * np.pi / n)
    pts = np.c_[np.cos(t), np.sin(t)]
    return _frozen(pts[rng.permutation(n)] if shuffled else pts)


def sphere(rng: np.random.Generator, n: int) -> np.ndarray:
    """n points on the unit sphere in random order: every point a hull vertex, 2n - 4 faces."""
    v = rng.standard_normal((n, 3))
    return _frozen(v / np.linalg.norm(v, axis=1)[:, None])


@dataclass(frozen=True)
class WorstCase:
    """The input on which an algorithm cannot finish early, and why."""

    make: Callable[[np.random.Generator, int], np.ndarray]
    why: str


_SPHERE_3D = WorstCase(sphere, "all n points on a sphere: h = n, so every one of ~2n faces is wrapped or inserted")
#: Per algorithm family (the registry name up to any variant suffix).
WORST_CASE: dict[str, WorstCase] = {
    "naive-2d": WorstCase(flat_arc, "convex position on a flat arc, in arc order: ~n^2/4 pairs get the full O(n) test"),
    "monotone-chain": WorstCase(circle, "every point on the circle: h = n, nothing is deleted; the sort dominates"),
    "jarvis-march": WorstCase(
        lambda rng, n: circle(rng, n, shuffled=False),
        "every point on the circle in angular order: h = n wraps, nextTarget changes at nearly every point",
    ),
    "gift-wrap-3d": _SPHERE_3D,
    "henckel": _SPHERE_3D,
    "kenwright": _SPHERE_3D,
}


def worst_case_for(name: str) -> WorstCase:
    """The worst case of ``name`` or of the algorithm it is a variant of (``henckel-normalised`` -> ``henckel``)."""
    family = max((k for k in WORST_CASE if name == k or name.startswith(k + "-")), key=len, default=None)
    if family is None:
        raise KeyError(f"no worst-case input known for {name!r}; add one to WORST_CASE")
    return WORST_CASE[family]


@dataclass(frozen=True)
class Row:
    """One timing: ``seconds`` is None when the size was skipped or the call raised."""

    algorithm: str
    input: str
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


CLOCKS: dict[str, Callable[[], float]] = {"cpu": time.process_time, "wall": time.perf_counter}


def best_time(call: Callable[[], object], repeat: int, max_seconds: float, clock: str = "cpu") -> float:
    """Best of ``repeat`` calls on ``clock``; stops repeating once a call exceeds ``max_seconds``."""
    now = CLOCKS[clock]
    best = math.inf
    for _ in range(repeat):
        start = now()
        call()
        elapsed = now() - start
        best = min(best, elapsed)
        if elapsed > max_seconds:
            break
    return best


def growth_exponent(sizes: Sequence[int], seconds: Sequence[float | None], last: int = _FIT_SIZES) -> float | None:
    """Least-squares slope of log(seconds) against log(n) over the ``last`` largest sizes; None below two."""
    pairs = sorted((n, t) for n, t in zip(sizes, seconds) if t is not None and t > 0)[-last:]
    if len(pairs) < 2:
        return None
    x = np.log([p[0] for p in pairs])
    y = np.log([p[1] for p in pairs])
    return float(np.polyfit(x, y, 1)[0])


def bench_one(
    spec,
    kind: str,
    sizes: Sequence[int],
    *,
    repeat: int,
    max_seconds: float,
    seed: int,
    sphere_variant: bool,
    clock: str = "cpu",
) -> list[Row]:
    """Time ``spec`` (an AlgorithmSpec) and scipy on input ``kind`` over ``sizes``."""
    from hullstress.sphere import map_back, sphere_project

    def run(points: np.ndarray) -> object:
        if not sphere_variant:
            return spec.func(points)
        projected, original = sphere_project(points)
        projected.setflags(write=False)
        return map_back(spec.func(projected), original)

    def make(n: int) -> np.ndarray:
        rng = np.random.default_rng(seed)
        if kind == "random":
            return random_points(rng, n, spec.dim)
        return worst_case_for(spec.name).make(rng, n)

    rows: list[Row] = []
    done_n: list[int] = []
    done_t: list[float] = []
    stop = ""
    for n in sizes:
        if stop:
            rows.append(Row(spec.name, kind, spec.dim, n, None, None, stop))
            continue
        if done_t:
            exponent = growth_exponent(done_n, done_t, last=2) or _DEFAULT_EXPONENT
            predicted = done_t[-1] * (n / done_n[-1]) ** max(exponent, 1.0)
            if predicted > max_seconds:
                stop = f"skipped: predicted {predicted:.3g} s > {max_seconds:g} s"
                rows.append(Row(spec.name, kind, spec.dim, n, None, None, stop))
                continue
        points = make(n)
        try:
            seconds = best_time(lambda: run(points), repeat, max_seconds, clock)
        except Exception as exc:  # a benchmark reports a broken call and goes on
            reason = str(exc).splitlines()[0] if str(exc) else ""
            reason = reason if len(reason) <= 70 else reason[:67] + "..."
            rows.append(Row(spec.name, kind, spec.dim, n, None, None, f"{type(exc).__name__}: {reason}"))
            stop = f"skipped: n={n} raised {type(exc).__name__}"
            continue
        scipy_seconds = best_time(lambda: ConvexHull(points), repeat, max_seconds, clock)
        rows.append(Row(spec.name, kind, spec.dim, n, seconds, scipy_seconds))
        done_n.append(n)
        done_t.append(seconds)
        if seconds > max_seconds:
            stop = f"skipped: n={n} took {seconds:.3g} s > {max_seconds:g} s"
    return rows


def _fmt(value: float | None, spec: str = ".4g") -> str:
    return "" if value is None else format(value, spec)


def markdown(rows: Sequence[Row]) -> str:
    """The timing table and the growth table, in Markdown."""
    out = [
        "| algorithm | input | dim | n | seconds | scipy seconds | ratio | note |",
        "| --- | --- | ---: | ---: | ---: | ---: | ---: | --- |",
    ]
    for r in rows:
        ratio = r.seconds / r.scipy_seconds if r.seconds is not None and r.scipy_seconds else None
        out.append(
            f"| {r.algorithm} | {r.input} | {r.dim} | {r.n} | {_fmt(r.seconds)} | {_fmt(r.scipy_seconds)} "
            f"| {_fmt(ratio)} | {r.note} |"
        )
    out += [
        "",
        "| algorithm | input | sizes fitted | growth exponent | scipy's | ratio at largest n | note |",
        "| --- | --- | --- | ---: | ---: | ---: | --- |",
    ]
    for name, kind in dict.fromkeys((r.algorithm, r.input) for r in rows):
        group = [r for r in rows if (r.algorithm, r.input) == (name, kind)]
        mine = [r for r in group if r.seconds is not None]
        fitted = sorted(r.n for r in mine)[-_FIT_SIZES:]
        k = growth_exponent([r.n for r in mine], [r.seconds for r in mine])
        q = growth_exponent([r.n for r in mine], [r.scipy_seconds for r in mine])
        last = max(mine, key=lambda r: r.n) if mine else None
        ratio = last.seconds / last.scipy_seconds if last and last.scipy_seconds else None
        errors = sorted({r.note.split(":")[0] for r in group if r.seconds is None and not r.note.startswith("skipped")})
        note = ("raised " + ", ".join(errors)) if errors else ""
        sizes = f"{fitted[0]}-{fitted[-1]}" if fitted else "-"
        out.append(f"| {name} | {kind} | {sizes} | {_fmt(k, '.2f')} | {_fmt(q, '.2f')} | {_fmt(ratio, '.3g')} | {note} |")
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
    parser.add_argument("--sizes", type=_sizes, default=[256, 512, 1024, 2048, 4096, 8192, 16384],
                        help="comma-separated n, grown in order (default 256,512,...,16384)")
    parser.add_argument("--repeat", type=_positive(int), default=3, help="best of this many calls (default 3)")
    parser.add_argument("--max-seconds", type=_positive(float), default=10.0,
                        help="per-call limit for growing n (default 10)")
    parser.add_argument("--seed", type=int, default=0, help="random seed for the inputs (default 0)")
    parser.add_argument("--algorithm", action="append", help="only this algorithm (repeatable)")
    parser.add_argument("--input", choices=(*INPUTS, "both"), default="both",
                        help="random input, each algorithm's worst case, or both (default)")
    parser.add_argument("--sphere", action="store_true",
                        help="apply the sphere variant (sphere_project) inside each timed call")
    parser.add_argument("--clock", choices=sorted(CLOCKS), default="cpu",
                        help="cpu: this process's CPU time (default; robust on a shared machine); wall: elapsed time")
    add_figures_option(parser, "bench_algorithms")
    args = parser.parse_args(argv)
    with recorded(args.figures, 'bench_algorithms', "scipy.spatial.ConvexHull on the same points (each '/ scipy' column)", argv):

        import_modules()
        from hullstress._registry import algorithms

        specs = [s for s in algorithms() if s.origin == "in-house"]
        if args.algorithm:
            known = {s.name for s in specs}
            unknown = sorted(set(args.algorithm) - known)
            if unknown:
                parser.error(f"--algorithm must be one of {', '.join(sorted(known))}, got {', '.join(unknown)}")
            specs = [s for s in specs if s.name in args.algorithm]
        kinds = INPUTS if args.input == "both" else (args.input,)
        rows: list[Row] = []
        for spec in specs:
            for kind in kinds:
                print(f"timing {spec.name} on {kind} input ...", file=sys.stderr, flush=True)
                rows += bench_one(
                    spec,
                    kind,
                    sorted(args.sizes),
                    repeat=args.repeat,
                    max_seconds=args.max_seconds,
                    seed=args.seed,
                    sphere_variant=args.sphere,
                    clock=args.clock,
                )
        print(
            f"seed={args.seed} repeat={args.repeat} max-seconds={args.max_seconds:g} clock={args.clock} "
            f"sphere={'on' if args.sphere else 'off'}; {platform.machine()}, {os.cpu_count()} cores, "
            f"numpy {np.__version__}; ratios are to scipy ConvexHull on the same points in the same run"
        )
        print()
        print("worst-case inputs:\n")  # a blank line: Markdown starts the list only after one
        for name in dict.fromkeys(s.name for s in specs):
            print(f"- {name}: {worst_case_for(name).why}")
        print()
        print(markdown(rows))
        return 0


if __name__ == "__main__":
    sys.exit(main())
