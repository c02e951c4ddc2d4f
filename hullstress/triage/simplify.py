"""Exact coordinate simplifications: fewer mantissa bits, power-of-two scaling."""

from __future__ import annotations

import numpy as np

__all__ = ["round_mantissa", "mantissa_bits", "pow2_normalize", "coordinate_candidates"]


def round_mantissa(values: np.ndarray, bits: int) -> np.ndarray:
    """Round every finite value to ``bits`` significant binary digits (ties to even).

    Parameters
    ----------
    values : ndarray of float64
    bits : int
        1 to 53.

    Returns
    -------
    ndarray of float64
        Same shape; zeros, infinities and NaNs unchanged; finite values stay
        finite (values that would round up past the largest double are
        truncated instead).

    Examples
    --------
    >>> round_mantissa(np.array([0.1, 3.0, -7.0, 0.0]), 2).tolist()
    [0.09375, 3.0, -8.0, 0.0]
    """
    if not 1 <= bits <= 53:
        raise ValueError(f"bits must be in 1..53, got {bits}")
    arr = np.asarray(values, dtype=np.float64)
    finite = np.isfinite(arr)
    mant, expo = np.frexp(np.where(finite, arr, 0.0))  # mant in [0.5, 1)
    # Scaling by 2**bits and back is exact; np.round rounds half to even.
    scaled = np.ldexp(mant, bits)
    with np.errstate(over="ignore"):
        rounded = np.ldexp(np.round(scaled), expo - bits)
        # Rounding up the very largest doubles overflows: truncate those instead.
        rounded = np.where(np.isfinite(rounded), rounded, np.ldexp(np.trunc(scaled), expo - bits))
    return np.where(finite, rounded, arr)


def mantissa_bits(values: np.ndarray) -> np.ndarray:
    """Significant binary digits of each value (0 for zero and non-finite values).

    Examples
    --------
    >>> mantissa_bits(np.array([1.0, 3.0, 0.1, 0.0])).tolist()
    [1, 2, 52, 0]
    """
    arr = np.asarray(values, dtype=np.float64)
    out = np.zeros(arr.shape, dtype=np.int64)
    finite = np.isfinite(arr) & (arr != 0)
    mant, _ = np.frexp(arr[finite])
    ints = np.abs(np.ldexp(mant, 53)).astype(np.uint64)  # exact: a 53-bit integer, never 0
    lowest = ints & (~ints + np.uint64(1))  # its lowest set bit, 2**(trailing zeros)
    _, expo = np.frexp(lowest.astype(np.float64))  # exact for a power of two: 2**k = 0.5 * 2**(k + 1)
    out[finite] = 53 - (expo.astype(np.int64) - 1)
    return out


def pow2_normalize(points: np.ndarray) -> np.ndarray | None:
    """Scale by a power of two so the largest finite magnitude lies in [1, 2).

    Returns None when there is nothing to do (all zero, already in range) or
    when the scaling would not be exact (a value would under- or overflow).

    Examples
    --------
    >>> pow2_normalize(np.array([[1024.0, -3072.0]])).tolist()
    [[0.5, -1.5]]
    >>> pow2_normalize(np.array([[1.5, 0.25]])) is None
    True
    """
    arr = np.asarray(points, dtype=np.float64)
    finite = arr[np.isfinite(arr)]
    if finite.size == 0 or not np.any(finite):
        return None
    _, expo = np.frexp(np.max(np.abs(finite)))  # max in [2**(expo-1), 2**expo)
    shift = 1 - int(expo)
    if shift == 0:
        return None
    scaled = np.ldexp(arr, shift)
    with np.errstate(invalid="ignore"):
        exact = np.array_equal(np.ldexp(scaled, -shift), arr, equal_nan=True)
    return scaled if exact else None


def coordinate_candidates(value: float, ladder: tuple[int, ...] = (1, 2, 4, 8, 16, 24, 32, 40)) -> list[float]:
    """Simpler replacements for one coordinate, simplest first: 0, an integer, fewer bits.

    Only candidates with fewer significant bits (or zero) than ``value`` and
    different from it are returned.

    Examples
    --------
    >>> coordinate_candidates(2.75)
    [0.0, 3.0, 2.0]
    >>> coordinate_candidates(0.0)
    []
    """
    if not np.isfinite(value) or value == 0.0:
        return []
    current = int(mantissa_bits(np.array([value]))[0])
    out = [0.0]
    integer = float(np.round(value))
    if integer != value and integer != 0.0 and int(mantissa_bits(np.array([integer]))[0]) < current:
        out.append(integer)
    for bits in ladder:
        if bits >= current:
            break
        cand = float(round_mantissa(np.array([value]), bits)[0])
        if cand != value:
            out.append(cand)
    return list(dict.fromkeys(out))
