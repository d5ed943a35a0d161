#!/usr/bin/env bash
# Each bad case file must make `talus check` and `talus run` exit with status 2 and print the
# expected message (file, line, key) on stderr, never crash.
set -u
talus=$1
dir=$2
out=$(mktemp -d)
status=0
while IFS='|' read -r file expected; do
  for cmd in check run; do
    args=("$cmd" "$dir/$file")
    [ "$cmd" = run ] && args+=(--out "$out/$file")
    msg=$("$talus" "${args[@]}" 2>&1 >/dev/null)
    code=$?
    if [ "$code" -ne 2 ]; then
      echo "FAIL $cmd $file: exit $code, expected 2 ($msg)"; status=1
    elif [[ "$msg" != *"$expected"* ]]; then
      echo "FAIL $cmd $file: message '$msg' lacks '$expected'"; status=1
    else
      echo "ok   $cmd $file: $msg"
    fi
  done
done < "$dir/expected.txt"
rm -rf "$out"
exit $status
