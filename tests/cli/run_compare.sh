#!/usr/bin/env bash
# `romp run --compare REFERENCE` prints the run's position error against a reference run of the same
# scene (per frame with --frames): 0 % against an identical run, and a failure (non-zero exit, an error
# naming the reference) against a reference of other particles.
set -uo pipefail
romp="$1"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
source "$(dirname "$0")/cube_scene.sh"
write_cube_scene "$work/cube.toml" compare_cube
sed 's/size = \[0.06, 0.06, 0.06\]/size = [0.04, 0.04, 0.04]/' "$work/cube.toml" > "$work/smaller.toml"
run() { "$romp" --device cpu --threads 1 run --no-progress "$@" > "$work/log" 2>&1; }
fail() { echo "FAIL: $1"; cat "$work/log"; exit 1; }
run "$work/cube.toml" -o "$work/reference.h5" --deterministic || fail "the reference run"
run "$work/cube.toml" -o "$work/again.h5" --deterministic --compare "$work/reference.h5" --frames ||
  fail "the run with --compare exited $?"
grep -q "accumulated position error 0% over 6 frames" "$work/log" || fail "no 0 % error over 6 frames"
grep -q "position error %" "$work/log" || fail "--frames printed no per-frame table"
run "$work/smaller.toml" -o "$work/smaller.h5" --compare "$work/reference.h5"
code=$?
[ "$code" -ne 0 ] || fail "a reference of other particles was accepted"
grep -qF "$work/reference.h5" "$work/log" || fail "the error does not name the reference"
echo "run --compare: ok (mismatch exits $code)"
