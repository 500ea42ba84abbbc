#!/usr/bin/env bash
# The CI test run: builds and tests the ci preset (optimised, assertions on,
# warnings are errors), then the asan preset (clang 14, AddressSanitizer +
# UBSan): the whole suite, and the six libFuzzer targets built in the same tree,
# each fuzzed for about 15 s (label fuzz; docs/fuzzing.md). One sanitised
# build serves both, so the library is compiled twice, not three times.
# Every phase runs even if an earlier one failed, so one report shows all
# failures; the exit status is non-zero if any phase failed.
set -euo pipefail
# The tests that need gnuplot, Chromium or script fail here rather than skip
# when it is missing (tests/support/required_tool.h): setup installs them.
export CAMDYN_CI=1
cd "$(dirname "${BASH_SOURCE[0]}")/.."

failed=()
summary=()

# phase NAME COMMAND...: runs COMMAND, records its elapsed time and outcome.
phase() {
  local name="$1"
  shift
  echo "==> $name: $*"
  local start=$SECONDS outcome=ok
  if ! "$@"; then
    outcome=FAILED
    failed+=("$name")
  fi
  local elapsed=$((SECONDS - start))
  summary+=("$(printf '%-12s %-7s %4dm%02ds' "$name" "$outcome" $((elapsed / 60)) $((elapsed % 60)))")
  echo "==> $name: $outcome after ${elapsed}s"
}

for preset in ci asan; do
  phase "build $preset" bash scripts/setup.sh "$preset"
  if [[ "$preset" == ci ]]; then
    # Once setup has installed clang-format and clang-tidy: the layer order of
    # the include graph, the function-length limit and the docs the code
    # cites, and the formatting
    # (seconds each); clang-tidy on the sources (not tests) the last change touched
    # (about 15 s a file).
    phase "structure" python3 scripts/check_structure.py
    phase "format" bash scripts/check_format.sh
    phase "tidy" bash scripts/check_tidy.sh
  fi
  if [[ " ${failed[*]-} " == *" build $preset "* ]]; then
    echo "==> test $preset: skipped, the build failed"
    summary+=("$(printf '%-12s %-7s' "test $preset" skipped)")
    continue
  fi
  phase "test $preset" ctest --preset "$preset"
  if [[ "$preset" == ci ]]; then
    # Every number the README quotes, from a fresh run of the committed
    # studies, within its stated tolerance (scripts/readme_numbers.py).
    phase "readme" /usr/bin/python3 scripts/readme_numbers.py --check --camdyn build/ci/camdyn
  fi
done

echo
echo "==> summary"
printf '    %s\n' "${summary[@]}"
if ((${#failed[@]} > 0)); then
  echo "==> FAILED: ${failed[*]}"
  exit 1
fi
echo "==> all phases passed"
