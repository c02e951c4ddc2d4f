"""``python -m hullstress export CASE``: write a case for qconvex or any other tool.

Points formats (``npy``, ``csv``, ``qhull``, ``off``, ``xyz``) write the
case's exact points.  ``i`` and ``Fx`` write the case's hull as Qhull's
programs print it (``qconvex i`` / ``qconvex Fx``), computed by the checker's
Qhull reference (:func:`hullstress.checker.qhull_reference`): ``i`` lists
facets (3D: clockwise seen from outside, as Qhull does; 2D: directed edges),
``Fx`` the extreme points (2D: counter-clockwise).  A file written this way
reads back with ``check POINTS FACES`` (3D ``i`` with ``--clockwise``).
"""

from __future__ import annotations

import argparse
import sys
import tempfile
from pathlib import Path

from ..errors import UsageError
from . import EXIT_STATUS_HELP

__all__ = ["add_parser", "export_command", "load_case_points"]

#: Points formats, then Qhull's hull output formats.
POINT_FORMATS = ("npy", "csv", "qhull", "off", "xyz")
HULL_FORMATS = ("i", "Fx")
FORMATS = POINT_FORMATS + HULL_FORMATS


def add_parser(sub: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    p = sub.add_parser(
        "export",
        help="write a case's points (npy, csv, qhull, off, xyz) or its hull as Qhull prints it (i, Fx)",
        description="Write a case's exact points for another tool, e.g. "
        "`python -m hullstress export tests/corpus/ID.json --format qhull | qconvex Tv`, or its hull in "
        "Qhull's 'i' / 'Fx' output format (from the checker's Qhull reference; 3D 'i' facets clockwise "
        "seen from outside, as qconvex prints them). CASE is a corpus file, a corpus entry id (looked up "
        "in --corpus), any points file --points-file reads, or '-' for stdin. " + EXIT_STATUS_HELP,
    )
    p.add_argument("case", metavar="CASE", help="corpus .json file, corpus entry id, points file, or '-' (stdin)")
    p.add_argument("--format", choices=FORMATS, required=True, help="output format")
    p.add_argument("-o", "--output", default=None, metavar="FILE", help="output file (default: stdout; required for npy)")
    p.add_argument("--corpus", default="tests/corpus", metavar="DIR", help="where to look up an entry id (default tests/corpus)")
    p.add_argument("--qhull-options", default=None, metavar="OPTIONS",
                   help="Qhull options for the hull of --format i / Fx (tried first, then the usual fallbacks)")
    p.set_defaults(handler=export_command)


def load_case_points(spec: str, corpus_dir: str):
    """Points of CASE: a corpus file, an entry id in ``corpus_dir``, a points file or ``-`` (stdin)."""
    from ..corpus.store import FORMAT, load_entry
    from ..io import STDIN, read_points

    if spec == STDIN:
        return read_points(STDIN)
    path = Path(spec)
    if not path.exists():
        candidate = Path(corpus_dir) / f"{spec}.json"
        if candidate.exists():
            path = candidate
        else:
            raise UsageError(f"CASE {spec!r}: no such file, and no entry {spec!r} in corpus {corpus_dir!r}")
    if path.suffix == ".json":
        head = path.read_text(encoding="utf-8", errors="replace")[:200]
        if FORMAT in head:
            return load_entry(path).case.points
    return read_points(path)


def _hull_text(points, fmt: str, qhull_options: str | None, case: str) -> str:
    """The case's hull in Qhull's ``i`` or ``Fx`` layout, from the checker's Qhull reference."""
    from ..checker import qhull_reference
    from ..qhull_format import check_qhull_options, format_fx, format_i

    check_qhull_options(qhull_options)
    ref = qhull_reference(points, options=qhull_options)
    if ref.faces is None or ref.vertices is None:
        raise UsageError(f"CASE {case!r}: Qhull found no hull to export: {ref.error}")
    dim = points.shape[1]
    if fmt == "Fx":
        return format_fx(ref.vertices if dim == 2 else sorted(int(v) for v in ref.vertices))
    if dim == 2:
        return format_i(ref.faces, 2)
    return format_i([list(face)[::-1] for face in ref.faces.polygons()], 3)  # Qhull's 'i' is clockwise in 3D


def export_command(args: argparse.Namespace) -> int:
    from ..errors import CorpusError
    from ..files import atomic_write_bytes
    from ..io import write_points

    try:
        points = load_case_points(args.case, args.corpus)
    except CorpusError as exc:
        raise UsageError(str(exc)) from None
    if points.ndim != 2 or points.shape[1] not in (2, 3):
        raise UsageError(f"CASE {args.case!r}: points of shape {points.shape} cannot be exported (need (n, 2) or (n, 3))")
    if args.format == "off" and points.shape[1] != 3:
        raise UsageError(f"--format off needs 3D points, CASE {args.case!r} is {points.shape[1]}D")
    if args.format == "npy" and not args.output:
        raise UsageError("--format npy writes binary: give -o FILE")
    if args.format in HULL_FORMATS:
        data = _hull_text(points, args.format, args.qhull_options, args.case).encode("utf-8")
    else:
        with tempfile.TemporaryDirectory() as tmp:
            data = write_points(Path(tmp) / f"case.{args.format}", points, args.format).read_bytes()
    if args.output:
        output = Path(args.output)
        if output.is_dir():
            raise UsageError(f"-o {args.output!r} is a folder, expected a file name")
        if not output.parent.is_dir():
            raise UsageError(f"-o {args.output!r}: no such folder {str(output.parent)!r}")
        atomic_write_bytes(output, data)  # a refused write is an EnvironmentFailure naming the path (exit 4)
        return 0
    sys.stdout.write(data.decode("utf-8"))
    return 0
