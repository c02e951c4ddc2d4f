"""The run folder: ``results.csv`` (+ ``results.parquet``), ``run.json``, the sweep's tables and ``summary.md``.

Rows are streamed to ``results.partial.csv`` as they arrive, so a run that is
killed still leaves a readable table; the final, sorted ``results.csv``
replaces it when the run ends (also on Ctrl-C / SIGTERM, marked incomplete).
"""

from __future__ import annotations

import csv
import json
import os
import platform
import sys
import time
from collections.abc import Mapping
from importlib.metadata import PackageNotFoundError, version
from pathlib import Path
from typing import Any

import pandas as pd

from ..errors import UsageError
from ..files import atomic_write_text, atomic_write_with
from ..results import ROW_COLUMNS, ResultRow

__all__ = ["new_run_dir", "RowStream", "write_report", "write_run_json", "package_versions"]


def new_run_dir(out: str | os.PathLike[str], run_name: str) -> Path:
    """Create ``out/<run_name>`` (suffixing ``-2``, ``-3`` ... if taken) and check it is writable.

    Raises
    ------
    UsageError
        When the folder cannot be created or written, naming ``out``.
    """
    base = Path(out)
    try:
        base.mkdir(parents=True, exist_ok=True)
        run_dir = base / run_name
        k = 1
        while True:
            try:
                run_dir.mkdir()
                break
            except FileExistsError:
                k += 1
                run_dir = base / f"{run_name}-{k}"
        probe = run_dir / ".write-test"
        probe.write_text("ok")
        probe.unlink()
    except OSError as exc:
        raise UsageError(f"--out {str(out)!r}: cannot create a run folder there: {exc.strerror or exc}") from None
    return run_dir


class RowStream:
    """Appends rows to ``results.partial.csv`` as they arrive, flushed row by row."""

    def __init__(self, run_dir: Path) -> None:
        self.path = run_dir / "results.partial.csv"
        self._fh = open(self.path, "w", newline="", encoding="utf-8")
        self._writer = csv.DictWriter(self._fh, fieldnames=list(ROW_COLUMNS), extrasaction="ignore")
        self._writer.writeheader()
        self._fh.flush()
        self.count = 0

    def __call__(self, row: ResultRow) -> None:
        self._writer.writerow({k: ("" if v is None else v) for k, v in row.values.items()})
        self._fh.flush()
        self.count += 1

    def close(self, *, remove: bool) -> None:
        if not self._fh.closed:
            self._fh.close()
        if remove:
            self.path.unlink(missing_ok=True)


def package_versions() -> dict[str, str]:
    """Versions of hullstress, Python and the libraries that shape results."""
    out = {"python": platform.python_version()}
    for name in ("hullstress", "numpy", "scipy", "pandas", "hypothesis", "pyarrow", "matplotlib", "dask", "distributed", "shapely"):
        try:
            out[name] = version(name)
        except PackageNotFoundError:
            continue
    return out


def _markdown(df: pd.DataFrame) -> str:
    """A pipe table without the optional ``tabulate`` dependency."""
    if df.empty:
        return "_(none)_\n"
    cols = [str(c) for c in df.columns]
    lines = ["| " + " | ".join(cols) + " |", "|" + "|".join("---" for _ in cols) + "|"]
    for rec in df.itertuples(index=False):
        lines.append("| " + " | ".join("" if pd.isna(v) else str(v) for v in rec) + " |")
    return "\n".join(lines) + "\n"


def write_report(run_dir: Path, df: pd.DataFrame, meta: Mapping[str, Any]) -> dict[str, Path]:
    """Write the run's tables and metadata into ``run_dir``.

    Returns
    -------
    dict of str to Path
        The files written, by kind (``csv``, ``parquet``, ``summary``, ``json``).
    """
    written: dict[str, Path] = {}
    csv_path = run_dir / "results.csv"
    atomic_write_with(csv_path, lambda fh: df.to_csv(fh, index=False))
    written["csv"] = csv_path
    try:
        import pyarrow  # noqa: F401
    except ImportError:
        pass
    else:
        pq_path = run_dir / "results.parquet"
        df.to_parquet(pq_path, index=False)
        written["parquet"] = pq_path
    from .summary import summary_markdown, write_summary, write_sweep_tables

    write_sweep_tables(run_dir, df)
    written["summary"] = write_summary(run_dir, summary_markdown(df, meta))
    written["json"] = write_run_json(run_dir, meta)
    return written


def write_run_json(run_dir: Path, meta: Mapping[str, Any]) -> Path:
    """Write ``run.json`` alone (the pipeline adds the report's own time once it is written)."""
    meta_path = Path(run_dir) / "run.json"
    atomic_write_text(meta_path, json.dumps(meta, indent=2, sort_keys=True, default=str) + "\n")
    return meta_path


def run_metadata(
    *, run_id: str, arguments: Mapping[str, Any], df: pd.DataFrame, wall_seconds: float,
    complete: bool, skipped: list[str], extra: Mapping[str, Any] | None = None,
) -> dict[str, Any]:
    """``run.json``'s content: arguments, seed, versions, timings, counts, completeness."""
    algo = float(df["seconds"].sum()) if len(df) else 0.0
    check = float(df["check_seconds"].sum()) if len(df) else 0.0
    meta: dict[str, Any] = {
        "run_id": run_id,
        "profile": arguments.get("profile"),
        "seed": arguments.get("seed"),
        "arguments": dict(arguments),
        "versions": package_versions(),
        "platform": {"system": platform.platform(), "cpus": os.cpu_count(), "executable": sys.executable},
        "finished": time.strftime("%Y-%m-%dT%H:%M:%S%z"),
        "complete": complete,
        "calls": int(len(df)),
        "cases": int(df["case_id"].nunique()) if len(df) else 0,
        "status_counts": {k: int(v) for k, v in df["status"].value_counts().items()} if len(df) else {},
        "timings": {
            "wall_seconds": round(wall_seconds, 3),
            "algorithm_seconds": round(algo, 3),
            "check_seconds": round(check, 3),
        },
        "skipped": skipped,
    }
    if extra:
        meta.update(extra)
    return meta
