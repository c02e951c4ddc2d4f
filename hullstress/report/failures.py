"""One folder per cause: ``failures/<slug>/``.

A cause is one or more failure groups whose minimal cases coincide (see
:class:`hullstress.triage.records.Cause`); its folder holds the minimal case
of its representative (the worst group) and says which other configs and
families fail the same way on it.  Everything in a folder is a function of
the run's results, never of its timing: two runs with the same seed write
byte-identical folders (only the run folder's own path, which carries the
start time, appears in the reproduce command).

Contents:

``points.csv`` and/or ``points.npy``
    The minimal case, exact (``.csv`` prints ``repr`` floats, which read back
    bit for bit through :func:`hullstress.io.read_points`; inputs the reader
    refuses, with NaN or of odd shapes, have only the ``.npy``).
``case.json``
    The cause: the representative's signature and config, the original case
    (family, params, seed, id, size), the shrink (sizes, evaluations, steps,
    notes), the families and every member group with its own signature,
    counts and minimal points, and the reproduce command.
``faces.json``
    The algorithm's output on the minimal case, in input indices.
``verdict.json``
    Status, stage, reason, frame, the checker's verdict columns and offending indices.
``picture.png``
    For the top causes (the profile's picture count): see :mod:`hullstress.report.pictures`.
``repro.py`` (or ``input.txt``, ``command.txt`` and ``repro.sh`` for a program), ``certificate.json``, ``verify.py``, ``bug-report.md``
    For the maintainer of the code that failed, who need not install
    hullstress: see :mod:`hullstress.report.handover`.
``reproduce.txt``
    One shell command, runnable from any directory, that re-runs the case and
    exits 1 while the failure persists: ``hullstress reproduce <folder>`` with
    the full path of the interpreter that ran.
"""

from __future__ import annotations

import dataclasses
import json
import math
import shlex
import sys
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from ..files import atomic_write_bytes, atomic_write_text, atomic_write_with
from ..results import ResultRow
from ..triage.grouping import FailureGroup
from ..triage.records import Cause, TriageRecord
from ..triage.signature import Signature

__all__ = ["FailureRecord", "write_cause_folder", "write_failure_folder", "draw_picture", "picture_request",
           "picture_png", "with_picture", "reproduce_command", "report_run_command",
           "python_command", "CASE_FILE", "TIMING_KEYS"]

#: The file of a folder that ``hullstress reproduce`` reads.
CASE_FILE = "case.json"
#: Row values that measure time: never written into a folder (they differ between identical runs).
TIMING_KEYS = ("seconds", "check_seconds")


@dataclass(frozen=True, eq=False)
class FailureRecord:
    """What was written for one cause (the report, the summary and JUnit read these).

    Attributes
    ----------
    cause : Cause
    folder : Path
    command : str
        The one-line reproduce command.
    points : ndarray of shape (n, dim)
        The minimal case's points.
    picture : bytes or None
        PNG bytes (also written to ``picture.png``).
    """

    cause: Cause
    folder: Path
    command: str
    points: np.ndarray
    picture: bytes | None = None

    # The representative's facts, for the report's convenience.
    @property
    def signature(self) -> Signature:
        return self.cause.signature

    @property
    def record(self) -> TriageRecord:
        return self.cause.representative

    @property
    def group(self) -> FailureGroup | None:
        return self.record.group

    @property
    def original_size(self) -> int:
        return self.record.shrink.original_size

    @property
    def minimal_size(self) -> int:
        return self.record.shrink.minimal_size

    @property
    def shrunk(self) -> bool:
        return self.record.shrink.reproduced

    @property
    def shrink_calls(self) -> int:
        return self.record.shrink.calls

    @property
    def note(self) -> str:
        return self.record.shrink.note

    @property
    def verified(self) -> bool | None:
        return self.record.verified

    @property
    def reason(self) -> str:
        row = self.record.shrink.row
        return str(row.get("reason") or "") if row is not None else ""

    @property
    def failed_checks(self) -> str:
        return self.signature.checks

    @property
    def offending(self) -> Mapping[str, list[int]]:
        return _offending(self.record.shrink.row)


def python_command() -> str:
    """The full path of the interpreter running now: reproduce commands work outside an activated venv."""
    return sys.executable


def reproduce_command(folder: Path) -> str:
    """``<this python> -m hullstress reproduce <folder>``: exits 1 while the failure persists.

    Examples
    --------
    >>> reproduce_command(Path("/r/failures/x")).split(" -m ", 1)[1]
    'hullstress reproduce /r/failures/x'
    """
    return shlex.join([python_command(), "-m", "hullstress", "reproduce", str(Path(folder).absolute())])


def report_run_command(run_dir: Path) -> str:
    """``<this python> -m hullstress report <run folder>``: triages a run folder's rows and writes its report.

    Examples
    --------
    >>> report_run_command(Path("/r/20260101-000000-quick-seed0")).split(" -m ", 1)[1]
    'hullstress report /r/20260101-000000-quick-seed0'
    """
    return shlex.join([python_command(), "-m", "hullstress", "report", str(Path(run_dir).absolute())])


def _plugin_arg(spec: str) -> str:
    path = Path(spec)
    return str(path.resolve()) if (spec.endswith(".py") or path.is_file()) else spec


def _jsonable(value: Any) -> Any:
    if value is None:
        return None
    if isinstance(value, np.integer):
        return int(value)
    if isinstance(value, (float, np.floating)):
        f = float(value)
        return f if math.isfinite(f) else repr(f)
    if isinstance(value, np.bool_):
        return bool(value)
    try:
        import pandas as pd

        if value is pd.NA:
            return None
    except ImportError:  # pragma: no cover
        pass
    return value


def _offending(row: ResultRow | None) -> dict[str, list[int]]:
    if row is None:
        return {}
    try:
        return dict(json.loads(row.get("offending") or "{}"))
    except (TypeError, ValueError):
        return {}


def verdict_values(row: ResultRow | None) -> dict[str, Any]:
    """A row's verdict as JSON-ready values: status, stage, reason, frame, checks, offending; no timings."""
    if row is None:
        return {}
    from ..verdict import VERDICT_COLUMNS

    keys = ("status", "stage", "reason", "error_frame", "eps_value", "degenerate", "invalid_input")
    out = {k: _jsonable(row.get(k)) for k in keys if k not in TIMING_KEYS}
    for col in VERDICT_COLUMNS:
        out[col] = _jsonable(row.get(col))
    out["offending"] = _offending(row)
    return out


def points_json(points: np.ndarray) -> Any:
    """Exact points for JSON (``repr`` floats round-trip; NaN and infinities as Python writes them)."""
    return np.asarray(points, dtype=np.float64).tolist()


def _contract_label(config: Any) -> str:
    """The declared contract the cause was judged against (empty when its plug-in is not loaded here)."""
    try:
        return config.spec.contract.label
    except Exception:
        return ""


def _write_points(folder: Path, points: np.ndarray, storage: str) -> str:
    """Write points.npy and, when triage found it exact, points.csv; return the readable file's name."""
    from ..io import write_points

    atomic_write_with(folder / "points.npy",
                      lambda fh: np.save(fh, np.asarray(points, dtype=np.float64), allow_pickle=False), binary=True)
    if storage == "csv":
        write_points(folder / "points.csv", points, "csv")
        return "points.csv"
    return "points.npy"


def _shrink_json(record: TriageRecord) -> dict[str, Any]:
    res = record.shrink
    return {"reproduced": res.reproduced, "evaluations": res.calls, "exhausted": res.exhausted,
            "adopted": res.adopted, "steps": list(res.steps), "note": res.note}


def _member_json(record: TriageRecord, representative: TriageRecord) -> dict[str, Any]:
    group = record.group
    same = np.array_equal(np.asarray(record.case.points), np.asarray(representative.case.points), equal_nan=True)
    return {
        "slug": record.signature.slug,
        "config": record.config.label,
        "signature": record.signature.as_dict(),
        "failures": record.failures,
        "calls": group.calls if group is not None else None,
        "families": dict(record.families),
        "original_size": record.shrink.original_size,
        "minimal_size": record.shrink.minimal_size,
        "shrink": _shrink_json(record),
        "verified": record.verified,
        # A member's minimal case equals the representative's up to exact transforms; its own is kept.
        "points": None if same else points_json(record.case.points),
    }


def write_cause_folder(
    root: Path,
    cause: Cause,
    *,
    plugins: Sequence[str] = (),
    timeout: float | None = None,
    picture: bool = True,
    registration: Sequence[str] = (),
) -> FailureRecord:
    """Write ``root/<cause slug>/`` for one cause.

    Parameters
    ----------
    root : Path
        The ``failures`` folder (created if missing).
    cause : Cause
        From :func:`hullstress.triage.stage.triage_failures`.
    plugins : sequence of str
        ``--plugin`` specs the cause's algorithms need (recorded for ``reproduce``).
    timeout : float, optional
        The per-call timeout to reproduce with (recorded for ``reproduce``).
    picture : bool
        Draw ``picture.png`` now (or later, with :func:`draw_picture`).
    registration : sequence of str
        The run's ``--exec`` / ``--clockwise`` arguments the cause's algorithms
        need, recorded for ``reproduce`` (which registers them again).

    Returns
    -------
    FailureRecord
    """
    rep = cause.representative
    sig, config, result = rep.signature, rep.config, rep.shrink
    folder = Path(root) / cause.slug
    folder.mkdir(parents=True, exist_ok=True)
    case = result.case
    points = np.asarray(case.points)
    points_file = _write_points(folder, points, rep.storage)
    command = reproduce_command(folder)
    original = result.original
    atomic_write_text(folder / "faces.json", json.dumps({"faces": rep.faces, "note": rep.faces_note}, indent=1) + "\n")
    atomic_write_text(folder / "verdict.json", json.dumps(
        {"signature": sig.as_dict(), "config": config.label, **verdict_values(result.row)},
        indent=2, default=repr) + "\n")
    meta = {
        "cause": cause.slug,
        "label": sig.label,
        "signature": sig.as_dict(),
        "config": config.label,
        "contract": _contract_label(config),
        "dim": case.dim,
        "points_file": points_file,
        "storage": rep.storage,
        "plugins": [_plugin_arg(p) for p in plugins],
        "registration": list(registration),
        "timeout": timeout,
        "failures": cause.failures,
        "configs": list(cause.configs),
        "families": dict(cause.families),
        "original_case": {
            "case_id": original.case_id, "family": original.family, "params": json.loads(original.params_json),
            "seed": original.seed, "size": original.size, "n_points": original.n_points, "source": original.source,
        },
        "minimal_case_id": case.case_id,
        "original_size": result.original_size,
        "minimal_size": result.minimal_size,
        "shrink": _shrink_json(rep),
        "verified": rep.verified,
        "members": [_member_json(r, rep) for r in cause.records],
        "reproduce": command,
    }
    atomic_write_text(folder / CASE_FILE, json.dumps(meta, indent=2, default=repr) + "\n")
    atomic_write_text(folder / "reproduce.txt", command + "\n")
    from .handover import write_handover

    write_handover(folder, rep)
    out = FailureRecord(cause=cause, folder=folder, command=command, points=points)
    return draw_picture(out) if picture else out


def write_failure_folder(root: Path, record: TriageRecord, *, plugins: Sequence[str] = (),
                         timeout: float | None = None, picture: bool = True,
                         registration: Sequence[str] = ()) -> FailureRecord:
    """Write the folder of one triaged failure on its own (``shrink`` and ``fuzz`` commands)."""
    from ..triage.canonical import canonical_key

    cause = Cause(key=canonical_key(np.asarray(record.case.points)), records=(record,))
    return write_cause_folder(root, cause, plugins=plugins, timeout=timeout, picture=picture,
                              registration=registration)


def draw_picture(record: FailureRecord) -> FailureRecord:
    """Draw ``picture.png`` in a written folder; the record with the PNG bytes.

    Reads the folder's ``faces.json`` so that the picture shows exactly what was saved.
    """
    return with_picture(record, picture_png(*picture_request(record)))


def picture_request(record: FailureRecord) -> tuple[Path, np.ndarray, dict[str, list[int]], str]:
    """What :func:`picture_png` needs to draw ``record``'s picture: plain values another process can take."""
    return (record.folder, record.points, dict(record.offending),
            f"{record.signature.label}: {record.minimal_size} points")


def picture_png(folder: Path, points: np.ndarray, offending: Mapping[str, Sequence[int]], title: str) -> bytes:
    """The PNG bytes of a written folder's picture (its points, its saved faces, the offending indices)."""
    from .pictures import failure_picture

    saved = json.loads((folder / "faces.json").read_text())
    dim = json.loads((folder / CASE_FILE).read_text())["dim"]
    return failure_picture(points, saved.get("faces"), dim=dim, offending=offending, title=title)


def with_picture(record: FailureRecord, png: bytes) -> FailureRecord:
    """Write ``png`` as the folder's ``picture.png``; the record with those bytes."""
    atomic_write_bytes(record.folder / "picture.png", png)
    return dataclasses.replace(record, picture=png)
