#!/usr/bin/env bash
# Builds the libFuzzer target (clang, ASan + UBSan) and fuzzes the case parser, the polygon
# loader and the set-up for SECONDS (default 60) from the committed corpus. New interesting
# inputs go to a scratch folder; a crash is written to tests/fuzz/crashes/ (commit it with the
# fix: it is then replayed by the fuzz_corpus_replay test in every build).
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-60}
cmake --preset fuzz >/dev/null
cmake --build --preset fuzz
scratch=$(mktemp -d)
mkdir -p "$scratch/new"
trap 'rm -rf "$scratch"' EXIT
# Seeds: the committed corpus, the malformed cases, and every case shipped with Talus.
mkdir -p "$scratch/seeds"
cp tests/fuzz/corpus/* tests/cli/bad_cases/*.toml "$scratch/seeds/"
for f in cases/*/*.toml bench/*.toml; do cp "$f" "$scratch/seeds/$(echo "$f" | tr / _)"; done
UBSAN_OPTIONS=print_stacktrace=1 build/fuzz/tests/talus_fuzz -max_total_time="$seconds" \
  -rss_limit_mb=4096 -timeout=20 -max_len=16384 -print_final_stats=1 \
  -artifact_prefix=tests/fuzz/crashes/ -dict=tests/fuzz/case.dict "$scratch/new" "$scratch/seeds" \
  2>&1 | tail -n 25
