"""Judging a row against its algorithm's declared contract (:mod:`hullstress.hull_contract`).

The exact checker decides whether an output is *a* correct hull under the
lenient reading (any boundary point may be a vertex, polygons allowed, flat
input may raise).  A declared contract can promise more; :func:`apply_contract`
turns a row that keeps the lenient rules but breaks a declared promise into a
``fail`` and names the promise in ``failed_checks``
(:data:`~hullstress.hull_contract.CONTRACT_CHECKS`) and in the reason.  It never
makes a row pass that the checker failed: a contract only adds promises.
"""

from __future__ import annotations

from typing import Any

from .contract import FaceSet
from .hull_contract import HullContract
from .records import Stage, Status
from .results import ResultRow

__all__ = ["apply_contract", "DECLARED_REASON"]

#: How the reason of a row failed by its declared contract begins.
DECLARED_REASON = "declared contract"


def _broken_promises(row: ResultRow, contract: HullContract, faces: Any, degenerate: bool) -> list[tuple[str, str]]:
    """(check, why) for every promise of ``contract`` that ``row`` breaks."""
    broken: list[tuple[str, str]] = []
    status = row.get("status")
    if status == Status.PASS:
        kept = row.get("n_boundary_nonextreme")
        if contract.vertices == "extreme" and kept is not None and int(kept) > 0:
            broken.append(("extreme_only", f"{int(kept)} hull vertices are not extreme points "
                                           "(on an edge or face of the hull), but only extreme points may be"))
        if contract.faces == "triangles" and isinstance(faces, FaceSet) and not faces.is_triangles:
            big = int((faces.sizes != 3).sum())
            broken.append(("face_shape", f"{big} faces are not triangles, but every face must be"))
        if contract.flat == "raise" and degenerate and row.get("invalid_input") in ("", None):
            broken.append(("flat_input", "returned an answer for flat input (affine rank "
                                         f"{row.get('affine_rank')}), but flat input must raise"))
    elif status == Status.REJECTED and contract.flat == "lower-dim" and degenerate \
            and row.get("invalid_input") in ("", None):
        broken.append(("flat_input", f"raised on flat input ({row.get('reason')}), but flat input must be "
                                     "answered with its lower-dimensional hull"))
    return broken


def apply_contract(row: ResultRow, contract: HullContract, faces: Any, *, degenerate: bool) -> ResultRow:
    """``row`` judged against ``contract`` as well: a ``fail`` naming each broken promise, or unchanged.

    Parameters
    ----------
    row : ResultRow
        The row the status rules and the exact checker produced.
    contract : HullContract
        The algorithm's declared contract.
    faces : ndarray or FaceSet or None
        The normalised output the row judged (None when there was none).
    degenerate : bool
        The input is affinely degenerate (flat).

    Examples
    --------
    >>> from hullstress.hull_contract import STRICT, LENIENT
    >>> row = ResultRow({"status": "pass", "n_boundary_nonextreme": 1, "failed_checks": "", "reason": ""})
    >>> apply_contract(row, STRICT, None, degenerate=False)["failed_checks"]
    'extreme_only'
    >>> apply_contract(row, LENIENT, None, degenerate=False)["status"]
    'pass'
    """
    broken = _broken_promises(row, contract, faces, degenerate)
    if not broken:
        return row
    values = dict(row.values)
    earlier = [c for c in str(values.get("failed_checks") or "").split(",") if c]
    values["status"] = Status.FAIL.value
    values["stage"] = Stage.ALGORITHM.value
    values["failed_checks"] = ",".join(earlier + [check for check, _ in broken])
    values["reason"] = (f"{DECLARED_REASON} ({contract.label}): " + "; ".join(why for _, why in broken))[:500]
    return ResultRow(values)
