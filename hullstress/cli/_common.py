"""What several subcommands share: registration options and number checks for argparse.

* :func:`add_registration_options` / :func:`load_registrations`: ``--plugin``,
  ``--exec NAME=COMMAND`` and (where outputs are judged) ``--clockwise NAME``.
* ``type=`` converters (:func:`seconds`, :func:`mebibytes`, :func:`count`):
  a bad number is an argparse error, so it is refused before anything loads,
  on one line naming the option and the value (exit status 2).
"""

from __future__ import annotations

import argparse
import math
from collections.abc import Callable

__all__ = ["add_registration_options", "load_registrations", "seconds", "mebibytes", "count", "registration_args",
           "PROCESS"]


class _Process:
    """Whether the command line owns this process (the ``hullstress`` program, ``python -m hullstress``).

    Only then does ``run`` lower the process's CPU priority for its workers
    (:attr:`hullstress.pipeline.RunOptions.yield_cpu`); :func:`hullstress.cli.main`
    called from other code (a test, a script) leaves its caller's priority alone.
    """

    owned = False


PROCESS = _Process()


def _finite(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number, got {text!r}") from None
    if not math.isfinite(value):
        raise argparse.ArgumentTypeError(f"must be a finite number, got {text!r}")
    return value


def seconds(*, zero: bool = False) -> Callable[[str], float]:
    """A converter for a duration in seconds: finite and positive (or 0 when ``zero``)."""

    def convert(text: str) -> float:
        value = _finite(text)
        if value < 0 or (value == 0 and not zero):
            raise argparse.ArgumentTypeError(
                f"must be {'0 or more' if zero else 'a positive number of'} seconds, got {text!r}")
        return value

    convert.__name__ = "seconds"  # argparse names the type in its own messages
    return convert


def mebibytes(text: str) -> float:
    """A memory limit in MiB: 0 (no limit) or a finite number of at least ``DEFAULTS.min_memory_limit_mb``."""
    from ..options import DEFAULTS

    value = _finite(text)
    if value < 0:
        raise argparse.ArgumentTypeError(f"must be 0 (no limit) or a positive number of MiB, got {text!r}")
    if 0 < value < DEFAULTS.min_memory_limit_mb:
        raise argparse.ArgumentTypeError(
            f"{text!r} MiB is below the minimum of {DEFAULTS.min_memory_limit_mb:g} MiB that a worker needs beyond "
            "its libraries to judge a case (0 for no limit)")
    return value


def count(*, minimum: int) -> Callable[[str], int]:
    """A converter for an integer of at least ``minimum``."""

    def convert(text: str) -> int:
        try:
            value = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"expected an integer, got {text!r}") from None
        if value < minimum:
            raise argparse.ArgumentTypeError(f"must be at least {minimum}, got {text!r}")
        return value

    convert.__name__ = "count"
    return convert


def add_registration_options(parser: argparse.ArgumentParser, *, clockwise: bool = True) -> None:
    """Add ``--plugin``, ``--exec`` and (with ``clockwise``) ``--clockwise`` to ``parser``."""
    parser.add_argument("--plugin", action="append", default=[], metavar="MODULE_OR_FILE",
                        help="import a module or .py file that registers algorithms or generators (repeatable)")
    parser.add_argument("--exec", action="append", default=[], metavar="NAME=COMMAND", dest="exec_specs",
                        help="register a program in any language as algorithm NAME (repeatable): it reads "
                        "Qhull-format points on stdin and writes its hull on stdout; NAME[dim=2|3,output=i|Fx|off,"
                        "mode=spawn|persistent] sets the dimension (default 3), the output format (default i: "
                        "Qhull's facet indices; Fx: 2D extreme points; off: OFF) and the mode (default spawn: one "
                        "process per case; persistent: one per worker, answering case after case, see "
                        "docs/executables.md), e.g. qconvex='qconvex Qt i'")
    if clockwise:
        parser.add_argument("--clockwise", action="append", default=[], metavar="NAME", dest="clockwise_names",
                            help="algorithm NAME writes faces clockwise seen from outside (as Qhull's 3D 'i' "
                            "does); reverse them before checking (repeatable)")
        parser.add_argument("--contract", action="append", default=[], metavar="NAME=CONTRACT",
                            dest="contract_specs",
                            help="judge algorithm NAME against its declared contract (repeatable): 'strict' "
                            "(only extreme points as vertices), 'lenient' (the default) or KEY=VALUE items "
                            "(vertices=boundary|extreme, faces=any|triangles, flat=either|raise|lower-dim, "
                            "orientation=ccw|cw), e.g. --contract 'my-hull=strict,flat=raise'")


def load_registrations(args: argparse.Namespace) -> None:
    """Import the plug-ins, register the executables and mark the clockwise algorithms.

    Raises
    ------
    UsageError
        A plug-in that cannot be imported, a malformed ``--exec``, a program
        not found, a name registered twice, an unknown ``--clockwise`` name.
    """
    from .._registry import probe_executable, register_executable, set_clockwise, set_contract
    from ..errors import UsageError
    from ..adapters.executable import parse_exec_spec
    from ..plugins import load_plugin

    for spec in getattr(args, "plugin", []):
        load_plugin(spec)
    names = []
    for text in getattr(args, "exec_specs", []):
        name, command, options = parse_exec_spec(text)
        register_executable(name, command, dim=options["dim"], output=options["output"], mode=options["mode"],
                            probe=False)
        names.append(name)
    for name in getattr(args, "clockwise_names", []):
        set_clockwise(name)
    for text in getattr(args, "contract_specs", []):
        name, sep, contract = text.partition("=")
        if not sep or not name.strip():
            raise UsageError(f"--contract {text!r}: expected NAME=CONTRACT (e.g. my-hull=strict)")
        set_contract(name.strip(), contract)
    for name in names:  # every option checked: now run each program once (refusing bad ones before the sweep)
        probe_executable(name)


def registration_args(args: argparse.Namespace) -> tuple[str, ...]:
    """The registration options as command-line arguments (for reproduce commands)."""
    out: list[str] = []
    for spec in getattr(args, "plugin", []):
        out += ["--plugin", spec]
    for text in getattr(args, "exec_specs", []):
        out += ["--exec", text]
    for name in getattr(args, "clockwise_names", []):
        out += ["--clockwise", name]
    for text in getattr(args, "contract_specs", []):
        out += ["--contract", text]
    return tuple(out)
