"""The run folder: ``results.csv`` (+ ``results.parquet``), ``summary.md``, ``run.json``.

Rows are streamed to ``results.partial.csv`` as they arrive, so a run that is
killed still leaves a readable table; the final, sorted ``results.csv``
replaces it when the run ends (also on Ctrl-C / SIGTERM, marked incomplete).
"""

from __future__ import annotations

import csv
import io
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
from .claim import markdown_table as _markdown
from .tables import failure_counts, status_counts

__all__ = ["new_run_dir", "RowStream", "write_report", "package_versions"]


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


def summary_markdown(df: pd.DataFrame, meta: Mapping[str, Any]) -> str:
    """``summary.md``: status totals, per-config totals, failures by algorithm x variant x family."""
    buf = io.StringIO()
    state = "complete" if meta.get("complete", True) else "INCOMPLETE (interrupted or out of time budget)"
    buf.write(f"# hullstress run {meta.get('run_id', '')}\n\n")
    buf.write(
        f"Profile `{meta.get('profile')}`, seed {meta.get('seed')}, {len(df)} calls over "
        f"{df['case_id'].nunique() if len(df) else 0} cases, {meta.get('timings', {}).get('wall_seconds', 0):.1f} s; {state}.\n\n"
    )
    buf.write("## Calls by status\n\n")
    totals = df["status"].value_counts().reindex(["pass", "fail", "rejected", "error", "timeout", "crash"], fill_value=0)
    buf.write(_markdown(totals.rename_axis("status").reset_index(name="calls")))
    buf.write("\n## By algorithm and variant\n\n")
    buf.write(_markdown(status_counts(df, ["algorithm", "sphere", "eps"])) if len(df) else "_(no calls)_\n")
    buf.write("\n## Failures by algorithm x variant x family\n\n")
    buf.write(_markdown(failure_counts(df)) if len(df) else "_(no calls)_\n")
    skipped = meta.get("skipped") or []
    if skipped:
        buf.write(f"\n## Cases not generated ({len(skipped)})\n\n")
        for line in skipped:
            buf.write(f"- {line}\n")
    return buf.getvalue()


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
    summary = run_dir / "summary.md"
    atomic_write_text(summary, summary_markdown(df, meta))
    written["summary"] = summary
    meta_path = run_dir / "run.json"
    atomic_write_text(meta_path, json.dumps(meta, indent=2, sort_keys=True, default=str) + "\n")
    written["json"] = meta_path
    return written


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
