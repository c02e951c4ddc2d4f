"""The output contract of docs/design.md, enforced: raw algorithm output -> normalised faces.

An algorithm's return value is untrusted.  :func:`normalize_output` either
turns it into a :class:`FaceSet` (3D) or a 1-D index array (2D), or raises
:class:`~hullstress.errors.ContractViolation` with a one-line reason that
names the offending value.  A violation makes the call's status ``fail``.

A face needs at least three vertices, except in the lower-dimensional answers
of docs/lower-dimensional.md: a 3D input of affine rank 0 or 1
(one point, a segment) may be answered with a face of one or two vertices.
Whoever normalises before the rank is known passes ``min_face_size=1`` and
applies :func:`require_face_size` once it is.

:func:`canonical_output` puts a normalised output in one canonical order
(each face, and a 2D polygon, rotated to start at its lexicographically least
rotation, i.e. at its smallest index; faces sorted), so that a results table
never depends on the order in which a library emits its faces.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from .errors import ContractViolation

__all__ = [
    "FaceSet",
    "normalize_output",
    "normalize_polygon",
    "normalize_faces",
    "validate_face_set",
    "require_face_size",
    "canonical_output",
    "least_rotation",
    "reverse_orientation",
]

#: The fewest vertices of a face of a closed surface (a full-dimensional 3D hull).
MIN_FACE_SIZE = 3

_INT64_MIN, _INT64_MAX = int(np.iinfo(np.int64).min), int(np.iinfo(np.int64).max)


@dataclass(frozen=True, eq=False)
class FaceSet:
    """Polygonal faces in compressed-row form.

    Attributes
    ----------
    indices : ndarray of shape (k,), int64
        All faces' vertex indices, concatenated.
    offsets : ndarray of shape (m + 1,), int64
        Face ``i`` is ``indices[offsets[i]:offsets[i + 1]]``.

    Examples
    --------
    >>> fs = FaceSet.from_triangles([[0, 1, 2], [0, 2, 3]])
    >>> fs.n_faces, fs.is_triangles, fs.face(1).tolist()
    (2, True, [0, 2, 3])
    """

    indices: np.ndarray
    offsets: np.ndarray

    @classmethod
    def from_triangles(cls, triangles: Any) -> "FaceSet":
        tri = np.asarray(triangles, dtype=np.int64).reshape(-1, 3)
        return cls(tri.ravel().copy(), np.arange(0, 3 * len(tri) + 1, 3, dtype=np.int64))

    @classmethod
    def from_polygons(cls, polygons: Sequence[Sequence[int]]) -> "FaceSet":
        sizes = np.fromiter((len(p) for p in polygons), dtype=np.int64, count=len(polygons))
        offsets = np.zeros(len(polygons) + 1, dtype=np.int64)
        np.cumsum(sizes, out=offsets[1:])
        if len(polygons):
            indices = np.concatenate([np.asarray(p, dtype=np.int64).ravel() for p in polygons])
        else:
            indices = np.zeros(0, dtype=np.int64)
        return cls(indices, offsets)

    @property
    def n_faces(self) -> int:
        return int(len(self.offsets) - 1)

    @property
    def sizes(self) -> np.ndarray:
        return np.diff(self.offsets)

    @property
    def is_triangles(self) -> bool:
        return bool(np.all(self.sizes == 3))

    def face(self, i: int) -> np.ndarray:
        return self.indices[self.offsets[i] : self.offsets[i + 1]]

    def polygons(self) -> list[np.ndarray]:
        return [self.face(i) for i in range(self.n_faces)]

    def triangles(self) -> np.ndarray:
        """The faces as an (m, 3) array; raises ValueError unless every face is a triangle."""
        if not self.is_triangles:
            raise ValueError("not every face is a triangle; use fan_triangles()")
        return self.indices.reshape(-1, 3)

    def fan_triangles(self) -> tuple[np.ndarray, np.ndarray]:
        """Fan-triangulate every face from its first vertex.

        Returns
        -------
        triangles : ndarray of shape (t, 3), int64
        face_of : ndarray of shape (t,), int64
            The face each triangle came from.
        """
        sizes = self.sizes
        n_tri = np.maximum(sizes - 2, 0)
        face_of = np.repeat(np.arange(self.n_faces, dtype=np.int64), n_tri)
        if len(face_of) == 0:
            return np.zeros((0, 3), dtype=np.int64), face_of
        first = np.repeat(np.cumsum(n_tri) - n_tri, n_tri)
        k = np.arange(len(face_of), dtype=np.int64) - first  # 0..size-3 within each face
        base = self.offsets[face_of]
        tri = np.stack(
            [self.indices[base], self.indices[base + k + 1], self.indices[base + k + 2]], axis=1
        )
        return tri, face_of

    def vertex_set(self) -> np.ndarray:
        """Sorted unique vertex indices used by any face."""
        return np.unique(self.indices)

    def to_python(self) -> list[list[int]]:
        return [self.face(i).tolist() for i in range(self.n_faces)]


def _describe(value: Any) -> str:
    if isinstance(value, np.ndarray):
        return f"ndarray of dtype {value.dtype} and shape {value.shape}"
    text = repr(value)
    return f"{type(value).__name__} {text[:60]}{'...' if len(text) > 60 else ''}"


def _as_index_array(value: Any, what: str) -> np.ndarray:
    """Convert to int64 without accepting floats, bools, strings or ragged nesting."""
    try:
        arr = np.asarray(value)
    except (ValueError, TypeError) as exc:
        raise ContractViolation(f"{what} must be integer indices, got {_describe(value)}: {exc}") from None
    if arr.size == 0 and arr.dtype.kind in "fiu":
        # An empty list becomes float64 in numpy; there is no entry to be wrong.
        return np.zeros(arr.shape, dtype=np.int64)
    if arr.dtype == object:
        # A list mixing Python ints and numpy ints is fine; anything else is not.
        flat = arr.ravel().tolist()
        if not all(isinstance(x, (int, np.integer)) and not isinstance(x, (bool, np.bool_)) for x in flat):
            bad = next(
                (x for x in flat if not isinstance(x, (int, np.integer)) or isinstance(x, (bool, np.bool_))),
                None,
            )
            raise ContractViolation(f"{what} must be integer indices, got element {bad!r}")
        big = next((x for x in flat if not _INT64_MIN <= x <= _INT64_MAX), None)
        if big is not None:  # a Python int beyond int64 (numpy keeps such a list as objects)
            raise ContractViolation(f"{what} holds an index outside the int64 range: {big}")
        arr = np.array(flat, dtype=np.int64).reshape(arr.shape)
    elif arr.ndim == 1 and arr.dtype.kind in "iu" and not isinstance(value, np.ndarray):
        # numpy turns a bool among Python ints into 0 or 1: find it in the sequence itself.
        bad = next((x for x in value if isinstance(x, (bool, np.bool_))), None)
        if bad is not None:
            raise ContractViolation(f"{what} must be integer indices, got element {bad!r}")
    if arr.dtype.kind == "b" or arr.dtype.kind not in "iu":
        raise ContractViolation(f"{what} must be integer indices, got {_describe(value)}")
    if arr.dtype.kind == "u" and arr.size and arr.max() > np.iinfo(np.int64).max:
        raise ContractViolation(f"{what} holds an index too large for int64: {arr.max()}")
    return arr.astype(np.int64, copy=False)


def _check_range(arr: np.ndarray, n_points: int, what: str) -> None:
    if arr.size == 0:
        return
    lo, hi = int(arr.min()), int(arr.max())
    if lo < 0:
        raise ContractViolation(f"{what} holds index {lo}, out of range for {n_points} points")
    if hi >= n_points:
        raise ContractViolation(f"{what} holds index {hi}, out of range for {n_points} points")


def normalize_polygon(output: Any, n_points: int) -> np.ndarray:
    """Validate a 2D result: a counter-clockwise sequence of vertex indices.

    Returns
    -------
    ndarray of shape (k,), int64

    Raises
    ------
    ContractViolation
        On ``None``, non-integer entries, nesting, or indices outside ``[0, n_points)``.
    """
    if output is None:
        raise ContractViolation("the algorithm returned None instead of vertex indices")
    if isinstance(output, (str, bytes)):
        raise ContractViolation(f"vertex indices must be integers, got {_describe(output)}")
    arr = _as_index_array(output, "vertex indices")
    if arr.ndim != 1:
        raise ContractViolation(
            f"a 2D hull must be a 1-D sequence of vertex indices, got shape {arr.shape}"
        )
    _check_range(arr, n_points, "vertex indices")
    return arr.copy()


def normalize_faces(output: Any, n_points: int, *, min_face_size: int = MIN_FACE_SIZE) -> FaceSet:
    """Validate a 3D result: an (m, 3) integer array or a list of polygons.

    Parameters
    ----------
    output : object
        What the algorithm returned.
    n_points : int
        Number of input points (indices must be below it).
    min_face_size : int
        Fewest vertices a face may have: 3 (a closed surface), or 1 while
        the input's affine rank is not known yet (see :func:`require_face_size`).

    Returns
    -------
    FaceSet

    Raises
    ------
    ContractViolation
        On ``None``, wrong shapes, non-integer entries, faces with fewer than
        ``min_face_size`` vertices, or indices outside ``[0, n_points)``.
    """
    if output is None:
        raise ContractViolation("the algorithm returned None instead of faces")
    if isinstance(output, (str, bytes, dict)):
        raise ContractViolation(f"faces must be an (m, 3) integer array or a list of polygons, got {_describe(output)}")
    if isinstance(output, FaceSet):
        validate_face_set(output, n_points, min_face_size=min_face_size)
        if output.indices.dtype == np.int64 and output.offsets.dtype == np.int64:
            return output
        return FaceSet(output.indices.astype(np.int64), output.offsets.astype(np.int64))
    if isinstance(output, np.ndarray):
        if output.ndim != 2 or (output.shape[1] != 3 and output.shape[0] > 0):
            raise ContractViolation(
                f"faces must be an (m, 3) integer array, got shape {output.shape}"
            )
        arr = _as_index_array(output, "faces")
        _check_range(arr, n_points, "faces")
        return FaceSet.from_triangles(arr)
    try:
        polygons = list(output)
    except TypeError:
        raise ContractViolation(
            f"faces must be an (m, 3) integer array or a list of polygons, got {_describe(output)}"
        ) from None
    checked = []
    for i, poly in enumerate(polygons):
        try:
            ndim = None if poly is None or isinstance(poly, (str, bytes)) else np.ndim(poly)
        except (ValueError, TypeError):  # ragged nesting such as [0, 2, 1, [3]] (issue 33, F6)
            ndim = None
        if ndim != 1:
            raise ContractViolation(f"face {i} must be a sequence of vertex indices, got {_describe(poly)}")
        arr = _as_index_array(poly, f"face {i}")
        if len(arr) < min_face_size:
            raise ContractViolation(_too_small(i, len(arr)))
        _check_range(arr, n_points, f"face {i}")
        checked.append(arr)
    return FaceSet.from_polygons(checked)


def validate_face_set(faces: FaceSet, n_points: int, *, min_face_size: int = MIN_FACE_SIZE) -> None:
    """Raise ContractViolation unless ``faces`` is a well-formed FaceSet over ``n_points`` points.

    A FaceSet is a plain record anyone can build, so its arrays are checked
    like any other output: integer indices in range, offsets a 1-D integer
    array starting at 0, non-decreasing, ending at ``len(indices)``, and
    every face at least ``min_face_size`` vertices.  O(k) for k indices.

    Examples
    --------
    >>> validate_face_set(FaceSet(np.array([0, 1, 2]), np.array([], dtype=np.int64)), 3)
    Traceback (most recent call last):
    ...
    hullstress.errors.ContractViolation: FaceSet offsets must be a 1-D integer array starting at 0, got ndarray of dtype int64 and shape (0,)
    """
    idx, off = faces.indices, faces.offsets
    if not isinstance(idx, np.ndarray) or idx.ndim != 1 or idx.dtype.kind not in "iu":
        raise ContractViolation(f"FaceSet indices must be a 1-D integer array, got {_describe(idx)}")
    if (not isinstance(off, np.ndarray) or off.ndim != 1 or off.dtype.kind not in "iu" or not len(off)
            or off[0] != 0):
        raise ContractViolation(f"FaceSet offsets must be a 1-D integer array starting at 0, got {_describe(off)}")
    if int(off[-1]) != len(idx):
        raise ContractViolation(f"FaceSet offsets end at {int(off[-1])}, but there are {len(idx)} indices")
    sizes = np.diff(off.astype(np.int64))
    if sizes.size and sizes.min() < 0:
        i = int(np.argmax(sizes < 0))
        raise ContractViolation(f"FaceSet offsets decrease at face {i} ({int(off[i])} then {int(off[i + 1])})")
    if idx.dtype.kind == "u" and idx.size and idx.max() > _INT64_MAX:
        raise ContractViolation(f"FaceSet indices hold an index too large for int64: {idx.max()}")
    _check_range(idx, n_points, "faces")
    small = np.flatnonzero(sizes < min_face_size)
    if len(small):
        raise ContractViolation(_too_small(int(small[0]), int(sizes[small[0]])))


def normalize_output(output: Any, n_points: int, dim: int, *, min_face_size: int = MIN_FACE_SIZE) -> np.ndarray | FaceSet:
    """Validate raw algorithm output for a ``dim``-dimensional case of ``n_points`` points.

    ``min_face_size`` applies to 3D faces (see :func:`normalize_faces`).
    """
    if dim == 2:
        return normalize_polygon(output, n_points)
    return normalize_faces(output, n_points, min_face_size=min_face_size)


def _too_small(i: int, size: int) -> str:
    return (f"face {i} has {size} vertices; a face needs at least {MIN_FACE_SIZE} "
            "(fewer only in the answer for a collinear or one-point input)")


def require_face_size(faces: FaceSet, minimum: int = MIN_FACE_SIZE) -> None:
    """Raise ContractViolation naming the first face with fewer than ``minimum`` vertices.

    Examples
    --------
    >>> require_face_size(FaceSet.from_polygons([[0, 1, 2], [0, 1]]))
    Traceback (most recent call last):
    ...
    hullstress.errors.ContractViolation: face 1 has 2 vertices; a face needs at least 3 (fewer only in the answer for a collinear or one-point input)
    """
    small = np.flatnonzero(faces.sizes < minimum)
    if len(small):
        i = int(small[0])
        raise ContractViolation(_too_small(i, int(faces.sizes[i])))


def least_rotation(seq: Sequence[int]) -> int:
    """The start of the lexicographically least rotation of ``seq`` (Booth's algorithm, O(k)).

    Examples
    --------
    >>> least_rotation([3, 1, 2]), least_rotation([0, 5, 0, 2]), least_rotation([])
    (1, 2, 0)
    """
    s = list(seq)
    n = len(s)
    if n < 2:
        return 0
    fail = [-1] * (2 * n)
    k = 0
    for j in range(1, 2 * n):
        c = s[j % n]
        i = fail[j - k - 1]
        while i != -1 and c != s[(k + i + 1) % n]:
            if c < s[(k + i + 1) % n]:
                k = j - i - 1
            i = fail[i]
        if i == -1 and c != s[(k + i + 1) % n]:
            if c < s[(k + i + 1) % n]:
                k = j
            fail[j - k] = -1
        else:
            fail[j - k] = i + 1
    return k % n


def _rotate_faces(faces: FaceSet) -> np.ndarray:
    """Every face rotated to its least rotation; the concatenated indices."""
    idx, offsets, sizes = faces.indices, faces.offsets, faces.sizes
    m = faces.n_faces
    if m == 0 or not idx.size:
        return idx.copy()
    starts = offsets[:-1]
    face_of = np.repeat(np.arange(m, dtype=np.int64), sizes)
    mins = np.minimum.reduceat(idx, starts)
    is_min = idx == mins[face_of]
    n_min = np.add.reduceat(is_min.astype(np.int64), starts)
    # The first position of each face's minimum (every face holds its minimum once at least).
    hit = np.flatnonzero(is_min)
    _, first = np.unique(face_of[hit], return_index=True)
    shift = hit[first] - starts
    # A face holding its minimum twice (a repeated vertex) needs Booth's algorithm.
    for f in np.flatnonzero(n_min > 1).tolist():
        shift[f] = least_rotation(idx[offsets[f] : offsets[f + 1]].tolist())
    local = np.arange(idx.size, dtype=np.int64) - starts[face_of]
    out = np.empty_like(idx)
    out[starts[face_of] + (local - shift[face_of]) % sizes[face_of]] = idx
    return out


def _face_order(rotated: np.ndarray, faces: FaceSet) -> np.ndarray:
    """The order that sorts the rotated faces lexicographically (a shorter prefix first)."""
    sizes = faces.sizes
    m = faces.n_faces
    if m < 2:
        return np.arange(m, dtype=np.int64)
    if np.all(sizes == sizes[0]):
        table = rotated.reshape(m, int(sizes[0]))
        return np.lexsort(table.T[::-1]).astype(np.int64)
    offsets = faces.offsets.tolist()
    values = rotated.tolist()
    return np.array(sorted(range(m), key=lambda f: values[offsets[f] : offsets[f + 1]]), dtype=np.int64)


def canonical_output(output: np.ndarray | FaceSet) -> np.ndarray | FaceSet:
    """A normalised output in canonical order; the same hull whatever order it was emitted in.

    A 2D polygon is rotated to its least rotation (it starts at its smallest
    index; its direction is kept).  In 3D every face is rotated the same way
    and the faces are sorted lexicographically.  Orientation is never changed,
    so the canonical output passes or fails every check exactly as the
    original does.

    Parameters
    ----------
    output : ndarray of shape (k,), int64, or FaceSet
        From :func:`normalize_output`.

    Returns
    -------
    ndarray or FaceSet
        A new object of the same kind.

    Examples
    --------
    >>> canonical_output(np.array([4, 2, 7])).tolist()
    [2, 7, 4]
    >>> canonical_output(FaceSet.from_triangles([[3, 1, 2], [2, 0, 1]])).to_python()
    [[0, 1, 2], [1, 2, 3]]
    """
    if not isinstance(output, FaceSet):
        poly = np.asarray(output, dtype=np.int64)
        if len(poly) < 2:
            return poly.copy()
        start = int(np.argmin(poly))
        if np.count_nonzero(poly == poly[start]) > 1:
            start = least_rotation(poly.tolist())
        return np.roll(poly, -start)
    rotated = _rotate_faces(output)
    order = _face_order(rotated, output)
    sizes = output.sizes[order]
    offsets = np.zeros(len(order) + 1, dtype=np.int64)
    np.cumsum(sizes, out=offsets[1:])
    starts = output.offsets[:-1][order]
    if len(order):
        take = np.repeat(starts - offsets[:-1], sizes) + np.arange(int(offsets[-1]), dtype=np.int64)
        indices = rotated[take]
    else:
        indices = rotated[:0]
    return FaceSet(indices, offsets)


def reverse_orientation(faces: np.ndarray | FaceSet) -> np.ndarray | FaceSet:
    """Reverse every face (3D) or the polygon (2D): a clockwise output made counter-clockwise.

    Examples
    --------
    >>> reverse_orientation(np.array([0, 1, 2])).tolist()
    [2, 1, 0]
    >>> reverse_orientation(FaceSet.from_polygons([[0, 1, 2], [0, 2, 3, 4]])).to_python()
    [[2, 1, 0], [4, 3, 2, 0]]
    """
    if not isinstance(faces, FaceSet):
        return np.asarray(faces)[::-1].copy()
    sizes = faces.sizes
    face_of = np.repeat(np.arange(faces.n_faces, dtype=np.int64), sizes)
    position = np.arange(len(faces.indices), dtype=np.int64)
    # Within each face, position p maps to (start + end - 1 - p).
    mirrored = faces.offsets[face_of] + faces.offsets[face_of + 1] - 1 - position
    return FaceSet(faces.indices[mirrored], faces.offsets.copy())
