"""The command line: ``python -m hullstress <subcommand>``.

Exit status (DESIGN.md): 0 nothing (new) failed; 1 failures found; 2 usage or
input error (one line on stderr naming the offending value); 3 internal error;
130 interrupted (Ctrl-C or SIGTERM; the partial report is written first).
"""

from __future__ import annotations

import argparse
import importlib
import sys
from collections.abc import Sequence
from typing import NoReturn

from ..errors import UsageError

__all__ = ["main", "build_parser", "EXIT_OK", "EXIT_FAILURES", "EXIT_USAGE", "EXIT_INTERNAL", "EXIT_INTERRUPTED"]

EXIT_OK = 0
EXIT_FAILURES = 1
EXIT_USAGE = 2
EXIT_INTERNAL = 3
EXIT_INTERRUPTED = 130

#: Subcommand modules, in --help order.  Each defines ``add_parser(subparsers)``
#: which registers the subcommand and sets ``handler(args) -> int`` as its default.
SUBCOMMANDS = ("run", "replay", "list", "check", "shrink", "fuzz", "export", "findings")


class _Parser(argparse.ArgumentParser):
    """argparse with a one-line error and exit status 2 (its default prints usage too)."""

    def error(self, message: str) -> NoReturn:
        self.exit(EXIT_USAGE, f"{self.prog}: error: {message}\n")


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(
        prog="python -m hullstress",
        description="Robustness test harness and degeneracy fuzzer for convex hull algorithms.",
        epilog="Exit status: 0 nothing (new) failed, 1 failures found, 2 usage or input error, "
        "3 internal error, 130 interrupted (partial report written).",
    )
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)
    sub.required = True
    for name in SUBCOMMANDS:
        importlib.import_module(f"{__name__}._{name}").add_parser(sub)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line; returns the exit status (never raises on bad input)."""
    parser = build_parser()
    try:
        args = parser.parse_args(argv)
    except SystemExit as exc:  # --help, or argparse's one-line usage error
        return int(exc.code or 0) if not isinstance(exc.code, str) else EXIT_USAGE
    try:
        return int(args.handler(args))
    except UsageError as exc:
        print(f"hullstress: error: {exc}", file=sys.stderr)
        return EXIT_USAGE
    except KeyboardInterrupt:
        print("hullstress: interrupted", file=sys.stderr)
        return EXIT_INTERRUPTED
    except BrokenPipeError:
        return EXIT_OK
    except Exception as exc:  # an internal error: one line, plus where to look
        print(
            f"hullstress: internal error: {type(exc).__name__}: {exc} "
            "(set HULLSTRESS_DEBUG=1 for the traceback)",
            file=sys.stderr,
        )
        import os

        if os.environ.get("HULLSTRESS_DEBUG"):
            import traceback

            traceback.print_exc()
        return EXIT_INTERNAL
