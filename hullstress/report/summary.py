"""``summary.md`` on one screen, the long tables in CSV files beside it.

The summary leads with what a user acts on: the run in two lines, then the
top causes (at most :data:`TOP_CAUSES`) with their folders, then links to
every full table, the findings in a few sentences and how triage ran.  The
tables that grow with the sweep (one row per config, per config x family,
per failure group, per cause) are CSV files next to it (:data:`TABLES`), and
``report.html`` shows everything with pictures.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import pandas as pd

from ..files import atomic_write_text
from ..results import STATUSES
from ..triage.grouping import FailureGroup, groups_frame
from ..triage.records import Cause
from .tables import failure_counts, status_counts
from ..records import FAILED_STATUSES

__all__ = ["TOP_CAUSES", "TABLES", "write_sweep_tables", "causes_frame", "groups_table", "summary_markdown",
           "write_summary", "cause_table_rows", "untriaged_line", "run_folder_of"]

#: Causes listed in summary.md and at the end of the terminal output.
TOP_CAUSES = 12

#: The full tables, by what they hold: file names in the run folder.
TABLES = {
    "causes": "causes.csv",
    "groups": "groups.csv",
    "failures by config x family": "failures_by_config_family.csv",
    "calls by config": "status_by_config.csv",
    "the seeds' claims": "findings.md",
}


def write_sweep_tables(run_dir: Path, table: pd.DataFrame) -> None:
    """The sweep's long tables: calls by config and status, failures by config x family."""
    by_config = status_counts(table, ["algorithm", "sphere", "eps"]) if len(table) else pd.DataFrame()
    by_family = failure_counts(table) if len(table) else pd.DataFrame()
    atomic_write_text(run_dir / TABLES["calls by config"], by_config.to_csv(index=False))
    atomic_write_text(run_dir / TABLES["failures by config x family"], by_family.to_csv(index=False))


def causes_frame(causes: Sequence[Cause], folders: Mapping[str, str] | None = None) -> pd.DataFrame:
    """One row per cause, worst first: what failed, where, how small, and its folder."""
    rows = []
    for rank, cause in enumerate(causes, start=1):
        sig, rep = cause.signature, cause.representative
        rows.append({
            "rank": rank, "cause": cause.headline, "slug": cause.slug, "status": sig.status, "stage": sig.stage,
            "checks": sig.checks, "severity": sig.severity, "error": sig.error, "frame": sig.frame,
            "failures": cause.failures, "groups": len(cause.records), "configs": " ".join(cause.configs),
            "n_families": len(cause.families), "families": " ".join(f"{f}:{n}" for f, n in cause.families),
            "original_size": rep.shrink.original_size, "minimal_size": rep.shrink.minimal_size,
            "minimised": rep.shrink.reproduced, "verified": rep.verified,
            "folder": (folders or {}).get(cause.slug, ""),
        })
    return pd.DataFrame(rows)


def groups_table(groups: Sequence[FailureGroup], causes: Sequence[Cause]) -> pd.DataFrame:
    """Every failure group with its cause, minimal size and how its shrink went."""
    frame = groups_frame(list(groups))
    by_slug = {r.signature.slug: (c, r) for c in causes for r in c.records}
    extra = []
    for slug in frame["slug"]:
        cause, rec = by_slug.get(slug, (None, None))
        extra.append({
            "cause": cause.slug if cause is not None else "",
            "minimal_size": rec.shrink.minimal_size if rec is not None else pd.NA,
            "minimised": rec.shrink.reproduced if rec is not None else False,
            "adopted": rec.shrink.adopted if rec is not None else False,
            "evaluations": rec.shrink.calls if rec is not None else 0,
            "verified": rec.verified if rec is not None else pd.NA,
            "note": rec.shrink.note if rec is not None else "not triaged",
        })
    return pd.concat([frame, pd.DataFrame(extra, index=frame.index)], axis=1) if len(frame) else frame


def _md_cell(value: Any) -> str:
    return str(value).replace("|", "\\|")


def cause_table_rows(causes: Sequence[Cause], folders: Mapping[str, str], top: int) -> list[str]:
    """The Markdown table of the top causes (a header and one line per cause)."""
    lines = ["| # | cause | failures | families | points | folder |", "|---:|---|---:|---|---:|---|"]
    for rank, cause in enumerate(causes[:top], start=1):
        fams = [f for f, _ in cause.families]
        shown = ", ".join(fams[:3]) + (f" +{len(fams) - 3}" if len(fams) > 3 else "")
        size = f"{cause.minimal_size}" if cause.minimised else f"{cause.minimal_size} (not shrunk)"
        folder = folders.get(cause.slug, "")
        link = f"[{cause.slug}]({folder}/)" if folder else ""
        lines.append(f"| {rank} | {_md_cell(cause.headline)} | {cause.failures} | {_md_cell(shown)} | {size} | {link} |")
    return lines


def summary_markdown(
    table: pd.DataFrame,
    meta: Mapping[str, Any],
    *,
    causes: Sequence[Cause] | None = None,
    groups: Sequence[FailureGroup] = (),
    folders: Mapping[str, str] | None = None,
    reading: Sequence[str] = (),
    notes: Sequence[str] = (),
    top: int = TOP_CAUSES,
) -> str:
    """The whole of ``summary.md``.

    Parameters
    ----------
    table : DataFrame
        The results table.
    meta : mapping
        ``run.json``'s content.
    causes : sequence of Cause, optional
        Triage's causes, worst first (None before triage has run).
    groups : sequence of FailureGroup
    folders : mapping of str to str
        Cause slug -> its folder, relative to the run folder.
    reading : sequence of str
        The findings in sentences.
    notes : sequence of str
        How triage and the report ran.
    top : int
        Causes listed.
    """
    state = _state_words(meta)
    n_cases = int(table["case_id"].nunique()) if len(table) else 0
    wall = (meta.get("timings") or {}).get("wall_seconds", 0) or 0
    counts = table["status"].value_counts() if len(table) else pd.Series(dtype=int)
    failed = int(sum(counts.get(s, 0) for s in FAILED_STATUSES))
    lines = [f"# hullstress run {meta.get('run_id', '')}", "",
             f"Profile `{meta.get('profile')}`, seed {meta.get('seed')}: {len(table)} calls over {n_cases} cases, "
             f"sweep {float(wall):.1f} s; {state}.",
             "Calls: " + ", ".join(f"{int(counts.get(s, 0))} {s}" for s in STATUSES) + ".", ""]
    programs = meta.get("executables") or {}
    if programs:
        lines[-1:-1] = ["Programs: " + "; ".join(
            f"`{name}` = `{p.get('command')}` ({p.get('mode')}"
            + "".join(f", {p[k]}" for k in ("driver", "library") if p.get(k)) + ")"
            for name, p in sorted(programs.items())) + "."]
    folders = folders or {}
    if causes is None:
        lines += ["Triage has not run yet: failure groups and causes follow when it has.", ""]
    elif not causes:
        lines += ["## No failures" if not failed else "## Causes", "",
                  "Nothing failed." if not failed else untriaged_line(failed, meta), ""]
    else:
        shown = min(top, len(causes))
        lines += [f"## Top causes ({shown} of {len(causes)})", "",
                  f"{failed} failed calls in {len(groups)} failure groups (one per signature: config, stage, "
                  f"status, failed checks and severity, or exception and frame), merged into {len(causes)} causes "
                  "(groups whose minimal cases coincide). Each folder holds the minimal case, its verdict, a "
                  "picture and `reproduce.txt`.", ""]
        lines += cause_table_rows(causes, folders, top)
        if len(causes) > shown:
            lines += ["", f"{len(causes) - shown} more causes in [causes.csv](causes.csv)."]
        lines.append("")
    lines += ["## Full tables", ""]
    lines += [f"- {what}: [{name}]({name})" for what, name in TABLES.items()
              if causes is not None or what not in ("causes", "groups")]
    lines += ["- everything, with pictures: [report.html](report.html)" if causes is not None
              else "- results: [results.csv](results.csv)", ""]
    if reading:
        lines += ["## Findings: the seeds' claims against this run", ""] + [f"- {r}" for r in reading] + [""]
    if notes:
        lines += ["## How triage ran", ""] + [f"- {n}" for n in notes] + [""]
    skipped = meta.get("skipped") or []
    if skipped:
        lines += [f"{len(skipped)} cases could not be generated; run.json lists them.", ""]
    return "\n".join(lines).rstrip("\n") + "\n"


def _state_words(meta: Mapping[str, Any]) -> str:
    """How the run ended, for the summary's first line."""
    state = str(meta.get("state") or "")
    if meta.get("complete", True) and state in ("", "complete"):
        return "complete"
    words = {
        "crashed": "INCOMPLETE: the code under test crashed the run (no isolation)",
        "running": "INCOMPLETE: the process ended before the sweep did (killed)",
        "interrupted": f"INCOMPLETE: interrupted ({meta.get('signal') or 'Ctrl-C or SIGTERM'})",
        "environment-failure": "INCOMPLETE: a write was refused",
        "incomplete": "INCOMPLETE: out of time budget",
    }
    return words.get(state, "INCOMPLETE (interrupted or out of time budget)")


def run_folder_of(meta: Mapping[str, Any]) -> Path | None:
    """The run folder ``run.json`` describes (its ``--out`` and run id), or None when it does not say."""
    out = (meta.get("arguments") or {}).get("out")
    run_id = meta.get("run_id")
    if not out or not run_id:
        return None
    return Path(str(out)) / str(run_id)


def untriaged_line(failed: int, meta: Mapping[str, Any]) -> str:
    """Failed calls that triage did not group (an interrupt came first), with the command that triages them."""
    from .failures import report_run_command

    folder = run_folder_of(meta)
    how = f": run `{report_run_command(folder)}`" if folder is not None else " with `python -m hullstress report RUN_FOLDER`"
    return f"{failed} failed calls were not triaged (the run stopped before triage); triage them{how}."


def write_summary(run_dir: Path, text: str) -> Path:
    path = Path(run_dir) / "summary.md"
    atomic_write_text(path, text)
    return path
