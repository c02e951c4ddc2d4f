"""When do two minimal inputs coincide?  Up to the exact metamorphic transforms.

Two point sets are the same input for triage when one becomes the other by

* a translation,
* a scaling by a power of two,
* a permutation of the rows (``permute-rows`` in :mod:`generators.transforms`),
* a permutation of the coordinate axes (``permute-axes``).

:func:`canonical_form` maps every point set of such a class to one
representative, computed exactly with rationals (a translation is rarely
exact in floating point, so it is never applied to the doubles): subtract
each axis's minimum, divide by the power of two that puts the largest
coordinate in [1, 2), sort the rows, and take the smallest of the forms
over every order of the axes.  :func:`canonical_key` is its digest.

Reflections (``reflect``) are left out on purpose: an orientation bug may
show on a point set and not on its mirror image.  Sets with non-finite
coordinates or an unusual shape (the ``bad-input`` family) are compared
exactly, rows sorted.
"""

from __future__ import annotations

import hashlib
import itertools
from fractions import Fraction

import numpy as np

__all__ = ["canonical_form", "canonical_key"]


def _pow2_floor(x: Fraction) -> int:
    """The integer e with 2**e <= x < 2**(e+1), for x > 0 (exact)."""
    e = x.numerator.bit_length() - x.denominator.bit_length()
    # 2**(e-1) < x < 2**(e+1): one comparison settles it.
    if Fraction(2) ** e > x:
        e -= 1
    return e


def canonical_form(points: np.ndarray) -> tuple:
    """A hashable representative of ``points`` up to translation, 2**k scaling, row and axis order.

    Parameters
    ----------
    points : ndarray of shape (n, d), float64

    Returns
    -------
    tuple
        ``("exact", rows)`` with rational coordinates for finite (n, d)
        arrays, ``("raw", ...)`` otherwise.

    Examples
    --------
    >>> a = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 3.0]])
    >>> b = np.array([[12.0, 10.0], [12.0, 10.5], [13.5, 10.0]])  # halved, shifted, axes swapped, rows shuffled
    >>> canonical_form(a) == canonical_form(b)
    True
    >>> canonical_form(a) == canonical_form(a * [1.0, -1.0])  # a reflection is another input
    False
    """
    arr = np.asarray(points, dtype=np.float64)
    if arr.ndim != 2 or arr.shape[0] == 0 or not np.isfinite(arr).all():
        rows = sorted(tuple(float(x).hex() for x in row) for row in arr.reshape(len(arr), -1)) if arr.ndim >= 1 else []
        return ("raw", arr.shape, tuple(rows))
    exact = [[Fraction(float(x)) for x in row] for row in arr]
    d = arr.shape[1]
    lows = [min(row[j] for row in exact) for j in range(d)]
    shifted = [[row[j] - lows[j] for j in range(d)] for row in exact]
    peak = max((x for row in shifted for x in row), default=Fraction(0))
    if peak > 0:
        factor = Fraction(2) ** _pow2_floor(peak)
        shifted = [[x / factor for x in row] for row in shifted]
    best = None
    for perm in itertools.permutations(range(d)):
        form = tuple(sorted(tuple(row[j] for j in perm) for row in shifted))
        if best is None or form < best:
            best = form
    return ("exact", d, best)


def canonical_key(points: np.ndarray) -> str:
    """16 hex digits naming :func:`canonical_form` of ``points``.

    Examples
    --------
    >>> canonical_key(np.array([[0.0, 1.0], [2.0, 3.0]])) == canonical_key(np.array([[6.0, 4.0], [2.0, 0.0]]))
    True
    """
    return hashlib.sha256(repr(canonical_form(points)).encode()).hexdigest()[:16]
