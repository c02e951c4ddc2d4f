#!/usr/bin/env bash
# Mutation testing of the verdict-deciding code: hullstress/checker/*, hullstress/contract.py and hullstress/evaluate.py (stage attribution).
#
#   pip install -e ".[mutation]" && tools/mutation.sh
#   tools/mutation.sh 'hullstress.checker.lowdim.*'    # only the mutants whose names match
#
# mutmut (configured in pyproject.toml, [tool.mutmut]) plants one mutant at a time and runs
# only the fast checker tests that reach the mutated function, with the deterministic
# `mutation` Hypothesis profile.  Afterwards tools/mutation_report.py writes
# reports/mutation/mutation-report.md (score, survivors with their recorded reasons; for a
# restricted run, of the named mutants only) and exits 1 if a survivor has no reason in
# tools/mutation_survivors/*.toml.
#
# Reuse between runs.  mutants/ holds the generated mutants, mutmut's stats (which test
# reaches which function: collecting them runs the whole test selection once, 10-20
# minutes) and the results.  A run restricted to mutant names keeps mutants/ when the code
# mutmut copied into it is byte-identical to the working tree's (a fingerprint of every
# file under hullstress/ and generators/ and of pyproject.toml, kept in
# mutants/source.sha256); any difference, a run over every mutant, or MUTATION_FRESH=1
# deletes it first, so no result computed against other code is ever reported.  The
# named mutants are always re-run (mutmut re-runs every mutant it is given by name) and
# the report counts only them, so a restricted run's score is measured with today's
# tests; tests added since the stats were collected get their stats collected by mutmut
# itself before the run.
#
# MUTATION_JOBS (default 2) sets mutmut's parallel children; the run is niced.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
if ! command -v mutmut >/dev/null 2>&1; then
  # Checked before anything is deleted: a missing tool must not cost the kept mutants/.
  echo "tools/mutation.sh: mutmut not found on PATH (pip install -e \".[mutation]\" in the active environment)" >&2
  exit 2
fi
jobs="${MUTATION_JOBS:-2}"
out=reports/mutation
mkdir -p "$out"
fingerprint=$(find hullstress generators pyproject.toml -type f ! -path '*/__pycache__/*' -print0 \
  | LC_ALL=C sort -z | xargs -0 sha256sum | sha256sum | cut -d' ' -f1)
if [[ $# -eq 0 || "${MUTATION_FRESH:-0}" == 1 || "$(cat mutants/source.sha256 2>/dev/null)" != "$fingerprint" ]]; then
  rm -rf mutants  # no results, stats or copies of an earlier checker
  echo "tools/mutation.sh: fresh run (mutants/ deleted)"
else
  echo "tools/mutation.sh: reusing mutants/ (same source; stats kept, the named mutants re-run)"
fi
start=$(date +%s)
# The fingerprint is written before the run: mutmut copies the tree first thing, and a run
# stopped half-way leaves results of this same source, each one complete.
mkdir -p mutants && echo "$fingerprint" > mutants/source.sha256
HYPOTHESIS_PROFILE=mutation nice -n 10 mutmut run --max-children "$jobs" "$@" > "$out/mutmut-run.log" 2>&1 || {
  echo "tools/mutation.sh: mutmut run failed, see $out/mutmut-run.log" >&2
  tail -n 20 "$out/mutmut-run.log" >&2
  exit 2
}
python tools/mutation_report.py --seconds "$(( $(date +%s) - start ))" --jobs "$jobs" --out "$out/mutation-report.md" "$@"
