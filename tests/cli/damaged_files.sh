#!/usr/bin/env bash
# A damaged or foreign HDF5 input (the reference snapshot of `romp run --compare`, a learned law of `--law`, a
# reduced-order model of `--rom`) makes romp exit 3 (invalid input) with a message naming the file: a flipped
# byte in its data or metadata (checksums), a truncated file, a text file, a file of another kind. Never exit
# 0, never a crash. A sweep manifest of the wrong form or content, for `train-rom`, likewise.
set -uo pipefail
romp="$1"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
source "$(dirname "$0")/cube_scene.sh"
write_cube_scene "$work/cube.toml" damaged_files_cube
run() { "$romp" --device cpu --threads 1 run --no-progress "$@" > "$work/log" 2>&1; }
fail() { echo "FAIL: $1"; cat "$work/log"; exit 1; }
run "$work/cube.toml" -o "$work/reference.h5" || fail "the reference run"
size=$(stat -c %s "$work/reference.h5")

# One bit flipped every 997 bytes of the second half (data and metadata alike).
cp "$work/reference.h5" "$work/flipped.h5"
python3 - "$work/flipped.h5" "$size" <<'PY'
import sys
path, size = sys.argv[1], int(sys.argv[2])
data = bytearray(open(path, "rb").read())
for offset in range(size // 2, size, 997):
    data[offset] ^= 0x10
open(path, "wb").write(bytes(data))
PY
head -c $((size / 2)) "$work/reference.h5" > "$work/truncated.h5"
cp "$work/cube.toml" "$work/foreign.h5"

# A romp HDF5 file of another kind: the shipped jelly law.
cp "$(dirname "$0")/../../scenes/nclaw/laws/jelly.h5" "$work/other_kind.h5"

for damaged in flipped truncated foreign other_kind; do
  run "$work/cube.toml" -o "$work/again_$damaged.h5" --compare "$work/$damaged.h5"
  code=$?
  [ "$code" -eq 3 ] || fail "$damaged reference: exit code $code, expected 3"
  grep -qF "$work/$damaged.h5" "$work/log" || fail "$damaged reference: the message does not name the file"
done
echo "damaged references: exit 3 each"

# A learned law or a reduced-order model that is another kind of file (here the snapshot) or damaged.
for input in "--law jelly=$work/reference.h5" "--law jelly=$work/truncated.h5" "--rom $work/reference.h5"; do
  run "$work/cube.toml" -o "$work/with_input.h5" $input
  code=$?
  [ "$code" -eq 3 ] || fail "$input: exit code $code, expected 3"
  grep -qF "$work/" "$work/log" || fail "$input: the message does not name the file"
done
echo "foreign and damaged law and model files: exit 3 each"

# A sweep folder for train-rom whose manifest is not one romp sweep writes: not JSON, of another format,
# listing no members, or a member whose snapshot is the damaged file.
sweep="$work/sweep"
mkdir -p "$sweep"
member='{"index": 0, "values": {}, "split": "train", "snapshot": "../flipped.h5"}'
for manifest in '{' '{"format": "romp-model", "format_version": 1}' \
    '{"format": "romp-sweep", "format_version": 1, "parameters": [], "members": []}' \
    "{\"format\": \"romp-sweep\", \"format_version\": 1, \"parameters\": [], \"members\": [$member]}"; do
  printf '%s' "$manifest" > "$sweep/manifest.json"
  "$romp" --device cpu --threads 1 train-rom "$sweep" -o "$work/model.h5" --epochs 1 > "$work/log" 2>&1
  code=$?
  [ "$code" -eq 3 ] || fail "train-rom, manifest $manifest: exit code $code, expected 3"
  grep -qF "$sweep" "$work/log" || fail "train-rom, manifest $manifest: the message does not name the sweep"
done
echo "unusable sweep manifests: exit 3 each"
