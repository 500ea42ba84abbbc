#!/usr/bin/env bash
# clang-tidy (.clang-tidy) on the C++ sources (src/, optim/, bench/, python/)
# a change touches, with the ci build's compile_commands.json; our own
# headers they include are checked too.
# The tests are left out: GoogleTest's macros send the analyzer down paths no
# test takes, and clang 14 cannot compile some C++20 they use (structured
# bindings captured by lambdas).
#   scripts/check_tidy.sh [BASE]   files changed since BASE (a commit)
# Without BASE: since the merge base with origin/main when HEAD is ahead of
# it, otherwise the last commit (CI runs on a clean clone of main). Files
# changed in the work tree and not yet committed are included. `--all`
# checks every source file (slow: about 15 s each).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
root="$(pwd)"

tidy="$(command -v clang-tidy || command -v clang-tidy-14 || true)"
if [[ -z "$tidy" ]]; then
  echo "check_tidy: clang-tidy not found (Debian package clang-tidy)" >&2
  exit 1
fi
if [[ ! -f build/ci/compile_commands.json ]]; then
  echo "check_tidy: build/ci/compile_commands.json missing; build the ci preset first (scripts/setup.sh ci)" >&2
  exit 1
fi

if [[ "${1-}" == "--all" ]]; then
  mapfile -t files < <(git ls-files '*.cc' | grep -E '^(src|optim|bench|python)/')
  what="every source file"
else
  base="${1-}"
  if [[ -z "$base" ]]; then
    upstream="$(git merge-base HEAD origin/main 2>/dev/null || true)"
    if [[ -n "$upstream" && "$upstream" != "$(git rev-parse HEAD)" ]]; then
      base="$upstream"
    elif git rev-parse -q --verify HEAD~1 >/dev/null; then
      base="HEAD~1"
    else
      base="$(git hash-object -t tree /dev/null)"  # the first commit: every file
    fi
  fi
  mapfile -t files < <({
    git diff --name-only --diff-filter=AM "$base" HEAD
    git diff --name-only --diff-filter=AM HEAD
  } | grep -E '^(src|optim|bench|python)/.*\.cc$' | sort -u)
  what="the sources changed since $(git rev-parse --short "$base" 2>/dev/null || echo "$base")"
fi

if ((${#files[@]} == 0)); then
  echo "check_tidy: no C++ source changed since $base"
  exit 0
fi
echo "check_tidy: ${#files[@]} files ($what)"
# The ci build is a unity build (docs/architecture.md, "Build time"): its
# compile_commands.json names the batches, not the files. Each file a batch
# includes gets the batch's command in a database of our own.
db_dir="$(mktemp -d)"
trap 'rm -rf "$db_dir"' EXIT
python3 - build/ci/compile_commands.json "$db_dir/compile_commands.json" <<'PY'
import json, re, sys
entries = []
for c in json.load(open(sys.argv[1])):
    if "/Unity/unity_" not in c["file"]:
        entries.append(c)
        continue
    for source in re.findall(r'^#include "([^"]+)"', open(c["file"]).read(), re.M):
        entries.append(dict(c, file=source, command=c["command"].replace(c["file"], source)))
json.dump(entries, open(sys.argv[2], "w"), indent=0)
PY
failed=()
for file in "${files[@]}"; do
  # Files a preset leaves out of the build (the MPI runner without MPI) have no compile command.
  if ! grep -q "\"file\": \"$root/$file\"" "$db_dir/compile_commands.json"; then
    echo "check_tidy: $file is not in the ci build; skipped"
    continue
  fi
  if ! "$tidy" -p "$db_dir" --quiet --header-filter="^$root/(src|optim|bench|include|python)/" "$file" 2>/dev/null; then
    failed+=("$file")
  fi
done
if ((${#failed[@]} > 0)); then
  printf 'check_tidy: findings in %s\n' "${failed[@]}" >&2
  exit 1
fi
echo "check_tidy: ${#files[@]} files clean"
