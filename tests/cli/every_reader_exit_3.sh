#!/usr/bin/env bash
# Every command-line slot that names a file romp reads, fed every kind of file it cannot use: a snapshot with
# flipped bits, truncated, cut after its header, a text file, an empty file, and romp files of the other kinds
# (a law, a ROM model, a run checkpoint, a run of another scene, a snapshot where a law or model is expected).
# Each must exit 3 (invalid input) naming the file; a folder or a missing path given to an option that takes
# an existing file is a bad argument (exit 2).
# The cases where the file is what the slot wants (a law for --law, a run for --compare) are skipped. Found this
# way: a model trained on another body, a run compared with a run of another scene, a learn-law trajectory
# whose scene the differentiable step cannot reproduce and a resume checkpoint of another run exited 1, as if
# the machine had failed.
set -uo pipefail
romp="$1"
root="$(cd "$(dirname "$0")/../.." && pwd)"
w="$(mktemp -d)"
trap 'rm -rf "$w"' EXIT
source "$(dirname "$0")/cube_scene.sh"
write_cube_scene "$w/cube.toml" every_reader_cube
sed -e 's/every_reader_cube/every_reader_other/' -e 's/0.06, 0.06, 0.06/0.08, 0.08, 0.08/' "$w/cube.toml" > "$w/other.toml"
R() { "$romp" --device cpu --threads 1 "$@" > "$w/log" 2>&1; }
fail() { echo "FAIL: $1"; cat "$w/log"; exit 1; }
R run --no-progress "$w/cube.toml" -o "$w/ref.h5" || fail "the reference run"
R run --no-progress "$w/other.toml" -o "$w/other_scene.h5" || fail "the other scene's run"
size=$(stat -c %s "$w/ref.h5")
python3 - "$w/ref.h5" "$w/flipped.h5" "$size" <<'PY'
import sys
source, target, size = sys.argv[1], sys.argv[2], int(sys.argv[3])
data = bytearray(open(source, "rb").read())
for offset in range(size // 2, size, 997):
    data[offset] ^= 0x10
open(target, "wb").write(bytes(data))
PY
head -c $((size / 2)) "$w/ref.h5" > "$w/truncated.h5"
head -c 200 "$w/ref.h5" > "$w/header_only.h5"
cp "$w/cube.toml" "$w/text.h5"
: > "$w/empty.h5"
mkdir "$w/folder.h5"
cp "$root/scenes/nclaw/laws/jelly.h5" "$w/law.h5"
cp "$root/tests/fuzz/corpus/model/model_mlp.h5" "$w/model.h5"
cp "$root/tests/fuzz/corpus/checkpoint/two_particles.checkpoint" "$w/checkpoint.h5"
cp "$w/ref.h5" "$w/snapshot.h5"

checked=0
for kind in flipped truncated header_only text empty law model checkpoint snapshot other_scene folder missing; do
  f="$w/$kind.h5"
  [ "$kind" = missing ] && f="$w/nothing_here.h5"
  for slot in run_compare run_law run_rom run_points run_resume compare_run compare_ref totals learn_law; do
    case "$slot:$kind" in
      # What the slot reads, or files it may read: not unusable there.
      run_law:law | run_compare:snapshot | run_points:snapshot | run_points:other_scene | compare_*:snapshot | \
      totals:snapshot | totals:other_scene) continue ;;
      # The other scene's run is refused only where it must be the same scene.
      run_law:other_scene | run_rom:other_scene | learn_law:other_scene) ;;
    esac
    rm -rf "$w/o.h5" "$w/o.h5".* "$w/law_out.h5"*
    case "$slot" in
      run_compare) R run --no-progress "$w/cube.toml" -o "$w/o.h5" --compare "$f" ;;
      run_law) R run --no-progress "$w/cube.toml" -o "$w/o.h5" --law "jelly=$f" ;;
      run_rom) R run --no-progress "$w/cube.toml" -o "$w/o.h5" --rom "$f" ;;
      run_points) R run --no-progress "$w/cube.toml" -o "$w/o.h5" --output-points "$f" ;;
      run_resume)
        # An interrupted run's partial output and checkpoint, both replaced by the file.
        [ -f "$f" ] || continue
        cp "$f" "$w/o.h5.partial" && cp "$f" "$w/o.h5.checkpoint"
        R run --no-progress "$w/cube.toml" -o "$w/o.h5" --resume ;;
      compare_run) R compare "$f" "$w/ref.h5" ;;
      compare_ref) R compare "$w/ref.h5" "$f" ;;
      totals) R totals "$f" ;;
      learn_law) R learn-law "$f" -o "$w/law_out.h5" --epochs 1 --steps 5 ;;
    esac
    code=$?
    expected=3
    # A path option checked by the command line (CLI11's existing-file check) is a bad argument; --law's NAME=FILE
    # is checked with the scene.
    if { [ "$kind" = folder ] || [ "$kind" = missing ]; } && [ "$slot" != run_law ]; then expected=2; fi
    [ "$code" -eq "$expected" ] || fail "$slot with $kind file: exit code $code, expected $expected"
    named="$f"
    [ "$slot" = run_resume ] && named="$w/o.h5."
    grep -qF "$named" "$w/log" || fail "$slot with $kind file: the message does not name $named"
    checked=$((checked + 1))
  done
done
echo "$checked unusable inputs: exit 3 (2 for folders and missing paths), each naming its file"
