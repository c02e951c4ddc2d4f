"""The verdict record: what the checker concludes about one hull of one point set.

The checker (``hullstress.checker``) fills it; the sweep flattens it into table
columns with :meth:`Verdict.as_row`.  :data:`VERDICT_COLUMNS` fixes the column
order, and rows for calls that produced no hull (errors, timeouts, crashes)
carry the same columns with missing values, so every table has one schema.
"""

from __future__ import annotations

import json
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

from .hull_contract import CONTRACT_CHECKS
from .records import Status

__all__ = [
    "Verdict",
    "VERDICT_COLUMNS",
    "CHECKS",
    "SEVERITIES",
    "AGREE",
    "DISAGREE",
    "QHULL_WRONG",
    "QHULL_AGREEMENTS",
    "empty_verdict_row",
]

#: The four checks of docs/design.md, in report order.
CHECKS = ("convexity", "containment", "manifoldness", "qhull_agreement")

#: Every value the "failed check" part of a failure signature can take (``shrink --check`` accepts
#: these; :mod:`hullstress.triage.signature`).  Here, beside the checks, so that building the
#: command line's parser imports nothing heavy.
FAILED_CHECKS = (("contract",) + CHECKS + CONTRACT_CHECKS + ("collapsed", "invalid-input")
                 + (Status.ERROR.value, Status.TIMEOUT.value, Status.CRASH.value))

#: ``qhull_agreement``: the hull's extreme vertex set and volume agree with Qhull's, whose
#: own hull passed the exact checks.
AGREE = "agree"
#: ``qhull_agreement``: they differ from a Qhull hull that passed the exact checks: the
#: algorithm is wrong (a failed check).
DISAGREE = "disagree"
#: ``qhull_agreement``: Qhull's own hull fails the exact checks, so it is no reference here;
#: never a failed check of the algorithm, which is judged by the exact checks alone.
QHULL_WRONG = "qhull-wrong"
#: Every value of ``qhull_agreement`` besides missing (no reference: Qhull not run, or
#: failed under every option set).
QHULL_AGREEMENTS = (AGREE, DISAGREE, QHULL_WRONG)
#: Severity of the worst violation: none, within a small multiple of Qhull's DISTround, or beyond.
SEVERITIES = ("none", "roundoff", "gross")

#: Verdict columns as they appear in results tables (after the provenance and status columns).
VERDICT_COLUMNS = (
    "convexity",
    "containment",
    "manifoldness",
    "qhull_agreement",
    "failed_checks",
    "severity",
    "max_violation",
    "distround",
    "n_faces",
    "n_hull_vertices",
    "n_extreme",
    "n_missing_extreme",
    "n_boundary_nonextreme",
    "n_outside",
    "n_nonconvex_edges",
    "n_degenerate_faces",
    "volume",
    "qhull_volume",
    "qhull_options",
    "qhull_ok",
    "affine_rank",
    "offending",
)


@dataclass(frozen=True)
class Verdict:
    """The certified verdict on one hull.

    Attributes
    ----------
    convexity, containment, manifoldness : bool
        docs/design.md's checks, decided with exact predicates.
    qhull_agreement : {"agree", "disagree", "qhull-wrong"} or None
        Whether the extreme vertex set and the volume (area) agree with
        Qhull's: ``"agree"`` or ``"disagree"`` (a failed check) against a
        Qhull hull that passes the exact checks; ``"qhull-wrong"`` when
        Qhull's own hull fails them (Qhull is then no reference and the
        algorithm is not charged); ``None`` without a reference (Qhull not
        run, or failed even with retried options).  The volumes are compared
        exactly, within a shell of ``VOLUME_TOLERANCE_MULTIPLE`` DISTround
        times Qhull's surface area.
    severity : {"none", "roundoff", "gross"}
        Of the worst violation, in units of Qhull's DISTround for the input.
    max_violation : float
        The worst violation's magnitude divided by DISTround (0.0 when none).
    distround : float
        Qhull's DISTround for the input (the unit of ``max_violation``).
    n_faces, n_hull_vertices : int
        Size of the surface checked.
    n_extreme : int or None
        Number of true extreme points of the input (None when it could not be certified).
    n_missing_extreme : int
        Extreme points that are not vertices of the hull.
    n_boundary_nonextreme : int
        Hull vertices on the boundary but not extreme (allowed, counted).
    n_outside : int
        Input points strictly outside some facet.
    n_nonconvex_edges : int
        Edges whose neighbouring facet's far vertex is strictly above.
    n_degenerate_faces : int
        Faces that are degenerate, non-planar or non-convex.
    volume : float
        Volume (area in 2D) of the checked hull: a function of its face set
        only (never of face order), exact where the float sum is not.  It is
        the signed volume of the cones from the surface's lowest-index vertex
        to its faces: on a closed surface any apex gives the same value; on an
        open one this choice makes it well defined.
    qhull_volume : float or None
        The same for Qhull's faces.
    qhull_options : str or None
        The Qhull options that produced the reference (e.g. ``"Qt"``, ``"QJ"``).
    qhull_ok : bool or None
        Whether Qhull's own hull passes the same exact checks.
    affine_rank : int
        Exact affine rank of the input (``dim`` for a full-dimensional input).
    offending : mapping of str to tuple of int
        Up to a limit of offending point or face indices per check, e.g.
        ``{"containment": (17, 40), "convexity_faces": (3,)}``.
    detail : str
        One human-readable line summarising what failed.
    """

    convexity: bool
    containment: bool
    manifoldness: bool
    qhull_agreement: str | None
    severity: str = "none"
    max_violation: float = 0.0
    distround: float = 0.0
    n_faces: int = 0
    n_hull_vertices: int = 0
    n_extreme: int | None = None
    n_missing_extreme: int = 0
    n_boundary_nonextreme: int = 0
    n_outside: int = 0
    n_nonconvex_edges: int = 0
    n_degenerate_faces: int = 0
    volume: float = 0.0
    qhull_volume: float | None = None
    qhull_options: str | None = None
    qhull_ok: bool | None = None
    affine_rank: int = 0
    offending: Mapping[str, tuple[int, ...]] = field(default_factory=dict)
    detail: str = ""

    @property
    def failed_checks(self) -> tuple[str, ...]:
        """Names of the checks that failed, in :data:`CHECKS` order."""
        return tuple(c for c in CHECKS if getattr(self, c) in (False, DISAGREE))

    @property
    def ok(self) -> bool:
        """True when no check failed (a missing or ``"qhull-wrong"`` agreement does not count as failed)."""
        return not self.failed_checks

    def as_row(self) -> dict[str, Any]:
        """The verdict as table columns, in :data:`VERDICT_COLUMNS` order."""
        row: dict[str, Any] = {}
        for col in VERDICT_COLUMNS:
            if col == "failed_checks":
                row[col] = ",".join(self.failed_checks)
            elif col == "offending":
                row[col] = json.dumps(
                    {k: list(map(int, v)) for k, v in sorted(self.offending.items())},
                    separators=(",", ":"),
                )
            else:
                row[col] = getattr(self, col)
        return row


def empty_verdict_row() -> dict[str, Any]:
    """Verdict columns for a call that produced no checkable hull (all missing)."""
    return {col: None for col in VERDICT_COLUMNS}
