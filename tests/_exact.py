"""Exact rational geometry for the tests, independent of the code under test (generators._common, the checker)."""

from __future__ import annotations

import math
from fractions import Fraction

import numpy as np


def frac_rows(points: np.ndarray) -> list[list[Fraction]]:
    """Every coordinate as the exact rational value of its double."""
    return [[Fraction(float(x)) for x in row] for row in points]


def det_frac(m: list[list[Fraction]]) -> Fraction:
    """Determinant by cofactor expansion (the matrices here are at most 3 x 3)."""
    if len(m) == 1:
        return m[0][0]
    if len(m) == 2:
        return m[0][0] * m[1][1] - m[0][1] * m[1][0]
    return sum(((-1) ** j) * m[0][j] * det_frac([row[:j] + row[j + 1 :] for row in m[1:]]) for j in range(len(m)))


def orient_frac(rows: list[list[Fraction]]) -> Fraction:
    """det[p1 - p0, ..., pd - p0] for d+1 rational points of dimension d."""
    base = rows[0]
    return det_frac([[r[j] - base[j] for j in range(len(base))] for r in rows[1:]])


def orient2d(a, b, c):
    """Exact orient2d of integer or Fraction points: positive when ``c`` is left of ``a -> b``."""
    return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])


def winding_number(ring, o) -> int:
    """The winding number of a closed (x, y) polygon of integer or Fraction points around ``o`` (not on it)."""
    w = 0
    for i, a in enumerate(ring):
        b = ring[(i + 1) % len(ring)]
        if a[1] <= o[1] < b[1] and orient2d(a, b, o) > 0:
            w += 1
        elif b[1] <= o[1] < a[1] and orient2d(a, b, o) < 0:
            w -= 1
    return w


def affine_rank(points: np.ndarray) -> int:
    """Exact affine rank of a point set (0 for one distinct point, 1 collinear, 2 coplanar...)."""
    rows = frac_rows(points)
    if not rows:
        return -1
    base = rows[0]
    mat = [[r[j] - base[j] for j in range(len(base))] for r in rows[1:]]
    rank = 0
    for c in range(len(base)):
        piv = next((i for i in range(rank, len(mat)) if mat[i][c] != 0), None)
        if piv is None:
            continue
        mat[rank], mat[piv] = mat[piv], mat[rank]
        for i in range(len(mat)):
            if i != rank and mat[i][c] != 0:
                f = mat[i][c] / mat[rank][c]
                mat[i] = [a - f * b for a, b in zip(mat[i], mat[rank])]
        rank += 1
    return rank


def nextafter_steps(a: float, b: float, limit: int) -> int | None:
    """How many math.nextafter steps lead from a to b (None if more than ``limit``)."""
    x = float(a)
    for k in range(limit + 1):
        if x == b:
            return k
        x = math.nextafter(x, b)
    return None
