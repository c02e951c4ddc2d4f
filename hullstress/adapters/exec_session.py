"""A program in persistent mode: started once per process, answering case after case.

The protocol (handshake, framing) is in :mod:`hullstress.adapters.exec_protocol`.
One :class:`PersistentProgram` per registered program per worker process
(:func:`session_for`).  Isolation is kept: a per-case timeout (the pool kills
the worker and its process group, program included: the row is ``timeout``
and the next case starts a new program), a crash ends only the case (a
``crash`` row; the next case starts a new program), the memory limit is the
worker's (``RLIMIT_AS`` is inherited).
"""

from __future__ import annotations

import atexit
import time
from typing import Any

from .exec_process import Program, ProgramTimedOut
from .exec_protocol import PROTOCOL_ENV, PROTOCOL_VERSION, Handshake, ProtocolError, answer_header, case_header, \
    parse_handshake

__all__ = ["PersistentProgram", "ProgramEnded", "session_for", "close_sessions", "HANDSHAKE_TIMEOUT"]

#: Seconds a program has to start and write its handshake.
HANDSHAKE_TIMEOUT = 10.0


class ProgramEnded(Exception):
    """The program closed its stdout in the middle of a case (it exited or died); ``returncode`` says how."""

    def __init__(self, returncode: int | None, stderr: bytes) -> None:
        super().__init__(returncode)
        self.returncode = returncode
        self.stderr = stderr


class PersistentProgram:
    """A running persistent-mode program and the number of the last case it was given.

    Parameters
    ----------
    argv : sequence of str
    formats : tuple of str
        The output formats the harness reads (for the handshake's check).
    deadline : float, optional
        ``time.monotonic()`` by which the handshake must have arrived (default: :data:`HANDSHAKE_TIMEOUT`).

    Raises
    ------
    OSError
        The program cannot be started.
    ProgramEnded
        It closed its stdout before its handshake.
    ProgramTimedOut
        No handshake before the deadline (the program has been killed).
    UsageError
        The handshake is not one, or of another protocol version.
    """

    def __init__(self, argv: tuple[str, ...], formats: tuple[str, ...], *, deadline: float | None = None) -> None:
        self.program = Program(argv, env={PROTOCOL_ENV: str(PROTOCOL_VERSION)})
        self.number = 0
        try:
            if not self.program.exchange(b"", lambda out: b"\n" in out,
                                         deadline=deadline or time.monotonic() + HANDSHAKE_TIMEOUT):
                raise self._ended()
            line, _, rest = bytes(self.program.out).partition(b"\n")
            del self.program.out[: len(line) + 1]
            self.handshake: Handshake = parse_handshake(line.decode("utf-8", errors="replace"), formats=formats)
        except BaseException:
            self.program.kill()
            raise

    def _ended(self) -> ProgramEnded:
        self.program.close_stdin()
        self.program.exchange(b"")  # whatever it still writes on stderr, to end of file
        code = self.program.wait(timeout=1.0)
        if code is None:
            self.program.kill()
            code = self.program.returncode
        return ProgramEnded(code, self.program.take_stderr())

    @property
    def alive(self) -> bool:
        return self.program.returncode is None and self.program.stdout is not None

    def solve(self, points_text: bytes, *, deadline: float | None = None) -> tuple[str | None, str]:
        """Give the program one case; return (the error message or None, the answer's text).

        Raises
        ------
        ProgramEnded
            It exited or died during the case.
        ProtocolError
            It answered out of step or with garbage (the program is killed: start a new one).
        ProgramTimedOut
            No answer before ``deadline`` (the program is killed).
        """
        self.number += 1
        number = self.number
        out = self.program.out
        end_marker = b"\nend %d\n" % number
        state: dict[str, Any] = {}

        def answered(buffer: bytearray) -> bool:
            if "header" not in state:
                cut = buffer.find(b"\n")
                if cut < 0:
                    return False
                try:
                    state["header"] = (answer_header(bytes(buffer[:cut]), number), cut)
                except ProtocolError as exc:
                    state["bad"] = exc
                    return True
            message, cut = state["header"]
            if message is not None:
                return True
            return buffer.find(end_marker, cut) >= 0

        try:
            if not self.program.exchange(case_header(number) + points_text, answered, deadline=deadline):
                raise self._ended()
        except (ProgramEnded, ProgramTimedOut):
            self.program.kill()
            raise
        if "bad" in state:
            self.program.kill()
            raise state["bad"]
        message, cut = state["header"]
        if message is not None:
            del out[: cut + 1]
            return message, ""
        end = out.find(end_marker, cut) + len(end_marker)
        text = bytes(out[cut + 1 : end - len(end_marker) + 1])
        del out[:end]
        if out:
            shown = bytes(out[:80]).decode("utf-8", errors="replace")
            self.program.kill()
            raise ProtocolError(f"wrote {shown!r} after 'end {number}', before being given a case")
        return None, text.decode("utf-8", errors="replace")

    def take_stderr(self) -> bytes:
        """What the program wrote on stderr so far and not yet taken."""
        self.program.drain_stderr()
        return self.program.take_stderr()

    def close(self) -> None:
        """Tell the program to stop (end of file on its stdin), then make sure it has."""
        self.program.close_stdin()
        if self.program.wait(timeout=0.5) is None:
            self.program.kill()
        self.program.close()


_sessions: dict[Any, PersistentProgram] = {}


def session_for(key: Any, argv: tuple[str, ...], formats: tuple[str, ...]) -> PersistentProgram:
    """This process's running program for ``key``, started (and its handshake read) if needed."""
    session = _sessions.get(key)
    if session is None or not session.alive:
        _sessions.pop(key, None)
        session = PersistentProgram(argv, formats)
        _sessions[key] = session
    return session


def drop_session(key: Any) -> None:
    """Forget ``key``'s program (after it died or was killed): the next case starts a new one."""
    session = _sessions.pop(key, None)
    if session is not None:
        session.program.kill()


@atexit.register
def close_sessions() -> None:
    """Stop every running program of this process."""
    while _sessions:
        _, session = _sessions.popitem()
        try:
            session.close()
        except OSError:
            pass
