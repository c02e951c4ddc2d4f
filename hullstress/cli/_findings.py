"""``python -m hullstress findings RUN``: the claims checked against one run's results table."""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

from ..errors import UsageError

__all__ = ["add_parser", "findings_command", "find_results_table"]


def add_parser(sub: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    p = sub.add_parser(
        "findings",
        help="check the seeds' claims against a run's results table (findings.md, findings.csv)",
        description="Compute the findings from a run's results table: the sphere method per dimension with "
        "its two causes (vertex loss, face-structure change), eps policies across scales, the uniform "
        "family's failures by variant and size, and each algorithm's failures on the degenerate families "
        "against the uniform control. Prints the Markdown and writes findings.md and findings.csv into the "
        "run folder (or --out). The report of `run` writes the same files. Exit status 0; 2 when RUN "
        "holds no readable results table or --out is not a folder; 4 when the disk refuses --out "
        "(read-only, full).",
    )
    p.add_argument("run", metavar="RUN", help="a run folder (with results.parquet or results.csv), or a results table")
    p.add_argument("--out", default=None, metavar="DIR",
                   help="write findings.md and findings.csv here (default: the run folder)")
    p.add_argument("--quiet", action="store_true", help="print only the paths written")
    p.set_defaults(handler=findings_command)


def find_results_table(spec: str) -> Path:
    """The results table named by RUN: the file itself, or the first of ``RESULTS_FILES`` in the folder.

    Raises
    ------
    UsageError
        When RUN does not exist, or is a folder without a results table.
    """
    from ..results import RESULTS_FILES

    path = Path(spec)
    if not path.exists():
        raise UsageError(f"RUN {spec!r}: no such file or directory")
    if path.is_dir():
        for name in RESULTS_FILES:
            if (path / name).is_file():
                return path / name
        raise UsageError(f"RUN {spec!r}: no results table in this folder (expected {' or '.join(RESULTS_FILES)})")
    return path


def _source(table_path: Path) -> str:
    """The run's description from ``run.json`` beside the table ("" when there is none or it is unreadable)."""
    from ..report.findings import run_source

    try:
        meta = json.loads((table_path.parent / "run.json").read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return f"`{table_path}`"
    return run_source(meta) if isinstance(meta, dict) else f"`{table_path}`"


def findings_command(args: argparse.Namespace) -> int:
    from ..errors import EnvironmentFailure, is_environment_error, one_line
    from ..report.findings import compute_findings, findings_markdown, write_findings
    from ..results import REQUIRED_COLUMNS, read_frame

    table_path = find_results_table(args.run)
    try:
        table = read_frame(table_path, required=(*REQUIRED_COLUMNS, "case_id", "dim"))
    except (OSError, ValueError, ImportError) as exc:
        raise UsageError(f"RUN {args.run!r}: cannot read the results table {str(table_path)!r}: {one_line(exc)}") from None
    out = Path(args.out) if args.out is not None else table_path.parent
    findings = compute_findings(table, source=_source(table_path))
    try:
        out.mkdir(parents=True, exist_ok=True)
        md, csv = write_findings(out, findings)
    except OSError as exc:
        message = f"--out {str(out)!r}: cannot write the findings there: {exc.strerror or exc}"
        if is_environment_error(exc):  # a read-only or full disk: the environment's status, not a usage error
            raise EnvironmentFailure(message) from None
        raise UsageError(message) from None
    if not args.quiet:
        sys.stdout.write(findings_markdown(findings, level=1) + "\n")
    print(f"findings: {md} {csv}")
    return 0
