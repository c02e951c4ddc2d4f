"""The run folder: ``results.csv`` (+ ``results.parquet``), ``run.json``, the sweep's tables and ``summary.md``.

Rows are streamed to ``results.partial.csv`` as they arrive, so a run that is
killed still leaves a readable table; the final, sorted ``results.csv``
replaces it when the run ends (also on Ctrl-C / SIGTERM, marked incomplete).
"""

from __future__ import annotations

import csv
import functools
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

from ..errors import EnvironmentFailure, UsageError, is_environment_error
from ..files import atomic_write_text, atomic_write_with, writable_folder
from ..results import ROW_COLUMNS, ResultRow
from .failures import python_command
from .picture_helper import PictureDrawer

__all__ = ["new_run_dir", "RowStream", "OutputLog", "write_report", "write_run_json", "package_versions",
           "prepare_report"]


def new_run_dir(out: str | os.PathLike[str], run_name: str) -> Path:
    """Create ``out/<run_name>`` (suffixing ``-2``, ``-3`` ... if taken) and check it is writable.

    Raises
    ------
    EnvironmentFailure
        When the folder is read-only, not writable or on a full disk, naming ``out``.
    UsageError
        When ``out`` cannot be a folder (a path through a file), naming it.
    """
    base = writable_folder(out, "--out")
    run_dir = base / run_name
    k = 1
    try:
        while True:
            try:
                run_dir.mkdir()
                break
            except FileExistsError:
                k += 1
                run_dir = base / f"{run_name}-{k}"
    except OSError as exc:
        refused = EnvironmentFailure if is_environment_error(exc) else UsageError
        raise refused(f"--out {str(out)!r}: cannot create a run folder there: {exc.strerror or exc}") from None
    return run_dir


class RowStream:
    """Appends rows to ``results.partial.csv`` as they arrive, flushed row by row."""

    def __init__(self, run_dir: Path) -> None:
        self.path = run_dir / "results.partial.csv"
        try:
            self._fh = open(self.path, "w", newline="", encoding="utf-8")
            # A plain writer fed one list per row: DictWriter builds a dict and then a list from
            # it per row, most of the parent's own CPU time per call in a sweep of small cases.
            self._writer = csv.writer(self._fh)
            self._writer.writerow(ROW_COLUMNS)
            self._fh.flush()
        except OSError as exc:
            raise self._refused(exc) from exc
        self.count = 0

    def __call__(self, row: ResultRow) -> None:
        """Append ``row``; a full disk raises :class:`EnvironmentFailure` naming the file."""
        try:
            # csv writes None (and so a missing column) as an empty field.
            self._writer.writerow(map(row.values.get, ROW_COLUMNS))
            self._fh.flush()
        except OSError as exc:
            raise self._refused(exc) from exc
        self.count += 1

    def _refused(self, exc: OSError) -> Exception:
        return EnvironmentFailure.writing(self.path, exc) if is_environment_error(exc) else exc

    def close(self, *, remove: bool) -> None:
        if not self._fh.closed:
            try:
                self._fh.close()
            except OSError:
                pass  # the flush of a full disk failed already, and was reported then
        if remove:
            self.path.unlink(missing_ok=True)


@functools.lru_cache(maxsize=1)
def _versions() -> tuple[tuple[str, str], ...]:
    out = {"python": platform.python_version()}
    for name in ("hullstress", "numpy", "scipy", "pandas", "hypothesis", "pyarrow", "matplotlib", "dask", "distributed", "shapely"):
        try:
            out[name] = version(name)
        except PackageNotFoundError:
            continue
    return tuple(out.items())


class OutputLog:
    """``calls.log``: what each call printed (its ``call_output``), appended as rows arrive.

    The file is created with the first call that printed anything; a run whose
    code under test printed nothing has none.
    """

    def __init__(self, run_dir: Path) -> None:
        self.path = run_dir / "calls.log"
        self._fh: Any = None

    def __call__(self, row: ResultRow) -> None:
        text = row.get("call_output") or ""
        if not text:
            return
        try:
            if self._fh is None:
                self._fh = open(self.path, "a", encoding="utf-8")
            self._fh.write(f"== {row['config']} on case {row['case_id']} ({row['generator']}): {row['status']}\n"
                           f"{text}\n")
            self._fh.flush()
        except OSError as exc:
            raise (EnvironmentFailure.writing(self.path, exc) if is_environment_error(exc) else exc) from exc

    def close(self) -> None:
        if self._fh is not None:
            try:
                self._fh.close()
            except OSError:
                pass


def executables_in_use() -> dict[str, dict[str, str]]:
    """What each registered ``--exec`` program is: command, mode, and the driver and library it named."""
    from .._registry import ALGORITHMS

    return {spec.name: spec.func.identity() for spec in ALGORITHMS.specs()
            if callable(getattr(spec.func, "identity", None))}


def package_versions() -> dict[str, str]:
    """Versions of hullstress, Python and the libraries that shape results (read once per process)."""
    return dict(_versions())


def prepare_report(*, pictures: bool = True, workers: int = 1) -> PictureDrawer:
    """Load now what writing the report needs (Parquet, package versions, the plotting library).

    The pipeline calls this before the sweep, so that the report of an
    interrupted run is written within its promised two seconds instead of
    paying for imports then.  Returns the run's picture drawer, not begun:
    with one worker matplotlib (the slowest import) loads now, in a
    background thread, while the sweep runs; with more, the drawer's helper
    processes load it once :meth:`~.picture_helper.PictureDrawer.begin` is
    called (the pipeline calls it when the sweep's tail first leaves a core
    idle).  The caller closes the drawer.
    """
    _versions()
    _parquet_available()
    python_command()
    return PictureDrawer(pictures=pictures, workers=workers)


@functools.lru_cache(maxsize=1)
def _parquet_available() -> bool:
    try:
        import pyarrow.parquet  # noqa: F401  (pandas' writer imports it on first use)
    except ImportError:
        return False
    return True


def write_report(run_dir: Path, df: pd.DataFrame, meta: Mapping[str, Any], *, tables: bool = True) -> dict[str, Path]:
    """Write the run's tables and metadata into ``run_dir``.

    Parameters
    ----------
    tables : bool
        Also (re)write ``results.csv`` and ``results.parquet``; False when
        they are on disk already and only the summary and metadata changed.

    Returns
    -------
    dict of str to Path
        The files written, by kind (``csv``, ``parquet``, ``summary``, ``json``).
    """
    written: dict[str, Path] = {}
    csv_path = run_dir / "results.csv"
    if tables:
        atomic_write_with(csv_path, lambda fh: df.to_csv(fh, index=False))
        written["csv"] = csv_path
    if tables and _parquet_available():
        pq_path = run_dir / "results.parquet"
        atomic_write_with(pq_path, lambda fh: df.to_parquet(fh, index=False), binary=True)
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
        "executables": executables_in_use(),
    }
    if extra:
        meta.update(extra)
    return meta
