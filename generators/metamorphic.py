"""Metamorphic testing with the transforms: seeded chains, and comparing the two answers.

A metamorphic check runs an algorithm on a case and on a transformed copy
whose true hull is known from the original's (see :mod:`generators.transforms`),
then compares the answers: no reference hull is needed, so it finds bugs
where every checker agrees with a wrong answer, and it is the most common way
users meet order dependence ("the hull changes when I shuffle my points").

:func:`apply_transforms` applies a chain of named transforms, step i drawing
its parameters from :func:`transform_rng` (seed, name, i), so a case plus a
chain and a seed is reproducible bytewise.  :func:`vertex_set_change`
compares an answer on the original with one on the transformed copy as sets
of input points, exactly, and says in one line what differs.
"""

from __future__ import annotations

import zlib
from collections.abc import Iterable, Sequence
from typing import Any

import numpy as np

from ._common import GeneratorValueError
from .transforms import Transformed, _as_points, apply_transform

__all__ = ["transform_rng", "apply_transforms", "vertex_set_change"]


def transform_rng(seed: int, name: str, index: int) -> np.random.Generator:
    """The generator step ``index`` of a chain draws from: ``default_rng([seed, crc32(name), index])``.

    crc32 is stable across runs and platforms (unlike ``hash``), so the same
    (seed, chain) gives the same transformed bytes everywhere.
    """
    return np.random.default_rng([int(seed), zlib.crc32(str(name).encode("utf-8")), int(index)])


def apply_transforms(points: np.ndarray, names: str | Sequence[str], *, seed: int) -> Transformed:
    """Apply a chain of registered transforms, step i drawing from :func:`transform_rng`.

    Parameters
    ----------
    points : ndarray of shape (n, d), float64
    names : str or sequence of str
        Names from :data:`TRANSFORMS`, applied left to right.
    seed : int
        Non-negative; with the names it fixes every drawn parameter.

    Returns
    -------
    Transformed
        ``name`` joins the chain with ``+``; ``source_rows`` maps the final
        rows to the input rows (-1 for added ones); ``params`` lists each
        step's parameters; ``orientation_preserved`` is the parity of the
        flips; ``witness`` is kept only for a single ``add-interior`` step
        (later steps move the rows it names).

    Examples
    --------
    >>> t = apply_transforms(np.eye(3), ["duplicate-all", "permute-rows"], seed=0)
    >>> t.name, sorted(t.source_rows.tolist())
    ('duplicate-all+permute-rows', [0, 0, 1, 1, 2, 2])
    """
    chain = [names] if isinstance(names, str) else list(names)
    if not chain:
        raise GeneratorValueError("apply_transforms: names must name at least one transform, got none")
    p = _as_points(points, "apply_transforms")
    rows = np.arange(len(p), dtype=np.int64)
    steps: list[dict[str, Any]] = []
    preserved = True
    last: Transformed | None = None
    for i, name in enumerate(chain):
        last = apply_transform(name, p, transform_rng(seed, name, i))
        p = last.points
        # compose the index maps; rows added by a step stay -1
        rows = np.where(last.source_rows >= 0, rows[np.maximum(last.source_rows, 0)], -1)
        steps.append({"name": last.name, **last.params})
        preserved = preserved == last.orientation_preserved
    assert last is not None
    return Transformed(
        np.ascontiguousarray(p),
        rows.astype(np.int64),
        "+".join(chain),
        {"steps": steps},
        orientation_preserved=preserved,
        witness=last.witness if len(chain) == 1 else None,
    )


def vertex_set_change(
    points: np.ndarray,
    vertices: Iterable[int],
    transformed: Transformed,
    transformed_vertices: Iterable[int],
    *,
    limit: int = 5,
) -> str | None:
    """Compare an answer on the original with an answer on a transformed input, as sets of input points.

    Parameters
    ----------
    points : ndarray of shape (n, d), float64
        The original input.
    vertices : iterable of int
        Hull vertex indices into ``points`` (flatten 3D faces first).
    transformed : Transformed
        What a transform made of ``points``.
    transformed_vertices : iterable of int
        Hull vertex indices into ``transformed.points``.
    limit : int
        How many offending input rows to name.

    Returns
    -------
    str or None
        None when both answers name the same set of input points (compared
        by exact coordinates, so picking another copy of a duplicated point
        is no change); otherwise one line saying which input rows were lost,
        gained, or which added interior rows were reported as vertices.

    Notes
    -----
    The comparison is exact and order-free.  An algorithm may legitimately
    report non-extreme boundary points (collinear points on an edge) on one
    input and not on the other; compare the extreme vertices when the
    answers may contain such points.

    Examples
    --------
    >>> from generators.transforms import reverse_rows
    >>> pts = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [0.2, 0.2]])
    >>> t = reverse_rows(pts)
    >>> vertex_set_change(pts, [0, 1, 2], t, [3, 2, 1]) is None
    True
    >>> vertex_set_change(pts, [0, 1, 2], t, [3, 2, 0])
    'reverse-rows changed the hull vertex set: lost input row 2; gained input row 3'
    """
    p = _as_points(points, "vertex_set_change")
    src = np.asarray(transformed.source_rows, dtype=np.int64)
    before_rows = sorted({int(i) for i in vertices})
    after_idx = sorted({int(j) for j in transformed_vertices})
    added = [j for j in after_idx if src[j] < 0]
    after_rows = sorted({int(src[j]) for j in after_idx if src[j] >= 0})

    def key(row: int) -> tuple[float, ...]:
        return tuple(float(x) + 0.0 for x in p[row])  # + 0.0 folds -0.0 into 0.0

    before = {key(r): r for r in reversed(before_rows)}
    after = {key(r): r for r in reversed(after_rows)}
    lost = sorted(before[k] for k in before.keys() - after.keys())
    gained = sorted(after[k] for k in after.keys() - before.keys())
    if not (lost or gained or added):
        return None

    def rows(what: str, items: list[int]) -> str:
        shown = ", ".join(map(str, items[:limit])) + (f" and {len(items) - limit} more" if len(items) > limit else "")
        return f"{what} row{'s' if len(items) > 1 else ''} {shown}"

    parts = []
    if lost:
        parts.append(rows("lost input", lost))
    if gained:
        parts.append(rows("gained input", gained))
    if added:
        parts.append(rows("reported added interior", added))
    return f"{transformed.name} changed the hull vertex set: " + "; ".join(parts)
