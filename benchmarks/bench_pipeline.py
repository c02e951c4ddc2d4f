"""Measure a whole run end to end, phase by phase, with 1 and 2 workers (issue 15's timing targets).

A script, not a test::

    python benchmarks/bench_pipeline.py                    # quick profile, seed 0, 1 vs 2 workers
    python benchmarks/bench_pipeline.py --workers 1,2,4 --seed 3
    python benchmarks/bench_pipeline.py --algorithm gift-wrap-3d --generator coplanar-grid

Each worker count runs ``python -m hullstress run`` as a user runs it, in a
fresh interpreter: generating the cases, the sweep, triage and the report.
The table gives the command's wall time, the phases recorded in its
``run.json`` (``phase_seconds``: ``generate`` is building the cases and
loading what the report needs, then the sweep, triage and the report), the
rest (``start-up``: the interpreter, the command line's imports and the
exit; what the command's wall time has beyond the phases) and the speed-up
over the first worker count, overall and per phase.  The runs alternate between worker counts
(``--repeat`` rounds), so a change of the machine's load falls on every
count alike; each count keeps its best round.

The issue's targets: the quick profile in at most 30 s end to end on
2 cores, and 2 workers at least 1.8x faster than 1 end to end.  On a shared
machine the seconds move with the load (printed before and after); the
speed-ups, measured in the same run, much less.
"""

from __future__ import annotations

import argparse
import sys
import tempfile
from dataclasses import dataclass
from pathlib import Path

from _bench_common import add_run_options, load_average, timed_run  # a sibling: benchmarks run as scripts
from _figures import add_figures_option, recorded  # a sibling: benchmarks run as scripts

#: The phases ``run.json`` times, in order.
PHASES = ("generate", "sweep", "triage", "report")


@dataclass(frozen=True)
class Measured:
    """One ``hullstress run``: its wall time, phases and triage counts."""

    workers: int
    wall: float
    phases: dict[str, float]
    triage: dict

    @property
    def start_up(self) -> float:
        return max(0.0, self.wall - sum(self.phases.get(p, 0.0) for p in PHASES))

    def seconds(self, what: str) -> float:
        return self.wall if what == "end to end" else self.start_up if what == "start-up" else self.phases.get(what, 0.0)


def run_once(args: argparse.Namespace, workers: int, out: Path) -> Measured:
    """One ``python -m hullstress run`` with ``workers``, timed from outside; its run.json read back."""
    wall, meta = timed_run(args, workers, out)
    return Measured(workers=workers, wall=wall, phases={p: float(meta.get("phase_seconds", {}).get(p, 0.0))
                                                        for p in PHASES}, triage=meta.get("triage") or {})


def table(results: list[Measured]) -> str:
    """The Markdown table: seconds per phase and end to end, and the speed-up over the first row."""
    columns = ("end to end", *PHASES, "start-up")
    first = results[0]
    lines = ["| workers | " + " | ".join(f"{c} s" for c in columns) + " | evaluations | causes | "
             + " | ".join(f"speed-up {c}" for c in ("end to end", *PHASES)) + " |",
             "|---:" * (3 + 2 * len(columns) - 1) + "|"]
    for m in results:
        secs = " | ".join(f"{m.seconds(c):.1f}" for c in columns)
        ups = " | ".join(f"{first.seconds(c) / m.seconds(c):.2f}x" if m.seconds(c) > 0 else "-"
                         for c in ("end to end", *PHASES))
        lines.append(f"| {m.workers} | {secs} | {m.triage.get('evaluations', '')} | {m.triage.get('causes', '')} "
                     f"| {ups} |")
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    add_run_options(parser)
    parser.add_argument("--keep", type=Path, default=None, metavar="DIR",
                        help="write the runs' report folders under DIR and keep them (default: a temporary folder)")
    add_figures_option(parser, "bench_pipeline")
    args = parser.parse_args(argv)
    with recorded(args.figures, 'bench_pipeline', "the first worker count's run of the same command (the speed-up columns)", argv):
        print(f"load average before: {load_average()}")
        best: dict[int, Measured] = {}
        with tempfile.TemporaryDirectory(prefix="hullstress-bench-pipeline-") as tmp:
            root = args.keep if args.keep is not None else Path(tmp)
            for r in range(args.repeat):
                for workers in args.workers:
                    got = run_once(args, workers, root / f"r{r}-w{workers}")
                    print(f"  round {r + 1}, {workers} workers: {got.wall:.1f} s", file=sys.stderr)
                    if workers not in best or got.wall < best[workers].wall:
                        best[workers] = got
        print(f"load average after: {load_average()}\n")
        print(f"## `python -m hullstress run --profile {args.profile} --seed {args.seed}` end to end\n")
        print(table([best[w] for w in args.workers]))
        return 0


if __name__ == "__main__":
    sys.exit(main())
