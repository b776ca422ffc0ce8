#!/usr/bin/env bash
# Mutation testing of the engine (issue 8): mutmut over era, tcm, cera, hankel,
# indicators, signals, result and stabilisation, against the engine tests only.
# Not run in CI (16 min for the 3432 mutants with --max-children 1; longer when
# the 2 cores are busy with other work).
#
#   bash benchmarks/mutation.sh            # fresh run (deletes mutants/), then the kill rate
#   bash benchmarks/mutation.sh --resume   # continue an interrupted run, then the kill rate
#   bash benchmarks/mutation.sh --report   # only the kill rate of the last run
#
# Which modules and tests: [tool.mutmut] in pyproject.toml. The property tests
# run under the Hypothesis profile "mutation" (tests/hypothesis_profiles.py:
# derandomised, no example database), so a verdict does not depend on the
# draw. Surviving mutants judged equivalent are listed, with the reason, in
# benchmarks/mutation_survivors.md; the kill rate is over the others.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$ROOT"
export OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1 MKL_NUM_THREADS=1

MODE="${1:-run}"
EXTRA=test
source workflow/setup.sh
if ! .venv/bin/python -c "import mutmut" 2>/dev/null; then
    .venv/bin/python -m pip install --quiet "mutmut>=3.8,<4"   # the [mutation] extra
fi

run_mutmut() {
    mkdir -p mutants
    # Both cores; each mutant runs only the engine tests that reach its function.
    if ! .venv/bin/mutmut run --max-children 2 > mutants/run.log 2>&1; then
        tail -c 3000 mutants/run.log >&2
        exit 1
    fi
}
case "$MODE" in
    run) rm -rf mutants; run_mutmut ;;
    --resume) run_mutmut ;;
    --report) ;;
    *) echo "usage: bash benchmarks/mutation.sh [--resume | --report]" >&2; exit 2 ;;
esac

.venv/bin/mutmut results --all true > mutants/results.txt
.venv/bin/python benchmarks/mutation_report.py mutants/results.txt benchmarks/mutation_survivors.md
