"""Result rows: one frozen record per (case, algorithm config), and the one place they become a DataFrame."""

from __future__ import annotations

import os
from collections.abc import Iterable, Mapping
from pathlib import Path
from dataclasses import dataclass, field
from typing import Any

import pandas as pd

from .case import Case
from .config import AlgorithmConfig
from .records import FAILED_STATUSES, Stage, Status
from .sphere_causes import SPHERE_CAUSE_COLUMNS, SphereCauses, empty_sphere_causes
from .verdict import VERDICT_COLUMNS, Verdict, empty_verdict_row

__all__ = [
    "STATUSES",
    "ResultRow",
    "ROW_COLUMNS",
    "TIMING_COLUMNS",
    "make_row",
    "to_frame",
    "read_frame",
    "REQUIRED_COLUMNS",
    "RESULTS_FILES",
]

#: Every call ends in exactly one of these (docs/design.md, "Statuses and stages").
STATUSES = tuple(s.value for s in Status)

_PROVENANCE = ("case_id", "generator", "params", "transform", "dim", "n_points", "size", "seed", "source")
_CONFIG = ("algorithm", "origin", "sphere", "eps", "config", "contract")
_OUTCOME = ("status", "stage", "sphere_method", *SPHERE_CAUSE_COLUMNS, "reason", "error_frame", "seconds",
            "check_seconds", "eps_value", "degenerate", "invalid_input", "call_output")

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
        return self.values["status"] in FAILED_STATUSES


def make_row(
    case: Case,
    config: AlgorithmConfig,
    *,
    status: str,
    stage: Stage | str = Stage.ALGORITHM,
    sphere_method: str = "",
    sphere_causes: SphereCauses | None = None,
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
    contract: str | None = None,
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
    sphere_causes : SphereCauses, optional
        With sphere on, the method's vertex loss and face-structure change on
        this case (:mod:`hullstress.sphere_causes`); missing values without one.
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
    contract : str, optional
        The declared contract's label, for a process where the algorithm is
        not registered (a runner's parent building a timeout or crash row);
        by default the registered spec's.
    """
    if status not in STATUSES:
        raise ValueError(f"status must be one of {STATUSES}, got {status!r}")
    stage = Stage(stage)
    try:
        spec = config.spec
    except Exception:  # an algorithm from a plug-in not loaded here
        spec = None
    if origin is None:
        origin = spec.origin if spec is not None else "unknown"
    if contract is None:
        contract = spec.contract.label if spec is not None else ""  # the promise the row was judged against
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
        "contract": contract,
        "status": Status(status).value,  # a plain string in the table, whichever spelling came in
        "stage": stage.value,
        "sphere_method": str(sphere_method),
        **(sphere_causes.columns() if sphere_causes is not None else empty_sphere_causes()),
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
    return _typed(pd.DataFrame.from_records(records, columns=list(ROW_COLUMNS)))


def _typed(df: pd.DataFrame) -> pd.DataFrame:
    """``df`` with every column of :data:`ROW_COLUMNS` present and of its table dtype."""
    for col in ROW_COLUMNS:
        if col not in df.columns:  # a table written before the column existed
            df[col] = pd.NA
    for col in ("convexity", "containment", "manifoldness", "qhull_ok", "degenerate"):
        df[col] = df[col].astype("boolean")
    for col in (
        "dim", "n_points", "size", "seed", "n_faces", "n_hull_vertices", "n_extreme",
        "n_missing_extreme", "n_boundary_nonextreme", "n_outside", "n_nonconvex_edges",
        "n_degenerate_faces", "affine_rank", "sphere_extreme", "sphere_lost_extreme",
    ):
        df[col] = pd.to_numeric(df[col], errors="coerce").astype("Int64")
    for col in ("seconds", "check_seconds", "eps_value", "max_violation", "distround", "volume", "qhull_volume"):
        df[col] = pd.to_numeric(df[col], errors="coerce").astype("float64")
    for col in ("qhull_agreement", "failed_checks", "severity", "qhull_options", "offending", "reason", "error_frame",
                "invalid_input", "transform", "stage", "contract", "sphere_method", "sphere_structure", "sphere_kept_structure", "call_output"):
        df[col] = df[col].astype("string")
    return df


#: Text columns whose empty value means "none", not "missing".
_TEXT_COLUMNS = ("params", "transform", "source", "contract", "sphere_method", "sphere_structure", "sphere_kept_structure",
                 "reason", "invalid_input", "failed_checks", "severity", "qhull_options", "offending", "stage",
                 "error_frame", "call_output")

#: The results tables a run folder holds, in the order a reader prefers them (Parquet keeps every bit).
RESULTS_FILES = ("results.parquet", "results.csv")

#: Columns without which a file is not a results table.
REQUIRED_COLUMNS = ("algorithm", "sphere", "eps", "generator", "status")


def read_frame(path: str | os.PathLike[str], *, required: Iterable[str] = REQUIRED_COLUMNS) -> pd.DataFrame:
    """Read a results table written by a run (``results.csv`` or ``results.parquet``), with its dtypes.

    Columns added since the table was written are filled with missing values;
    text columns that were empty in the CSV are empty strings again.

    Parameters
    ----------
    path : path
        ``.parquet`` is read as Parquet, anything else as CSV.
    required : iterable of str
        Columns the file must have (default :data:`REQUIRED_COLUMNS`).

    Raises
    ------
    OSError, ValueError, ImportError
        When the file cannot be read or is not a results table (the message
        names what is missing); callers turn these into one-line errors.
    """
    p = Path(path)
    if p.suffix == ".parquet":
        df = pd.read_parquet(p)
    else:
        # "n/a" is the eps column's value for algorithms without eps, not a missing value.
        df = pd.read_csv(p, dtype={c: "string" for c in _TEXT_COLUMNS}, keep_default_na=False, na_values=[""])
    missing = sorted(set(required) - set(df.columns))
    if missing:
        raise ValueError(f"not a hullstress results table (missing columns {missing})")
    df = _typed(df)
    for col in _TEXT_COLUMNS:
        df[col] = df[col].fillna("")
    return df

