"""Writing files atomically: the one writer behind reports, failure folders and the corpus.

Every file hullstress writes goes through a temporary file in the same folder
and ``os.replace``, so a reader (a browser on ``report.html``, a concurrent
replay on the corpus, CI collecting ``junit.xml``) never sees half a file, and
two runs writing the same corpus entry cannot interleave.  This module is
light (standard library only) so that any stage can use it.

A write the environment refuses (a full disk, a read-only or unwritable
folder) raises :class:`~hullstress.errors.EnvironmentFailure` naming the path
(exit status 4), never a bare ``OSError`` from deep inside a stage; and
:func:`writable_folder` checks an output folder before any work is done.
A destination that is not a regular file (``/dev/stdout``, a named pipe) is
written in place: renaming over it would replace the device.
"""

from __future__ import annotations

import os
import tempfile
from collections.abc import Callable
from pathlib import Path
from typing import IO, Any

from .errors import EnvironmentFailure, UsageError, is_environment_error

__all__ = ["atomic_write_text", "atomic_write_bytes", "atomic_write_with", "writable_folder", "written_in_place"]


def atomic_write_with(path: str | os.PathLike[str], write: Callable[[IO[Any]], Any], *,
                      binary: bool = False, durable: bool = False) -> Path:
    """Create ``path`` by calling ``write(fh)`` on a temporary file, then renaming it into place.

    Parameters
    ----------
    path : path-like
        The destination; its folder must exist.
    write : callable
        Receives the open temporary file and writes the content.
    binary : bool
        Open the temporary file in binary mode.
    durable : bool
        ``fsync`` before the rename, so the content survives a power cut
        (the corpus asks for it; reports do not need it).

    Returns
    -------
    Path
        ``path``.

    Raises
    ------
    EnvironmentFailure
        The filesystem refused (a read-only folder, a full disk), naming
        ``path``; the temporary file is removed and ``path`` is left as it was.
    OSError
        Any other filesystem error (a missing folder, say).
    """
    target = Path(path)
    mode = "wb" if binary else "w"
    kwargs: dict[str, Any] = {} if binary else {"encoding": "utf-8", "newline": ""}
    if written_in_place(target):
        try:
            with open(target, mode, **kwargs) as fh:
                write(fh)
        except OSError as exc:
            raise _refused(target, exc) from exc
        return target
    tmp = None
    try:
        fd, tmp = tempfile.mkstemp(prefix=f".{target.name}.", suffix=".tmp", dir=target.parent)
        with os.fdopen(fd, mode, **kwargs) as fh:
            write(fh)
            if durable:
                fh.flush()
                os.fsync(fh.fileno())
        os.replace(tmp, target)
    except BaseException as exc:
        if tmp is not None:
            Path(tmp).unlink(missing_ok=True)
        if isinstance(exc, OSError):
            raise _refused(target, exc) from exc
        raise
    return target


def written_in_place(path: Path) -> bool:
    """True for an existing destination that is not a regular file (a device, a pipe): no rename over it."""
    try:
        return path.exists() and not path.is_file()
    except OSError:
        return False


def _refused(path: Path, exc: OSError) -> OSError | EnvironmentFailure:
    return EnvironmentFailure.writing(path, exc) if is_environment_error(exc) else exc


def writable_folder(path: str | os.PathLike[str], option: str) -> Path:
    """Create ``path`` (and its parents) if needed and check a file can be written in it.

    Parameters
    ----------
    path : path-like
        An output folder (``--out``, ``--save-corpus``, the folder of ``--junit``).
    option : str
        The option that named it, for messages.

    Raises
    ------
    EnvironmentFailure
        The folder is read-only, not writable or on a full disk (exit status 4).
    UsageError
        The path cannot be a folder (it runs through a file, say).
    """
    folder = Path(path)
    try:
        folder.mkdir(parents=True, exist_ok=True)
        fd, probe = tempfile.mkstemp(prefix=".hullstress-write-test-", dir=folder)
        os.close(fd)
        os.unlink(probe)
    except OSError as exc:
        message = f"{option} {str(path)!r}: cannot write there: {exc.strerror or exc}"
        if is_environment_error(exc):
            raise EnvironmentFailure(message) from None
        raise UsageError(message) from None
    return folder


def atomic_write_text(path: str | os.PathLike[str], text: str, *, durable: bool = False) -> Path:
    """Write ``text`` (UTF-8) to ``path`` atomically.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> folder = pathlib.Path(tempfile.mkdtemp())
    >>> atomic_write_text(folder / "a.txt", "hello\\n").read_text()
    'hello\\n'
    """
    return atomic_write_with(path, lambda fh: fh.write(text), durable=durable)


def atomic_write_bytes(path: str | os.PathLike[str], data: bytes, *, durable: bool = False) -> Path:
    """Write ``data`` to ``path`` atomically."""
    return atomic_write_with(path, lambda fh: fh.write(data), binary=True, durable=durable)
