"""The exception tree of hullstress.

Every error the harness raises on purpose derives from :class:`HullstressError`.
The command line maps :class:`UsageError` (and its subclasses) to exit status 2
and :class:`EnvironmentFailure` to exit status 4, each with the message on one
line; anything else escaping is an internal error (exit status 3).
"""

from __future__ import annotations

import errno
import re
import signal
from enum import IntEnum
from types import TracebackType

__all__ = [
    "ExitStatus",
    "Interrupted",
    "ENVIRONMENT_ERRNOS",
    "HullstressError",
    "UsageError",
    "UnknownNameError",
    "DuplicateNameError",
    "InputFileError",
    "ContractViolation",
    "AlgorithmStepLimit",
    "CorpusError",
    "GeneratorValueError",
    "EnvironmentFailure",
    "CodeCrashed",
    "is_environment_error",
    "one_line",
    "code_frame",
]


class ExitStatus(IntEnum):
    """The exit statuses of every command (docs/design.md, "Exit statuses")."""

    #: Nothing (new) failed.
    OK = 0
    #: Failures found (with a baseline: new failure groups).
    FAILURES = 1
    #: A usage or input error: one line on stderr naming the offending value.
    USAGE = 2
    #: A bug of hullstress itself (never a user's input or environment).
    INTERNAL = 3
    #: The environment refused an output: a full disk, a read-only or unwritable
    #: path (one line naming it); what was computed before stays on disk.
    ENVIRONMENT = 4
    #: Nothing was done: no call ran (a time budget spent before the first call,
    #: an empty corpus), as pytest's 5 for "no tests collected".
    NO_WORK = 5
    #: Interrupted by SIGINT (Ctrl-C) or SIGTERM, after writing the partial report.
    SIGINT = 130
    SIGTERM = 143


#: errno values that mean "the environment refused" (exit status 4), not "you gave a wrong path" (2).
ENVIRONMENT_ERRNOS = frozenset(
    getattr(errno, name) for name in ("ENOSPC", "EDQUOT", "EFBIG", "EROFS", "EACCES", "EPERM", "EIO", "ETXTBSY")
    if hasattr(errno, name)
)


class Interrupted(KeyboardInterrupt):
    """A SIGINT or SIGTERM arrived while a stage was running (it stops the stage)."""

    def __init__(self, signum: int) -> None:
        super().__init__(signal.Signals(signum).name)
        self.signum = signum

    @property
    def exit_status(self) -> int:
        """130 for SIGINT, 143 for SIGTERM (the shell's 128 + signal number)."""
        return int(ExitStatus.SIGTERM if self.signum == signal.SIGTERM else ExitStatus.SIGINT)


class HullstressError(Exception):
    """Root of every error raised by hullstress itself."""


class UsageError(HullstressError):
    """A bad argument or option value given by the user (exit status 2)."""


class UnknownNameError(UsageError, KeyError):
    """A registry lookup for a name that is not registered."""

    def __str__(self) -> str:  # KeyError would quote the message
        return str(self.args[0]) if self.args else ""


class DuplicateNameError(UsageError):
    """A second, different object registered under a name already taken (a usage error: exit status 2)."""


class InputFileError(UsageError):
    """A points or faces file that is missing, unreadable or malformed."""


class ContractViolation(HullstressError):
    """An algorithm's output breaks the output contract of docs/design.md."""


class AlgorithmStepLimit(HullstressError):
    """An in-house algorithm hit its iteration guard (it would loop forever)."""


class CorpusError(HullstressError):
    """A regression-corpus file that cannot be read or written."""


class GeneratorValueError(UsageError, ValueError):
    """A generator argument out of range, e.g. too few points for the family (also a ValueError)."""


class EnvironmentFailure(HullstressError):
    """The environment refused an output: a full disk, a read-only or unwritable path (exit status 4)."""

    @classmethod
    def writing(cls, path: object, exc: OSError, what: str = "") -> "EnvironmentFailure":
        """``cannot write <what> '<path>': <reason>`` from the OSError that refused it."""
        label = f"{what} " if what else ""
        return cls(f"cannot write {label}{str(path)!r}: {exc.strerror or exc}")


def is_environment_error(exc: BaseException) -> bool:
    """An OSError that says the disk is full or a path is not writable (exit status 4)."""
    return isinstance(exc, OSError) and exc.errno in ENVIRONMENT_ERRNOS


class CodeCrashed(HullstressError):
    """The code under test died by a signal (an executable killed by SIGSEGV, say): its row is a ``crash``."""


def one_line(exc: BaseException) -> str:
    """``TypeName: message`` on one line: the form of every ``reason`` in a results table.

    Qhull appends "While executing: ... run-id <random>" to its errors; that
    tail differs between runs and would make identical runs' tables differ, so
    it is cut.

    Examples
    --------
    >>> one_line(ValueError("need\\n3 points"))
    'ValueError: need 3 points'
    """
    text = re.split(r"\s+While executing:", str(exc), maxsplit=1)[0]
    text = " ".join(text.split())
    return f"{type(exc).__name__}: {text}" if text else type(exc).__name__


#: Modules of hullstress that are themselves under test: the in-house
#: algorithms, the library adapters and the sphere method's preprocessing.
#: Every other hullstress module is the harness.
_UNDER_TEST = ("hullstress.algorithms", "hullstress.adapters", "hullstress.sphere")


def _within(module: str, package: str) -> bool:
    return module == package or module.startswith(package + ".")


def code_frame(tb: TracebackType | None, owner: str) -> str:
    """Where the code under test raised: ``module:line in function`` of its innermost frame.

    Parameters
    ----------
    tb : traceback or None
        The caught exception's ``__traceback__``.
    owner : str
        ``__module__`` of the algorithm's function; its package (the module
        itself for a top-level module) is the code under test.

    Returns
    -------
    str
        The innermost frame in ``owner``'s package; failing that, the
        innermost in a hullstress module under test (algorithms, adapters,
        the sphere method); failing that, the innermost frame outside
        hullstress's harness; ``""`` when there is none.  Module names, not
        file paths, so the text is the same wherever the package is installed.

    Examples
    --------
    >>> def buggy():
    ...     return 1 / 0
    >>> try:
    ...     buggy()
    ... except ZeroDivisionError as exc:
    ...     code_frame(exc.__traceback__, __name__).split(" in ")[1]
    'buggy'
    """
    frames = []  # (frame, line) from the outermost to the innermost
    while tb is not None:
        frames.append((tb.tb_frame, tb.tb_lineno))
        tb = tb.tb_next
    package = owner.rsplit(".", 1)[0] if "." in owner else owner
    if package == "hullstress":  # an algorithm defined in a hullstress module outside the usual packages
        package = owner

    def module_of(frame: object) -> str:
        return str(getattr(frame, "f_globals", {}).get("__name__", "") or "")

    preferences = (
        lambda m: _within(m, package),
        lambda m: any(_within(m, p) for p in _UNDER_TEST),
        lambda m: not _within(m, "hullstress"),
    )
    for wanted in preferences:
        for frame, line in reversed(frames):
            module = module_of(frame)
            if module and wanted(module):
                code = frame.f_code
                name = getattr(code, "co_qualname", code.co_name)
                return f"{module}:{line} in {name}"
    return ""
