"""Result rows: one frozen record per (case, algorithm config), and the one place they become a DataFrame."""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from typing import Any

import pandas as pd

from .case import Case
from .config import AlgorithmConfig
from .records import Stage
from .verdict import VERDICT_COLUMNS, Verdict, empty_verdict_row

__all__ = [
    "STATUSES",
    "ResultRow",
    "ROW_COLUMNS",
    "TIMING_COLUMNS",
    "make_row",
    "to_frame",
]

#: Every call ends in exactly one of these (DESIGN.md, "The runner").
STATUSES = ("pass", "fail", "rejected", "error", "timeout", "crash")

_PROVENANCE = ("case_id", "generator", "params", "transform", "dim", "n_points", "size", "seed", "source")
_CONFIG = ("algorithm", "origin", "sphere", "eps", "config")
_OUTCOME = ("status", "stage", "sphere_method", "reason", "error_frame", "seconds", "check_seconds", "eps_value",
            "degenerate", "invalid_input", "call_output")

#: Column order of every results table.
ROW_COLUMNS = _PROVENANCE + _CONFIG + _OUTCOME + VERDICT_COLUMNS
#: Columns that measure time and so differ between otherwise identical runs.
TIMING_COLUMNS = ("seconds", "check_seconds")


@dataclass(frozen=True)
class ResultRow:
    """The outcome of running one algorithm config on one case.

    ``values`` holds every column of :data:`ROW_COLUMNS`; use :meth:`get` or
    ``row["status"]`` to read one.  Rows are plain data (picklable, no arrays)
    so they travel cheaply from worker processes and Dask workers.
    """

    values: Mapping[str, Any] = field(default_factory=dict)

    def __getitem__(self, key: str) -> Any:
        return self.values[key]

    def get(self, key: str, default: Any = None) -> Any:
        return self.values.get(key, default)

    @property
    def status(self) -> str:
        return self.values["status"]

    @property
    def stage(self) -> str:
        """The stage that produced the verdict (:class:`~hullstress.records.Stage` value)."""
        return self.values.get("stage", Stage.ALGORITHM.value)

    @property
    def failed(self) -> bool:
        """True for outcomes that count as failures: fail, error, timeout, crash."""
        return self.values["status"] in ("fail", "error", "timeout", "crash")


def make_row(
    case: Case,
    config: AlgorithmConfig,
    *,
    status: str,
    stage: Stage | str = Stage.ALGORITHM,
    sphere_method: str = "",
    reason: str = "",
    seconds: float = 0.0,
    check_seconds: float = 0.0,
    eps_value: float | None = None,
    degenerate: bool | None = None,
    invalid_input: str | None = None,
    verdict: Verdict | None = None,
    origin: str | None = None,
    call_output: str = "",
    error_frame: str = "",
) -> ResultRow:
    """Assemble a :class:`ResultRow` from its parts.

    Parameters
    ----------
    case, config
        What ran.
    status : str
        One of :data:`STATUSES`.
    stage : Stage
        The stage that produced the verdict (``algorithm`` unless preprocessing
        or the checker did).
    sphere_method : str
        With sphere on, the sphere method's own verdict: ``pass`` (the hull
        maps back to the input's hull), ``fail``, ``rejected`` or ``error``
        (preprocessing declined or broke); empty when sphere is off or the
        method could not be judged (the algorithm failed first).
    reason : str
        One line: the exception, the contract violation, the failed checks, the signal.
    verdict : Verdict, optional
        The checker's verdict; its columns are missing values when absent.
    call_output : str
        What the call wrote on stdout and stderr (a library's warnings, a
        program's messages), its tail, captured by the runner.
    error_frame : str
        For an exception: the innermost frame of the code under test that
        raised it (``module:line in function``).
    """
    if status not in STATUSES:
        raise ValueError(f"status must be one of {STATUSES}, got {status!r}")
    stage = Stage(stage)
    if origin is None:
        try:
            origin = config.spec.origin
        except Exception:  # an algorithm from a plug-in not loaded here
            origin = "unknown"
    values: dict[str, Any] = {
        "case_id": case.case_id,
        "generator": case.family,
        "params": case.params_json,
        "transform": case.params.get("transform", "") if isinstance(case.params, Mapping) else "",
        "dim": case.dim,
        "n_points": case.n_points,
        "size": case.size,
        "seed": case.seed,
        "source": case.source,
        "algorithm": config.algorithm,
        "origin": origin,
        "sphere": config.sphere,
        "eps": config.eps,
        "config": config.label,
        "status": status,
        "stage": stage.value,
        "sphere_method": sphere_method,
        "reason": " ".join(str(reason).split())[:500],
        "error_frame": error_frame,
        "seconds": float(seconds),
        "check_seconds": float(check_seconds),
        "eps_value": eps_value,
        "degenerate": degenerate,
        "invalid_input": invalid_input or "",
        "call_output": call_output,
    }
    values.update(verdict.as_row() if verdict is not None else empty_verdict_row())
    return ResultRow(values)


def to_frame(rows: Iterable[ResultRow]) -> pd.DataFrame:
    """The results table: one row per (case, config), columns in :data:`ROW_COLUMNS` order.

    Boolean check columns use pandas' nullable ``boolean`` dtype (missing when
    no hull was checked), counts use nullable ``Int64``.
    """
    records = [r.values for r in rows]
    df = pd.DataFrame.from_records(records, columns=list(ROW_COLUMNS))
    for col in ("convexity", "containment", "manifoldness", "qhull_ok", "degenerate"):
        df[col] = df[col].astype("boolean")
    for col in (
        "dim", "n_points", "size", "seed", "n_faces", "n_hull_vertices", "n_extreme",
        "n_missing_extreme", "n_boundary_nonextreme", "n_outside", "n_nonconvex_edges",
        "n_degenerate_faces", "affine_rank",
    ):
        df[col] = pd.to_numeric(df[col], errors="coerce").astype("Int64")
    for col in ("seconds", "check_seconds", "eps_value", "max_violation", "distround", "volume", "qhull_volume"):
        df[col] = pd.to_numeric(df[col], errors="coerce").astype("float64")
    for col in ("qhull_agreement", "failed_checks", "severity", "qhull_options", "offending", "reason", "error_frame",
                "invalid_input", "transform", "stage", "sphere_method", "call_output"):
        df[col] = df[col].astype("string")
    return df
