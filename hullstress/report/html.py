"""``report.html``: the run's report as one self-contained file.

No external assets: the style sheet is inline and every picture is a
``data:image/png;base64`` URI, so the file can be mailed, attached to a CI
run or opened from an archive.  Sections: the run, calls by status, failure
rates by algorithm x variant x family, the findings, then every cause with
its picture, configs, families, sizes and reproduce command, and every
failure group with a link to its cause.
"""

from __future__ import annotations

import base64
import html
import math
from collections.abc import Mapping, Sequence
from typing import Any

import pandas as pd

from ..io import points_text
from ..results import STATUSES
from ..triage.grouping import FailureGroup
from .failures import FailureRecord
from .findings import Findings
from ..records import Stage
from .summary import TOP_CAUSES
from .tables import failed_mask, failure_counts, status_counts

__all__ = ["render_html", "png_data_uri", "rate_matrix"]

_CSS = """
body{font-family:system-ui,-apple-system,Segoe UI,Helvetica,Arial,sans-serif;margin:2em auto;max-width:75em;
color:#222;line-height:1.4;padding:0 1em}
h1{font-size:1.6em}h2{border-bottom:1px solid #ccc;padding-bottom:.2em;margin-top:2em}
table{border-collapse:collapse;margin:.6em 0;font-size:.85em;display:block;max-width:100%;overflow-x:auto}
th,td{border:1px solid #ccc;padding:.25em .5em;text-align:right;vertical-align:top}
th{background:#f3f3f3}td.l,th.l{text-align:left}
pre,code{font-family:ui-monospace,Menlo,Consolas,monospace;font-size:.85em}
pre{background:#f6f8fa;border:1px solid #ddd;padding:.6em;overflow-x:auto;white-space:pre-wrap;word-break:break-all}
.group{border:1px solid #ddd;border-radius:6px;padding:.8em 1em;margin:1.2em 0}
.group img{max-width:100%;height:auto;border:1px solid #eee}
.meta{color:#555}.bad{color:#b00}.ok{color:#080}
dl{display:grid;grid-template-columns:max-content auto;gap:.2em 1em;margin:.6em 0}dt{font-weight:600}dd{margin:0}
"""


#: Key columns of the findings' tables (left-aligned).
_FINDINGS_KEYS = ("dim", "algorithm", "group", "variant", "placement", "n")


def png_data_uri(png: bytes) -> str:
    """``data:image/png;base64,...`` for PNG bytes."""
    return "data:image/png;base64," + base64.b64encode(png).decode("ascii")


def _e(value: Any) -> str:
    if value is None or (isinstance(value, float) and math.isnan(value)) or value is pd.NA:
        return ""
    return html.escape(str(value))


def _table(df: pd.DataFrame, *, left: Sequence[str] = (), cell: Any = None) -> str:
    """An HTML table; ``cell(column, value) -> (html, style)`` may style cells."""
    if df.empty:
        return "<p><em>(none)</em></p>"
    cols = [str(c) for c in df.columns]
    head = "".join(f'<th class="{"l" if c in left else ""}">{_e(c)}</th>' for c in cols)
    body = []
    for rec in df.itertuples(index=False):
        tds = []
        for c, v in zip(cols, rec):
            text, style = (cell(c, v) if cell else (None, ""))
            cls = ' class="l"' if c in left else ""
            sty = f' style="{style}"' if style else ""
            tds.append(f"<td{cls}{sty}>{text if text is not None else _e(v)}</td>")
        body.append("<tr>" + "".join(tds) + "</tr>")
    return f"<table><thead><tr>{head}</tr></thead><tbody>{''.join(body)}</tbody></table>"


def _heat(rate: float) -> str:
    """A background from white (0) to red (1); rates are in [0, 1]."""
    if rate is None or (isinstance(rate, float) and math.isnan(rate)):
        return ""
    r = min(max(float(rate), 0.0), 1.0)
    g = int(255 - 150 * r)
    return f"background:rgb(255,{g},{g})"


def rate_matrix(table: pd.DataFrame) -> pd.DataFrame:
    """Failure rates with configs as rows and families as columns (``failed/calls`` strings kept separate).

    Returns
    -------
    DataFrame
        Index: config labels; columns: families; values: failure rate in [0, 1]
        (NaN where the config did not run on the family).
    """
    if table.empty:
        return pd.DataFrame()
    failed = failed_mask(table)
    rates = failed.groupby([table["config"], table["generator"]], observed=True).mean()
    return rates.unstack("generator").sort_index()


def _rate_matrix_html(table: pd.DataFrame) -> str:
    m = rate_matrix(table)
    if m.empty:
        return "<p><em>(no calls)</em></p>"
    counts = failed_mask(table).groupby([table["config"], table["generator"]], observed=True).agg(
        lambda s: f"{int(s.sum())}/{len(s)}")
    head = "<th class=l>config \\ family</th>" + "".join(f"<th>{_e(c)}</th>" for c in m.columns)
    rows = []
    for config, rates in m.iterrows():
        tds = [f"<td class=l><code>{_e(config)}</code></td>"]
        for family, rate in rates.items():
            if pd.isna(rate):
                tds.append("<td></td>")
            else:
                tds.append(f'<td style="{_heat(rate)}" title="{_e(counts[(config, family)])} failed">{rate:.0%}</td>')
        rows.append("<tr>" + "".join(tds) + "</tr>")
    return f"<table><thead><tr>{head}</tr></thead><tbody>{''.join(rows)}</tbody></table>"


def _pct_cell(column: str, value: Any) -> tuple[str | None, str]:
    if column in ("rate", "failure_rate", "sphere_off", "sphere_on", "sphere_method", "sphere_end_to_end",
                  "eps_scaled", "eps_fixed"):
        if value is None or (isinstance(value, float) and math.isnan(value)):
            return "", ""
        return f"{float(value):.0%}", _heat(float(value))
    return None, ""


def _cause_html(rec: FailureRecord) -> str:
    cause, sig = rec.cause, rec.signature
    parts = [f'<section class="group" id="{_e(cause.slug)}">', f"<h3>{_e(cause.headline)}</h3>"]
    if rec.picture:
        parts.append(f'<img src="{png_data_uri(rec.picture)}" alt="{_e(sig.label)}: minimal case">')
    items = [("failures", f"{cause.failures} failing calls in {len(cause.records)} failure groups")]
    items.append(("configs", "<br>".join(f"<code>{_e(c)}</code>" for c in cause.configs)))
    items.append(("families", _e(", ".join(f"{f} ({n})" for f, n in cause.families))))
    row = rec.record.shrink.row
    if row is not None and row.get("contract"):
        items.append(("declared contract", f"<code>{_e(row.get('contract'))}</code>"))
    shrunk = f"{rec.original_size} &rarr; {rec.minimal_size} points"
    shrunk += f" ({rec.shrink_calls} evaluations)" if rec.shrunk else " (not shrunk)"
    items.append(("size", shrunk))
    if rec.note:
        items.append(("note", _e(rec.note)))
    if sig.frame:
        items.append(("raised at", f"<code>{_e(sig.frame)}</code>"))
    if rec.reason:
        items.append(("reason", _e(rec.reason)))
    if rec.offending:
        items.append(("offending", "<code>" + _e(", ".join(f"{k}: {list(v)}" for k, v in rec.offending.items()))
                      + "</code>"))
    verified = {True: '<span class="ok">yes</span>', False: '<span class="bad">NO</span>', None: "not checked"}
    items.append(("fails again when re-run", verified[rec.verified]))
    items.append(("folder", f"<code>{_e(rec.folder)}</code>"))
    items.append(("for the maintainer", "<code>bug-report.md</code>, a reproducer without hullstress "
                  "(<code>repro.py</code> or <code>repro.sh</code>), <code>certificate.json</code> checked by "
                  "<code>python verify.py</code>"))
    parts.append("<dl>" + "".join(f"<dt>{k}</dt><dd>{v}</dd>" for k, v in items) + "</dl>")
    if rec.command:
        parts.append(f"<p>Reproduce (prints the verdict and its witness; exits 1 while the failure persists):</p>"
                     f"<pre>{_e(rec.command)}</pre>")
    if len(rec.points) <= 64:
        parts.append(f"<details><summary>minimal points ({len(rec.points)}, exact)</summary>"
                     f"<pre>{_e(points_text(rec.points))}</pre></details>")
    parts.append("</section>")
    return "\n".join(parts)


def _causes_index(records: Sequence[FailureRecord]) -> str:
    """One row per cause, worst first, linking to its section."""
    verified = {True: "yes", False: "NO", None: ""}
    rows = [{"cause": f'<a href="#{_e(r.cause.slug)}">{_e(r.cause.headline)}</a>', "failures": r.cause.failures,
             "groups": len(r.cause.records), "families": len(r.cause.families), "minimal": r.minimal_size,
             "verified": verified[r.verified]} for r in records]
    return _table(pd.DataFrame(rows), left=("cause",), cell=lambda c, v: (v, "") if c == "cause" else (None, ""))


def _groups_index(groups: Sequence[FailureGroup], records: Sequence[FailureRecord]) -> str:
    """One row per failure group, worst first, linking to the section of its cause."""
    cause_of = {m.signature.slug: r for r in records for m in r.cause.records}
    rows = []
    for g in groups:
        rec = cause_of.get(g.slug)
        label = _e(g.signature.label)
        rows.append({
            "group": label, "failures": g.count, "calls": g.calls, "families": len(g.families),
            "smallest": g.smallest_n_points,
            "cause": f'<a href="#{_e(rec.cause.slug)}">{_e(rec.cause.slug)}</a>' if rec else "",
        })
    return _table(pd.DataFrame(rows), left=("group", "cause"),
                  cell=lambda c, v: (v, "") if c in ("group", "cause") else (None, ""))


def render_html(
    table: pd.DataFrame,
    meta: Mapping[str, Any],
    records: Sequence[FailureRecord],
    findings: Findings,
    *,
    notes: Sequence[str] = (),
    groups: Sequence[FailureGroup] | None = None,
) -> str:
    """The whole report as one HTML string.

    Parameters
    ----------
    table : DataFrame
        The results table.
    meta : mapping
        ``run.json``'s content (run id, profile, seed, timings, completeness).
    records : sequence of FailureRecord
        One per cause folder written, worst first.
    findings : Findings
        From :func:`hullstress.report.findings.compute_findings` (the same
        claims as ``findings.md``).
    notes : sequence of str
        Lines about how triage ran (budgets, groups not shrunk).
    groups : sequence of FailureGroup, optional
        Every failure group (default: those of ``records``' causes).

    Returns
    -------
    str
    """
    run_id = str(meta.get("run_id", ""))
    out = ["<!DOCTYPE html>", '<html lang="en">', "<head>", '<meta charset="utf-8">',
           '<meta name="viewport" content="width=device-width, initial-scale=1">',
           f"<title>hullstress report {_e(run_id)}</title>", f"<style>{_CSS}</style>", "</head>", "<body>"]
    out.append(f"<h1>hullstress run {_e(run_id)}</h1>")
    complete = meta.get("complete", True)
    wall = (meta.get("timings") or {}).get("wall_seconds")
    n_cases = int(table["case_id"].nunique()) if len(table) else 0
    out.append(
        f'<p class="meta">Profile <code>{_e(meta.get("profile"))}</code>, seed {_e(meta.get("seed"))}, '
        f"{len(table)} calls over {n_cases} cases"
        + (f", {float(wall):.1f} s" if wall is not None else "")
        + ("" if complete else ', <strong class="bad">INCOMPLETE</strong> (interrupted or out of time budget)')
        + ".</p>"
    )
    if groups is None:
        groups = [m.group for r in records for m in r.cause.records if m.group is not None]
    failed = int(failed_mask(table).sum()) if len(table) else 0
    method = int(failed_mask(table, Stage.PREPROCESS).sum()) if len(table) else 0
    internal = int(failed_mask(table, Stage.CHECK).sum()) if len(table) else 0
    out.append(f"<p>{failed} calls in which the algorithm failed, {method} failures of the sphere method or eps "
               f"set-up (stage preprocess), {internal} internal errors (stage check): {len(groups)} failure groups "
               f"(signature: config, stage, status, failed checks and severity, or exception and frame), merged "
               f"into {len(records)} causes (groups whose minimal cases coincide up to translation, power-of-two "
               "scaling, row and axis order).</p>")

    out.append('<p class="meta">Jump to: <a href="#top-causes">top causes</a> &middot; <a href="#status">calls by '
               'status</a> &middot; <a href="#rates">failure rates</a> &middot; <a href="#findings">findings</a> '
               '&middot; <a href="#causes">every cause</a>' + (' &middot; <a href="#groups">failure groups</a>'
                                                              if groups else "") + "</p>")
    # What is broken comes first: a reader's first screen is the worst causes, as in summary.md.
    out.append(f'<h2 id="top-causes">Top causes ({min(TOP_CAUSES, len(records))} of {len(records)})</h2>')
    out.append(_causes_index(records[:TOP_CAUSES]) if records else "<p>No failures.</p>")

    out.append('<h2 id="status">Calls by status</h2>')
    totals = (table["status"].value_counts().reindex(list(STATUSES), fill_value=0) if len(table)
              else pd.Series(0, index=list(STATUSES)))
    out.append(_table(totals.rename_axis("status").reset_index(name="calls"), left=("status",)))
    if len(table):
        out.append("<h3>By algorithm and variant</h3>")
        out.append(_table(status_counts(table, ["algorithm", "sphere", "eps"]),
                          left=("algorithm", "sphere", "eps"), cell=_pct_cell))

    out.append('<h2 id="rates">Failure rates by algorithm x variant x family</h2>')
    out.append("<p>Share of calls in which the algorithm failed: fail, error, timeout or crash at stage "
               "algorithm (rejected degenerate input is acceptable behaviour; failures of the sphere method "
               "and internal errors are not the algorithm's and not counted). Hover a cell for failed/calls.</p>")
    out.append(_rate_matrix_html(table))
    if len(table):
        out.append("<h3>Failure counts (groups with a failure, worst first)</h3>")
        out.append(_table(failure_counts(table), left=("algorithm", "sphere", "eps", "generator"), cell=_pct_cell))

    out.append('<h2 id="findings">Findings: the claims against this run</h2>')
    out.append("<p>The same claims as <code>findings.md</code> and <code>findings.csv</code> "
               "(<code>python -m hullstress findings</code>). Cells count failed/calls; a variant's findings "
               "never charge the algorithm it wraps.</p>")
    for claim in findings.claims:
        out.append(f"<h3>{_e(claim.title)}</h3>")
        out.append(f'<p class="meta">Scope: {_e(claim.scope)}</p>')
        items = [_e(line) for line in claim.reading] + [f"<strong>Why:</strong> {_e(line)}" for line in claim.why]
        out.append("<ul>" + "".join(f"<li>{item}</li>" for item in items) + "</ul>")
        for caption, frame in claim.tables:
            out.append(f"<p>{_e(caption)}:</p>")
            out.append(_table(frame, left=_FINDINGS_KEYS))

    out.append(f'<h2 id="causes">Causes ({len(records)})</h2>')
    for line in notes:
        out.append(f'<p class="meta">{_e(line)}</p>')
    if records:
        out.append(_causes_index(records))
        out.extend(_cause_html(r) for r in records)
    else:
        out.append("<p>No failures.</p>")
    if groups:
        out.append(f'<h2 id="groups">Failure groups ({len(groups)})</h2>')
        out.append(_groups_index(groups, records))
    skipped = meta.get("skipped") or []
    if skipped:
        out.append(f"<h2>Cases not generated ({len(skipped)})</h2><ul>"
                   + "".join(f"<li>{_e(s)}</li>" for s in skipped) + "</ul>")
    out.append("</body>")
    out.append("</html>")
    return "\n".join(out) + "\n"
