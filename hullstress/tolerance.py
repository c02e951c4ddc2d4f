"""The two epsilon policies shared by every in-house algorithm.

Paul Nathan's gift-wrapping seed (000_*.txt, "Elucidation", step 1) scales the
tolerance to the geometry: flatten the points onto the X-Y plane and take

    eps = eps_machine * (sqrt(max P'.P') - sqrt(min P'.P'))

``scaled`` is exactly that formula; ``fixed`` is the same without the extent
factor, i.e. plain ``eps_machine``.  In 2D the "flattened" points are the
points themselves.  The seed's quirk is kept: when every flattened point has
the same distance from the origin (a circle around it, or the sphere variant's
projection) the scaled tolerance is zero.

Units.  ``scaled`` is a length (eps_machine is a pure number, the spread a
distance), the unit of the seed's signed distances ``d = n.(P - V0)`` it is
compared with.  ``fixed`` is the pure number ``2**-52`` used as a length: on
purpose, it is the control that shows what the extent factor changes.  Where
an in-house algorithm compares eps with an area (the Jarvis march and the
monotone chain compare it with an orientation determinant), that is the
seed's literal test, kept and documented in the algorithm's module.

Extreme scale.  ``P'.P'`` overflows above about 1e154 and underflows below
about 1e-154, so the formula is evaluated on the points multiplied by an exact
power of two (the largest coordinate brought into [0.5, 1)) and the result
multiplied back: at every finite scale the tolerance is finite, and at
ordinary scales it has exactly the bits of the literal formula (a power of two
changes no rounding).  Non-finite input gives a non-finite tolerance, as the
seed's formula would.
"""

from __future__ import annotations

import numpy as np

from .errors import UsageError
from .records import EpsPolicy

__all__ = ["MACHINE_EPSILON", "EpsPolicy", "tolerance"]

#: The seed's eps_machine: the gap between 1.0 and the next double, 2**-52.
MACHINE_EPSILON: float = float(np.finfo(np.float64).eps)


def tolerance(points: np.ndarray, policy: EpsPolicy | str = EpsPolicy.SCALED) -> float:
    """Return the comparison tolerance for ``points`` under ``policy``.

    Parameters
    ----------
    points : ndarray of shape (n, d), float64
        The points the algorithm will see (after any preprocessing).
    policy : {"scaled", "fixed"}
        ``scaled``: machine epsilon times the spread of the flattened points'
        distances from the origin (Nathan's formula); ``fixed``: machine
        epsilon alone.

    Returns
    -------
    float
        A non-negative tolerance, finite for every finite input (NaN or inf
        for input with non-finite coordinates).  Zero for empty input, and
        for inputs whose flattened points are all equally far from the origin
        (kept on purpose).

    Examples
    --------
    >>> tolerance(np.array([[0.0, 0.0, 0.0], [3.0, 4.0, 9.0]]))  # 5 * 2**-52
    1.1102230246251565e-15
    >>> tolerance(np.array([[1.0, 0.0], [0.0, 1.0]]))  # all on the unit circle
    0.0
    >>> tolerance(np.zeros((0, 3)), "fixed")
    2.220446049250313e-16
    >>> tolerance(np.array([[0.0, 0.0], [1e300, 0.0]]))  # (1e300)**2 would overflow
    2.2204460492503132e+284
    """
    try:
        policy = EpsPolicy(policy)
    except ValueError:
        raise UsageError(
            f"eps policy must be one of 'scaled', 'fixed', got {policy!r}"
        ) from None
    if policy is EpsPolicy.FIXED:
        return MACHINE_EPSILON
    pts = np.asarray(points, dtype=np.float64)
    if pts.ndim != 2 or pts.shape[0] == 0:
        return 0.0
    flat = pts[:, :2]
    with np.errstate(over="ignore", invalid="ignore"):
        largest = float(np.abs(flat).max()) if flat.size else 0.0
    if not np.isfinite(largest):
        return float("nan") if np.isnan(flat).any() else float("inf")
    # An exact power-of-two rescale keeps P'.P' in range (see the module docstring).
    exponent = int(np.frexp(largest)[1]) if largest > 0.0 else 0
    unit = np.ldexp(flat, -exponent)
    r2 = np.einsum("ij,ij->i", unit, unit)
    spread = float(np.sqrt(r2.max()) - np.sqrt(r2.min()))
    # spread <= 2, so eps_machine * spread * 2**exponent <= 2**-51 * 2**1024: always finite.
    return float(np.ldexp(MACHINE_EPSILON * spread, exponent))
