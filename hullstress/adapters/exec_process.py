"""Starting a hull program and talking to it over pipes, at the program's own speed.

Why not :mod:`subprocess`: a worker process is large (NumPy, SciPy and
hullstress are loaded), and ``subprocess`` with a ``preexec_fn`` forks it
whole, copying its page tables, about 8 ms per call on a busy machine.
:func:`os.posix_spawn` starts the program with ``vfork`` semantics (glibc's
``clone(CLONE_VM|CLONE_VFORK)``): nothing is copied, whatever the size of the
worker.  The pipes are driven by one :func:`select.poll` loop that blocks
until the program writes (no polling interval, no thread per pipe).

How a hung program dies with its worker without ``PR_SET_PDEATHSIG`` (which
needs code between fork and exec, the ``preexec_fn`` this avoids): an
isolated worker leads a process group of its own
(:func:`programs_die_with_process_group`), programs started in it stay in
that group, and the pool kills the whole group when it kills the worker
(its per-call timeout).  In any other process (``--workers 0``, the
registration probe) a program gets a session of its own, so that a Ctrl-C in
the terminal is the harness's to handle, not the program's.
"""

from __future__ import annotations

import os
import select
import signal
import time
from collections.abc import Callable, Mapping, Sequence

__all__ = ["Program", "programs_die_with_process_group", "ProgramTimedOut"]

#: Bytes read or written per system call.
CHUNK = 1 << 16

_in_worker_group = False


def programs_die_with_process_group() -> None:
    """Make this process lead a process group that its programs share (called by isolated workers).

    The pool kills the group, program included, when it kills the worker.
    """
    global _in_worker_group
    try:
        if os.getpgrp() != os.getpid():
            os.setpgid(0, 0)
        _in_worker_group = True
    except (OSError, AttributeError):
        _in_worker_group = False  # the program gets a session of its own, as anywhere else


class ProgramTimedOut(Exception):
    """The program did not answer before the deadline it was given (the program has been killed)."""


class Program:
    """A started program with pipes on its stdin, stdout and stderr.

    Parameters
    ----------
    argv : sequence of str
        ``argv[0]`` is an absolute path (no ``PATH`` search here).
    env : mapping, optional
        Extra environment variables on top of this process's.

    Raises
    ------
    OSError
        The program cannot be started (not executable, bad format).
    """

    def __init__(self, argv: Sequence[str], env: Mapping[str, str] | None = None) -> None:
        pipes = [os.pipe() for _ in range(3)]  # non-inheritable: only the dup2'd ends reach the program
        (in_r, in_w), (out_r, out_w), (err_r, err_w) = pipes
        actions = [(os.POSIX_SPAWN_DUP2, in_r, 0), (os.POSIX_SPAWN_DUP2, out_w, 1),
                   (os.POSIX_SPAWN_DUP2, err_w, 2)]
        environment = os.environ if not env else {**os.environ, **env}
        try:
            self.pid = os.posix_spawn(argv[0], list(argv), environment, file_actions=actions,
                                      setsid=not _in_worker_group)
        except BaseException:
            for fd in (in_r, in_w, out_r, out_w, err_r, err_w):
                os.close(fd)
            raise
        for fd in (in_r, out_w, err_w):
            os.close(fd)
        self.stdin: int | None = in_w
        self.stdout: int | None = out_r
        self.stderr: int | None = err_r
        os.set_blocking(in_w, False)
        self.out = bytearray()
        self.err = bytearray()
        self.returncode: int | None = None
        self._poller = select.poll()
        self._poller.register(out_r, select.POLLIN)
        self._poller.register(err_r, select.POLLIN)

    # -- pipes -------------------------------------------------------------

    def exchange(self, data: bytes, done: Callable[[bytearray], bool] | None = None, *,
                 close_stdin: bool = False, deadline: float | None = None) -> bool:
        """Write ``data`` on stdin and read stdout (into :attr:`out`) and stderr (into :attr:`err`).

        Returns True as soon as ``done(out)`` is true, False at end of file
        on stdout (the program closed it or died).  Without ``done``, reads
        until end of file.  With ``close_stdin``, stdin is closed once
        ``data`` is written (a spawn-mode program reads to end of file).

        Raises
        ------
        ProgramTimedOut
            ``time.monotonic()`` passed ``deadline`` (the program is killed).
        """
        view = memoryview(data)
        poller = self._poller
        writing = self.stdin is not None and (len(view) > 0 or close_stdin)
        if writing:
            poller.register(self.stdin, select.POLLOUT)
        try:
            while True:
                if done is not None and done(self.out):
                    return True
                if self.stdout is None:
                    return False
                if deadline is None:
                    events = poller.poll()
                else:
                    left = deadline - time.monotonic()
                    if left <= 0:
                        self.kill()
                        raise ProgramTimedOut()
                    events = poller.poll(max(1, int(left * 1000)))
                for fd, _ in events:
                    if fd == self.stdin:
                        try:
                            if len(view):
                                view = view[os.write(fd, view[:CHUNK]):]
                        except BlockingIOError:
                            continue
                        except BrokenPipeError:
                            view = view[len(view):]  # the program stopped reading: what it wrote still counts
                        if not len(view):
                            poller.unregister(fd)
                            writing = False
                            if close_stdin:
                                self.close_stdin()
                    elif fd == self.stdout:
                        chunk = os.read(fd, CHUNK)
                        if chunk:
                            self.out += chunk
                        else:
                            self._close_read("stdout")
                    elif fd == self.stderr:
                        chunk = os.read(fd, CHUNK)
                        if chunk:
                            self.err += chunk
                        else:
                            self._close_read("stderr")
        finally:
            if writing and self.stdin is not None:
                poller.unregister(self.stdin)

    def drain_stderr(self) -> None:
        """Read what the program has written on stderr so far, without waiting."""
        while self.stderr is not None and select.select([self.stderr], [], [], 0)[0]:
            chunk = os.read(self.stderr, CHUNK)
            if not chunk:
                self._close_read("stderr")
                return
            self.err += chunk

    def take_stderr(self) -> bytes:
        """What the program wrote on stderr since the last call, emptied."""
        data = bytes(self.err)
        self.err.clear()
        return data

    def close_stdin(self) -> None:
        """Close the program's stdin (it reads end of file)."""
        if self.stdin is not None:
            try:
                os.close(self.stdin)
            finally:
                self.stdin = None

    def _close_read(self, which: str) -> None:
        fd = getattr(self, which)
        if fd is not None:
            self._poller.unregister(fd)
            os.close(fd)
            setattr(self, which, None)

    # -- the process -------------------------------------------------------

    def wait(self, timeout: float | None = None) -> int | None:
        """Reap the program and return its exit status (negative: the signal), or None when still running."""
        if self.returncode is not None:
            return self.returncode
        deadline = None if timeout is None else time.monotonic() + timeout
        delay = 0.0005
        while True:
            pid, status = os.waitpid(self.pid, 0 if deadline is None else os.WNOHANG)
            if pid:
                self.returncode = os.waitstatus_to_exitcode(status)
                return self.returncode
            assert deadline is not None
            if time.monotonic() >= deadline:
                return None
            time.sleep(delay)  # only after end of file on its stdout: it is exiting
            delay = min(delay * 2, 0.05)

    def kill(self) -> None:
        """Kill the program (SIGKILL) and reap it; close the pipes."""
        if self.returncode is None:
            try:
                os.kill(self.pid, signal.SIGKILL)
            except ProcessLookupError:
                pass
            self.wait()
        self.close()

    def close(self) -> None:
        """Close every pipe (the program, if still running, reads end of file)."""
        self.close_stdin()
        self._close_read("stdout")
        self._close_read("stderr")
