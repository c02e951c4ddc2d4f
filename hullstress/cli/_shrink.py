"""``python -m hullstress shrink``: minimise one failing case from a points file.

Exit status: 1 when the case fails (and, unless ``--no-shrink``, was shrunk
and written); 0 when it does not fail; 2 for bad arguments or input (an
unknown ``--check`` lists the valid ones); 130/143 when interrupted.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

from ..config import single_config
from ..errors import UsageError
from ..verdict import FAILED_CHECKS
from . import EXIT_STATUS_HELP
from ._common import add_registration_options, count, seconds

__all__ = ["add_parser", "shrink_command"]


def add_parser(sub: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    p = sub.add_parser(
        "shrink",
        help="minimise one failing case (points file + algorithm config)",
        description="Run one algorithm config on a points file; if it fails, shrink the points to a small "
        "set that fails with exactly the same signature (delete points, then fewer mantissa bits and "
        "power-of-two scaling) and write a failure folder with the minimal case, picture and reproduce command. "
        "1 means the case fails (and was shrunk), 0 that it does not fail. " + EXIT_STATUS_HELP,
    )
    p.add_argument("points_file", metavar="POINTS_FILE",
                   help="the failing case (.npy, .csv, .xyz, Qhull/rbox text; '-' reads stdin)")
    p.add_argument("--algorithm", required=True, metavar="NAME", help="the algorithm (see `list algorithms`)")
    p.add_argument("--sphere", choices=("off", "on"), default="off", help="sphere projection first (default off)")
    p.add_argument("--eps", choices=("scaled", "fixed"), default=None,
                   help="eps policy for algorithms taking eps (default: scaled for in-house algorithms, not passed "
                   "to plug-ins; ignored for algorithms without eps)")
    p.add_argument("--check", default=None, metavar="CHECK",
                   help="only shrink if the case fails this way: one of " + ", ".join(FAILED_CHECKS) + "; the shrink "
                   "keeps the case's whole signature")
    p.add_argument("--budget", type=seconds(), default=120.0, metavar="SECONDS",
                   help="wall-clock safety net (default 120): the result then depends on the machine's speed")
    p.add_argument("--max-calls", type=count(minimum=1), default=5000, metavar="N",
                   help="evaluation budget: judged calls (default 5000); the result depends only on it")
    p.add_argument("--timeout", type=seconds(), default=None, metavar="SECONDS",
                   help="per-call timeout of isolated calls (default 10)")
    p.add_argument("--no-shrink", action="store_true",
                   help="only run the case once and report; exit 1 if it fails (writes nothing)")
    p.add_argument("--raw", action="store_true",
                   help="load a .npy file as it is (non-finite values and odd shapes allowed, for bad-input cases)")
    p.add_argument("--dim", type=int, choices=(2, 3), default=None,
                   help="the case's dimension (default: the algorithm's)")
    add_registration_options(p)
    p.add_argument("--out", default="reports", metavar="DIR",
                   help="where the shrink folder goes (default: reports)")
    p.set_defaults(handler=shrink_command)


def _load(args: argparse.Namespace, dim: int):  # -> Case
    from ..case import Case
    from ..io import read_points

    path = Path(args.points_file)
    if args.raw:
        if path.suffix.lower() != ".npy":
            raise UsageError(f"--raw needs a .npy points file, got {args.points_file!r}")
        try:
            pts = np.load(path, allow_pickle=False)
        except (OSError, ValueError) as exc:
            raise UsageError(f"points file {args.points_file!r}: cannot load: {exc}") from None
        return Case(points=np.asarray(pts, dtype=np.float64), dim=dim, family="file",
                    params={"file": path.name}, source=str(path))
    return Case.from_points(read_points(path, dim=dim), family="file", params={"file": path.name},
                            source=str(path))


def shrink_command(args: argparse.Namespace) -> int:
    from .._registry import get_algorithm
    from ..report.failures import write_failure_folder
    from ..triage.stage import triage_one
    from ..report.writer import new_run_dir
    from ..triage import run_config, shrink, signature_of
    from ._common import registration_args

    if args.check is not None and args.check not in FAILED_CHECKS:
        from ..suggest import did_you_mean

        raise UsageError(f"--check {args.check!r} is not a failure hullstress knows"
                         f"{did_you_mean(args.check, FAILED_CHECKS)}; valid checks: " + ", ".join(FAILED_CHECKS))
    spec = get_algorithm(args.algorithm)
    dim = args.dim if args.dim is not None else spec.dim
    if dim != spec.dim:
        raise UsageError(f"--dim {dim} does not match algorithm {spec.name!r}, which takes {spec.dim}D points")
    config = single_config(spec, args.sphere, args.eps)
    case = _load(args, dim)
    row = run_config(case, config, timeout=args.timeout)
    sig = signature_of(row)
    if sig is None or (args.check is not None and sig.check != args.check):
        print(f"{config.label} on {case.n_points} points: {row.status}"
              + (f" ({sig.check}, not {args.check})" if sig is not None else "")
              + (f": {row.get('reason')}" if row.get("reason") else "") + " -- the failure does not reproduce")
        return 0
    print(f"{config.label} on {case.n_points} points: {row.status} ({sig.check}): {row.get('reason')}")
    if args.no_shrink:
        return 1
    result = shrink(case, config, sig, max_calls=args.max_calls, budget_seconds=args.budget, timeout=args.timeout)
    run_dir = new_run_dir(args.out, f"shrink-{time.strftime('%Y%m%d-%H%M%S')}-{spec.name}")
    rec = write_failure_folder(run_dir / "failures", triage_one(result, config, timeout=args.timeout),
                               timeout=args.timeout, registration=registration_args(args))
    state = "" if not result.exhausted else " (budget spent; may not be minimal)"
    print(f"shrunk {result.original_size} -> {result.minimal_size} points in {result.calls} evaluations, "
          f"{result.seconds:.1f} s{state}")
    if result.note and not result.reproduced:
        print(f"note: {result.note}", file=sys.stderr)
    print(f"minimal case: {rec.folder}")
    print(f"reproduce: {rec.command}")
    return 1 if result.reproduced else 0
