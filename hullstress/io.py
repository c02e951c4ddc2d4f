"""Reading and writing point sets and hull faces, exactly.

Points are read as float64 and every decimal literal is parsed with Python's
``float()``, which rounds correctly, so a file written by any program that
prints enough digits gives back the exact doubles it meant.  Hexadecimal
literals (``0x1.8p-3``, as printed by C's ``%a`` or ``float.hex``) are read
exactly too.  Writers print ``repr(float)``, the shortest decimal that reads
back to the same double, so ``read_points(write_points(...))`` is bit-exact.

Formats
-------
points
    ``.npy`` (a 2-D numeric array); ``.csv`` (comma or whitespace separated,
    optional header line); ``.xyz`` (whitespace separated, optional count
    line); Qhull/rbox text (first line the dimension, second the count, or the
    other way round as Qhull allows, then one point per line, comments after
    the numbers or on lines starting with a non-numeric character, e.g.
    ``3 rbox 10 D3``); ``.off`` (the vertex block of an OFF file).  Any other
    extension is sniffed: Qhull/rbox text when the first two lines each begin
    with a lone integer, plain rows otherwise.
faces
    ``.npy`` (an (m, k) or 1-D integer array); ``.csv`` / plain text (one face
    per row, rows may differ in length, optional header); ``.off`` (the face
    block, each row ``k i1 ... ik``); Qhull ``i`` output (first line the count,
    then one face per line).  A 2D hull is one row (or one index per line); a
    2D file of directed edges ``a b`` (Qhull's ``i`` output in 2D) is chained
    into the polygon when ``dim=2`` is given.

Every problem raises :class:`~hullstress.errors.InputFileError` with a one-line
message naming the file and the problem.
"""

from __future__ import annotations

import io
import math
import os
import re
import sys
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from .errors import InputFileError
from .literals import parse_float

__all__ = [
    "POINT_FORMATS",
    "FACE_FORMATS",
    "read_points",
    "read_points_text",
    "read_points_bytes",
    "points_file_bytes",
    "read_faces",
    "write_points",
    "write_faces",
    "points_text",
    "parse_float",
]

#: Formats accepted by :func:`write_points` (reading also takes ``.xyz`` and sniffed text).
POINT_FORMATS = ("npy", "csv", "qhull", "off", "xyz")
#: Formats accepted by :func:`write_faces`.
FACE_FORMATS = ("npy", "csv", "qhull", "off")

_INT_RE = re.compile(r"^[+-]?\d+$")
_SPLIT_RE = re.compile(r"[,\s;]+")
#: Largest integer magnitude that converts to float64 without rounding.
_EXACT_INT = 2**53


def _label(path: Path, what: str) -> str:
    return f"{what} file '{path}'"


#: The file name that means "read standard input" (Qhull's and rbox's habit: ``rbox 10 | ...``).
STDIN = "-"


def _read_text_lines(path: Path, what: str) -> list[tuple[int, list[str]]]:
    """Non-blank, non-comment lines as (1-based line number, tokens); ``-`` reads standard input."""
    try:
        text = sys.stdin.read() if str(path) == STDIN else path.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise InputFileError(f"{_label(path, what)} does not exist") from None
    except IsADirectoryError:
        raise InputFileError(f"{_label(path, what)} is a directory, expected a file") from None
    except UnicodeDecodeError:
        raise InputFileError(f"{_label(path, what)} is not UTF-8 text (use .npy for binary arrays)") from None
    except OSError as exc:
        raise InputFileError(f"{_label(path, what)} cannot be read: {exc.strerror or exc}") from None
    return _text_rows(text, path, what)


def _text_rows(text: str, path: Path, what: str) -> list[tuple[int, list[str]]]:
    rows = []
    for number, line in enumerate(text.splitlines(), start=1):
        stripped = line.strip()
        if not stripped or stripped.startswith("#"):
            continue
        rows.append((number, [t for t in _SPLIT_RE.split(stripped) if t]))
    if not rows:
        raise InputFileError(f"{_label(path, what)} is empty")
    return rows


def _is_number(token: str) -> bool:
    try:
        parse_float(token)
    except ValueError:
        return False
    return True


def _leading_int(tokens: list[str]) -> int | None:
    """The line's first token as an int when it is an integer literal, else None."""
    if tokens and _INT_RE.match(tokens[0]):
        return int(tokens[0])
    return None


def _load_npy(path: Path, what: str, data: bytes | None = None) -> np.ndarray:
    """The array in the ``.npy`` file ``path`` (or in ``data``, that file's bytes)."""
    try:
        arr = np.load(path if data is None else io.BytesIO(data), allow_pickle=False)
    except FileNotFoundError:
        raise InputFileError(f"{_label(path, what)} does not exist") from None
    except (ValueError, OSError, EOFError) as exc:
        first = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
        raise InputFileError(f"{_label(path, what)} is not a readable .npy array: {first}") from None
    if not isinstance(arr, np.ndarray):
        raise InputFileError(f"{_label(path, what)} holds {type(arr).__name__}, expected one array")
    return arr


# --------------------------------------------------------------------------- points


def _point_rows(path: Path, rows: list[tuple[int, list[str]]], dim: int | None) -> np.ndarray:
    """Parse rows of coordinates, each row one point with the same number of columns."""
    width = dim if dim is not None else len(rows[0][1])
    values: list[float] = []
    first_bad: tuple[int, int, str] | None = None  # (point, line, token) of the first non-finite row
    n_bad = 0
    for point, (number, tokens) in enumerate(rows):
        if len(tokens) != width:
            raise InputFileError(
                f"{_label(path, 'points')}: ragged rows: line {number} has {len(tokens)} values, expected {width}"
            )
        row_bad = None
        for tok in tokens:
            try:
                x = parse_float(tok)
            except ValueError:
                raise InputFileError(
                    f"{_label(path, 'points')}: non-numeric token {tok!r} at line {number}"
                ) from None
            if row_bad is None and not math.isfinite(x):
                row_bad = tok  # "nan", "inf", or a literal that overflows such as 1e999
            values.append(x)
        if row_bad is not None:
            n_bad += 1
            first_bad = first_bad or (point, number, row_bad)
    if first_bad is not None:
        point, number, tok = first_bad
        others = f" ({n_bad} points in all)" if n_bad > 1 else ""
        raise InputFileError(
            f"{_label(path, 'points')}: point {point} at line {number} has a non-finite coordinate "
            f"{tok!r}{others}; hull inputs must be finite"
        )
    return np.array(values, dtype=np.float64).reshape(len(rows), width)


def _strip_header(rows: list[tuple[int, list[str]]]) -> list[tuple[int, list[str]]]:
    """Drop a first line that is a header (no token of it is a number)."""
    if rows and not any(_is_number(t) for t in rows[0][1]):
        return rows[1:]
    return rows


def _qhull_header(rows: list[tuple[int, list[str]]]) -> tuple[list[int], int]:
    """The first two integers of a Qhull/rbox header and the index of the first body row.

    Qhull reads "dimension and number of points (or vice-versa)" from the first
    lines; anything after them on a line is a comment (``3 rbox 10 D3``).
    """
    ints: list[int] = []
    i = 0
    while len(ints) < 2 and i < len(rows):
        for tok in rows[i][1]:
            if len(ints) == 2 or not _INT_RE.match(tok):
                break
            ints.append(int(tok))
        i += 1
    return ints, i


def _qhull_points(path: Path, rows: list[tuple[int, list[str]]]) -> np.ndarray:
    """Qhull/rbox input: dimension and count first (either order), then one point per line."""
    ints, start = _qhull_header(rows)
    if len(ints) < 2:
        raise InputFileError(f"{_label(path, 'points')}: Qhull format needs the dimension and the count first")
    body = [(n, t) for n, t in rows[start:] if _is_number(t[0])]  # Qhull skips comment lines
    a, b = ints
    dim, count = (b, a) if (b in (2, 3) and len(body) == a and a not in (2, 3)) else (a, b)
    # Qhull ignores a comment after the coordinates on a point's line.
    trimmed = []
    for number, tokens in body:
        if len(tokens) > dim and all(_is_number(t) for t in tokens[:dim]) and not _is_number(tokens[dim]):
            tokens = tokens[:dim]
        trimmed.append((number, tokens))
    if dim not in (2, 3):
        raise InputFileError(f"{_label(path, 'points')}: wrong dimension: the header gives {dim}, expected 2 or 3")
    if len(trimmed) != count:
        raise InputFileError(
            f"{_label(path, 'points')}: the header announces {count} points, the file has {len(trimmed)}"
        )
    if not trimmed:
        raise InputFileError(f"{_label(path, 'points')} holds no points")
    return _point_rows(path, trimmed, dim)


def _xyz_points(path: Path, rows: list[tuple[int, list[str]]]) -> np.ndarray:
    """Whitespace rows, optionally preceded by a line with the point count alone."""
    if len(rows[0][1]) == 1 and _leading_int(rows[0][1]) is not None and len(rows) > 1 and len(rows[1][1]) > 1:
        count = int(rows[0][1][0])
        if count != len(rows) - 1:
            raise InputFileError(
                f"{_label(path, 'points')}: the count line announces {count} points, the file has {len(rows) - 1}"
            )
        rows = rows[1:]
    return _point_rows(path, rows, None)


def _off_points(path: Path, rows: list[tuple[int, list[str]]]) -> tuple[np.ndarray, list[tuple[int, list[str]]]]:
    """The vertex block of an OFF file, and the remaining (face) rows."""
    header = rows[0][1]
    # Qhull's 'o' output writes the dimension where OFF has its keyword.
    qhull_style = len(header) == 1 and header[0] in ("2", "3")
    if not header or not (header[0].upper().endswith("OFF") or qhull_style):
        raise InputFileError(f"{_label(path, 'OFF')}: the first line must be 'OFF' (or Qhull's dimension), got {' '.join(header)!r}")
    counts = header[1:] if len(header) > 1 else (rows[1][1] if len(rows) > 1 else [])
    start = 1 if len(header) > 1 else 2
    try:
        n_vertices, n_faces = int(counts[0]), int(counts[1])
    except (IndexError, ValueError):
        raise InputFileError(f"{_label(path, 'OFF')}: the counts line must be 'n_vertices n_faces n_edges'") from None
    dim = int(header[0]) if qhull_style else 3
    vertex_rows = rows[start : start + n_vertices]
    if len(vertex_rows) != n_vertices:
        raise InputFileError(
            f"{_label(path, 'OFF')}: the header announces {n_vertices} vertices, the file has {len(vertex_rows)}"
        )
    pts = _point_rows(path, vertex_rows, dim) if n_vertices else np.zeros((0, dim))
    face_rows = rows[start + n_vertices :]
    if len(face_rows) != n_faces:
        raise InputFileError(
            f"{_label(path, 'OFF')}: the header announces {n_faces} faces, the file has {len(face_rows)}"
        )
    return pts, face_rows


def _looks_like_qhull(rows: list[tuple[int, list[str]]]) -> bool:
    """Sniff Qhull/rbox text: two header integers, then rows as wide as one of them."""
    if len(rows) < 2 or _leading_int(rows[0][1]) is None:
        return False
    first, second = rows[0][1], rows[1][1]
    if len(first) >= 2 and not _is_number(first[1]):
        return _leading_int(second) is not None  # "3 rbox 10 D3" then "10"
    if len(first) == 1:
        return len(second) == 1 and _leading_int(second) is not None
    if len(first) == 2 and _INT_RE.match(first[1]):
        # "3 10" on one line: only when the rest is exactly that many rows of that width.
        a, b = int(first[0]), int(first[1])
        widths = {len(t) for _, t in rows[1:]}
        n_body = len(rows) - 1
        return (widths == {a} and n_body == b) or (widths == {b} and n_body == a)
    return False


def _validate_points(path: Path, pts: np.ndarray, dim: int | None) -> np.ndarray:
    if pts.ndim != 2:
        raise InputFileError(f"{_label(path, 'points')}: expected a 2-D array of shape (n, 2|3), got shape {pts.shape}")
    if pts.shape[0] == 0:
        raise InputFileError(f"{_label(path, 'points')} holds no points")
    d = pts.shape[1]
    if dim is not None and d != dim:
        raise InputFileError(f"{_label(path, 'points')}: wrong dimension: expected {dim} coordinates per point, got {d}")
    if d not in (2, 3):
        raise InputFileError(f"{_label(path, 'points')}: wrong dimension: expected 2 or 3 coordinates per point, got {d}")
    bad_rows = np.flatnonzero(~np.all(np.isfinite(pts), axis=1))
    if len(bad_rows):  # text formats are checked per line in _point_rows; this names the array row
        row = int(bad_rows[0])
        value = float(pts[row][~np.isfinite(pts[row])][0])
        others = f" ({len(bad_rows)} points in all)" if len(bad_rows) > 1 else ""
        raise InputFileError(
            f"{_label(path, 'points')}: point {row} (row {row} of the array) has a non-finite coordinate "
            f"{value!r}{others}; hull inputs must be finite"
        )
    return np.ascontiguousarray(pts, dtype=np.float64)


def read_points(path: str | os.PathLike[str], *, dim: int | None = None) -> np.ndarray:
    """Read a point set from ``.npy``, ``.csv``, ``.xyz``, ``.off`` or Qhull/rbox text.

    Parameters
    ----------
    path : str or path-like
        The file; its extension picks the format (others are sniffed); ``-``
        reads standard input (text formats).
    dim : {2, 3} or None
        The expected dimension; ``None`` accepts 2 or 3.

    Returns
    -------
    ndarray of shape (n, d), float64
        C-contiguous, finite, ``n >= 1``, ``d`` in (2, 3).  Decimal literals are
        correctly rounded, hex literals exact; integer ``.npy`` arrays must be
        exactly representable (``|x| <= 2**53``).

    Raises
    ------
    InputFileError
        Missing or empty file, ragged rows, a non-numeric token, a wrong
        dimension, a non-finite coordinate, a count that does not match.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> p = pathlib.Path(tempfile.mkdtemp()) / "pts.txt"
    >>> _ = p.write_text("2 rbox 3 D2\\n3\\n0 0\\n1 0\\n0x1p-1 0.5\\n")
    >>> read_points(p).tolist()
    [[0.0, 0.0], [1.0, 0.0], [0.5, 0.5]]
    >>> _ = p.write_text("0 0 0\\n1 1\\n")
    >>> read_points(p)
    Traceback (most recent call last):
    ...
    hullstress.errors.InputFileError: points file '...pts.txt': ragged rows: line 2 has 2 values, expected 3
    """
    path = Path(path)
    if dim is not None and dim not in (2, 3):
        raise InputFileError(f"dim must be 2, 3 or None, got {dim!r}")
    if path.suffix.lower() == ".npy":
        return _npy_points(path, _load_npy(path, "points"), dim)
    return _text_points(path, _read_text_lines(path, "points"), dim)


def read_points_bytes(data: bytes, *, name: str, dim: int | None = None) -> np.ndarray:
    """Read the bytes of a points file named ``name`` exactly as :func:`read_points` reads the file.

    The extension of ``name`` picks the format, as for a file; ``name`` also
    names the source in error messages.  With :func:`points_file_bytes` it
    proves that a point set survives a file without touching the disk.

    Examples
    --------
    >>> pts = np.array([[0.1, 5e-324], [1e300, -0.0]])
    >>> np.array_equal(read_points_bytes(points_file_bytes(pts, "csv"), name="pts.csv"), pts)
    True
    """
    path = Path(name)
    if dim is not None and dim not in (2, 3):
        raise InputFileError(f"dim must be 2, 3 or None, got {dim!r}")
    if path.suffix.lower() == ".npy":
        return _npy_points(path, _load_npy(path, "points", data), dim)
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError:
        raise InputFileError(f"{_label(path, 'points')} is not UTF-8 text (use .npy for binary arrays)") from None
    return _text_points(path, _text_rows(text, path, "points"), dim)


def _npy_points(path: Path, arr: np.ndarray, dim: int | None) -> np.ndarray:
    """The points of a ``.npy`` array: float64, or integers exactly representable as such."""
    if arr.dtype.kind in "iu":
        if arr.size and int(np.abs(arr.astype(object)).max()) > _EXACT_INT:
            raise InputFileError(f"{_label(path, 'points')}: integer coordinates beyond 2**53 are not exact in float64")
        arr = arr.astype(np.float64)
    elif arr.dtype.kind != "f":
        raise InputFileError(f"{_label(path, 'points')}: expected a float or integer array, got dtype {arr.dtype}")
    return _validate_points(path, arr.astype(np.float64, copy=False), dim)


def _text_points(path: Path, rows: list[tuple[int, list[str]]], dim: int | None) -> np.ndarray:
    """The points of a text file's rows, in the format its extension names (or the one sniffed)."""
    ext = path.suffix.lower()
    if ext == ".off":
        pts, _ = _off_points(path, rows)
    elif ext == ".csv":
        pts = _point_rows(path, _strip_header(rows) or rows, None)
    elif ext == ".xyz":
        pts = _xyz_points(path, rows)
    elif _looks_like_qhull(rows):
        pts = _qhull_points(path, rows)
    else:
        pts = _xyz_points(path, _strip_header(rows) or rows)
    return _validate_points(path, pts, dim)


def read_points_text(text: str, *, label: str, dim: int | None = None) -> np.ndarray:
    """Read points from Qhull/rbox text (or plain rows) already in memory, as :func:`read_points` would.

    Parameters
    ----------
    text : str
        E.g. what ``rbox`` printed.
    label : str
        Names the source in error messages.
    dim : {2, 3} or None

    Examples
    --------
    >>> read_points_text("2 rbox 2 D2\\n2\\n0 0\\n1 0.5\\n", label="rbox").tolist()
    [[0.0, 0.0], [1.0, 0.5]]
    """
    path = Path(label)
    rows = _text_rows(text, path, "points")
    pts = _qhull_points(path, rows) if _looks_like_qhull(rows) else _xyz_points(path, _strip_header(rows) or rows)
    return _validate_points(path, pts, dim)


# --------------------------------------------------------------------------- faces


def _index_rows(path: Path, rows: list[tuple[int, list[str]]]) -> list[list[int]]:
    faces = []
    for number, tokens in rows:
        face = []
        for tok in tokens:
            if not _INT_RE.match(tok):
                raise InputFileError(f"{_label(path, 'faces')}: non-integer token {tok!r} at line {number}")
            face.append(int(tok))
        faces.append(face)
    return faces


def _chain_edges(path: Path, edges: list[list[int]]) -> list[int]:
    """Chain directed edges ``a -> b`` into one closed polygon (the one chainer: :mod:`hullstress.qhull_format`)."""
    from .errors import ContractViolation
    from .qhull_format import chain_edges

    try:
        return chain_edges(edges, where=_label(path, "faces"))
    except ContractViolation as exc:
        raise InputFileError(str(exc)) from None


def read_faces(path: str | os.PathLike[str], *, dim: int | None = None) -> Any:
    """Read hull faces from ``.npy``, ``.csv`` / text, ``.off`` or Qhull ``i`` output.

    Parameters
    ----------
    path : str or path-like
    dim : {2, 3} or None
        With ``dim=2`` the result is one polygon: a single row, one index per
        line, or directed edges ``a b`` chained in order.  With ``dim=3`` or
        ``None`` every row is a face.

    Returns
    -------
    list of int (2D) or list of list of int / ndarray of shape (m, k), int64 (3D)
        Raw faces, to be validated by :func:`hullstress.contract.normalize_output`.

    Raises
    ------
    InputFileError

    Examples
    --------
    >>> import tempfile, pathlib
    >>> p = pathlib.Path(tempfile.mkdtemp()) / "hull.i"
    >>> _ = p.write_text("2\\n0 1 2\\n0 2 3\\n")
    >>> read_faces(p)
    [[0, 1, 2], [0, 2, 3]]
    >>> _ = p.write_text("3\\n0 1\\n2 0\\n1 2\\n")  # 2D Qhull 'i' output: directed edges
    >>> read_faces(p, dim=2)
    [0, 1, 2]
    """
    path = Path(path)
    if dim is not None and dim not in (2, 3):
        raise InputFileError(f"dim must be 2, 3 or None, got {dim!r}")
    ext = path.suffix.lower()
    if ext == ".npy":
        arr = _load_npy(path, "faces")
        if arr.dtype.kind not in "iu":
            raise InputFileError(f"{_label(path, 'faces')}: expected an integer array, got dtype {arr.dtype}")
        if arr.ndim not in (1, 2):
            raise InputFileError(f"{_label(path, 'faces')}: expected a 1-D or 2-D array, got shape {arr.shape}")
        if dim == 2 and arr.ndim == 2:
            if arr.shape[0] == 1 or arr.shape[1] == 1:
                return arr.ravel().astype(np.int64).tolist()
            if arr.shape[1] == 2:
                return _chain_edges(path, arr.astype(np.int64).tolist())
        if arr.ndim == 1:
            return arr.astype(np.int64).tolist()
        return arr.astype(np.int64)
    rows = _read_text_lines(path, "faces")
    if ext == ".off":
        _, face_rows = _off_points(path, rows)
        faces = []
        for number, tokens in face_rows:
            idx = _index_rows(path, [(number, tokens)])[0]
            if not idx or idx[0] != len(idx) - 1:
                # Trailing colour values after the indices are allowed by OFF.
                if idx and len(idx) - 1 > idx[0]:
                    idx = idx[: idx[0] + 1]
                else:
                    raise InputFileError(
                        f"{_label(path, 'faces')}: line {number} announces {idx[0] if idx else 0} indices, has {len(idx) - 1}"
                    )
            faces.append(idx[1:])
    else:
        rows = _strip_header(rows) or rows
        faces = _index_rows(path, rows)
        # Qhull 'i' output: a lone count on the first line, then that many rows
        # (in 2D also Qhull's 'Fx': the count, then one index per line).
        if len(faces) > 1 and len(faces[0]) == 1 and faces[0][0] == len(faces) - 1 and (len(faces[1]) > 1 or dim == 2):
            faces = faces[1:]
    if not faces:
        raise InputFileError(f"{_label(path, 'faces')} holds no faces")
    if dim == 2:
        if len(faces) == 1:
            return faces[0]
        if all(len(f) == 1 for f in faces):
            return [f[0] for f in faces]
        if all(len(f) == 2 for f in faces):
            return _chain_edges(path, faces)
        raise InputFileError(
            f"{_label(path, 'faces')}: a 2D hull must be one row of indices or directed edges 'a b', "
            f"got rows of {sorted({len(f) for f in faces})} indices"
        )
    return faces


# --------------------------------------------------------------------------- writers


def points_text(points: Any, *, indent: str = "") -> str:
    """The points one per line, coordinates as exact ``repr`` floats, for a report to show.

    Any shape is shown as it is: an empty set (the bad-input family's
    ``empty`` case, shape ``(0, d)``) is a line that says so, a row of another
    length than its neighbours' is not an error.

    Parameters
    ----------
    points : array_like
        The points, usually shape ``(n, d)``.
    indent : str
        Put before every line.

    Returns
    -------
    str
        ``"x, y[, z]"`` per point, lines joined by newlines.

    Examples
    --------
    >>> print(points_text(np.array([[0.5, 1.0], [2.0, -0.0]]), indent="  "))
      0.5, 1.0
      2.0, -0.0
    >>> points_text(np.zeros((0, 3)))
    '(no points: shape (0, 3))'
    """
    arr = np.asarray(points, dtype=np.float64)
    if arr.size == 0:
        return f"{indent}(no points: shape {tuple(arr.shape)})"
    rows = arr.reshape(arr.shape[0], -1) if arr.ndim >= 1 else arr.reshape(1, 1)
    return "\n".join(indent + ", ".join(repr(float(x)) for x in row) for row in rows)


def _format_float(x: float, hex_floats: bool) -> str:
    return float.hex(x) if hex_floats else repr(x)


def write_points(
    path: str | os.PathLike[str],
    points: np.ndarray,
    format: str | None = None,
    *,
    faces: Sequence[Sequence[int]] | None = None,
    hex_floats: bool = False,
) -> Path:
    """Write a point set so that :func:`read_points` gives back the same doubles.

    Parameters
    ----------
    path : str or path-like
    points : ndarray of shape (n, d), float64
    format : {"npy", "csv", "qhull", "off", "xyz"} or None
        ``None`` takes it from the extension (``.txt`` means ``qhull``).
    faces : sequence of sequences of int, optional
        For ``off``: the face block (points alone otherwise).
    hex_floats : bool
        Print ``float.hex`` literals instead of the shortest round-tripping decimal.

    Returns
    -------
    Path
        The path written.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> p = pathlib.Path(tempfile.mkdtemp()) / "pts.csv"
    >>> pts = np.array([[0.1, 5e-324], [1e300, -0.0]])
    >>> np.array_equal(read_points(write_points(p, pts)), pts)
    True
    """
    path = Path(path)
    fmt = format or {".npy": "npy", ".csv": "csv", ".off": "off", ".xyz": "xyz"}.get(path.suffix.lower(), "qhull")
    path.write_bytes(points_file_bytes(points, fmt, faces=faces, hex_floats=hex_floats))
    return path


def points_file_bytes(
    points: np.ndarray,
    format: str,
    *,
    faces: Sequence[Sequence[int]] | None = None,
    hex_floats: bool = False,
) -> bytes:
    """The bytes :func:`write_points` writes for ``points`` in ``format``.

    Parameters
    ----------
    points : ndarray of shape (n, d), float64
    format : {"npy", "csv", "qhull", "off", "xyz"}
    faces : sequence of sequences of int, optional
        For ``off``: the face block.
    hex_floats : bool
        Print ``float.hex`` literals instead of the shortest round-tripping decimal.

    Examples
    --------
    >>> points_file_bytes(np.array([[0.5, -0.0], [1.0, 1e-300]]), "csv")
    b'x,y\\n0.5,-0.0\\n1.0,1e-300\\n'
    """
    pts = np.asarray(points, dtype=np.float64)
    if pts.ndim != 2 or pts.shape[1] not in (2, 3):
        raise ValueError(f"points must have shape (n, 2) or (n, 3), got {pts.shape}")
    fmt = format
    if fmt not in POINT_FORMATS:
        raise ValueError(f"format must be one of {', '.join(POINT_FORMATS)}, got {fmt!r}")
    if fmt == "npy":
        buffer = io.BytesIO()
        np.save(buffer, pts, allow_pickle=False)
        return buffer.getvalue()
    rows = [" ".join(_format_float(float(x), hex_floats) for x in row) for row in pts.tolist()]
    n, d = pts.shape
    if fmt == "csv":
        header = ",".join("xyz"[:d])
        text = header + "\n" + "\n".join(r.replace(" ", ",") for r in rows)
    elif fmt == "qhull":
        text = f"{d}\n{n}\n" + "\n".join(rows)
    elif fmt == "xyz":
        text = "\n".join(rows)
    else:
        if d != 3:
            raise ValueError(f"OFF holds 3D points, got shape {pts.shape}")
        faces = [list(map(int, f)) for f in (faces or [])]
        lines = [f"{len(f)} " + " ".join(map(str, f)) for f in faces]
        text = f"OFF\n{n} {len(faces)} 0\n" + "\n".join(rows + lines)
    return (text + "\n").encode("utf-8")


def write_faces(path: str | os.PathLike[str], faces: Any, format: str | None = None) -> Path:
    """Write faces (a 2D index sequence, (m, 3) triangles or polygons) for :func:`read_faces`.

    Parameters
    ----------
    path : str or path-like
    faces : sequence of int (2D polygon), ndarray of shape (m, k) or list of sequences of int
    format : {"npy", "csv", "qhull"} or None
        ``qhull`` writes Qhull's ``i`` layout (count line, then one face per
        line); ``None`` takes it from the extension (``qhull`` by default).

    Returns
    -------
    Path
    """
    path = Path(path)
    fmt = format or {".npy": "npy", ".csv": "csv"}.get(path.suffix.lower(), "qhull")
    if fmt not in ("npy", "csv", "qhull"):
        raise ValueError(f"format must be one of npy, csv, qhull, got {fmt!r}")
    if isinstance(faces, np.ndarray):
        rows = faces.tolist() if faces.ndim == 2 else [faces.tolist()]
    else:
        faces = list(faces)
        rows = [list(map(int, f)) for f in faces] if faces and np.ndim(faces[0]) == 1 else [list(map(int, faces))]
    if fmt == "npy":
        sizes = {len(r) for r in rows}
        if len(sizes) > 1:
            raise ValueError(f"npy faces need equal face sizes, got sizes {sorted(sizes)}")
        with open(path, "wb") as fh:
            np.save(fh, np.array(rows, dtype=np.int64), allow_pickle=False)
        return path
    sep = "," if fmt == "csv" else " "
    body = "\n".join(sep.join(map(str, r)) for r in rows)
    text = body if fmt == "csv" else f"{len(rows)}\n{body}"
    path.write_text(text + "\n", encoding="utf-8")
    return path
