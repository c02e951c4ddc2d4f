"""Standalone reproducers: the failure in the terms of the code that failed, without hullstress.

For Python code (a library adapter, a plug-in, an in-house algorithm) the
folder gets ``repro.py``: the points as exact ``float.fromhex`` literals, the
same call with the same options (a sphere variant's projected points and an
eps value written out as literals), the output printed, and an inline exact
check (:data:`INLINE_CHECK`, ``fractions`` only) that prints the first reason
the output is not the convex hull and exits 1, or exits 0 when it finds none.

* scipy / shapely / CGAL adapters: the library's own API call
  (``ConvexHull(points, qhull_options=...)``, ``MultiPoint(points).convex_hull``,
  ``CGAL_Convex_hull_2.convex_hull_2``, ``convex_hull_3``), mapped to input
  indices in plain code;
* a plug-in: its file imported by path (or its module by name), with a
  stand-in ``hullstress`` module whose ``register_algorithm`` does nothing, so
  that the plug-in's own ``from hullstress import register_algorithm`` works
  without hullstress;
* an in-house algorithm: hullstress *is* the library, so the repro imports it.

For a program (``--exec``) the folder gets ``input.txt`` (exactly the bytes
the program read on stdin), ``command.txt`` (the exact command line) and
``repro.sh`` (runs it from the folder).
"""

from __future__ import annotations

import inspect
from pathlib import Path
from typing import Any

import numpy as np

from .._registry import AlgorithmSpec
from ..files import atomic_write_text
from ..records import Origin

__all__ = ["write_reproducer", "python_repro", "points_literal", "INLINE_CHECK", "repro_command"]

#: The exact check every ``repro.py`` ends with (standard library only).
INLINE_CHECK = r'''
# ---- why this output is not the convex hull: exact rational arithmetic, nothing else ----
from fractions import Fraction as F


def _why_wrong(points, out, dim, direction=None, strict=False):
    P = [[F(x) for x in p] for p in points]
    sub = lambda a, b: [x - y for x, y in zip(a, b)]
    if dim == 2:
        poly = [int(v) for v in out]
        k = len(poly)
        turn = lambda a, b, c: (P[b][0] - P[a][0]) * (P[c][1] - P[a][1]) - (P[b][1] - P[a][1]) * (P[c][0] - P[a][0])
        if len(set(poly)) < k:
            return "a vertex appears twice in the polygon %s" % poly
        if len({tuple(P[v]) for v in poly}) < k:
            return "two vertices of the polygon %s are the same point (a zero-length edge)" % poly
        for i in range(k):
            a, b = poly[i], poly[(i + 1) % k]
            if k >= 3 and turn(a, b, poly[(i + 2) % k]) < 0:
                return "the polygon turns clockwise at vertex %d (exact orientation < 0)" % b
            for q in range(len(P)):
                if turn(a, b, q) < 0:
                    return "point %d %s lies strictly outside edge %d->%d (exact orientation < 0)" % (
                        q, points[q], a, b)
        order = sorted(range(len(P)), key=lambda i: (P[i], i))
        hull = []
        for seq in (order, order[::-1]):  # Andrew's monotone chain, exact
            part = []
            for i in seq:
                while len(part) >= 2 and turn(part[-2], part[-1], i) <= 0:
                    part.pop()
                part.append(i)
            hull += part[:-1]
        extreme = {tuple(P[i]) for i in hull} if len(hull) > 1 else {tuple(P[i]) for i in order[:1]}
        used = {tuple(P[v]) for v in poly}
        for e in sorted(extreme - used):
            return "the extreme point %s is not a vertex of the output" % ([float(x) for x in e],)
        if strict:
            for v in poly:
                if tuple(P[v]) not in extreme:
                    return "vertex %d %s is not an extreme point (the contract promises only extreme points)" % (
                        v, points[v])
        return None
    faces = [[int(v) for v in f] for f in out]
    for n, f in enumerate(faces):
        if len({tuple(P[v]) for v in f}) < len(f):
            return "two vertices of face %d %s are the same point" % (n, f)
    cross = lambda a, b: [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
    dot = lambda a, b: sum(x * y for x, y in zip(a, b))
    above = lambda a, b, c, d: dot(cross(sub(P[b], P[a]), sub(P[c], P[a])), sub(P[d], P[a]))
    edges = {}
    for n, f in enumerate(faces):
        for i in range(len(f)):
            edges.setdefault((f[i], f[(i + 1) % len(f)]), []).append(n)
    for (u, v), fs in sorted(edges.items()):
        if len(fs) > 1 or len(edges.get((v, u), [])) != 1:
            return "edge %d-%d is in %d faces one way and %d the other: not a closed surface" % (
                u, v, len(fs), len(edges.get((v, u), [])))
    for n, f in enumerate(faces):
        for i in range(1, len(f) - 1):
            for q in range(len(P)):
                if above(f[0], f[i], f[i + 1], q) > 0:
                    return "point %d %s lies strictly outside face %d %s (exact orientation > 0)" % (
                        q, points[q], n, f)
        for (u, v) in zip(f, f[1:] + f[:1]):
            g = faces[edges[(v, u)][0]]
            x = f[(f.index(v) + 1) % len(f)]
            for w in g:
                if above(u, v, x, w) > 0:
                    return "edge %d-%d is reflex: vertex %d of the neighbouring face is above face %d" % (u, v, w, n)
    if direction is not None:
        p, c = direction
        c = [F(x) for x in c]
        if tuple(P[p]) not in {tuple(P[v]) for f in faces for v in f} and all(
                dot(c, r) < dot(c, P[p]) for r in P if r != P[p]):
            return "point %d %s is the only highest point in direction %s, so extreme, but not a vertex" % (
                p, points[p], c)
    return None


_reason = _why_wrong(points, output, DIM, DIRECTION, STRICT)
print("wrong:", _reason if _reason else "no failure found: the output is a correct hull")
raise SystemExit(1 if _reason else 0)
'''


def points_literal(points: np.ndarray) -> str:
    """``np.array([...])`` of ``float.fromhex`` literals: exact, whatever the values (NaN, -0.0, subnormals)."""
    arr = np.asarray(points, dtype=np.float64)
    rows = arr.reshape(len(arr), -1).tolist() if arr.ndim >= 1 and arr.size else []
    body = ",\n".join("    [" + ", ".join(f"H({float(x).hex()!r})" for x in row) + "]" for row in rows)
    text = f"H = float.fromhex\npoints = np.array([\n{body}\n], dtype=np.float64)"
    if arr.ndim != 2:
        text += f".reshape({tuple(arr.shape)!r})"
    return text


def _scipy_call(spec: AlgorithmSpec) -> tuple[str, str]:
    from ..adapters.scipy_qhull import QHULL_OPTIONS

    options = QHULL_OPTIONS.get(spec.name)
    call = (f"from scipy.spatial import ConvexHull\n\nhull = ConvexHull(points, qhull_options={options!r})\n")
    if spec.dim == 2:
        return "scipy", call + "output = hull.vertices.tolist()  # counter-clockwise in 2D\n"
    return "scipy", call + (
        "# simplices are unoriented: orient each as Qhull's own facet normal (hull.equations) says\n"
        "output = []\n"
        "for (a, b, c), eq in zip(hull.simplices.tolist(), hull.equations):\n"
        "    normal = np.cross(points[b] - points[a], points[c] - points[a])\n"
        "    output.append([a, b, c] if normal @ eq[:3] >= 0 else [a, c, b])\n")


def _shapely_call(spec: AlgorithmSpec) -> tuple[str, str]:
    return "shapely", (
        "from shapely.geometry import MultiPoint, Polygon\nfrom shapely.geometry.polygon import orient\n\n"
        "hull = MultiPoint(points).convex_hull\nprint('GEOS returned', hull.wkt)\n"
        "assert isinstance(hull, Polygon), 'not a polygon'\n"
        "index = {}\nfor i, p in enumerate(points.tolist()):\n    index.setdefault(tuple(p), i)\n"
        "output = [index[tuple(c)] for c in list(orient(hull, sign=1.0).exterior.coords)[:-1]]  # GEOS copies inputs\n")


_CGAL_2D = {"cgal-convex-hull-2d": "convex_hull_2", "cgal-graham-andrew-2d": "ch_graham_andrew",
            "cgal-jarvis-2d": "ch_jarvis"}


def _cgal_call(spec: AlgorithmSpec) -> tuple[str, str]:
    index = "index = {}\nfor i, p in enumerate(points.tolist()):\n    index.setdefault(tuple(p), i)\n"
    if spec.dim == 2:
        fn = _CGAL_2D.get(spec.name, "convex_hull_2")
        return "cgal", (
            "from CGAL.CGAL_Kernel import Point_2\nfrom CGAL import CGAL_Convex_hull_2\n\nresult = []\n"
            f"CGAL_Convex_hull_2.{fn}([Point_2(x, y) for x, y in points.tolist()], result)\n"
            + index + "output = [index[(p.x(), p.y())] for p in result]  # CGAL copies the input doubles\n")
    return "cgal", (
        "from CGAL.CGAL_Kernel import Point_3\nfrom CGAL.CGAL_Polyhedron_3 import Polyhedron_3\n"
        "from CGAL import CGAL_Convex_hull_3\n\npoly = Polyhedron_3()\n"
        "CGAL_Convex_hull_3.convex_hull_3([Point_3(x, y, z) for x, y, z in points.tolist()], poly)\n"
        + index + "output = []\nfor facet in poly.facets():\n    h, face = facet.halfedge(), []\n"
        "    for _ in range(facet.facet_degree()):\n        p = h.vertex().point()\n"
        "        face.append(index[(p.x(), p.y(), p.z())])\n        h = h.next()\n    output.append(face)\n")


_SHIM = ('# The plug-in registers itself with hullstress; a stand-in lets it import without hullstress.\n'
         'import sys, types\nif "hullstress" not in sys.modules:\n'
         '    _shim = types.ModuleType("hullstress")\n'
         '    _shim.register_algorithm = lambda *a, **k: (lambda f: f)\n'
         '    _shim.register_generator = lambda *a, **k: (lambda f: f)\n'
         '    sys.modules["hullstress"] = _shim\n')


def _module_call(spec: AlgorithmSpec, kwargs: str) -> tuple[str, str]:
    func = spec.func
    module = getattr(func, "__module__", "") or ""
    name = getattr(func, "__qualname__", getattr(func, "__name__", "hull"))
    if spec.origin == Origin.IN_HOUSE.value or module.startswith("hullstress."):
        return module, f"from {module} import {name}\n\noutput = {name}(points{kwargs})\n"
    try:
        source = inspect.getsourcefile(func)
    except TypeError:
        source = None
    # A --plugin file is imported under a made-up name (hullstress.plugins): import it by path, as given.
    from_file = module.startswith("hullstress_plugin_") or module == "__main__" or not _importable(module)
    if source and from_file:
        return source, (_SHIM + "import importlib.util\n"
                        f"_spec = importlib.util.spec_from_file_location('plugin_under_test', {str(Path(source).resolve())!r})\n"
                        "plugin = importlib.util.module_from_spec(_spec)\n_spec.loader.exec_module(plugin)\n\n"
                        f"output = plugin.{name}(points{kwargs})\n")
    return module, (_SHIM + f"from {module} import {name}\n\noutput = {name}(points{kwargs})\n")


def _importable(module: str) -> bool:
    """Whether ``module`` would import by name in a fresh interpreter (not a file the plug-in loader named)."""
    import importlib.util

    try:
        return importlib.util.find_spec(module) is not None
    except (ImportError, ValueError):
        return False


def python_repro(spec: AlgorithmSpec, points: np.ndarray, *, eps_value: float | None, sphere_note: str,
                 direction: tuple[int, list[str]] | None, strict: bool, header: str) -> str:
    """The text of ``repro.py`` for a Python algorithm on ``points`` (the points it was given)."""
    kwargs = "" if eps_value is None else f", eps=float.fromhex({float(eps_value).hex()!r})"
    module = spec.module or ""
    if module.startswith("hullstress.adapters.scipy_qhull"):
        library, call = _scipy_call(spec)
    elif module.startswith("hullstress.adapters.shapely_geos"):
        library, call = _shapely_call(spec)
    elif module.startswith("hullstress.adapters.cgal_hull"):
        library, call = _cgal_call(spec)
    else:
        library, call = _module_call(spec, kwargs)
    flip = ("# the contract says clockwise: reverse to counter-clockwise before checking\n"
            + ("output = output[::-1]\n" if spec.dim == 2 else "output = [list(f)[::-1] for f in output]\n")
            if spec.clockwise else "")
    lines = [
        f'"""{header}',
        "",
        f"Needs only numpy and {library}; run: python repro.py (exit 1: the failure is shown, 0: not reproduced).",
        '"""',
        "import numpy as np",
        "",
        sphere_note + points_literal(points),
        "",
        call.rstrip("\n"),
        "output = np.asarray(output).tolist() if not isinstance(output, list) else output",
        flip.rstrip("\n"),
        "print('output:', output)",
        f"DIM, STRICT = {spec.dim}, {strict!r}",
        f"DIRECTION = {direction!r}  # an exactly separating direction for an extreme point (from certificate.json)",
    ]
    return "\n".join(line for line in lines if line is not None) + "\n" + INLINE_CHECK


def repro_command(kind: str) -> str:
    """The command a maintainer runs inside the folder."""
    return "python repro.py" if kind == "python" else "sh repro.sh"


def write_reproducer(folder: Path, spec: AlgorithmSpec, points: np.ndarray, *, eps_value: float | None,
                     sphere_note: str = "", direction: tuple[int, list[str]] | None = None,
                     strict: bool = False, header: str = "") -> str:
    """Write the folder's reproducer for ``spec`` on ``points``; return its kind (``python`` or ``program``)."""
    from ..adapters.executable import ExecutableHull

    func = spec.func
    if isinstance(func, ExecutableHull):
        from ..qhull_format import format_points

        arr = np.asarray(points, dtype=np.float64)
        try:
            data = format_points(arr)
        except ValueError as exc:
            data = ""
            atomic_write_text(folder / "input.txt.missing", f"the points cannot be written in Qhull's format: {exc}\n")
        command = func.command
        atomic_write_text(folder / "input.txt", data)
        atomic_write_text(folder / "command.txt", f"{command} < input.txt\n")
        atomic_write_text(folder / "repro.sh", "#!/bin/sh\n# " + header.replace("\n", "\n# ")
                          + f"\ncd \"$(dirname \"$0\")\" && exec {command} < input.txt\n")
        (folder / "repro.sh").chmod(0o755)
        return "program"
    atomic_write_text(folder / "repro.py", python_repro(spec, points, eps_value=eps_value, sphere_note=sphere_note,
                                                         direction=direction, strict=strict, header=header))
    return "python"

