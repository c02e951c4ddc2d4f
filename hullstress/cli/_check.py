"""``python -m hullstress check POINTS FACES``: certify a hull produced by any program.

Reads the points (``.npy``, ``.csv``, ``.xyz``, ``.off``, Qhull/rbox text) and
the faces (``.npy``, ``.csv``, ``.off``, Qhull's ``i`` output), runs the exact
checker and prints a short verdict (or JSON with ``--json``).  Exit status 0
when the hull is valid, 1 when a check fails, 2 for unreadable or malformed
input (a :class:`~hullstress.errors.UsageError`, reported by ``main``).
"""

from __future__ import annotations

import argparse
import json
import math

from ..errors import ContractViolation, InputFileError
from ..io import read_faces, read_points
from ..verdict import AGREE, DISAGREE, QHULL_WRONG

__all__ = ["add_parser", "run_check"]


def add_parser(subparsers: argparse._SubParsersAction) -> argparse.ArgumentParser:
    """Register the ``check`` subcommand."""
    parser = subparsers.add_parser(
        "check",
        help="certify a hull produced by any program (points file + faces file)",
        description=(
            "Certify a convex hull with exact predicates: containment, convexity, manifoldness, "
            "and agreement with Qhull. Points: .npy, .csv, .xyz, .off or Qhull/rbox text. "
            "Faces: .npy, .csv, .off or Qhull 'i' output (2D: one row of vertex indices, "
            "counter-clockwise, or directed edges)."
        ),
        epilog="Exit status: 0 valid hull, 1 a check failed, 2 unreadable or malformed input.",
    )
    parser.add_argument("points", metavar="POINTS", help="points file")
    parser.add_argument("faces", metavar="FACES", help="faces file (3D faces counter-clockwise seen from outside)")
    parser.add_argument("--dim", type=int, choices=(2, 3), default=None, help="expected dimension of the points")
    parser.add_argument(
        "--clockwise",
        action="store_true",
        help="the faces are listed clockwise seen from outside (as in Qhull's 3D 'i' and 'o' output); "
        "each face is reversed before checking",
    )
    parser.add_argument("--json", action="store_true", help="print the verdict as one JSON object")
    parser.add_argument("--no-qhull", action="store_true", help="skip the comparison with Qhull")
    parser.add_argument(
        "--max-offending", type=int, default=20, metavar="N", help="list at most N offending indices per kind (default 20)"
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
    from ..checker import check  # imported here: `python -m hullstress list` need not load scipy

    points = read_points(args.points, dim=args.dim)
    dim = points.shape[1]
    faces = read_faces(args.faces, dim=dim)
    if args.clockwise:
        faces = [f[::-1] for f in faces] if dim == 3 else list(faces)[::-1]
    try:
        verdict = check(points, faces, qhull=not args.no_qhull, max_offending=max(0, args.max_offending))
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
