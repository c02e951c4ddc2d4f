"""``python -m hullstress search``: grow inputs toward new failures, then triage and report them as ``run`` does."""

from __future__ import annotations

import argparse
import sys

from ..config import EPS_CHOICES, SPHERE_CHOICES
from ..options import DEFAULTS
from . import EXIT_STATUS_HELP
from ._common import add_registration_options, count, mebibytes, registration_args, seconds

__all__ = ["add_parser", "search_command"]


def add_parser(sub: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    p = sub.add_parser(
        "search",
        help="search for new failures: mutate inputs, keep those that show new behaviour",
        description="Start from a few of the sweep's cases and mutate them (metamorphic transforms, ulp nudges, "
        "duplicated hull vertices, points snapped onto hull edges and faces, scaling and offsets, merged "
        "inputs), keeping a candidate when it shows a failure signature not seen before, raises the exact "
        "degeneracy score or makes two algorithms disagree on the extreme points.  Every failure is triaged, "
        "shrunk and reported in reports/<run-id>/ as by `run`.  The same --seed and --evaluations give the "
        "same cases and table; --time-budget may cut the search short. " + EXIT_STATUS_HELP,
    )
    p.add_argument("--evaluations", type=count(minimum=1), default=None, metavar="N",
                   help="inputs to evaluate, seeds included, each on every selected config (default 400, or "
                   "unlimited when only --time-budget is given)")
    p.add_argument("--time-budget", type=seconds(), default=None, metavar="SECONDS",
                   help="stop starting new inputs after this long (the report says the search was cut short)")
    p.add_argument("--seeds", type=count(minimum=1), default=None, metavar="N",
                   help="how many of the sweep's cases seed the search, round robin over families, smallest "
                   "first (default: a quarter of --evaluations)")
    p.add_argument("--max-points", type=count(minimum=4), default=200, metavar="N",
                   help="candidates with more rows are trimmed to N (default 200)")
    p.add_argument("--algorithm", action="append", default=[], metavar="NAME",
                   help="search with this algorithm (repeatable; default: every registered one)")
    p.add_argument("--generator", action="append", default=[], metavar="NAME[:KEY=VALUE,...]",
                   help="take seeds from this generator family (repeatable, as for `run`; default: every family)")
    p.add_argument("--sizes", type=str, default=None, metavar="N[,N...]",
                   help="sizes of the seed cases (default: the quick profile's)")
    p.add_argument("--sphere", choices=SPHERE_CHOICES, default=None, help="as for `run`")
    p.add_argument("--eps", choices=EPS_CHOICES, default=None, help="as for `run`")
    p.add_argument("--seed", type=int, default=0,
                   help="base seed of the seed cases and every mutation (default 0)")
    p.add_argument("--workers", type=count(minimum=0), default=None, metavar="N",
                   help="worker processes (default: all cores; 0 runs in this process without isolation); "
                   "the results do not depend on it")
    p.add_argument("--timeout", type=seconds(), default=None, metavar="SECONDS",
                   help="per-call timeout (default: the quick profile's)")
    p.add_argument("--memory-limit", type=mebibytes, default=DEFAULTS.memory_limit_mb, metavar="MB",
                   help="what the code under test may allocate per worker process in MiB, beyond the worker's own "
                   f"libraries (default {DEFAULTS.memory_limit_mb:g}; at least {DEFAULTS.min_memory_limit_mb:g}; "
                   "0 for none)")
    add_registration_options(p)
    p.add_argument("--out", default="reports", metavar="DIR", help="where the run folder goes (default: reports)")
    p.add_argument("--no-qhull", action="store_true", help="skip the Qhull agreement check")
    p.add_argument("--qhull-options", default=None, metavar="OPTIONS", help="as for `run`")
    p.add_argument("--no-shrink", action="store_true", help="do not minimise failing cases")
    p.add_argument("--junit", default=None, metavar="FILE", help="also write JUnit XML")
    p.add_argument("--baseline", default=None, metavar="RUN_OR_CORPUS",
                   help="an earlier run or a corpus folder: exit 1 only for failure groups new against it")
    p.add_argument("--save-corpus", default=None, metavar="DIR",
                   help="add the minimised new failures to this corpus folder")
    p.add_argument("--quiet", action="store_true", help="print only the report path and the exit summary line")
    p.set_defaults(handler=search_command)


def search_command(args: argparse.Namespace) -> int:
    """Build the seeds' sweep options and the search, run the pipeline with the search as its execute stage."""
    from ..pipeline import RunOptions, run
    from ..progress import progress_enabled
    from ..search import Search, SearchOptions
    from ..sweep import SweepOptions
    from ._run import parse_sizes, print_summary

    evaluations = args.evaluations
    if evaluations is None:
        evaluations = 400 if args.time_budget is None else 10**9
    search = SearchOptions(evaluations=evaluations, seeds=args.seeds, max_points=args.max_points,
                           time_budget=args.time_budget)
    sweep = SweepOptions(
        profile="quick", algorithms=tuple(args.algorithm), generators=tuple(args.generator), sphere=args.sphere,
        eps=args.eps, sizes=parse_sizes(args.sizes) if args.sizes is not None else None, seed=args.seed,
        workers=args.workers, timeout=args.timeout, qhull=not args.no_qhull, qhull_options=args.qhull_options,
        memory_limit_mb=args.memory_limit,
    )
    echo = None if args.quiet else (lambda line: print(line, file=sys.stderr, flush=True))
    executor = Search(search, sweep, echo=echo)
    options = RunOptions(
        sweep=sweep, out=args.out, shrink=not args.no_shrink, junit=args.junit, baseline=args.baseline,
        save_corpus=args.save_corpus, plugins=tuple(args.plugin), registration=registration_args(args),
        arguments={k: v for k, v in vars(args).items() if k != "handler"}, executor=executor,
    )
    the_run = run(options, echo=echo, progress=progress_enabled(sys.stderr, quiet=args.quiet))
    if not args.quiet:
        print(executor.summary())
    print_summary(the_run, args, quiet=args.quiet)
    return the_run.exit_status
