#!/usr/bin/env bash
# Fails if clang-format would change any C++ source (run with --fix to format in place).
set -euo pipefail
cd "$(dirname "$0")/.."
# Tracked files and new ones not yet added (git's ignore rules keep build/ out).
files=$(git ls-files --cached --others --exclude-standard '*.cpp' '*.hpp' '*.h')
if [ "${1:-}" = "--fix" ]; then
  clang-format -i $files
  exit 0
fi
clang-format --dry-run --Werror $files
# The layout's direction rests on every library header being included by its full name
# (talus/<library>/...): a relative include would reach past the include roots.
if git grep -n '#include "' -- 'src/talus/*' | grep -v '#include "talus/'; then
  echo "include the headers above by their full name, talus/<library>/..." >&2
  exit 1
fi
echo "clang-format: $(echo "$files" | wc -w) files clean"
