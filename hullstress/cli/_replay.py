"""``python -m hullstress replay [DIR]``: re-run the regression corpus against every algorithm config."""

from __future__ import annotations

import argparse
import sys

from ..corpus import DEFAULT_CORPUS
from ..errors import UsageError
from . import EXIT_NO_WORK, EXIT_STATUS_HELP
from ._common import add_registration_options, count, seconds

__all__ = ["add_parser", "replay_command"]


def add_parser(sub: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    p = sub.add_parser(
        "replay",
        help="re-run the regression corpus and compare with recorded expectations",
        description="Replay every corpus entry against every algorithm config of its dimension and compare "
        "each call's verdict with the recorded one: still-failing (the same failure: exit 0), fixed (passes "
        "now: exit 0), changed (fails another way: exit 1), new-failure (recorded passing, fails now: exit 1). "
        "Exit status: 1 if any call changed or newly fails; otherwise 2 if a corpus "
        "file could not be read (the others still replay); otherwise 5 if nothing was replayed (an empty "
        "corpus, or no algorithm of its dimensions); otherwise 0. " + EXIT_STATUS_HELP,
    )
    p.add_argument("corpus", nargs="?", default=str(DEFAULT_CORPUS), metavar="DIR",
                   help=f"corpus folder or one corpus file (default: {DEFAULT_CORPUS})")
    p.add_argument("--algorithm", action="append", default=[], metavar="NAME", help="replay only this algorithm (repeatable)")
    add_registration_options(p)
    p.add_argument("--accept", action="store_true",
                   help="record the current verdicts as the new expectations (after a fix or a reviewed change); "
                   "an entry whose failure group no longer fails that way is marked fixed and kept as a passing "
                   "regression case")
    p.add_argument("--workers", type=count(minimum=0), default=None, metavar="N",
                   help="worker processes (default: all cores; 0 in-process)")
    p.add_argument("--timeout", type=seconds(), default=10.0, metavar="SECONDS", help="per-call timeout (default 10)")
    p.add_argument("--verbose", action="store_true", help="list every (entry, config) outcome, not only the changes")
    p.set_defaults(handler=replay_command)


def replay_command(args: argparse.Namespace) -> int:
    import os

    from ..corpus.replay import OUTCOMES, REGRESSIONS, replay_corpus

    if not os.path.exists(args.corpus):
        raise UsageError(f"corpus {args.corpus!r}: no such file or directory")
    workers = args.workers if args.workers is not None else (os.cpu_count() or 1)
    result = replay_corpus(args.corpus, algorithm_names=tuple(args.algorithm), workers=workers,
                           timeout=args.timeout, accept=args.accept)
    for err in result.errors:
        print(f"hullstress: error: {err}", file=sys.stderr)
    table = result.table
    shown = table if args.verbose else table[table["outcome"] != "ok"]
    for rec in shown.itertuples(index=False):
        expected = rec.expected or "(nothing recorded)"
        print(f"{rec.outcome:<13} {rec.entry} {rec.family:<22} {rec.config:<40} expected {expected}; got {rec.actual}")
    per_entry = result.per_entry()
    counts = table["outcome"].value_counts()
    regress_entries = int((per_entry[list(REGRESSIONS)].sum(axis=1) > 0).sum()) if len(per_entry) else 0
    print(
        f"replayed {len(per_entry)} entries x configs = {len(table)} calls: "
        + ", ".join(f"{counts.get(k, 0)} {k}" for k in OUTCOMES)
        + f"; {regress_entries} entries with regressions; {len(result.errors)} unreadable files"
    )
    if result.accepted:
        print(f"accepted current verdicts as expectations in {len(result.accepted)} files")
        return 0
    if counts.get("fixed", 0):
        print(f"hint: {counts.get('fixed', 0)} recorded failures pass now: `python -m hullstress replay "
              f"{args.corpus} --accept` records it (the entries stay, as passing regression cases)", file=sys.stderr)
    if regress_entries:
        return 1
    if result.errors:
        return 2
    if not len(table):
        print(f"hullstress: no work done: nothing to replay in {args.corpus!r} "
              "(no corpus entry, or no selected algorithm of its entries' dimensions)", file=sys.stderr)
        return EXIT_NO_WORK
    return 0
