#!/usr/bin/env bash
# Ctrl-C (SIGINT) stops `romp learn-law` after the epoch under way: exit 130, a message naming the
# checkpoint, no law file; `--resume` continues from that checkpoint's epoch.
set -uo pipefail
romp="$1"
scene="$2"  # one frame per substep: a learn-law ground truth
work="$(mktemp -d)"
trap 'kill "$pid" 2>/dev/null; rm -rf "$work"' EXIT
pid=""
fail() { echo "FAIL: $1"; cat "$work/log"; exit 1; }
"$romp" --device cpu --threads 1 run --no-progress "$scene" -o "$work/cube.h5" > "$work/log" 2>&1 ||
  fail "the ground-truth run"

# Trains (far more epochs than it gets) in the background until its log shows epoch $1, then sends SIGINT.
learn_until_epoch() {
  local epoch="$1"
  shift
  "$romp" --device cpu --threads 1 learn-law "$work/cube.h5" -o "$work/law.h5" --steps 10 --epochs 100000 "$@" \
    > "$work/log" 2>&1 &
  pid=$!
  for _ in $(seq 600); do
    grep -q "epoch $epoch/100000" "$work/log" && break
    sleep 0.1
  done
  grep -q "epoch $epoch/100000" "$work/log" || fail "no epoch $epoch within 60 s"
  kill -INT "$pid"
  for _ in $(seq 300); do
    kill -0 "$pid" 2>/dev/null || break
    sleep 0.1
  done
  kill -0 "$pid" 2>/dev/null && kill -KILL "$pid" && fail "still training 30 s after SIGINT"
  wait "$pid"
  code=$?
  pid=""
}

learn_until_epoch 1
[ "$code" -eq 130 ] || fail "the interrupted run exited $code, not 130"
grep -q "interrupted after epoch .*--resume (checkpoint $work/law.h5.checkpoint)" "$work/log" ||
  fail "no message naming the checkpoint"
[ -f "$work/law.h5.checkpoint" ] || fail "no checkpoint left"
[ ! -e "$work/law.h5" ] || fail "a law file was written by an interrupted run"
done_before="$(sed -n 's/.*interrupted after epoch \([0-9]*\);.*/\1/p' "$work/log")"

learn_until_epoch $((done_before + 1)) --resume
[ "$code" -eq 130 ] || fail "the resumed run exited $code, not 130"
grep -q "resumed $work/law.h5.checkpoint after epoch $done_before" "$work/log" ||
  fail "the resumed run did not start after epoch $done_before"
echo "learn-law interrupt: ok (stopped after epoch $done_before, resumed from it)"
