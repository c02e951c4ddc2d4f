"""Helpers for tests that watch processes."""

from __future__ import annotations

import os
from pathlib import Path


def alive(pid: int) -> bool:
    """Whether process ``pid`` is still running code (a zombie answers ``kill(0)`` but does not)."""
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    try:
        return Path(f"/proc/{pid}/stat").read_text().split()[2] != "Z"
    except OSError:
        return False


def forked_from_a_fork_server_of(folder: Path) -> list[int]:
    """Live processes that are, or were forked from, a multiprocessing fork server started in ``folder``.

    A fork server's command line holds the ``sys.path`` it was started with,
    whose first entry is the starting process's working folder; the workers
    and helpers forked from it keep that command line.  Linux only (an empty
    list elsewhere).
    """
    found = []
    for proc in Path("/proc").glob("[0-9]*"):
        try:
            command = (proc / "cmdline").read_bytes().replace(b"\0", b" ").decode(errors="replace")
        except OSError:
            continue
        if "multiprocessing.forkserver" in command and f"'{folder}'" in command and alive(int(proc.name)):
            found.append(int(proc.name))
    return found
