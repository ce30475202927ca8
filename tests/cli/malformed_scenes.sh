#!/usr/bin/env bash
# Every malformed scene of tests/data/scenes/invalid makes `romp run` exit with code 3 (invalid
# input) and a message naming the file, without a crash and without writing any output.
set -uo pipefail
romp="$1"
corpus="$2"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
failures=0
count=0
for scene in "$corpus"/*.toml; do
  count=$((count + 1))
  (cd "$work" && "$romp" --device cpu run --no-progress "$scene" > "$work/.log" 2>&1)
  code=$?
  if [ "$code" -ne 3 ]; then
    echo "FAIL $scene: exit code $code, expected 3"; cat "$work/.log"; failures=$((failures + 1))
  elif ! grep -qF "$scene" "$work/.log"; then
    echo "FAIL $scene: the message does not name the file"; cat "$work/.log"; failures=$((failures + 1))
  fi
  if [ -n "$(ls -A "$work" | grep -v '^\.log$')" ]; then
    echo "FAIL $scene: left output behind: $(ls -A "$work")"; failures=$((failures + 1))
  fi
  rm -rf "${work:?}"/*
done
echo "$count malformed scenes, $failures failures"
[ "$count" -ge 30 ] && [ "$failures" -eq 0 ]
