"""One folder per failure group: ``failures/<signature>/``.

Contents:

``points.npy``, ``points.csv``
    The minimal case, exact (``.csv`` prints ``repr`` floats, which read back
    bit for bit through :func:`hullstress.io.read_points`).
``case.json``
    Provenance: signature, config, the original case (family, params, seed,
    id, size), the shrink (sizes, calls, seconds, steps), the group's counts,
    the reproduce command and whether it was verified.
``faces.json``
    The algorithm's output on the minimal case, in input indices.
``verdict.json``
    Status, reason, the checker's verdict columns and offending indices.
``picture.png``
    See :mod:`hullstress.report.pictures`.
``reproduce.txt``
    One shell command, runnable from any directory, that exits 1 when the
    failure reproduces.
"""

from __future__ import annotations

import dataclasses
import functools
import json
import math
import os
import shlex
import shutil
import subprocess
import sys
import tempfile
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from ..config import NO_EPS, AlgorithmConfig
from ..results import ResultRow
from ..files import atomic_write_bytes, atomic_write_text, atomic_write_with
from ..triage.grouping import FailureGroup
from ..triage.signature import Signature
from ..triage.records import TriageRecord

__all__ = ["FailureRecord", "write_failure_folder", "draw_picture", "reproduce_command", "python_command"]


@dataclass(frozen=True)
class FailureRecord:
    """What was written for one failure group (the report and JUnit read these).

    Attributes
    ----------
    signature : Signature
    folder : Path
    command : str
        The one-line reproduce command (``""`` when none could be built).
    points : ndarray of shape (n, dim)
        The minimal case's points.
    original_size, minimal_size : int
    shrunk : bool
        Shrinking ran and reproduced the failure.
    shrink_calls : int
    shrink_seconds : float
    note : str
        Why shrinking stopped early or did not run, or ``""``.
    verified : bool or None
        Re-reading the points file and re-running reproduced the failure
        (None when not checked).
    reason : str
        The minimal case's failure reason.
    failed_checks : str
    offending : mapping of str to list of int
    picture : bytes or None
        PNG bytes (also written to ``picture.png``).
    group : FailureGroup or None
    """

    signature: Signature
    folder: Path
    command: str
    points: np.ndarray
    original_size: int
    minimal_size: int
    shrunk: bool
    shrink_calls: int
    shrink_seconds: float
    note: str
    verified: bool | None
    reason: str
    failed_checks: str
    offending: Mapping[str, list[int]]
    picture: bytes | None
    group: FailureGroup | None = None


@functools.lru_cache(maxsize=1)
def python_command() -> str:
    """``python`` when that name on PATH is this interpreter, else this interpreter's absolute path."""
    found = shutil.which("python")
    if found is not None:
        try:
            out = subprocess.run([found, "-c", "import sys; print(sys.executable)"], capture_output=True,
                                 text=True, timeout=20, check=False).stdout.strip()
        except (OSError, subprocess.SubprocessError):
            out = ""
        if out and os.path.realpath(out) == os.path.realpath(sys.executable):
            return "python"
    return sys.executable


def _plugin_arg(spec: str) -> str:
    path = Path(spec)
    return str(path.resolve()) if (spec.endswith(".py") or path.is_file()) else spec


def reproduce_command(
    points_file: Path,
    config: AlgorithmConfig,
    *,
    plugins: Sequence[str] = (),
    timeout: float | None = None,
    isolate: bool = False,
    raw_npy: bool = False,
    dim: int | None = None,
    registration: Sequence[str] = (),
) -> str:
    """The one-line command that re-runs ``config`` on ``points_file`` and exits 1 if it fails.

    Parameters
    ----------
    points_file : Path
        Made absolute, so the command runs from any directory.
    config : AlgorithmConfig
    plugins : sequence of str
        ``--plugin`` specs (files made absolute).
    timeout : float, optional
        Per-call timeout (for timeout signatures).
    isolate : bool
        Run in a worker process (``--workers 1``): needed to observe a crash or
        timeout; otherwise in-process (``--workers 0``, faster).
    raw_npy : bool
        The points are not a valid ``--points-file`` (non-finite values, a
        shape the reader refuses): replay through ``shrink --no-shrink``,
        which loads the ``.npy`` as it is.
    dim : int, optional
        The case's dimension (needed with ``raw_npy``).
    registration : sequence of str
        Command-line arguments that register what the algorithm needs
        (``--plugin F``, ``--exec NAME=COMMAND``, ``--clockwise NAME``), appended as they are
        (plug-in files made absolute).

    Examples
    --------
    >>> cmd = reproduce_command(Path("/r/points.csv"), AlgorithmConfig("gift-wrap", "on", "fixed"))
    >>> cmd.split(" -m ", 1)[1].split(" --out")[0]
    'hullstress run --points-file /r/points.csv --algorithm gift-wrap --sphere on --eps fixed --workers 0'
    """
    path = str(Path(points_file).resolve())
    out = os.path.join(tempfile.gettempdir(), "hullstress-reproduce")
    if raw_npy:
        args = ["-m", "hullstress", "shrink", path, "--algorithm", config.algorithm, "--sphere", config.sphere,
                "--no-shrink", "--raw", "--dim", str(dim)]
        if config.eps != NO_EPS:
            args += ["--eps", config.eps]
        if timeout is not None:
            args += ["--timeout", _number(timeout)]
    else:
        args = ["-m", "hullstress", "run", "--points-file", path, "--algorithm", config.algorithm,
                "--sphere", config.sphere]
        if config.eps != NO_EPS:
            args += ["--eps", config.eps]
        args += ["--workers", "1" if isolate else "0"]
        if timeout is not None:
            args += ["--timeout", _number(timeout)]
        args += ["--out", out, "--no-shrink", "--quiet"]
    for spec in plugins:
        args += ["--plugin", _plugin_arg(spec)]
    for option, value in zip(registration[::2], registration[1::2]):
        args += [option, _plugin_arg(value) if option == "--plugin" else value]
    return shlex.join([python_command()] + args) if python_command() != "python" else "python " + shlex.join(args)


def _number(x: float) -> str:
    return str(int(x)) if float(x).is_integer() else repr(float(x))


def _jsonable(value: Any) -> Any:
    if value is None:
        return None
    if isinstance(value, (np.integer,)):
        return int(value)
    if isinstance(value, (float, np.floating)):
        f = float(value)
        return f if math.isfinite(f) else repr(f)
    if isinstance(value, (np.bool_,)):
        return bool(value)
    try:
        import pandas as pd

        if value is pd.NA:
            return None
    except ImportError:  # pragma: no cover
        pass
    return value


def _verdict(row: ResultRow | None) -> dict[str, Any]:
    if row is None:
        return {}
    from ..verdict import VERDICT_COLUMNS

    out = {k: _jsonable(row.get(k)) for k in ("status", "reason", "eps_value", "degenerate", "invalid_input")}
    for col in VERDICT_COLUMNS:
        out[col] = _jsonable(row.get(col))
    try:
        out["offending"] = json.loads(row.get("offending") or "{}")
    except (TypeError, ValueError):
        out["offending"] = {}
    return out


def _write_points(folder: Path, points: np.ndarray, storage: str) -> tuple[Path | None, Path]:
    """Write points.npy and, when triage found it exact, points.csv; return (readable file or None, npy)."""
    from ..io import write_points

    npy = folder / "points.npy"
    atomic_write_with(npy, lambda fh: np.save(fh, np.asarray(points, dtype=np.float64), allow_pickle=False),
                      binary=True)
    if storage == "csv":
        csv = folder / "points.csv"
        write_points(csv, points, "csv")
        return csv, npy
    return (npy if storage == "npy" else None), npy


def write_failure_folder(
    root: Path,
    record: TriageRecord,
    *,
    plugins: Sequence[str] = (),
    timeout: float | None = None,
    picture: bool = True,
    registration: Sequence[str] = (),
) -> FailureRecord:
    """Write ``root/<signature slug>/`` for one triaged failure group.

    Parameters
    ----------
    root : Path
        The ``failures`` folder (created if missing).
    record : TriageRecord
        From :func:`hullstress.triage.stage.triage_failures` (or
        :func:`~hullstress.triage.stage.triage_one`): the minimal case, the
        output faces, the storage form and whether it reproduced from it.
    plugins : sequence of str
        Plug-in specs the algorithm needs (added to the reproduce command).
    timeout : float, optional
        The sweep's per-call timeout (for timeout signatures).
    registration : sequence of str
        Registration arguments for the reproduce command (see :func:`reproduce_command`).
    picture : bool
        Draw ``picture.png`` (or later, with :func:`draw_picture`).

    Returns
    -------
    FailureRecord
    """
    sig, config, result = record.signature, record.config, record.shrink
    group = record.group
    folder = Path(root) / sig.slug
    folder.mkdir(parents=True, exist_ok=True)
    case = result.case
    points = np.asarray(case.points)
    readable, npy = _write_points(folder, points, record.storage)
    dangerous = sig.check in ("timeout", "crash")
    command = reproduce_command(
        readable if readable is not None else npy, config, plugins=plugins,
        timeout=timeout if sig.check == "timeout" else None, isolate=dangerous,
        raw_npy=readable is None, dim=case.dim, registration=registration,
    )
    verified = record.verified
    verdict = _verdict(result.row)
    offending = verdict.get("offending") or {}
    atomic_write_text(folder / "faces.json", json.dumps({"faces": record.faces, "note": record.faces_note},
                                                         indent=1) + "\n")
    atomic_write_text(folder / "verdict.json", json.dumps(
        {"signature": sig.as_dict(), "config": config.label, **verdict}, indent=2, default=repr) + "\n")
    original = result.original
    meta = {
        "signature": sig.as_dict(),
        "slug": sig.slug,
        "config": config.label,
        "original_case": {
            "case_id": original.case_id, "family": original.family, "params": json.loads(original.params_json),
            "seed": original.seed, "size": original.size, "n_points": original.n_points, "source": original.source,
        },
        "minimal_case_id": case.case_id,
        "dim": case.dim,
        "original_size": result.original_size,
        "minimal_size": result.minimal_size,
        "shrink": {"reproduced": result.reproduced, "calls": result.calls, "seconds": round(result.seconds, 3),
                   "exhausted": result.exhausted, "steps": list(result.steps), "note": result.note},
        "group": None if group is None else {
            "failures": group.count, "calls": group.calls, "cases": group.cases,
            "smallest_case_id": group.smallest_case_id, "representative_case_id": group.representative_case_id,
        },
        "points_file": str((readable or npy).resolve()),
        "reproduce": command,
        "verified": verified,
    }
    atomic_write_text(folder / "case.json", json.dumps(meta, indent=2, default=repr) + "\n")
    atomic_write_text(folder / "reproduce.txt", command + "\n")
    out = FailureRecord(
        signature=sig, folder=folder, command=command, points=points, original_size=result.original_size,
        minimal_size=result.minimal_size, shrunk=result.reproduced, shrink_calls=result.calls,
        shrink_seconds=result.seconds, note=result.note, verified=verified,
        reason=str(verdict.get("reason") or ""), failed_checks=str(verdict.get("failed_checks") or ""),
        offending=offending, picture=None, group=group,
    )
    return draw_picture(out) if picture else out


def draw_picture(record: FailureRecord) -> FailureRecord:
    """Draw ``picture.png`` in a written failure folder; the record with the PNG bytes.

    Reads the folder's ``faces.json`` so that the picture shows exactly what was saved.
    """
    from .pictures import failure_picture

    saved = json.loads((record.folder / "faces.json").read_text())
    dim = json.loads((record.folder / "case.json").read_text())["dim"]
    png = failure_picture(record.points, saved.get("faces"), dim=dim, offending=record.offending,
                          title=f"{record.signature.label}: {record.minimal_size} points")
    atomic_write_bytes(record.folder / "picture.png", png)
    return dataclasses.replace(record, picture=png)
