"""The two epsilon policies shared by every in-house algorithm.

Paul Nathan's gift-wrapping seed (000_*.txt, "Elucidation", step 1) scales the
tolerance to the geometry: flatten the points onto the X-Y plane and take

    eps = eps_machine * (sqrt(max P'.P') - sqrt(min P'.P'))

``scaled`` is exactly that formula; ``fixed`` is the same without the extent
factor, i.e. plain ``eps_machine``.  In 2D the "flattened" points are the
points themselves.  The seed's quirk is kept: when every flattened point has
the same distance from the origin (a circle around it, or the sphere variant's
projection) the scaled tolerance is zero.
"""

from __future__ import annotations

from enum import Enum

import numpy as np

from .errors import UsageError

__all__ = ["MACHINE_EPSILON", "EpsPolicy", "tolerance"]

#: The seed's eps_machine: the gap between 1.0 and the next double, 2**-52.
MACHINE_EPSILON: float = float(np.finfo(np.float64).eps)


class EpsPolicy(str, Enum):
    """How an algorithm's comparison tolerance is derived from its input."""

    SCALED = "scaled"
    FIXED = "fixed"


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
        A non-negative tolerance.  Zero for empty input, and for inputs whose
        flattened points are all equally far from the origin (kept on purpose).

    Examples
    --------
    >>> tolerance(np.array([[0.0, 0.0, 0.0], [3.0, 4.0, 9.0]]))  # 5 * 2**-52
    1.1102230246251565e-15
    >>> tolerance(np.array([[1.0, 0.0], [0.0, 1.0]]))  # all on the unit circle
    0.0
    >>> tolerance(np.zeros((0, 3)), "fixed")
    2.220446049250313e-16
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
        r2 = np.einsum("ij,ij->i", flat, flat)
        spread = float(np.sqrt(r2.max()) - np.sqrt(r2.min()))
    # Non-finite input gives a non-finite tolerance, as the seed's formula would.
    return MACHINE_EPSILON * spread
