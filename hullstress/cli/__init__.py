"""The command line: ``python -m hullstress <subcommand>``.

Exit status (every command; docs/design.md, :class:`hullstress.errors.ExitStatus`):

===  =======================================================================
0    nothing (new) failed
1    failures found (with ``--baseline``: new failure groups)
2    usage or input error: one line on stderr naming the offending value
3    internal error (a bug of hullstress; ``HULLSTRESS_DEBUG=1`` shows the traceback)
4    environment failure: a full disk, a read-only or unwritable output path;
     one line naming it, and what was computed before stays on disk
5    no work done: no call ran (a time budget spent before the first call,
     an empty corpus), like pytest's 5
130  interrupted by SIGINT (Ctrl-C), after writing the partial report
143  interrupted by SIGTERM, after writing the partial report
===  =======================================================================

This package only parses arguments and prints; the work is done by
:mod:`hullstress.pipeline` and the stage modules.
"""

from __future__ import annotations

import argparse
import importlib
import os
import signal
import sys
import threading
from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from typing import NoReturn

from ..errors import EnvironmentFailure, ExitStatus, Interrupted, UsageError, is_environment_error
from ..records import Origin

__all__ = [
    "main",
    "console_main",
    "build_parser",
    "EXIT_OK",
    "EXIT_FAILURES",
    "EXIT_USAGE",
    "EXIT_INTERNAL",
    "EXIT_ENVIRONMENT",
    "EXIT_NO_WORK",
    "EXIT_INTERRUPTED",
    "EXIT_TERMINATED",
    "EXIT_STATUS_HELP",
]

EXIT_OK = int(ExitStatus.OK)
EXIT_FAILURES = int(ExitStatus.FAILURES)
EXIT_USAGE = int(ExitStatus.USAGE)
EXIT_INTERNAL = int(ExitStatus.INTERNAL)
EXIT_ENVIRONMENT = int(ExitStatus.ENVIRONMENT)
EXIT_NO_WORK = int(ExitStatus.NO_WORK)
EXIT_INTERRUPTED = int(ExitStatus.SIGINT)
EXIT_TERMINATED = int(ExitStatus.SIGTERM)

#: The exit statuses as ``--help`` prints them.
EXIT_STATUS_HELP = (
    "Exit status: 0 nothing (new) failed, 1 failures found, 2 usage or input error, 3 internal error, "
    "4 environment failure (full disk, unwritable output path), 5 no work done (no call ran), "
    "130 interrupted by Ctrl-C, 143 by SIGTERM (partial report written)."
)

#: Subcommand modules, in --help order.  Each defines ``add_parser(subparsers)``
#: which registers the subcommand and sets ``handler(args) -> int`` as its default.
SUBCOMMANDS = ("run", "report", "search", "reproduce", "replay", "list", "check", "shrink", "fuzz", "export", "findings")


class _Parser(argparse.ArgumentParser):
    """argparse with a one-line error and exit status 2 (its default prints usage too)."""

    def error(self, message: str) -> NoReturn:
        self.exit(EXIT_USAGE, f"{self.prog}: error: {message}\n")

    def _check_value(self, action: argparse.Action, value: object) -> None:
        """argparse's check of a fixed choice (a subcommand, --profile, --sphere ...), with a "did you mean"."""
        try:
            super()._check_value(action, value)  # type: ignore[misc]
        except argparse.ArgumentError as exc:
            from ..suggest import did_you_mean

            exc.message += did_you_mean(value, [str(c) for c in action.choices or ()])
            raise


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(
        prog="python -m hullstress",
        description="Robustness test harness and degeneracy fuzzer for convex hull algorithms.",
        epilog=EXIT_STATUS_HELP,
    )
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)
    sub.required = True
    for name in SUBCOMMANDS:
        importlib.import_module(f"{__name__}._{name}").add_parser(sub)
    return parser


def _raise_interrupted(signum: int, frame: object) -> None:
    raise Interrupted(signum)


@contextmanager
def _signals_interrupt() -> Iterator[None]:
    """SIGTERM (like SIGINT) raises :class:`Interrupted` in every command, so it ends with 143 and a message.

    ``run`` installs its own handlers for the duration of the pipeline (which
    finish the report first); this covers everything else.
    """
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = {s: signal.signal(s, _raise_interrupted) for s in (signal.SIGINT, signal.SIGTERM)}
    try:
        yield
    finally:
        for s, h in previous.items():
            signal.signal(s, h)


@contextmanager
def _registrations(args: argparse.Namespace) -> Iterator[None]:
    """Load ``--plugin``/``--exec``/``--clockwise`` for the command; forget the latter two afterwards.

    Undoing matters only when :func:`main` runs several times in one process
    (tests, notebooks): a command's programs and flags must not leak into the next.
    """
    from .._registry import ALGORITHMS
    from ._common import load_registrations

    if not (getattr(args, "exec_specs", None) or getattr(args, "clockwise_names", None)
            or getattr(args, "contract_specs", None)):
        load_registrations(args)  # plug-ins only: nothing to undo (and no need to load the built-ins)
        yield
        return
    before = {name: ALGORITHMS.get(name) for name in ALGORITHMS.names()}
    try:
        load_registrations(args)
        yield
    finally:
        for name in ALGORITHMS.names():
            old = before.get(name)
            spec = ALGORITHMS.get(name)
            if old is None and spec.origin == Origin.EXECUTABLE:
                ALGORITHMS.remove(name)
            elif old is not None and (old.clockwise != spec.clockwise or old.contract != spec.contract):
                ALGORITHMS.replace(old)


def _error(message: str) -> None:
    print(f"hullstress: error: {message}", file=sys.stderr)


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line; returns the exit status (never raises on bad input)."""
    from ..plugins import shadowed_message, shadowing_folder

    shadow = shadowing_folder()
    if shadow is not None:  # nothing would work: `from hullstress import ...` finds an empty folder
        _error(shadowed_message(shadow))
        return EXIT_USAGE
    parser = build_parser()
    try:
        args = parser.parse_args(argv)
    except SystemExit as exc:  # --help, or argparse's one-line usage error
        return int(exc.code or 0) if not isinstance(exc.code, str) else EXIT_USAGE
    try:
        with _signals_interrupt(), _registrations(args):
            return int(args.handler(args))
    except UsageError as exc:
        _error(str(exc))
        return EXIT_USAGE
    except EnvironmentFailure as exc:
        _error(str(exc))
        return EXIT_ENVIRONMENT
    except KeyboardInterrupt as exc:
        status = exc.exit_status if isinstance(exc, Interrupted) else EXIT_INTERRUPTED
        name = "SIGTERM" if status == EXIT_TERMINATED else "SIGINT"
        print(f"hullstress: interrupted ({name})", file=sys.stderr)
        return status
    except BrokenPipeError:
        return EXIT_OK
    except OSError as exc:
        if is_environment_error(exc):  # an output path the dedicated handlers did not name
            where = exc.filename if exc.filename is not None else "an output file"
            _error(f"cannot write {str(where)!r}: {exc.strerror or exc}")
            return EXIT_ENVIRONMENT
        return _internal(exc)
    except Exception as exc:
        return _internal(exc)


def console_main() -> NoReturn:
    """The ``hullstress`` program and ``python -m hullstress``: :func:`main`, then a prompt exit.

    Tearing down an interpreter that has loaded NumPy, SciPy, pandas and
    matplotlib spends about a second collecting garbage, which an interrupted
    run (it promises to stop within 2 s) cannot afford: after the output is
    flushed and the ``atexit`` handlers ran (worker pools are closed there),
    the process leaves at once.
    """
    import atexit

    from ._common import PROCESS

    PROCESS.owned = True
    code = main()
    for stream in (sys.stdout, sys.stderr):
        try:
            stream.flush()
        except (OSError, ValueError):
            pass
    atexit._run_exitfuncs()
    for stream in (sys.stdout, sys.stderr):
        try:
            stream.flush()
        except (OSError, ValueError):
            pass
    os._exit(code)


def _internal(exc: BaseException) -> int:
    """An internal error: one line, plus where to look."""
    print(
        f"hullstress: internal error: {type(exc).__name__}: {exc} "
        "(set HULLSTRESS_DEBUG=1 for the traceback)",
        file=sys.stderr,
    )
    if os.environ.get("HULLSTRESS_DEBUG"):
        import traceback

        traceback.print_exc()
    return EXIT_INTERNAL
