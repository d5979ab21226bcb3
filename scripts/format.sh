#!/usr/bin/env bash
# Formats every C++ source of millnet with the project's .clang-format (clang-format 14, Debian 12).
# --check: change nothing; list the files that differ and exit 1 when any does (.ci/run).
set -euo pipefail
cd "$(dirname "$0")/.."
mapfile -t files < <(git ls-files '*.cpp' '*.hpp')
if [ "${1:-}" = "--check" ]; then
  bad=()
  for f in "${files[@]}"; do
    clang-format --style=file "$f" | cmp -s - "$f" || bad+=("$f")
  done
  if [ ${#bad[@]} -gt 0 ]; then
    printf 'format: %s differs from .clang-format (run scripts/format.sh)\n' "${bad[@]}" >&2
    exit 1
  fi
  echo "format: ${#files[@]} files as .clang-format says" >&2
else
  clang-format --style=file -i "${files[@]}"
fi
