#!/usr/bin/env bash
# Fails if clang-format would change any C++ source (run with --fix to format in place).
set -euo pipefail
cd "$(dirname "$0")/.."
files=$(git ls-files '*.cpp' '*.hpp' '*.h')
if [ "${1:-}" = "--fix" ]; then
  clang-format -i $files
  exit 0
fi
clang-format --dry-run --Werror $files
echo "clang-format: $(echo "$files" | wc -w) files clean"
