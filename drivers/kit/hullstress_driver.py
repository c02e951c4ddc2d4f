"""hullstress_driver.py: the Python driver kit of hullstress (docs/executables.md).

For a hull library installed in another Python environment than hullstress
(another version of it, another interpreter): copy this one file next to your
driver, which runs in that environment::

    from hullstress_driver import Reject, run_driver

    def my_hull(points):            # a list of (x, y[, z]) tuples of floats
        ...                         # return the answer's text, or raise Reject("why")

    run_driver(my_hull, dim=3, output="i", driver="my driver 1.0", library="mylib 2.3")

and register it with ``--exec 'NAME[mode=persistent]=/path/to/other/venv/bin/python driver.py'``.

With ``HULLSTRESS_EXEC_PROTOCOL`` set (persistent mode) it writes the
handshake and answers case after case (``case N`` and the points; ``hull N``,
the answer, ``end N``; or ``error N message``) until end of file; without it
(spawn mode) it reads one case, writes the answer and exits (status 1 with
the message on stderr when the case is rejected).  ``--version`` prints the
handshake line.  Standard library only; Python 3.8 or later.
"""

import os
import sys

PROTOCOL_VERSION = 1


class Reject(Exception):
    """Raised by a hull function to reject a case (an ``error`` row; the driver goes on)."""


def handshake(dim, output, driver="", library=""):
    """The handshake line (with its newline)."""
    return "hullstress-exec/%d\tdim=%d\toutput=%s\tdriver=%s\tlibrary=%s\n" % (
        PROTOCOL_VERSION, dim, output, driver, library)


def read_points(stream, dim):
    """Read one case in Qhull's input format from ``stream``: a list of tuples, or None at end of input."""
    header = []
    while len(header) < 2:
        line = stream.readline()
        if not line:
            return None
        header += line.split()
    a, b = int(header[0]), int(header[1])
    d, n = (b, a) if a != dim and b == dim else (a, b)  # Qhull reads either order
    if d != dim:
        raise Reject("cannot read %dD points in Qhull's format (header %s %s)" % (dim, a, b))
    points = []
    for _ in range(n):
        values = stream.readline().split()
        if len(values) < dim:
            raise Reject("cannot read %dD points in Qhull's format (a short line)" % dim)
        points.append(tuple(float(v) for v in values[:dim]))
    return points


def _text(answer):
    answer = str(answer)
    return answer if not answer or answer.endswith("\n") else answer + "\n"


def run_driver(hull, dim, output, driver="", library=""):
    """Serve ``hull`` in the mode hullstress started this program in (see the module docstring)."""
    out = sys.stdout
    if sys.argv[-1:] == ["--version"]:
        out.write(handshake(dim, output, driver, library))
        return
    if PROTOCOL_ENV not in os.environ:
        try:
            points = read_points(sys.stdin, dim)
            if points is None:
                raise Reject("no input")
            out.write(_text(hull(points)))
        except Reject as exc:
            sys.stderr.write("%s\n" % exc)
            sys.exit(1)
        return
    out.write(handshake(dim, output, driver, library))
    out.flush()
    stdin = sys.stdin
    while True:
        line = stdin.readline()
        if not line:
            return  # end of file: hullstress is done with us
        words = line.split()
        if not words:
            continue
        number = words[1] if len(words) > 1 and words[0] == "case" else "0"
        try:
            if words[0] != "case":
                raise Reject("expected 'case N', got %r" % line.strip()[:40])
            points = read_points(stdin, dim)
            if points is None:
                return
            answer = "hull %s\n%send %s\n" % (number, _text(hull(points)), number)
        except Exception as exc:  # a library's exception rejects the case; the driver goes on
            why = str(exc) if isinstance(exc, Reject) else "driver raised %s: %s" % (type(exc).__name__, exc)
            answer = "error %s %s\n" % (number, " ".join(why.split()) or "case rejected")
        out.write(answer)
        out.flush()


PROTOCOL_ENV = "HULLSTRESS_EXEC_PROTOCOL"
