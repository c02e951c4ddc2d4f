"""A program in any language as a hull algorithm: points on stdin, its hull on stdout.

``--exec NAME='COMMAND'`` and :func:`hullstress.registry.register_executable`
register an :class:`ExecutableHull`, a picklable callable that worker
processes run like any Python algorithm, so the program gets the same
isolation: the worker's per-call timeout (the parent kills the worker, and
the program with it), its memory limit (``RLIMIT_AS`` is inherited) and its
crash handling.  One call:

1. writes the points in Qhull's input format (:func:`hullstress.qhull_format.format_points`:
   the exact doubles, as ``rbox`` would) on the program's stdin;
2. waits for it; what it wrote on stderr is passed on to this process's
   stderr, where the runner captures it per call (the row's ``call_output``);
3. a death by a signal raises :class:`~hullstress.errors.CodeCrashed` (a
   ``crash`` row); a non-zero exit raises :class:`ExecutableFailed` (an
   ``error`` row, ``rejected`` on degenerate input, as an exception would be);
   both reasons end with the tail of the program's stderr;
4. parses stdout as Qhull ``i``, ``Fx`` or OFF (:func:`hullstress.qhull_format.parse_hull`);
   output it cannot read raises :class:`~hullstress.errors.ContractViolation`
   naming the line (a ``fail``).

The program runs in a session of its own (a Ctrl-C in the terminal is the
harness's to handle, not the program's) and, on Linux, is killed when the
worker that started it dies (``PR_SET_PDEATHSIG``), so a hung program never
outlives its timeout.  Programs it starts itself are its own business.
"""

from __future__ import annotations

import os
import re
import shlex
import shutil
import signal
import subprocess
import sys
import threading
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from ..errors import CodeCrashed, UsageError

__all__ = ["ExecutableHull", "ExecutableFailed", "OUTPUT_FORMATS", "locate_program", "parse_exec_spec"]

#: What a program may write: Qhull's ``i`` or ``Fx``, or OFF.
OUTPUT_FORMATS = ("i", "Fx", "off")
#: Characters of the program's stderr kept in a row's reason.
STDERR_TAIL = 300
#: Options of ``--exec NAME[OPTIONS]=COMMAND``, with their allowed values.
EXEC_OPTIONS = {"dim": ("2", "3"), "output": OUTPUT_FORMATS}

# Qhull ends its errors with "While executing: ... run-id <random>": different in every run.
_QHULL_TRAILER = re.compile(r"\s*While executing:.*", re.DOTALL)


class ExecutableFailed(Exception):
    """The program exited with a non-zero status (the executable's way of raising)."""


def locate_program(name: str) -> str | None:
    """The absolute path of program ``name``, or None when it cannot be found.

    Looks on ``PATH``, then beside this Python (a virtual environment's
    ``bin`` that is not activated).  ``pip install cmeel-qhull`` installs
    Qhull's ``qconvex`` and ``rbox`` as thin Python wrappers around the real
    programs in the ``cmeel`` prefix; a wrapper is replaced by the program it
    wraps (it starts faster, and a signal reaches the program itself).

    Examples
    --------
    >>> locate_program("sh") is not None
    True
    >>> locate_program("no-such-program-xyz") is None
    True
    """
    if os.sep in name or (os.altsep and os.altsep in name):
        path = Path(name)
        return os.path.abspath(path) if path.is_file() and os.access(path, os.X_OK) else None
    found = shutil.which(name) or shutil.which(name, path=str(Path(sys.executable).parent))
    if found is None:
        return None
    # Absolute but not resolved: a virtual environment's python is a symlink that must stay one.
    return _unwrapped(Path(found)) or os.path.abspath(found)


def _unwrapped(wrapper: Path) -> str | None:
    """The program a cmeel wrapper script runs, or None when ``wrapper`` is not one."""
    try:
        with open(wrapper, "rb") as fh:
            if b"cmeel_run" not in fh.read(512):
                return None
    except OSError:
        return None
    import importlib.util

    spec = importlib.util.find_spec("cmeel")
    if spec is None or spec.origin is None:
        return None
    candidate = Path(spec.origin).parent.parent / "cmeel.prefix" / "bin" / wrapper.name
    return str(candidate) if candidate.is_file() and os.access(candidate, os.X_OK) else None


@dataclass(frozen=True)
class ExecutableHull:
    """A registered program: what to run, on which points, and what it writes.

    Attributes
    ----------
    argv : tuple of str
        The command as given, split like a shell would (``("qconvex", "Qt", "i")``).
    program : str
        ``argv[0]`` resolved to an absolute path at registration.
    dim : {2, 3}
    output : {"i", "Fx", "off"}
    """

    argv: tuple[str, ...]
    program: str
    dim: int
    output: str

    @classmethod
    def from_command(cls, command: str | Sequence[str], *, dim: int, output: str = "i") -> "ExecutableHull":
        """Validate and resolve a command (raises :class:`UsageError` with the reason on one line)."""
        if isinstance(command, str):
            try:
                argv = tuple(shlex.split(command))
            except ValueError as exc:
                raise UsageError(f"command {command!r}: {exc}") from None
        else:
            argv = tuple(str(a) for a in command)
        if not argv:
            raise UsageError(f"command must name a program, got {command!r}")
        if output not in OUTPUT_FORMATS:
            raise UsageError(f"output must be one of {', '.join(OUTPUT_FORMATS)}, got {output!r}")
        if output == "Fx" and dim != 2:
            raise UsageError("output 'Fx' lists extreme points, a hull only in 2D: use 'i' or 'off' for dim 3")
        program = locate_program(argv[0])
        if program is None:
            raise UsageError(f"command {shlex.join(argv)!r}: program {argv[0]!r} not found on PATH")
        return cls(argv=argv, program=program, dim=int(dim), output=output)

    @property
    def command(self) -> str:
        """The command line as a shell would read it."""
        return shlex.join(self.argv)

    @property
    def registry_label(self) -> str:
        """How the registry names this entry in a duplicate-name error."""
        return f"the program {self.command!r}"

    def describe(self, *, clockwise: bool = False) -> str:
        """One line for ``list algorithms``: the command and its output format."""
        name = "OFF" if self.output == "off" else f"Qhull {self.output}"
        return f"{self.command} ({name} output{', clockwise' if clockwise else ''})"

    def __call__(self, points: Any) -> Any:
        return run_program(self, points)


def _stderr_tail(raw: bytes) -> str:
    text = _QHULL_TRAILER.sub("", raw.decode("utf-8", errors="replace"))
    text = " ".join(text.split())
    return text if len(text) <= STDERR_TAIL else "..." + text[-STDERR_TAIL:]


_libc: Any = None


def _die_with_worker() -> None:
    """In the child before exec: be killed when the worker that started us dies (Linux)."""
    if _libc is not None:
        _libc.prctl(1, int(signal.SIGKILL), 0, 0, 0)  # PR_SET_PDEATHSIG


def _preexec() -> Any:
    """The pre-exec hook, only where it is safe: Linux, and a single-threaded process."""
    global _libc
    if not sys.platform.startswith("linux") or threading.active_count() > 1:
        return None  # forking with threads and running Python before exec can deadlock
    if _libc is None:
        try:
            import ctypes

            _libc = ctypes.CDLL(None, use_errno=True)
        except OSError:
            return None
    return _die_with_worker


def run_program(hull: ExecutableHull, points: Any) -> Any:
    """Run ``hull``'s program on ``points`` once and return its raw faces.

    Raises
    ------
    CodeCrashed
        The program was killed by a signal.
    ExecutableFailed
        It exited with a non-zero status.
    ContractViolation
        Its output cannot be read (naming the line).
    ValueError
        The points cannot be given to the program: not an ``(n, dim)`` array,
        or fewer points than dimensions (Qhull's format cannot say that).
    """
    import numpy as np

    from ..qhull_format import format_points, parse_hull

    pts = np.asarray(points)
    if pts.ndim != 2 or pts.shape[1] != hull.dim:
        raise ValueError(f"points of shape {pts.shape} are not {hull.dim}D points: not given to {hull.argv[0]}")
    if 0 < len(pts) < hull.dim:
        # Qhull's format reads the smaller of its two header numbers as the dimension.
        raise ValueError(f"Qhull's input format cannot say {len(pts)} points in {hull.dim}D "
                         "(it reads the smaller header number as the dimension): not given to " + hull.argv[0])
    data = format_points(pts).encode("ascii")
    proc = subprocess.run(
        [hull.program, *hull.argv[1:]], input=data, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
        start_new_session=True, preexec_fn=_preexec(), check=False,
    )
    if proc.stderr:
        _forward(proc.stderr)
    tail = _stderr_tail(proc.stderr)
    said = f"; stderr: {tail}" if tail else "; no stderr"
    if proc.returncode < 0:
        try:
            name = signal.Signals(-proc.returncode).name
        except ValueError:
            name = "unknown signal"
        raise CodeCrashed(f"{hull.argv[0]} killed by signal {-proc.returncode} ({name}){said}")
    if proc.returncode > 0:
        raise ExecutableFailed(f"{hull.argv[0]} exited with code {proc.returncode}{said}")
    return parse_hull(proc.stdout.decode("utf-8", errors="replace"), hull.output, pts)


def _forward(raw: bytes) -> None:
    """Pass the program's stderr on to ours (fd 2), where the runner captures each call's output."""
    try:
        sys.stderr.flush()
        os.write(2, raw)
    except OSError:
        pass  # a closed stderr must not turn the call into an error


def parse_exec_spec(text: str) -> tuple[str, str, dict[str, Any]]:
    """Split an ``--exec`` value ``NAME[OPTIONS]=COMMAND`` into name, command and options.

    ``OPTIONS`` is a comma-separated list of ``dim=2|3`` (default 3) and
    ``output=i|Fx|off`` (default ``i``).

    Raises
    ------
    UsageError
        Naming the value and what is wrong with it.

    Examples
    --------
    >>> parse_exec_spec("qhull2[dim=2,output=Fx]=qconvex Fx")
    ('qhull2', 'qconvex Fx', {'dim': 2, 'output': 'Fx'})
    >>> parse_exec_spec("qconvex")
    Traceback (most recent call last):
    ...
    hullstress.errors.UsageError: --exec 'qconvex': expected NAME=COMMAND (e.g. qconvex='qconvex Qt i')
    """
    match = re.fullmatch(r"\s*([^\[\]=\s]+)\s*(?:\[([^\]]*)\])?\s*=(.*)", text, flags=re.DOTALL)
    if match is None or not match.group(3).strip():
        raise UsageError(f"--exec {text!r}: expected NAME=COMMAND (e.g. qconvex='qconvex Qt i')")
    name, option_text, command = match.group(1), match.group(2) or "", match.group(3)
    options: dict[str, Any] = {"dim": 3, "output": "i"}
    for item in filter(None, (o.strip() for o in option_text.split(","))):
        key, _, value = item.partition("=")
        key, value = key.strip(), value.strip()
        if key not in EXEC_OPTIONS:
            raise UsageError(f"--exec {text!r}: unknown option {key!r}; valid options: "
                             + ", ".join(f"{k}={'|'.join(v)}" for k, v in EXEC_OPTIONS.items()))
        if value not in EXEC_OPTIONS[key]:
            raise UsageError(f"--exec {text!r}: {key} must be one of {', '.join(EXEC_OPTIONS[key])}, got {value!r}")
        options[key] = int(value) if key == "dim" else value
    return name, command.strip(), options
