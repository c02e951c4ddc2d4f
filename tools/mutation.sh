#!/usr/bin/env bash
# Mutation testing of the verdict-deciding code: hullstress/checker/* and hullstress/contract.py.
#
#   pip install -e ".[mutation]" && tools/mutation.sh
#   tools/mutation.sh 'hullstress.checker.lowdim.*'    # only the mutants whose names match
#
# mutmut (configured in pyproject.toml, [tool.mutmut]) plants one mutant at a time and runs
# only the fast checker tests that reach the mutated function, with the deterministic
# `mutation` Hypothesis profile.  Afterwards tools/mutation_report.py writes
# reports/mutation/mutation-report.md (score, survivors with their recorded reasons) and
# exits 1 if a survivor has no reason in tools/mutation_survivors.toml.
#
# MUTATION_JOBS (default 2) sets mutmut's parallel children; the run is niced.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
jobs="${MUTATION_JOBS:-2}"
out=reports/mutation
mkdir -p "$out"
rm -rf mutants  # no results cached from an earlier checker
start=$(date +%s)
HYPOTHESIS_PROFILE=mutation nice -n 10 mutmut run --max-children "$jobs" "$@" > "$out/mutmut-run.log" 2>&1 || {
  echo "tools/mutation.sh: mutmut run failed, see $out/mutmut-run.log" >&2
  tail -n 20 "$out/mutmut-run.log" >&2
  exit 2
}
python tools/mutation_report.py --seconds "$(( $(date +%s) - start ))" --jobs "$jobs" --scope "$*" --out "$out/mutation-report.md"
