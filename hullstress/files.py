"""Writing files atomically: the one writer behind reports, failure folders and the corpus.

Every file hullstress writes goes through a temporary file in the same folder
and ``os.replace``, so a reader (a browser on ``report.html``, a concurrent
replay on the corpus, CI collecting ``junit.xml``) never sees half a file, and
two runs writing the same corpus entry cannot interleave.  This module is
light (standard library only) so that any stage can use it.
"""

from __future__ import annotations

import os
import tempfile
from collections.abc import Callable
from pathlib import Path
from typing import IO, Any

__all__ = ["atomic_write_text", "atomic_write_bytes", "atomic_write_with"]


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
    OSError
        Whatever the filesystem raised (a read-only folder, a full disk); the
        temporary file is removed and ``path`` is left as it was.
    """
    target = Path(path)
    fd, tmp = tempfile.mkstemp(prefix=f".{target.name}.", suffix=".tmp", dir=target.parent)
    try:
        mode = "wb" if binary else "w"
        kwargs: dict[str, Any] = {} if binary else {"encoding": "utf-8", "newline": ""}
        with os.fdopen(fd, mode, **kwargs) as fh:
            write(fh)
            if durable:
                fh.flush()
                os.fsync(fh.fileno())
        os.replace(tmp, target)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
    return target


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
