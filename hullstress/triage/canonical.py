"""When do two minimal inputs coincide?  Up to the exact metamorphic transforms.

Two point sets are the same input for triage when one becomes the other by

* a translation,
* a scaling by a power of two,
* a permutation of the rows (``permute-rows`` in :mod:`generators.transforms`),
* a permutation of the coordinate axes (``permute-axes``).

:func:`canonical_form` maps every point set of such a class to one
representative, computed exactly (a translation is rarely exact in floating
point, so it is never applied to the doubles; the integers over the input's
common power-of-two denominator are): subtract each axis's minimum, divide
by the power of two that puts the largest coordinate in [1, 2), sort the
rows, and take the smallest of the forms over every order of the axes.  :func:`canonical_key` is its digest.

Reflections (``reflect``) are left out on purpose: an orientation bug may
show on a point set and not on its mirror image.  Sets with non-finite
coordinates or an unusual shape (the ``bad-input`` family) are compared
exactly, rows sorted.
"""

from __future__ import annotations

import hashlib
import itertools
import math

import numpy as np

__all__ = ["canonical_form", "canonical_key"]


def canonical_form(points: np.ndarray) -> tuple:
    """A hashable representative of ``points`` up to translation, 2**k scaling, row and axis order.

    Parameters
    ----------
    points : ndarray of shape (n, d), float64

    Returns
    -------
    tuple
        ``("exact", d, s, rows)`` for finite (n, d) arrays: the canonical
        coordinates are ``rows[i][j] / 2**s`` exactly, integers over one
        power-of-two denominator reduced as far as it goes (``s`` may be
        negative); ``("raw", ...)`` otherwise.

    Notes
    -----
    Every double is a dyadic rational, and so is every difference and
    every quotient by a power of two: over the common denominator of the
    input the whole computation is integer arithmetic, which is what makes
    it cheap (rows compare as tuples of Python ints, not of fractions).

    Examples
    --------
    >>> a = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 3.0]])
    >>> b = np.array([[12.0, 10.0], [12.0, 10.5], [13.5, 10.0]])  # halved, shifted, axes swapped, rows shuffled
    >>> canonical_form(a) == canonical_form(b)
    True
    >>> canonical_form(a) == canonical_form(a * [1.0, -1.0])  # a reflection is another input
    False
    >>> canonical_form(a)  # (0, 0), (0, 1/2), (3/2, 0): axes swapped, scaled by 1/2
    ('exact', 2, 1, ((0, 0), (0, 1), (3, 0)))
    """
    arr = np.asarray(points, dtype=np.float64)
    if arr.ndim != 2 or arr.size == 0 or not np.isfinite(arr).all():
        # No exact form: the shape and every value's bits (an empty set, shape (0, d), is
        # a case of the bad-input family like any other, and may fail in its own way).
        flat = arr.reshape(arr.shape[0], math.prod(arr.shape[1:])) if arr.ndim >= 1 else arr.reshape(1, 1)
        rows = sorted(tuple(float(x).hex() for x in row) for row in flat)
        return ("raw", arr.shape, tuple(rows))
    d = arr.shape[1]
    ratios = [[float(x).as_integer_ratio() for x in row] for row in arr.tolist()]
    denom = max(den for row in ratios for _, den in row)  # a power of two: every other divides it
    exact = [[num * (denom // den) for num, den in row] for row in ratios]  # coordinates * denom
    lows = [min(row[j] for row in exact) for j in range(d)]
    shifted = [[row[j] - lows[j] for j in range(d)] for row in exact]
    peak = max((x for row in shifted for x in row), default=0)
    # Dividing by the power of two that puts the peak in [1, 2): the denominator becomes
    # 2**(bit_length(peak) - 1), whatever denom was.  Then reduce the common factors of two.
    s = peak.bit_length() - 1 if peak > 0 else 0
    nonzero = [x for row in shifted for x in row if x]
    if nonzero:
        twos = min((x & -x).bit_length() - 1 for x in nonzero)
        shifted = [[x >> twos for x in row] for row in shifted]
        s -= twos
    best = None
    for perm in itertools.permutations(range(d)):
        form = tuple(sorted(tuple(row[j] for j in perm) for row in shifted))
        if best is None or form < best:
            best = form
    return ("exact", d, s, best)


def canonical_key(points: np.ndarray) -> str:
    """16 hex digits naming :func:`canonical_form` of ``points``.

    Examples
    --------
    >>> canonical_key(np.array([[0.0, 1.0], [2.0, 3.0]])) == canonical_key(np.array([[6.0, 4.0], [2.0, 0.0]]))
    True
    """
    return hashlib.sha256(repr(canonical_form(points)).encode()).hexdigest()[:16]
