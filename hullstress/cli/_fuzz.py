"""``python -m hullstress fuzz``: Hypothesis-driven search for failures of one algorithm config.

Exit status: 1 when a failure was found (failure folders written), 0 when
none was, 2 for bad arguments, 130/143 when interrupted.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

from . import EXIT_STATUS_HELP
from ._common import add_registration_options, count, seconds

__all__ = ["add_parser", "fuzz_command"]


def add_parser(sub: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    p = sub.add_parser(
        "fuzz",
        help="Hypothesis-driven search with shrinking for one algorithm",
        description="Draw cases from the generator families with Hypothesis (family, variant, size, seed, "
        "coordinate rounding, power-of-two scale), steer toward larger violations with target(), shrink "
        "what fails (Hypothesis, then ddmin over points) and write failure folders. "
        "1 means a failure was found, 0 none. " + EXIT_STATUS_HELP,
    )
    p.add_argument("--algorithm", required=True, metavar="NAME", help="the algorithm to fuzz")
    p.add_argument("--generator", action="append", default=[], metavar="NAME",
                   help="draw from this family (repeatable; default: every family of the algorithm's dim)")
    p.add_argument("--sphere", choices=("off", "on"), default="off", help="sphere projection first (default off)")
    p.add_argument("--eps", choices=("scaled", "fixed"), default=None,
                   help="eps policy for algorithms taking eps (default: scaled for in-house algorithms, not passed "
                   "to plug-ins)")
    p.add_argument("--max-examples", type=count(minimum=1), default=200, metavar="N",
                   help="Hypothesis examples per search (default 200)")
    p.add_argument("--max-findings", type=count(minimum=1), default=3, metavar="N",
                   help="stop after this many distinct failed checks (default 3)")
    p.add_argument("--database", default=".hypothesis/hullstress-fuzz", metavar="DIR",
                   help="Hypothesis example database directory; failures found are replayed from it first "
                   "(default .hypothesis/hullstress-fuzz; 'none' keeps nothing)")
    p.add_argument("--seed", type=int, default=None,
                   help="seed Hypothesis's choices for a reproducible search (default: random; Hypothesis saves "
                   "failures to the database only from unseeded runs, seeded runs still replay it)")
    p.add_argument("--max-size", type=count(minimum=4), default=64, metavar="N",
                   help="largest point count drawn (default 64)")
    p.add_argument("--timeout", type=seconds(), default=None, metavar="SECONDS",
                   help="per-call timeout of isolated calls (default 10)")
    p.add_argument("--shrink-budget", type=seconds(zero=True), default=10.0, metavar="SECONDS",
                   help="point-level shrink time per finding after Hypothesis's shrink (default 10; 0 skips)")
    add_registration_options(p)
    p.add_argument("--out", default="reports", metavar="DIR", help="where the fuzz folder goes (default: reports)")
    p.set_defaults(handler=fuzz_command)


def fuzz_command(args: argparse.Namespace) -> int:
    from ..files import atomic_write_text
    from ..report.failures import write_failure_folder
    from ..report.writer import new_run_dir
    from ..triage.fuzzing import fuzz
    from ..triage.records import ShrinkResult
    from ..triage.stage import triage_one

    from ._common import registration_args

    database = None if str(args.database).lower() == "none" else Path(args.database)
    result = fuzz(
        args.algorithm, sphere=args.sphere, eps=args.eps, families=tuple(args.generator),
        max_examples=args.max_examples, database=database, seed=args.seed, timeout=args.timeout,
        max_findings=args.max_findings, max_size=args.max_size, shrink_budget_seconds=args.shrink_budget,
    )
    print(f"fuzz {result.config.label}: {result.examples} examples over {len(result.families)} families "
          f"in {result.seconds:.1f} s (seed {'random' if result.seed is None else result.seed}); "
          f"{len(result.findings)} failures found")
    if not result.findings:
        return 0
    seed_part = "" if result.seed is None else f"-seed{result.seed}"
    run_dir = new_run_dir(args.out, f"fuzz-{time.strftime('%Y%m%d-%H%M%S')}-{args.algorithm}{seed_part}")
    summary = []
    for finding in result.findings:
        shrunk = finding.shrunk
        if shrunk is None or not shrunk.reproduced:
            shrunk = ShrinkResult(case=finding.case, original=finding.case, signature=finding.signature,
                                  original_size=finding.case.n_points, minimal_size=finding.case.n_points,
                                  calls=0, seconds=0.0, reproduced=True, row=finding.row,
                                  note="Hypothesis's minimal example (no point-level shrink)")
        rec = write_failure_folder(run_dir / "failures", triage_one(shrunk, result.config, timeout=args.timeout),
                                   timeout=args.timeout, registration=registration_args(args))
        print(f"  {finding.signature.label}: {finding.case.n_points} -> {rec.minimal_size} points; "
              f"{finding.row.get('reason')}")
        print(f"    reproduce: {rec.command}")
        summary.append({"signature": finding.signature.as_dict(), "hypothesis_case": repr(finding.case),
                        "minimal_size": rec.minimal_size, "folder": str(rec.folder), "reproduce": rec.command})
    atomic_write_text(run_dir / "fuzz.json", json.dumps(
        {"config": result.config.label, "seed": result.seed, "examples": result.examples,
         "families": list(result.families), "database": None if database is None else str(database),
         "findings": summary}, indent=2) + "\n")
    print(f"report: {run_dir}", file=sys.stderr)
    return 1
