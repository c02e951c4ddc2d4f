"""``python -m hullstress export CASE``: write a case for qconvex or any other tool."""

from __future__ import annotations

import argparse
import sys
import tempfile
from pathlib import Path

from ..errors import UsageError

__all__ = ["add_parser", "export_command", "load_case_points"]

FORMATS = ("npy", "csv", "qhull", "off", "xyz")


def add_parser(sub: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    p = sub.add_parser(
        "export",
        help="write a corpus case or points file in another format (npy, csv, qhull, off, xyz)",
        description="Write a case's exact points for another tool, e.g. "
        "`python -m hullstress export tests/corpus/ID.json --format qhull | qconvex Tv`. "
        "CASE is a corpus file, a corpus entry id (looked up in --corpus), or any points file "
        "--points-file reads. Exit status 2 on a bad CASE or format.",
    )
    p.add_argument("case", metavar="CASE", help="corpus .json file, corpus entry id, or points file")
    p.add_argument("--format", choices=FORMATS, required=True, help="output format")
    p.add_argument("-o", "--output", default=None, metavar="FILE", help="output file (default: stdout; required for npy)")
    p.add_argument("--corpus", default="tests/corpus", metavar="DIR", help="where to look up an entry id (default tests/corpus)")
    p.set_defaults(handler=export_command)


def load_case_points(spec: str, corpus_dir: str):
    """Points of CASE: a corpus file, an entry id in ``corpus_dir``, or a points file."""
    from ..corpus.store import FORMAT, load_entry
    from ..io import read_points

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


def export_command(args: argparse.Namespace) -> int:
    from ..errors import CorpusError
    from ..io import write_points

    try:
        points = load_case_points(args.case, args.corpus)
    except CorpusError as exc:
        raise UsageError(str(exc)) from None
    if points.ndim != 2 or points.shape[1] not in (2, 3):
        raise UsageError(f"CASE {args.case!r}: points of shape {points.shape} cannot be exported (need (n, 2) or (n, 3))")
    if args.format == "off" and points.shape[1] != 3:
        raise UsageError(f"--format off needs 3D points, CASE {args.case!r} is {points.shape[1]}D")
    if args.output:
        write_points(args.output, points, args.format)
        return 0
    if args.format == "npy":
        raise UsageError("--format npy writes binary: give -o FILE")
    with tempfile.TemporaryDirectory() as tmp:
        out = write_points(Path(tmp) / f"case.{args.format}", points, args.format)
        sys.stdout.write(out.read_text(encoding="utf-8"))
    return 0
