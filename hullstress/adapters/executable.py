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

That is spawn mode, one process per case, started without copying the
worker (:mod:`hullstress.adapters.exec_process`).  In persistent mode
(``mode=persistent``) the program starts once per worker and answers case
after case (:mod:`hullstress.adapters.exec_protocol`,
:mod:`hullstress.adapters.exec_session`), with the same rows.

Before any sweep, :func:`probe` runs the program once on five points in
general position, so that a program that cannot start, prints nothing or
speaks another dimension is refused with one line (exit status 2) instead of
giving thousands of identical rows; it also learns what the program says it
is (its handshake, or ``COMMAND --version``), which ``run.json`` records.

A hung program dies with its worker: the pool kills the worker's process
group, which the program shares.  Programs it starts itself are its own business.
"""

from __future__ import annotations

import os
import re
import shlex
import shutil
import signal
import sys
import time
from collections.abc import Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

from ..errors import CodeCrashed, UsageError
from .exec_process import Program, ProgramTimedOut
from .exec_protocol import ProtocolError, parse_handshake
from .exec_session import PersistentProgram, ProgramEnded, drop_session, session_for

__all__ = ["ExecutableHull", "ExecutableFailed", "OUTPUT_FORMATS", "MODES", "locate_program", "parse_exec_spec",
           "probe", "run_program", "run_persistent"]

#: What a program may write: Qhull's ``i`` or ``Fx``, or OFF.
OUTPUT_FORMATS = ("i", "Fx", "off")
#: How a program is run: once per case (``spawn``), or once per worker answering case after case (``persistent``).
MODES = ("spawn", "persistent")
#: Characters of the program's stderr kept in a row's reason.
STDERR_TAIL = 300
#: Options of ``--exec NAME[OPTIONS]=COMMAND``, with their allowed values.
EXEC_OPTIONS = {"dim": ("2", "3"), "output": OUTPUT_FORMATS, "mode": MODES}
#: Seconds the registration probe gives a program for one small case (and for ``--version``).
PROBE_TIMEOUT = 10.0
#: The probe's cases: in general position, the first four points extreme, the last one inside.
PROBE_POINTS = {
    2: [[0.125, 0.25], [3.75, 0.5], [3.0, 2.875], [0.375, 3.25], [1.625, 1.75]],
    3: [[0.125, 0.25, 0.0625], [3.75, 0.5, 0.375], [0.625, 3.25, 0.25], [0.5, 0.75, 3.5], [1.0, 1.125, 1.0]],
}

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
    """A registered program: what to run, on which points, what it writes, and what it said it is.

    Attributes
    ----------
    argv : tuple of str
        The command as given, split like a shell would (``("qconvex", "Qt", "i")``).
    program : str
        ``argv[0]`` resolved to an absolute path at registration.
    dim : {2, 3}
    output : {"i", "Fx", "off"}
    mode : {"spawn", "persistent"}
        One process per case, or one per worker answering case after case
        (:mod:`hullstress.adapters.exec_protocol`).
    driver, library : str
        What the program said it is (its handshake, or the first line of
        ``COMMAND --version``); '' when it did not say.
    """

    argv: tuple[str, ...]
    program: str
    dim: int
    output: str
    mode: str = "spawn"
    driver: str = ""
    library: str = ""

    @classmethod
    def from_command(cls, command: str | Sequence[str], *, dim: int, output: str = "i",
                     mode: str = "spawn") -> "ExecutableHull":
        """Validate and resolve a command (raises :class:`UsageError` with the reason on one line).

        Nothing is run: :func:`probe` runs the program once.
        """
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
        if mode not in MODES:
            raise UsageError(f"mode must be one of {', '.join(MODES)}, got {mode!r}")
        if output == "Fx" and dim != 2:
            raise UsageError("output 'Fx' lists extreme points, a hull only in 2D: use 'i' or 'off' for dim 3")
        program = locate_program(argv[0])
        if program is None:
            raise UsageError(f"command {shlex.join(argv)!r}: program {argv[0]!r} not found on PATH")
        return cls(argv=argv, program=program, dim=int(dim), output=output, mode=mode)

    @property
    def command(self) -> str:
        """The command line as a shell would read it."""
        return shlex.join(self.argv)

    @property
    def registry_label(self) -> str:
        """How the registry names this entry in a duplicate-name error."""
        return f"the program {self.command!r}"

    def describe(self, *, clockwise: bool = False) -> str:
        """One line for ``list algorithms``: the command, its output format and mode, what it said it is."""
        name = "OFF" if self.output == "off" else f"Qhull {self.output}"
        said = "; ".join(filter(None, (self.driver, self.library)))
        return (f"{self.command} ({name} output{', clockwise' if clockwise else ''}"
                f"{', persistent' if self.mode == 'persistent' else ''}){f' [{said}]' if said else ''}")

    def identity(self) -> dict[str, str]:
        """What ran, for ``run.json`` and the report: command, mode, driver, library."""
        return {"command": self.command, "program": self.program, "mode": self.mode,
                "driver": self.driver, "library": self.library}

    def __call__(self, points: Any) -> Any:
        if self.mode == "persistent":
            return run_persistent(self, points)
        return run_program(self, points)


def probe(hull: ExecutableHull, *, timeout: float = PROBE_TIMEOUT) -> ExecutableHull:
    """Run ``hull``'s program once on a small case in general position, before any sweep.

    A program that cannot start, exits at start, prints nothing, never
    answers its handshake, speaks another dimension or output format, or
    cannot hull five points in general position would give thousands of
    identical rows: it is refused here with one line naming the program and
    the problem.  Returns ``hull`` with what the program said it is
    (``driver``, ``library``: its handshake, or ``COMMAND --version``).

    Raises
    ------
    UsageError
        Naming the program and the problem (exit status 2 on the command line).
    """
    import numpy as np

    def refuse(problem: str) -> UsageError:
        return UsageError(f"--exec program {hull.command!r} {problem}")

    points = np.array(PROBE_POINTS[hull.dim], dtype=np.float64)
    deadline = time.monotonic() + timeout
    if hull.mode == "persistent":
        try:
            session = PersistentProgram((hull.program, *hull.argv[1:]), OUTPUT_FORMATS, deadline=deadline)
        except OSError as exc:
            raise refuse(f"cannot be started: {exc.strerror or exc}") from None
        except ProgramTimedOut:
            raise refuse(f"never answered the handshake (nothing on its first line within {timeout:g} s)") from None
        except ProgramEnded as exc:
            tail = _stderr_tail(exc.stderr)
            raise refuse(f"exited at start ({_ended_how(exc.returncode)}) before its handshake"
                         + (f"; stderr: {tail}" if tail else "; no stderr")) from None
        except UsageError as exc:
            raise refuse(f"in persistent mode: {exc}") from None
        try:
            said = session.handshake
            if said.dim != hull.dim:
                raise refuse(f"speaks dim={said.dim} in its handshake, registered with dim={hull.dim}")
            if said.output != hull.output:
                raise refuse(f"writes output={said.output} by its handshake, registered with output={hull.output}")
            hull = replace(hull, driver=said.driver, library=said.library)
            _, data = _points_text(hull, points)
            try:
                message, text = session.solve(data, deadline=deadline)
            except ProgramTimedOut:
                raise refuse(f"gave no answer to a {len(points)}-point case within {timeout:g} s") from None
            except ProgramEnded as exc:
                tail = _stderr_tail(exc.stderr)
                raise refuse(f"ended ({_ended_how(exc.returncode)}) on a {len(points)}-point case in general "
                             "position" + (f"; stderr: {tail}" if tail else "")) from None
            except ProtocolError as exc:
                raise refuse(f"answered out of step: {exc}") from None
            if message is not None:
                raise refuse(f"rejected a {len(points)}-point case in general position: {message}")
        finally:
            session.close()
        _check_probe_answer(hull, text, points, refuse)
        return hull
    try:
        program = Program((hull.program, *hull.argv[1:]))
    except OSError as exc:
        raise refuse(f"cannot be started: {exc.strerror or exc}") from None
    _, data = _points_text(hull, points)
    try:
        program.exchange(data, close_stdin=True, deadline=deadline)
        returncode = program.wait()
    except ProgramTimedOut:
        raise refuse(f"did not finish on a {len(points)}-point case within {timeout:g} s") from None
    finally:
        program.kill()
    if returncode:
        tail = _stderr_tail(program.err)
        raise refuse(f"{_ended_how(returncode)} on a {len(points)}-point case in general position"
                     + (f"; stderr: {tail}" if tail else "; no stderr"))
    text = program.out.decode("utf-8", errors="replace")
    if not text.strip():
        raise refuse(f"printed nothing for a {len(points)}-point case in general position")
    _check_probe_answer(hull, text, points, refuse)
    return replace(hull, **_version_of(hull, timeout))


def _ended_how(returncode: int | None) -> str:
    if returncode is None:
        return "exit status unknown"
    if returncode < 0:
        try:
            return f"killed by signal {-returncode} ({signal.Signals(-returncode).name})"
        except ValueError:
            return f"killed by signal {-returncode}"
    return f"exited with code {returncode}"


def _check_probe_answer(hull: ExecutableHull, text: str, points: Any, refuse: Any) -> None:
    """The probe's answer must be readable and use exactly the extreme points (the first four)."""
    from ..errors import ContractViolation
    from ..qhull_format import parse_hull

    try:
        faces = parse_hull(text, hull.output, points)
    except ContractViolation as exc:
        raise refuse(f"wrote output that cannot be read as '{hull.output}' for a {len(points)}-point case "
                     f"in {hull.dim}D ({exc}): is it a {hull.dim}D program writing '{hull.output}'?") from None
    used: set[int] = set()
    for item in faces:
        used.update(item if isinstance(item, (list, tuple)) else [item])
    if used != {0, 1, 2, 3}:
        raise refuse(f"gave a hull through points {sorted(used)} of a {len(points)}-point case whose extreme "
                     f"points are [0, 1, 2, 3]: is it a {hull.dim}D program writing '{hull.output}'?")


def _version_of(hull: ExecutableHull, timeout: float) -> dict[str, str]:
    """What ``COMMAND --version`` says (a handshake line, or free text) within ``timeout`` s; {} when nothing.

    Its stdin is closed at once: a program that does not know ``--version``
    reads an empty case, fails or prints nothing, and says nothing here.
    """
    try:
        program = Program((hull.program, *hull.argv[1:], "--version"))
    except OSError:
        return {}
    try:
        program.exchange(b"", close_stdin=True, deadline=time.monotonic() + timeout)
        returncode = program.wait()
    except ProgramTimedOut:
        return {}
    finally:
        program.kill()
    line = program.out.decode("utf-8", errors="replace").strip().partition("\n")[0].strip()
    if returncode or not line or not re.search(r"[A-Za-z]", line):
        return {}
    try:
        said = parse_handshake(line, formats=OUTPUT_FORMATS)
        return {"driver": said.driver, "library": said.library}
    except UsageError:
        return {"driver": line[:200]}


def _stderr_tail(raw: bytes) -> str:
    text = _QHULL_TRAILER.sub("", raw.decode("utf-8", errors="replace"))
    text = " ".join(text.split())
    return text if len(text) <= STDERR_TAIL else "..." + text[-STDERR_TAIL:]


def _points_text(hull: ExecutableHull, points: Any) -> tuple[Any, bytes]:
    """The points as an array and in Qhull's input format; ValueError when the format cannot carry them."""
    import numpy as np

    from ..qhull_format import format_points

    pts = np.asarray(points)
    if pts.ndim != 2 or pts.shape[1] != hull.dim:
        raise ValueError(f"points of shape {pts.shape} are not {hull.dim}D points: not given to {hull.argv[0]}")
    if 0 < len(pts) < hull.dim:
        # Qhull's format reads the smaller of its two header numbers as the dimension.
        raise ValueError(f"Qhull's input format cannot say {len(pts)} points in {hull.dim}D "
                         "(it reads the smaller header number as the dimension): not given to " + hull.argv[0])
    return pts, format_points(pts).encode("ascii")


def _status_error(hull: ExecutableHull, returncode: int, stderr: bytes, *, where: str = "") -> Exception:
    """The exception a program's exit status means: CodeCrashed (a signal) or ExecutableFailed."""
    tail = _stderr_tail(stderr)
    said = f"; stderr: {tail}" if tail else "; no stderr"
    if returncode < 0:
        try:
            name = signal.Signals(-returncode).name
        except ValueError:
            name = "unknown signal"
        return CodeCrashed(f"{hull.argv[0]} killed by signal {-returncode} ({name}){where}{said}")
    return ExecutableFailed(f"{hull.argv[0]} exited with code {returncode}{where}{said}")


def run_program(hull: ExecutableHull, points: Any, *, deadline: float | None = None) -> Any:
    """Run ``hull``'s program on ``points`` once (spawn mode) and return its raw faces.

    Parameters
    ----------
    hull : ExecutableHull
    points : array_like, shape (n, dim)
    deadline : float, optional
        ``time.monotonic()`` after which the program is killed (raises
        :class:`~hullstress.adapters.exec_process.ProgramTimedOut`).  Workers
        leave it to the pool's per-call timeout.

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
    from ..qhull_format import parse_hull

    pts, data = _points_text(hull, points)
    program = Program((hull.program, *hull.argv[1:]))
    try:
        program.exchange(data, close_stdin=True, deadline=deadline)
        returncode = program.wait()
    finally:
        program.kill()  # a no-op once reaped; kills it when an alarm (--workers 0) interrupted the exchange
    stderr = program.take_stderr()
    if stderr:
        _forward(stderr)
    if returncode:
        raise _status_error(hull, returncode, stderr)
    return parse_hull(program.out.decode("utf-8", errors="replace"), hull.output, pts)


def run_persistent(hull: ExecutableHull, points: Any, *, deadline: float | None = None) -> Any:
    """Give ``points`` to ``hull``'s persistent program (started on first use) and return its raw faces.

    A program that dies during the case is restarted for the next one (the
    case is a ``crash``, or an ``error`` for a non-zero exit).  One that
    answers out of step or with output that cannot be read is restarted and
    the case is run once more in spawn mode, whose outcome is the call's (a
    note on stderr, in the row's ``call_output``, says so).

    Raises
    ------
    The exceptions of :func:`run_program`.
    """
    from ..errors import ContractViolation
    from ..qhull_format import parse_hull

    pts, data = _points_text(hull, points)
    key = (hull.argv, hull.dim, hull.output)
    try:
        session = session_for(key, (hull.program, *hull.argv[1:]), OUTPUT_FORMATS)
    except ProgramEnded as exc:
        raise _status_error(hull, exc.returncode if exc.returncode is not None else -9, exc.stderr,
                            where=" before its handshake (persistent mode)") from None
    except UsageError as exc:
        raise ExecutableFailed(f"{hull.argv[0]} (persistent mode): {exc}") from None
    try:
        message, text = session.solve(data, deadline=deadline)
    except ProgramEnded as exc:
        drop_session(key)
        _forward(exc.stderr)
        if exc.returncode != 0:
            raise _status_error(hull, exc.returncode if exc.returncode is not None else -9, exc.stderr,
                                where=" during the case (persistent mode; restarted for the next case)") from None
        why = "exited with code 0 in the middle of the case"
    except ProtocolError as exc:
        drop_session(key)
        _forward(session.take_stderr())
        why = str(exc)
    except BaseException:
        drop_session(key)  # interrupted mid-case (an alarm with --workers 0): its answer would be out of step
        raise
    else:
        _forward(session.take_stderr())
        if message is not None:
            raise ExecutableFailed(f"{hull.argv[0]} rejected the case: {message}")
        try:
            return parse_hull(text, hull.output, pts)
        except ContractViolation as exc:
            drop_session(key)
            why = str(exc)
    _forward(f"hullstress: persistent program {hull.argv[0]} out of step ({why}); restarted, "
             "and the case run again in spawn mode\n".encode())
    return run_program(hull, pts, deadline=deadline)


def _forward(raw: bytes) -> None:
    """Pass the program's stderr on to ours (fd 2), where the runner captures each call's output."""
    try:
        sys.stderr.flush()
        os.write(2, raw)
    except OSError:
        pass  # a closed stderr must not turn the call into an error


def parse_exec_spec(text: str) -> tuple[str, str, dict[str, Any]]:
    """Split an ``--exec`` value ``NAME[OPTIONS]=COMMAND`` into name, command and options.

    ``OPTIONS`` is a comma-separated list of ``dim=2|3`` (default 3),
    ``output=i|Fx|off`` (default ``i``) and ``mode=spawn|persistent``
    (default ``spawn``).

    Raises
    ------
    UsageError
        Naming the value and what is wrong with it.

    Examples
    --------
    >>> parse_exec_spec("qhull2[dim=2,output=Fx]=qconvex Fx")
    ('qhull2', 'qconvex Fx', {'dim': 2, 'output': 'Fx', 'mode': 'spawn'})
    >>> parse_exec_spec("qconvex")
    Traceback (most recent call last):
    ...
    hullstress.errors.UsageError: --exec 'qconvex': expected NAME=COMMAND (e.g. qconvex='qconvex Qt i')
    """
    match = re.fullmatch(r"\s*([^\[\]=\s]+)\s*(?:\[([^\]]*)\])?\s*=(.*)", text, flags=re.DOTALL)
    if match is None or not match.group(3).strip():
        raise UsageError(f"--exec {text!r}: expected NAME=COMMAND (e.g. qconvex='qconvex Qt i')")
    name, option_text, command = match.group(1), match.group(2) or "", match.group(3)
    options: dict[str, Any] = {"dim": 3, "output": "i", "mode": "spawn"}
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
