#!/usr/bin/env bash
# The CI test run: builds and tests the ci preset (optimised, assertions on,
# warnings are errors), then the asan preset (AddressSanitizer + UBSan), then
# the fuzz preset (clang: only the six libFuzzer targets, each fuzzed for about
# 25 s; docs/fuzzing.md).
# Every phase runs even if an earlier one failed, so one report shows all
# failures; the exit status is non-zero if any phase failed.
set -euo pipefail
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

for preset in ci asan fuzz; do
  if [[ "$preset" == fuzz ]]; then
    # Only what the fuzz targets link (the library, no tests or tools).
    phase "build fuzz" bash scripts/setup.sh fuzz config_fuzzer csv_fuzzer scene_fuzzer run_fuzzer export_fuzzer \
      journal_fuzzer
  else
    phase "build $preset" bash scripts/setup.sh "$preset"
  fi
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
