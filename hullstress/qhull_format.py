"""Qhull's text formats: points in (as ``rbox`` writes them), hulls out (``i``, ``Fx``, OFF).

These are the formats of the Qhull programs (``qconvex``, ``qhull``) and of
everything built to talk to them, so they are how hullstress exchanges hulls
with a program in any language:

``points`` (Qhull's input)
    the dimension, the count, then one point per line; coordinates are
    written as ``repr(float)``, the shortest decimal that reads back to the
    same double, so the program sees exactly the case's points.
``i``
    the number of facets, then one facet per line as input point indices.
    In 3D a facet is a polygon (a triangle with ``Qt``), clockwise seen from
    outside in Qhull's own output; in 2D a facet is an edge ``a b``, and the
    edges chain into the counter-clockwise polygon.
``Fx``
    the number of extreme points, then one index per line; in 2D Qhull lists
    them counter-clockwise, so they are the polygon.
``off``
    ``OFF``, the counts ``nv nf ne``, ``nv`` vertex coordinates, then ``nf``
    faces ``k i1 ... ik`` (extra colour values ignored); Qhull's ``o`` output
    writes the dimension instead of ``OFF``.  Vertices are matched to input
    points by exact coordinates.

:func:`parse_hull` turns a program's output into raw faces for the output
contract, raising :class:`~hullstress.errors.ContractViolation` with the
offending line's number and text for anything it cannot read.
:func:`check_qhull_options` refuses option strings Qhull does not accept
(``--qhull-options``) before any work.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from .errors import ContractViolation
from .literals import parse_float

__all__ = ["HULL_FORMATS", "format_points", "parse_hull", "format_i", "format_fx", "chain_edges",
           "check_qhull_options", "input_refusal"]

#: Hull output formats a program may write.
HULL_FORMATS = ("i", "Fx", "off")

#: Characters of an offending line shown in a message.
_SHOWN = 60


def input_refusal(points: Any, dim: int) -> str:
    """Why Qhull's input format cannot carry ``points`` as ``dim``-D points, or ``""`` when it can.

    The rule for programs (``--exec``): what the format cannot carry is not
    given to them.  It cannot carry another shape, fewer points than
    dimensions (no points included: the reader takes the smaller of the two
    header numbers as the dimension) nor a coordinate that is not a finite
    number (``rbox`` and Qhull read no ``nan`` or ``inf``).

    Examples
    --------
    >>> input_refusal(np.zeros((0, 3)), 3)
    "Qhull's input format cannot say 0 points in 3D (it reads the smaller header number as the dimension)"
    >>> input_refusal([[0.0, float("nan")], [1.0, 2.0]], 2)
    "Qhull's input format has no number for nan or inf (1 point with one)"
    >>> input_refusal([[0.0, 1.0], [1.0, 2.0]], 2)
    ''
    """
    try:
        pts = np.asarray(points, dtype=np.float64)
    except (TypeError, ValueError):
        return "Qhull's input format has no number for these coordinates"
    if pts.ndim != 2 or pts.shape[1] != dim:
        return f"points of shape {pts.shape} are not {dim}D points"
    if len(pts) < dim:
        return (f"Qhull's input format cannot say {len(pts)} points in {dim}D "
                "(it reads the smaller header number as the dimension)")
    bad = int((~np.isfinite(pts)).any(axis=1).sum())
    if bad:
        return f"Qhull's input format has no number for nan or inf ({bad} point{'' if bad == 1 else 's'} with one)"
    return ""


def format_points(points: Any) -> str:
    """Qhull's input format for ``points``: dimension, count, then one point per line.

    Parameters
    ----------
    points : array_like of shape (n, d), float64

    Returns
    -------
    str

    Raises
    ------
    ValueError
        When ``points`` is not a 2-D array (a bad-input case that cannot be written).

    Examples
    --------
    >>> print(format_points([[0.1, 1.0], [5e-324, -0.0]]), end="")
    2
    2
    0.1 1.0
    5e-324 -0.0
    """
    pts = np.asarray(points, dtype=np.float64)
    if pts.ndim != 2:
        raise ValueError(f"points of shape {pts.shape} cannot be written in Qhull's format (need (n, d))")
    lines = [str(pts.shape[1]), str(pts.shape[0])]
    lines += [" ".join(repr(x) for x in row) for row in pts.tolist()]
    return "\n".join(lines) + "\n"


def format_i(faces: Any, dim: int) -> str:
    """Qhull's ``i`` layout: the count, then one facet per line (2D: the polygon's edges ``a b``).

    Examples
    --------
    >>> print(format_i([0, 1, 2], 2), end="")
    3
    0 1
    1 2
    2 0
    """
    if dim == 2:
        poly = [int(i) for i in np.asarray(faces).ravel()]
        rows = [[a, b] for a, b in zip(poly, poly[1:] + poly[:1])]
    else:
        rows = [[int(i) for i in face] for face in faces]
    return "\n".join([str(len(rows))] + [" ".join(map(str, r)) for r in rows]) + "\n"


def format_fx(indices: Any) -> str:
    """Qhull's ``Fx`` layout: the count, then one index per line.

    Examples
    --------
    >>> print(format_fx([3, 0, 2]), end="")
    3
    3
    0
    2
    """
    idx = [int(i) for i in np.asarray(indices).ravel()]
    return "\n".join([str(len(idx))] + [str(i) for i in idx]) + "\n"


def _bad(number: int, line: str, what: str) -> ContractViolation:
    shown = line.strip()
    shown = shown if len(shown) <= _SHOWN else shown[:_SHOWN] + "..."
    return ContractViolation(f"unreadable output at line {number} {shown!r}: {what}")


def _rows(text: str) -> list[tuple[int, str]]:
    """Non-blank lines with their 1-based numbers."""
    return [(k, line) for k, line in enumerate(text.splitlines(), start=1) if line.strip()]


def _ints(number: int, line: str, n_points: int, tokens: Sequence[str] | None = None) -> list[int]:
    """The line's tokens (or ``tokens`` of it) as indices in ``[0, n_points)``."""
    out = []
    for token in line.split() if tokens is None else tokens:
        try:
            value = int(token)
        except ValueError:
            raise _bad(number, line, f"{token!r} is not an integer index") from None
        if not 0 <= value < n_points:
            raise _bad(number, line, f"index {value} is out of range for {n_points} points")
        out.append(value)
    return out


def _counted(rows: list[tuple[int, str]], what: str) -> tuple[int, list[tuple[int, str]]]:
    """The leading count line and the rows it announces (no more, no fewer)."""
    if not rows:
        raise ContractViolation(f"unreadable output: the program wrote nothing (expected the number of {what})")
    number, line = rows[0]
    try:
        count = int(line.strip())
    except ValueError:
        raise _bad(number, line, f"expected the number of {what} on a line of its own") from None
    body = rows[1:]
    if count < 0 or len(body) < count:
        raise ContractViolation(f"unreadable output: line {number} announces {count} {what}, "
                                f"the output has {len(body)} more lines")
    if len(body) > count:
        extra_number, extra = body[count]
        raise _bad(extra_number, extra, f"line {number} announced {count} {what}; this line is one too many")
    return count, body


def chain_edges(edges: Sequence[Sequence[int]], *, where: str = "output") -> list[int]:
    """Chain directed edges ``a -> b`` into one closed polygon (Qhull's 2D ``i`` output).

    Raises
    ------
    ContractViolation
        When the edges do not form exactly one cycle.

    Examples
    --------
    >>> chain_edges([[0, 1], [2, 0], [1, 2]])
    [0, 1, 2]
    """
    succ: dict[int, int] = {}
    for a, b in edges:
        if a in succ:
            raise ContractViolation(f"{where}: vertex {a} starts two edges; the edges do not form one polygon")
        succ[a] = b
    if not edges:
        return []
    start = edges[0][0]
    polygon = [start]
    v = succ[start]
    while v != start:
        if v not in succ or len(polygon) > len(edges):
            raise ContractViolation(f"{where}: the edges do not close into one polygon at vertex {v}")
        polygon.append(v)
        v = succ[v]
    if len(polygon) != len(edges):
        raise ContractViolation(f"{where}: the edges form more than one cycle "
                                f"({len(polygon)} of {len(edges)} edges chained)")
    return polygon


def _parse_i(rows: list[tuple[int, str]], dim: int, n_points: int) -> Any:
    _, body = _counted(rows, "facets")
    facets = []
    for number, line in body:
        idx = _ints(number, line, n_points)
        if dim == 2 and len(idx) != 2:
            raise _bad(number, line, f"a 2D facet is an edge of 2 indices, got {len(idx)}")
        if dim == 3 and len(idx) < 3:
            raise _bad(number, line, f"a 3D facet needs at least 3 indices, got {len(idx)}")
        facets.append(idx)
    if dim == 2:
        return chain_edges(facets, where="unreadable output (2D edges)")
    return facets


def _parse_fx(rows: list[tuple[int, str]], n_points: int) -> list[int]:
    _, body = _counted(rows, "extreme points")
    out = []
    for number, line in body:
        idx = _ints(number, line, n_points)
        if len(idx) != 1:
            raise _bad(number, line, f"expected one index per line, got {len(idx)}")
        out.append(idx[0])
    return out


def _parse_off(rows: list[tuple[int, str]], points: np.ndarray) -> Any:
    n_points, dim = points.shape
    if not rows:
        raise ContractViolation("unreadable output: the program wrote nothing (expected an OFF header)")
    number, line = rows[0]
    head = line.split()
    qhull_style = head in (["2"], ["3"])  # Qhull's 'o' writes the dimension where OFF has its keyword
    if not (qhull_style or (head and head[0].upper().endswith("OFF"))):
        raise _bad(number, line, "expected 'OFF' (or Qhull's dimension) on the first line")
    off_dim = int(head[0]) if qhull_style else 3
    if off_dim != dim:
        raise _bad(number, line, f"an OFF of {off_dim}D vertices for {dim}D points")
    counts_line = (number, " ".join(head[1:])) if len(head) > 1 else (rows[1] if len(rows) > 1 else (number, ""))
    rest = rows[1:] if len(head) > 1 else rows[2:]
    try:
        n_vertices, n_faces = (int(t) for t in counts_line[1].split()[:2])
    except ValueError:
        raise _bad(*counts_line, "expected the counts 'n_vertices n_faces n_edges'") from None
    if len(rest) != n_vertices + n_faces:
        raise ContractViolation(f"unreadable output: the OFF header announces {n_vertices} vertices and "
                                f"{n_faces} faces, the output has {len(rest)} more lines")
    vertices = []
    for number, line in rest[:n_vertices]:
        tokens = line.split()[:dim]
        try:
            coords = tuple(parse_float(t) for t in tokens)
        except ValueError:
            raise _bad(number, line, "expected vertex coordinates") from None
        if len(coords) != dim:
            raise _bad(number, line, f"expected {dim} coordinates")
        vertices.append((number, line, coords))
    vertex_index = _match_vertices(vertices, points)
    faces = []
    for number, line in rest[n_vertices:]:
        tokens = line.split()
        try:
            k = int(tokens[0])
        except ValueError:
            raise _bad(number, line, "expected a face 'k i1 ... ik'") from None
        if not 0 <= k <= len(tokens) - 1:  # more tokens than k are colour values, which OFF allows
            raise _bad(number, line, f"the face announces {k} vertices, has {len(tokens) - 1}")
        local = _ints(number, line, n_vertices, tokens[1 : 1 + k])
        faces.append([vertex_index[v] for v in local])
    if dim == 2:
        if any(len(f) != 2 for f in faces):
            raise ContractViolation("unreadable output: a 2D OFF must list edges of 2 vertices")
        return chain_edges(faces, where="unreadable output (2D OFF edges)")
    return faces


def _match_vertices(vertices: list[tuple[int, str, tuple[float, ...]]], points: np.ndarray) -> list[int]:
    """Input indices of OFF vertices: exactly equal coordinates, or Qhull's 'o' layout.

    Qhull's ``o`` lists every input point, in input order, printed to 16
    significant digits (not always the same double): such a vertex block is
    read as the identity when every vertex agrees with its input point to
    that precision.  Otherwise every vertex must be exactly an input point.
    """
    n = len(points)
    if len(vertices) == n and n:
        got = np.array([c for _, _, c in vertices], dtype=np.float64)
        scale = float(np.abs(points).max())
        with np.errstate(all="ignore"):
            if np.all(np.abs(got - points) <= 1e-15 * (np.abs(points) + scale) + 1e-300):
                return list(range(n))
    lookup: dict[tuple[float, ...], int] = {}
    for i, row in enumerate(points.tolist()):
        lookup.setdefault(tuple(row), i)
    out = []
    for number, line, coords in vertices:
        if coords not in lookup:
            raise _bad(number, line, "this vertex is not exactly one of the input points")
        out.append(lookup[coords])
    return out


def parse_hull(text: str, output: str, points: Any) -> Any:
    """Parse a program's hull output into raw faces for the output contract.

    Parameters
    ----------
    text : str
        What the program wrote on stdout.
    output : {"i", "Fx", "off"}
        The format (see the module docstring).
    points : ndarray of shape (n, d)
        The points the program was given (for index ranges and OFF vertices).

    Returns
    -------
    list of int (2D) or list of list of int (3D)
        In the order the program wrote them (orientation unchanged).

    Raises
    ------
    ContractViolation
        Naming the first line that cannot be read, and why.

    Examples
    --------
    >>> square = np.array([[0.0, 0], [1, 0], [1, 1], [0, 1]])
    >>> parse_hull("4\\n0 1\\n1 2\\n2 3\\n3 0\\n", "i", square)
    [0, 1, 2, 3]
    >>> parse_hull("2\\n0\\nseven\\n", "Fx", square)
    Traceback (most recent call last):
    ...
    hullstress.errors.ContractViolation: unreadable output at line 3 'seven': 'seven' is not an integer index
    """
    pts = np.asarray(points, dtype=np.float64)
    if output not in HULL_FORMATS:
        raise ValueError(f"output must be one of {', '.join(HULL_FORMATS)}, got {output!r}")
    n_points, dim = pts.shape
    rows = _rows(text)
    if output == "i":
        return _parse_i(rows, dim, n_points)
    if output == "Fx":
        return _parse_fx(rows, n_points)
    return _parse_off(rows, pts)


def check_qhull_options(options: str | None) -> None:
    """Refuse ``--qhull-options`` that Qhull does not accept, before anything runs.

    Raises
    ------
    UsageError
        Naming the options and Qhull's first line about them.
    """
    if not options:
        return
    from scipy.spatial import ConvexHull, QhullError

    from .errors import UsageError

    simplex = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [0.2, 0.2, 0.2]])
    try:
        ConvexHull(simplex, qhull_options=options)
    except (QhullError, ValueError) as exc:
        first = next((line.strip() for line in str(exc).splitlines() if line.strip()), type(exc).__name__)
        raise UsageError(f"--qhull-options {options!r}: Qhull refused them: {first}") from None
