"""What a failure folder hands to the maintainer of the code that failed.

:func:`write_handover` adds, beside the folder's case and verdict:

``repro.py`` (Python code) or ``input.txt`` + ``command.txt`` + ``repro.sh`` (a program)
    The failure in the terms of that code, without hullstress (:mod:`.repro`).
``certificate.json``
    Exact witnesses of every failed check (:mod:`.certificate_json`).
``verify.py``
    The standalone verifier (:mod:`.verify_certificate`, standard library only):
    ``python verify.py`` in the folder exits 0 only if every witness holds.
``bug-report.md``
    A report short enough to paste into the library's issue tracker.
"""

from __future__ import annotations

import json
import platform
import shutil
import warnings
from fractions import Fraction
from pathlib import Path
from typing import Any

import numpy as np

from ..files import atomic_write_text
from ..records import Sphere, Stage, Status
from . import verify_certificate
from .certificate_json import build_certificate, no_certificate

__all__ = ["write_handover", "HANDOVER_FILES", "library_of"]

#: Files every folder gets (plus ``repro.py`` or the program's ``input.txt``/``command.txt``/``repro.sh``).
HANDOVER_FILES = ("certificate.json", "verify.py", "bug-report.md")
#: Points shown inline in bug-report.md (more: see the points file).
_SHOWN = 40

_DISTRIBUTIONS = {"scipy_qhull": ("scipy", "scipy.spatial.ConvexHull (Qhull)"),
                  "shapely_geos": ("shapely", "shapely.geometry.MultiPoint(points).convex_hull (GEOS)"),
                  "cgal_hull": ("cgal", "CGAL (cgal Python bindings)")}


def library_of(spec: Any) -> tuple[str, str]:
    """(name with version, how it is called) of the code behind a registered algorithm."""
    from importlib.metadata import PackageNotFoundError, version

    from ..adapters.executable import ExecutableHull

    if spec is None:
        return "unknown (its plug-in was not loaded)", ""
    if isinstance(spec.func, ExecutableHull):
        return f"the program {spec.func.program}", spec.func.command
    module = spec.module or ""
    for key, (dist, what) in _DISTRIBUTIONS.items():
        if module.endswith(key):
            if key == "scipy_qhull":
                from ..adapters.scipy_qhull import QHULL_OPTIONS

                what = f"scipy.spatial.ConvexHull(points, qhull_options={QHULL_OPTIONS.get(spec.name)!r})"
            try:
                return f"{dist} {version(dist)}", what
            except PackageNotFoundError:
                return dist, what
    if module.startswith("hullstress."):
        from .. import __version__

        return f"hullstress {__version__} ({module})", f"{module}.{spec.func.__name__}"
    top = module.split(".")[0]
    try:
        return f"{top} {version(top)}", f"{module}.{getattr(spec.func, '__qualname__', '')}"
    except (PackageNotFoundError, ValueError):
        return f"plug-in {module}", f"{module}.{getattr(spec.func, '__qualname__', '')}"


def _given(case: Any, config: Any, row: Any, recorded_faces: Any) -> tuple[np.ndarray, float | None, Any, str]:
    """The points the algorithm was given, its eps, its output on them and a note on the sphere variant.

    Nothing of the code under test runs here (the report stage runs no code):
    with the sphere variant the projection is recomputed (hullstress's own,
    deterministic method) and the recorded output, saved in input rows, is
    turned back into rows of the projected points.
    """
    from ..config import sphere_duplicate_policy
    from ..sphere import sphere_project
    from ..tolerance import tolerance

    recorded = row.get("eps_value")
    eps_value = float(recorded) if recorded is not None and recorded == recorded else None
    points = np.asarray(case.points)
    if not (config.sphere == Sphere.ON and row.get("stage") == Stage.ALGORITHM
            and row.get("status") in (Status.FAIL, Status.ERROR)):
        return points, eps_value, recorded_faces, ""
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            given, index_map = sphere_project(points, eps=tolerance(points, sphere_duplicate_policy(config.eps)))
    except Exception:  # the method's own refusal was the row's error: the input is what the algorithm never got
        return points, eps_value, recorded_faces, ""
    note = ("# The sphere variant: the algorithm was given the input projected onto the unit sphere\n"
            "# (hullstress's sphere method); these are exactly those projected points.\n")
    if recorded_faces is None:
        return np.asarray(given), eps_value, None, note
    row_of = {int(r): i for i, r in enumerate(np.asarray(index_map).tolist())}
    if case.dim == 2:
        faces = [row_of[int(v)] for v in recorded_faces]
    else:
        faces = [[row_of[int(v)] for v in f] for f in recorded_faces]
    return np.asarray(given), eps_value, faces, note


def _exact_hull_vertices(points: np.ndarray, dim: int) -> list[int] | None:
    """Indices of the exact extreme points (one per distinct point), or None when not certified.

    2D: an exact monotone chain.  3D: Qhull's vertices when each is separated
    exactly and no other point is above an exactly oriented Qhull facet;
    otherwise, for small cases, a brute-force test of every point against the
    tetrahedra of the others (Caratheodory).
    """
    from .certificate_json import _extreme_3d, _hull_2d, _normal, _separates

    if not np.isfinite(points).all() or points.ndim != 2 or len(points) == 0:
        return None
    P = [[Fraction(float(x)) for x in row] for row in points.tolist()]
    if dim == 2:
        return _hull_2d(P)
    cand, tris = _extreme_3d(points, P)
    if cand and len(P) * len(tris) <= 200_000:
        separated = all(_separates(P, p, _sum_normals(P, tris, p, _normal)) for p in cand)
        inside = all(_dot3(_normal(P, t), [x - y for x, y in zip(P[q], P[t[0]])]) <= 0
                     for t in tris for q in range(len(P)))
        if separated and inside:
            return sorted(cand)
    return _extreme_brute_force(P) if len(P) <= 14 else None


def _dot3(a: list[Fraction], b: list[Fraction]) -> Fraction:
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def _sum_normals(P: list[list[Fraction]], tris: list[list[int]], p: int, normal: Any) -> list[Fraction]:
    c = [Fraction(0)] * 3
    for t in tris:
        if p in t:
            c = [x + y for x, y in zip(c, normal(P, t))]
    return c


def _extreme_brute_force(P: list[list[Fraction]]) -> list[int] | None:
    """Exact extreme points of a small full-dimensional 3D set: those in no tetrahedron of the others."""
    from itertools import combinations

    firsts: dict[tuple[Fraction, ...], int] = {}
    for i, p in enumerate(P):
        firsts.setdefault(tuple(p), i)
    ids = sorted(firsts.values())
    out = []
    for p in ids:
        others = [i for i in ids if i != p]
        if not any(_in_tetrahedron(P, p, quad) for quad in combinations(others, 4)):
            out.append(p)
    return out if len(out) >= 4 else None  # fewer: the set is flat, handled as such elsewhere


def _in_tetrahedron(P: list[list[Fraction]], p: int, quad: tuple[int, ...]) -> bool:
    a = P[quad[0]]
    cols = [[x - y for x, y in zip(P[j], a)] for j in quad[1:]]
    r = [x - y for x, y in zip(P[p], a)]

    def det(c0: list[Fraction], c1: list[Fraction], c2: list[Fraction]) -> Fraction:
        return _dot3(c0, [c1[1] * c2[2] - c1[2] * c2[1], c1[2] * c2[0] - c1[0] * c2[2], c1[0] * c2[1] - c1[1] * c2[0]])

    d = det(*cols)
    if d == 0:
        return False
    lam = [det(r, cols[1], cols[2]) / d, det(cols[0], r, cols[2]) / d, det(cols[0], cols[1], r) / d]
    return min(lam) >= 0 and sum(lam) <= 1


def _words(w: dict[str, Any], points: np.ndarray) -> str:
    """One witness in a sentence."""
    k = w["kind"]
    at = lambda i: f"point {i} {points[i].tolist()}"  # noqa: E731
    if k == "outside" and len(w["triangle"]) == 2:
        return (f"{at(w['point'])} lies strictly outside the polygon's edge {w['triangle'][0]}->{w['triangle'][1]} "
                f"(to its right: the exact orientation sign is {w['orient']:+d})")
    if k == "outside":
        return (f"{at(w['point'])} lies strictly outside face {w['face']} (vertices {w['triangle']}): "
                f"the exact orientation sign is {w['orient']:+d}")
    if k == "reflex":
        return (f"the edge {w['triangle'][:2]} between faces {w['faces']} is reflex: vertex {w['apex']} of face "
                f"{w['faces'][1]} lies above face {w['faces'][0]} (exact sign +1)")
    if k == "reflex-vertex":
        return f"the polygon turns clockwise at vertex {w['vertices'][1]} (exact orientation of {w['vertices']} is -1)"
    if k == "edge-count":
        return f"the edge {w['edge']} belongs to {w['count']} faces {w['faces']} (a closed surface has 2)"
    if k == "edge-direction":
        return f"the edge {w['edge']} is used in the same direction by faces {w['faces']}"
    if k == "repeated-vertex":
        return f"vertex {w['vertex']} appears twice in one face"
    if k in ("signed-area", "signed-volume"):
        measure = Fraction(_exact(w["value"]))
        if measure == 0:
            return (f"the output encloses exactly zero {k.split('-')[1]}, although points {w['spanning']} span "
                    "the space (exact orientation nonzero)")
        return f"the exact signed {k.split('-')[1]} enclosed is {measure}, negative: the output faces inward"
    if k == "non-planar":
        return f"face {w['face']} is not planar: vertices {w['vertices']} have exact orientation {w['orient']:+d}"
    if k == "non-convex":
        return f"face {w['face']} is not convex: its turns at {w['turns'][0][1]} and {w['turns'][1][1]} point opposite ways"
    if k == "missing-extreme":
        return (f"{at(w['point'])} is an extreme point (the only highest point in direction "
                f"{[float(_exact(x)) for x in w['direction']]}) but is not a vertex of the output")
    if k == "not-extreme":
        parts = " + ".join(f"{_exact(lam)}*p{i}" for i, lam in w["combination"])
        return f"vertex {w['vertex']} is not an extreme point: it equals {parts}"
    if k == "coincident":
        return f"vertices {w['vertices'][0]} and {w['vertices'][1]} of face {w['face']} are the same point (a zero-length edge)"
    if k == "zero-area":
        return f"face {w['face']} has no area: its distinct vertices lie on one line (exactly)"
    if k == "backtrack":
        return (f"on collinear input the output turns back at vertex {w['vertices'][1]}, which lies strictly "
                "inside the hull segment, so the walk is not the segment's boundary")
    if k == "face-size":
        return f"face {w['face']} has {w['size']} vertices, but the contract promises triangles"
    if k == "flat":
        return "every input point lies on one line/plane, so the contract promises an exception, not a hull"
    return k


def _exact(text: str) -> Fraction:
    return Fraction(float.fromhex(text)) if "x" in text else Fraction(text)


def _bug_report(*, spec: Any, row: Any, case: Any, points: np.ndarray, faces: Any, cert: dict[str, Any],
                kind: str, hull: list[int] | None, minimal: int, original: int, folder: Path) -> str:
    import numpy

    library, call = library_of(spec)
    status = str(row.get("status"))
    contract = spec.contract if spec is not None else None
    witnesses = cert.get("witnesses", [])
    if status == Status.FAIL and witnesses:
        what = f"The output is not the convex hull: {_words(witnesses[0], points)}."
        if len(witnesses) > 1:
            what += f" ({len(witnesses) - 1} more witnesses in certificate.json.)"
    elif status == Status.FAIL:
        what = f"The output is not the convex hull ({row.get('reason')}); no exact witness was found."
    else:
        what = f"The call ended in {status}: {row.get('reason')}."
    shown = points.reshape(len(points), -1) if points.ndim >= 1 and points.size else points
    listing = "\n".join(", ".join(repr(float(x)) for x in p) for p in shown[:_SHOWN])
    more = f"\n... ({len(shown) - _SHOWN} more rows in the folder's points file)" if len(shown) > _SHOWN else ""
    run = "python repro.py" if kind == "python" else "sh repro.sh   # i.e. " + (folder / "command.txt").read_text().strip()
    needs = (f"needs only numpy and {library.split()[0]}" if kind == "python"
             else "the input file exactly as the program read it on stdin")
    correct = ("unknown (no exactly certified hull)" if hull is None
               else f"the exact hull's vertices are the points {hull} "
                    f"({'counter-clockwise' if case.dim == 2 else 'sorted'}; computed in exact arithmetic)")
    if faces is None:
        returned = "nothing (" + status + ")"
    else:
        returned = json.dumps(faces) if len(json.dumps(faces)) < 1500 else json.dumps(faces)[:1500] + " ..."
    lines = [
        f"# {library}: {'wrong convex hull' if status == Status.FAIL else status} on {minimal} points",
        "",
        f"- **Library**: {library}" + (f", called as `{call}`" if call else ""),
        f"- **Platform**: {platform.platform()}, Python {platform.python_version()}, numpy {numpy.__version__}",
        f"- **Contract judged against**: {contract.describe() if contract is not None else 'unknown'}",
        f"- **Found by**: hullstress, generator `{case.family}`, shrunk from {original} to {minimal} points",
        "",
        f"## Minimal input ({minimal} points, {case.dim}D, exact: each value is a round-trip float)",
        "",
        "```text",
        listing + more,
        "```",
        "",
        "## What was returned",
        "",
        "```text",
        returned,
        "```",
        "",
        "## What is wrong",
        "",
        what,
        "",
        "## Reproduce",
        "",
        f"`{run}` ({needs}) prints the output and the reason it is wrong, in exact rational arithmetic.",
        "`python verify.py` checks `certificate.json` (every number exact) with the Python standard library only.",
        "",
        "## A correct answer",
        "",
        correct + ".",
        "",
    ]
    return "\n".join(lines)


def write_handover(folder: Path, record: Any) -> dict[str, Any]:
    """Write the reproducer, ``certificate.json``, ``verify.py`` and ``bug-report.md`` into a failure folder.

    Parameters
    ----------
    folder : Path
        The cause's folder (``case.json``, ``faces.json`` already written).
    record : TriageRecord
        The cause's representative.

    Returns
    -------
    dict
        The certificate written.
    """
    from .repro import write_reproducer

    config, result = record.config, record.shrink
    case, row = result.case, result.row
    row = row if row is not None else {}
    try:
        spec = config.spec
    except Exception:  # an algorithm from a plug-in not loaded in this process
        spec = None
    status = str(row.get("status", record.signature.status))
    recorded_faces = record.faces if status == Status.FAIL else None
    points, eps_value, faces, note = _given(case, config, row, recorded_faces)
    sphere_given = bool(note)
    failed = [c for c in str(row.get("failed_checks") or "").split(",") if c]
    if status != Status.FAIL or faces is None or not np.isfinite(points).all() or points.ndim != 2:
        why = row.get("reason") or record.faces_note or status
        cert = no_certificate(status, str(why))
    else:
        points_file = "given.json" if sphere_given else (
            "points.csv" if (folder / "points.csv").exists() else "points.npy")
        faces_file = "given.json" if sphere_given else "faces.json"
        if sphere_given:
            atomic_write_text(folder / "given.json", json.dumps(
                {"note": "the sphere variant's projected points the algorithm was given, and its output on them",
                 "points": [[float(x).hex() for x in p] for p in points.tolist()], "faces": faces}) + "\n")
        hints = [int(i) for k, v in json.loads(row.get("offending") or "{}").items() if "face" not in k
                 and "edge" not in k for i in v] if not sphere_given else []
        cert = build_certificate(points, faces, dim=case.dim, failed_checks=failed, hints=hints,
                                 points_file=points_file, faces_file=faces_file,
                                 algorithm=config.algorithm, config=config.label,
                                 contract=spec.contract.label if spec is not None else "", status=status)
    atomic_write_text(folder / "certificate.json", json.dumps(cert, indent=1) + "\n")
    shutil.copyfile(verify_certificate.__file__, folder / "verify.py")
    kind = "none"
    if spec is not None:
        direction = next(((w["point"], w["direction"]) for w in cert.get("witnesses", [])
                          if w["kind"] == "missing-extreme"), None)
        header = (f"Reproducer: {config.label}, declared contract {spec.contract.label}, "
                  f"{status} on {len(points)} points.")
        if row.get("stage") == Stage.PREPROCESS and config.sphere == Sphere.ON:
            header += ("\nThe failure is hullstress's sphere method (stage preprocess), not the algorithm: "
                       "`hullstress reproduce` (reproduce.txt) replays it.")
        kind = write_reproducer(folder, spec, points, eps_value=eps_value, sphere_note=note, direction=direction,
                                strict=spec.contract.vertices == "extreme", header=header)
    # Qhull proposes the 3D vertices: only on points it has already survived (a fail row's checker reference).
    hull = _exact_hull_vertices(np.asarray(points), case.dim) if status == Status.FAIL else None
    atomic_write_text(folder / "bug-report.md", _bug_report(
        spec=spec, row=row, case=case, points=np.asarray(points), faces=faces, cert=cert, kind=kind, hull=hull,
        minimal=result.minimal_size, original=result.original_size, folder=folder))
    return cert
