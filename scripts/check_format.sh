#!/usr/bin/env bash
# Checks that every C++ file of the project is formatted as .clang-format says
# (clang-format from Debian's clang-format package). `--fix` formats them in place.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

if ! command -v clang-format >/dev/null 2>&1; then
  echo "check_format: clang-format not found (Debian package clang-format)" >&2
  exit 1
fi
mapfile -t files < <(git ls-files '*.h' '*.cc' '*.cpp' | grep -E '^(src|optim|tests|bench|include|examples|python)/')
if [[ "${1-}" == "--fix" ]]; then
  # Only the files that differ: rewriting the others would touch their
  # timestamps and make the build recompile everything.
  fixed=0
  for file in "${files[@]}"; do
    if ! clang-format --dry-run --Werror "$file" >/dev/null 2>&1; then
      clang-format -i "$file"
      fixed=$((fixed + 1))
    fi
  done
  echo "check_format: formatted ${fixed} of ${#files[@]} files"
  exit 0
fi
unformatted=()
for file in "${files[@]}"; do
  clang-format --dry-run --Werror "$file" >/dev/null 2>&1 || unformatted+=("$file")
done
if ((${#unformatted[@]} > 0)); then
  printf 'check_format: not formatted: %s\n' "${unformatted[@]}" >&2
  echo "check_format: ${#unformatted[@]} of ${#files[@]} files differ; run: bash scripts/check_format.sh --fix" >&2
  exit 1
fi
echo "check_format: ${#files[@]} files formatted"
