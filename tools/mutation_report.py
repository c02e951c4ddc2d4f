"""Summarise a mutmut run of the checker: score, and every survivor with its reason.

Run by ``tools/mutation.sh`` after ``mutmut run`` (from the repository root, where
``mutants/`` holds mutmut's results).  Writes a Markdown report: the score
(killed and timed-out mutants over all checked ones; "no tests" counts as
surviving), counts per status, and one table row per surviving mutant with the
changed line and the reason it is equivalent or harmless, taken from
``tools/mutation_survivors/*.toml`` (one file per module).  Given mutant name patterns (those the run was
restricted to), it counts only the matching mutants: ``mutants/`` may hold results
of earlier restricted runs of other modules.  A survivor without a reason is listed as
UNEXPLAINED and makes the exit status 1: kill it with a test (preferably a
negative-corpus entry) or record why it cannot matter.

Reasons are matched by function and by the text of the mutated line, not by
mutmut's numbered mutant names, so they survive edits elsewhere in the checker.
"""

from __future__ import annotations

import argparse
import fnmatch
import re
import sys
import tomllib
from collections import Counter
from dataclasses import dataclass
from pathlib import Path

from mutmut.mutation.data import SourceFileMutationData
from mutmut.mutation.diff_apply import get_diff_for_mutant
from mutmut.stats import status_by_exit_code
from mutmut.utils.file_utils import walk_mutatable_files

#: One TOML file of reasons per mutated module; ``_common.toml`` (reasons for every module) is read first.
REASONS = Path(__file__).with_name("mutation_survivors")
DETECTED = {"killed", "timeout", "caught by type check", "segfault"}


@dataclass
class Survivor:
    name: str  # mutmut's mutant name
    function: str  # module.function (class methods as module.Class.method)
    status: str
    removed: str  # the original line(s)
    added: str  # the mutated line(s)
    reason: str | None = None


def function_of(mutant: str) -> str:
    """``hullstress.checker.api.x_check__mutmut_3`` -> ``hullstress.checker.api.check``."""
    module, _, mangled = mutant.rpartition(".")
    mangled = re.sub(r"__mutmut_\d+$", "", mangled)
    if mangled.startswith("xǁ"):
        mangled = mangled[2:].replace("ǁ", ".")
    elif mangled.startswith("x_"):
        mangled = mangled[2:]
    return f"{module}.{mangled}"


def change_of(removed: str, added: str, context: int = 20) -> str:
    """The differing middle of two lines with a little context: ``...a > b...`` -> ``...a >= b...``."""
    start = 0
    while start < min(len(removed), len(added)) and removed[start] == added[start]:
        start += 1
    end = 0
    while end < min(len(removed), len(added)) - start and removed[-1 - end] == added[-1 - end]:
        end += 1
    lo = max(0, start - context)

    def middle(text: str) -> str:
        hi = len(text) - max(0, end - context)
        return ("..." if lo else "") + text[lo:hi] + ("..." if hi < len(text) else "")

    return f"`{middle(removed)}` -> `{middle(added)}`".replace("|", "\\|")


def load_reasons(folder: Path = REASONS) -> list[dict]:
    """Every recorded reason, ``_common.toml`` first, then the module files in name order."""
    files = sorted(folder.glob("*.toml"), key=lambda f: (f.name != "_common.toml", f.name))
    return [entry for f in files for entry in tomllib.loads(f.read_text()).get("survivor", [])]


def explain(s: Survivor, reasons: list[dict]) -> str | None:
    """The first matching reason: by function, then by ``change`` (text in either line) or ``added``
    (text in the mutated line only: a reason for one mutation of a line, not for all of its others)."""
    for r in reasons:
        if not fnmatch.fnmatchcase(s.function, r["function"]):
            continue
        if "added" in r:
            if r["added"] in s.added:
                return r["reason"]
            continue
        change = r.get("change", "*")
        if change == "*" or change in s.added or change in s.removed:
            return r["reason"]
    return None


def in_scope(name: str, patterns: list[str]) -> bool:
    """Whether mutmut would run mutant ``name`` for these name patterns (none: every mutant)."""
    return not patterns or any(name == p or fnmatch.fnmatch(name, p) for p in patterns)


def collect(patterns: list[str]) -> tuple[Counter, list[Survivor]]:
    counts: Counter = Counter()
    survivors = []
    for path in walk_mutatable_files():
        data = SourceFileMutationData(path=path)
        data.load()
        for name, code in data.exit_code_by_key.items():
            if not in_scope(name, patterns):
                continue
            status = status_by_exit_code[code]
            counts[status] += 1
            if status in DETECTED or status == "not checked":
                continue
            diff = get_diff_for_mutant(name, path=path).splitlines()
            removed = " / ".join(x[1:].strip() for x in diff if x.startswith("-") and not x.startswith("---"))
            added = " / ".join(x[1:].strip() for x in diff if x.startswith("+") and not x.startswith("+++"))
            survivors.append(Survivor(name, function_of(name), status, removed, added))
    return counts, survivors


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=Path("reports/mutation/mutation-report.md"))
    parser.add_argument("--seconds", type=int, default=None, help="wall time of the run, for the report")
    parser.add_argument("--jobs", type=int, default=None, help="mutmut's --max-children, for the report")
    parser.add_argument("patterns", nargs="*", help="the mutant name patterns the run was restricted to")
    args = parser.parse_args(argv)

    counts, survivors = collect(args.patterns)
    reasons = load_reasons()
    for s in survivors:
        s.reason = explain(s, reasons)
    checked = sum(n for status, n in counts.items() if status != "not checked")
    detected = sum(counts[s] for s in DETECTED)
    unexplained = [s for s in survivors if s.reason is None]
    score = 100.0 * detected / checked if checked else 0.0

    scope = " ".join(args.patterns)
    if len(scope) > 200:
        scope = f"{scope[:200]}... ({len(args.patterns)} patterns)"
    title = f"mutants {scope}" if scope else "hullstress/checker/ and hullstress/contract.py"
    lines = [f"# Mutation testing: {title}", ""]
    run = f"{checked} mutants checked, {detected} killed: **score {score:.1f} %**"
    if args.seconds is not None:
        run += f"; {args.seconds // 60} min {args.seconds % 60} s wall"
        run += f" with {args.jobs} parallel children" if args.jobs else ""
    lines += [run, "", "| status | mutants |", "| --- | ---: |"]
    lines += [f"| {status} | {n} |" for status, n in sorted(counts.items(), key=lambda x: -x[1])]
    lines += ["", f"{len(survivors)} survivors, {len(unexplained)} without a recorded reason.", ""]
    lines += ["| mutant | change | why it may survive |", "| --- | --- | --- |"]
    for s in sorted(survivors, key=lambda s: (s.reason is not None, s.name)):
        change = change_of(s.removed, s.added)
        lines.append(f"| {s.name.replace('hullstress.', '')} ({s.status}) | {change} | {s.reason or '**UNEXPLAINED**'} |")
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text("\n".join(lines) + "\n")
    print(f"{run.replace('**', '')}; {len(unexplained)} unexplained survivors -> {args.out}")
    return 1 if unexplained else 0


if __name__ == "__main__":
    sys.exit(main())
