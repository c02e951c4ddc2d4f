"""The persistent-mode protocol between hullstress and a hull program: handshake and framing.

A program run with ``mode=persistent`` starts once per worker process and
answers case after case (as AFL's persistent mode or libFuzzer's in-process
loop do).  It is started with :data:`PROTOCOL_ENV` set to the protocol
version, so one driver binary can serve both modes.  The exchange, one UTF-8
text line at a time (``\\n`` ends every line):

1. **Handshake.**  The program's first line on stdout, fields separated by
   tabs::

       hullstress-exec/1<TAB>dim=3<TAB>output=i<TAB>driver=qhull_r driver 1.0<TAB>library=qhull_r 2020.2

   ``dim`` (2 or 3) and ``output`` (``i``, ``Fx`` or ``off``) are required
   and must agree with the registration; ``driver`` and ``library`` (free
   text without tabs) name what runs, and end up in ``run.json`` and the report.
2. **A case.**  hullstress writes ``case N`` (N counts from 1), then the
   points in Qhull's input format (the dimension, the count, one point per
   line): the count says where the case ends.
3. **The answer.**  Either ``hull N``, the hull in the announced output
   format, and ``end N``; or one line ``error N MESSAGE`` (the program
   rejects the case and goes on: an ``error`` row, as a non-zero exit is in
   spawn mode).

Anything else (a line before ``hull N``, a wrong ``N``, output that cannot be
read) is out of step: hullstress restarts the program and runs the case once
more in spawn mode to confirm.  End of file on stdin means stop.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

from ..errors import UsageError

__all__ = ["PROTOCOL_VERSION", "PROTOCOL_ENV", "MAGIC", "Handshake", "ProtocolError", "parse_handshake",
           "case_header", "answer_header"]

#: The version of the protocol this hullstress speaks.
PROTOCOL_VERSION = 1
#: Environment variable set (to the protocol version) when a program is started in persistent mode.
PROTOCOL_ENV = "HULLSTRESS_EXEC_PROTOCOL"
#: How a handshake line starts.
MAGIC = "hullstress-exec"
#: Characters of a handshake field kept (a version string, not a novel).
FIELD_CHARS = 200

_ANSWER = re.compile(rb"(hull|error) (\d+)(?: (.*))?")


class ProtocolError(Exception):
    """The program said something the protocol does not allow at this point (out of step, or garbage)."""


@dataclass(frozen=True)
class Handshake:
    """What a persistent program announced on its first line.

    Attributes
    ----------
    version : int
        Protocol version.
    dim : int
    output : str
    driver, library : str
        Free text naming the driver and the library it wraps, with versions ('' when not given).
    """

    version: int
    dim: int
    output: str
    driver: str = ""
    library: str = ""


def parse_handshake(line: str, *, formats: tuple[str, ...]) -> Handshake:
    """Read a handshake line (see the module docstring).

    Raises
    ------
    UsageError
        Naming what is wrong: not a handshake, another protocol version, a
        missing or bad ``dim``/``output``.

    Examples
    --------
    >>> parse_handshake("hullstress-exec/1\\tdim=2\\toutput=Fx\\tdriver=mc 1.0", formats=("i", "Fx", "off"))
    Handshake(version=1, dim=2, output='Fx', driver='mc 1.0', library='')
    """
    shown = line.strip()[:80]
    fields = line.rstrip("\r\n").split("\t")
    head, _, version_text = fields[0].partition("/")
    if head.strip() != MAGIC:
        raise UsageError(f"its first line {shown!r} is not a handshake ('{MAGIC}/{PROTOCOL_VERSION}<TAB>dim=...'); "
                         "is it a spawn-mode program (drop mode=persistent)?")
    if version_text.strip() != str(PROTOCOL_VERSION):
        raise UsageError(f"it speaks protocol version {version_text.strip()!r}; "
                         f"this hullstress speaks version {PROTOCOL_VERSION}")
    values: dict[str, str] = {}
    for field in fields[1:]:
        key, sep, value = field.partition("=")
        if sep:
            values[key.strip()] = value.strip()[:FIELD_CHARS]
    dim_text = values.get("dim", "")
    if dim_text not in ("2", "3"):
        raise UsageError(f"its handshake gives dim={dim_text!r}, expected 2 or 3")
    output = values.get("output", "")
    if output not in formats:
        raise UsageError(f"its handshake gives output={output!r}, expected one of {', '.join(formats)}")
    return Handshake(version=PROTOCOL_VERSION, dim=int(dim_text), output=output,
                     driver=values.get("driver", ""), library=values.get("library", ""))


def case_header(number: int) -> bytes:
    """The line that starts case ``number``."""
    return b"case %d\n" % number


def answer_header(line: bytes, number: int) -> str | None:
    """Read the first line of the answer to case ``number``: None for ``hull N``, the message for ``error N``.

    Raises
    ------
    ProtocolError
        Any other line (naming it), or an answer to another case.

    Examples
    --------
    >>> answer_header(b"hull 3", 3) is None
    True
    >>> answer_header(b"error 3 too few points", 3)
    'too few points'
    >>> answer_header(b"4", 3)
    Traceback (most recent call last):
    ...
    hullstress.adapters.exec_protocol.ProtocolError: expected 'hull 3' or 'error 3 ...', got '4'
    """
    match = _ANSWER.fullmatch(line.rstrip(b"\r"))
    if match is None or int(match.group(2)) != number:
        shown = line.decode("utf-8", errors="replace")[:80]
        raise ProtocolError(f"expected 'hull {number}' or 'error {number} ...', got {shown!r}")
    if match.group(1) == b"hull":
        return None
    return (match.group(3) or b"").decode("utf-8", errors="replace").strip() or "(no message)"
