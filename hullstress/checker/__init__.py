"""The exact checker: the judge of every hull (docs/design.md "Verdict semantics").

Public entry points:

* :func:`check` -- the verdict on one hull of one point set;
* :func:`qhull_reference` / :class:`QhullReference` -- Qhull's hull of the
  input, computed once per case, with its options and its own exact health;
* :func:`affine_rank` -- the exact affine rank behind the ``rejected`` rule;
* :func:`orient2d`, :func:`orient3d` (and the ``*_mean`` forms) -- exact,
  vectorised orientation predicates.
"""

from .api import check, validate_points
from .predicates import (
    collinear3d,
    orient2d,
    orient2d_mean,
    orient2d_sum_sign,
    orient3d,
    orient3d_mean,
    orient3d_sum_sign,
)
from .qhull import DEFAULT_OPTIONS, RETRY_OPTIONS, QhullReference, qhull_reference
from .rank import affine_rank, witness_simplex
from .severity import ROUNDOFF_MULTIPLE, VOLUME_TOLERANCE_MULTIPLE

__all__ = [
    "check",
    "validate_points",
    "qhull_reference",
    "QhullReference",
    "DEFAULT_OPTIONS",
    "RETRY_OPTIONS",
    "affine_rank",
    "witness_simplex",
    "orient2d",
    "orient3d",
    "orient2d_mean",
    "orient3d_mean",
    "orient2d_sum_sign",
    "orient3d_sum_sign",
    "collinear3d",
    "ROUNDOFF_MULTIPLE",
    "VOLUME_TOLERANCE_MULTIPLE",
]
