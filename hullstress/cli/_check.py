"""``python -m hullstress check POINTS FACES``: certify a hull produced by any program.

Reads the points (``.npy``, ``.csv``, ``.xyz``, ``.off``, Qhull/rbox text;
``-`` for stdin) and the faces (``.npy``, ``.csv``, ``.off``, Qhull's ``i`` or
``Fx`` output; ``--faces-format`` names the format instead of guessing it),
runs the exact checker and prints a short verdict (or JSON with ``--json``).
Exit status 0 when the hull is valid, 1 when a check fails, 2 for unreadable
or malformed input (a :class:`~hullstress.errors.UsageError`, reported by ``main``).

``qconvex i < points.txt > hull.i; python -m hullstress check points.txt hull.i --clockwise``
certifies Qhull's own output (its 3D ``i`` facets are clockwise seen from outside).
"""

from __future__ import annotations

import argparse
import json
import math

from ..errors import ContractViolation, InputFileError, UsageError
from ..io import STDIN, read_faces, read_points
from ..qhull_format import HULL_FORMATS
from ..verdict import AGREE, DISAGREE, QHULL_WRONG
from . import EXIT_STATUS_HELP
from ._common import count

__all__ = ["add_parser", "run_check"]

#: ``--faces-format`` values: guess from the file, or one of Qhull's output formats.
FACES_FORMATS = ("auto",) + HULL_FORMATS


def add_parser(subparsers: argparse._SubParsersAction) -> argparse.ArgumentParser:
    """Register the ``check`` subcommand."""
    parser = subparsers.add_parser(
        "check",
        help="certify a hull produced by any program (points file + faces file)",
        description=(
            "Certify a convex hull with exact predicates: containment, convexity, manifoldness, "
            "and agreement with Qhull. Points: .npy, .csv, .xyz, .off or Qhull/rbox text. "
            "Faces: .npy, .csv, .off or Qhull 'i' / 'Fx' output (2D: one row of vertex indices, "
            "counter-clockwise, or directed edges). Either file may be '-' (stdin), e.g. "
            "rbox 100 D3 | tee pts.txt | qconvex i | python -m hullstress check pts.txt - --clockwise."
        ),
        epilog="0 means a valid hull, 1 a failed check. " + EXIT_STATUS_HELP,
    )
    parser.add_argument("points", metavar="POINTS", help="points file ('-' reads stdin)")
    parser.add_argument("faces", metavar="FACES",
                        help="faces file ('-' reads stdin; 3D faces counter-clockwise seen from outside)")
    parser.add_argument("--faces-format", choices=FACES_FORMATS, default="auto",
                        help="how FACES is written: auto (guess from the name and content, default), i (Qhull's "
                        "facet indices; 2D: edges), Fx (Qhull's 2D extreme points, counter-clockwise) or off "
                        "(OFF, vertices matched to the points)")
    parser.add_argument("--dim", type=int, choices=(2, 3), default=None, help="expected dimension of the points")
    parser.add_argument(
        "--clockwise",
        action="store_true",
        help="the faces are listed clockwise seen from outside (as in Qhull's 3D 'i' and 'o' output); "
        "each face is reversed before checking",
    )
    parser.add_argument("--json", action="store_true", help="print the verdict as one JSON object")
    parser.add_argument("--no-qhull", action="store_true", help="skip the comparison with Qhull")
    parser.add_argument("--qhull-options", default=None, metavar="OPTIONS",
                        help="Qhull options for the reference hull (tried first, then the usual fallbacks)")
    parser.add_argument(
        "--max-offending", type=count(minimum=0), default=20, metavar="N",
        help="list at most N offending indices per kind (default 20)"
    )
    parser.set_defaults(handler=run_check)
    return parser


def _json_value(value):
    if isinstance(value, float) and not math.isfinite(value):
        return repr(value)
    return value


def run_check(args: argparse.Namespace) -> int:
    """Run the ``check`` subcommand; returns 0 (valid) or 1 (invalid).

    Raises
    ------
    InputFileError
        Unreadable points or faces, or faces that break the output contract.
    """
    from ..checker import check, qhull_reference  # imported here: `python -m hullstress list` need not load scipy
    from ..qhull_format import check_qhull_options

    if args.points == STDIN and args.faces == STDIN:
        raise UsageError("POINTS and FACES cannot both be '-': standard input holds one file")
    check_qhull_options(args.qhull_options)
    points = read_points(args.points, dim=args.dim)
    dim = points.shape[1]
    faces = _read_faces(args.faces, args.faces_format, points)
    if args.clockwise:
        faces = [f[::-1] for f in faces] if dim == 3 else list(faces)[::-1]
    reference = None
    if args.qhull_options and not args.no_qhull:
        reference = qhull_reference(points, options=args.qhull_options)
    try:
        verdict = check(points, faces, reference=reference, qhull=not args.no_qhull, max_offending=args.max_offending)
    except ContractViolation as exc:
        raise InputFileError(f"faces file '{args.faces}': {exc}") from None
    if args.json:
        row = {k: _json_value(v) for k, v in verdict.as_row().items()}
        row["offending"] = {k: list(v) for k, v in verdict.offending.items()}
        row["ok"] = verdict.ok
        row["detail"] = verdict.detail
        print(json.dumps(row, sort_keys=False))
    else:
        _print_human(verdict, dim)
    return 0 if verdict.ok else 1


def _read_faces(path: str, faces_format: str, points):
    """The faces file in ``faces_format`` (``auto``: :func:`hullstress.io.read_faces`'s guess)."""
    if faces_format == "auto":
        return read_faces(path, dim=points.shape[1])
    import sys
    from pathlib import Path

    from ..qhull_format import parse_hull

    try:
        text = sys.stdin.read() if path == STDIN else Path(path).read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        raise InputFileError(f"faces file '{path}' cannot be read: {getattr(exc, 'strerror', None) or exc}") from None
    try:
        return parse_hull(text, faces_format, points)
    except ContractViolation as exc:
        raise InputFileError(f"faces file '{path}' (--faces-format {faces_format}): {exc}") from None


def _print_human(verdict, dim: int) -> None:
    mark = {True: "pass", False: "FAIL", None: "n/a", AGREE: "pass", DISAGREE: "FAIL",
            QHULL_WRONG: "n/a (Qhull's own hull fails the exact checks)"}
    status = "VALID" if verdict.ok else "INVALID"
    print(f"{status}: {verdict.detail}")
    for name in ("containment", "convexity", "manifoldness", "qhull_agreement"):
        print(f"  {name:<16} {mark[getattr(verdict, name)]}")
    faces = "faces" if dim == 3 else "edges"
    extreme = "unknown" if verdict.n_extreme is None else verdict.n_extreme
    print(
        f"  {verdict.n_hull_vertices} hull vertices, {verdict.n_faces} {faces}; extreme points {extreme}, "
        f"missing {verdict.n_missing_extreme}, on boundary but not extreme {verdict.n_boundary_nonextreme}"
    )
    print(
        f"  outside {verdict.n_outside}, reflex {verdict.n_nonconvex_edges}, degenerate {verdict.n_degenerate_faces}; "
        f"severity {verdict.severity} (max {verdict.max_violation:.3g} DISTround, DISTround {verdict.distround:.3g})"
    )
    qhull = "not run" if verdict.qhull_options is None else f"options '{verdict.qhull_options}', own hull exact: {mark[verdict.qhull_ok]}"
    print(f"  volume {verdict.volume:.17g}; qhull {qhull}")
    for key, idx in sorted(verdict.offending.items()):
        print(f"  offending {key}: {' '.join(map(str, idx))}")
