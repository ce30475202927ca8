#!/usr/bin/env bash
# Builds one libFuzzer harness of tests/fuzz with clang (ASan and UBSan on) and runs it.
#   tools/fuzz.sh TARGET WORK_DIR [libFuzzer options...]
# TARGET: formula (the scene formula evaluator), snapshot (the snapshot reader and libhdf5 under it) or
# checkpoint (the run checkpoint reader of --resume).
# The run starts from the seed corpus tests/fuzz/corpus/TARGET (read only) and keeps what it finds in
# WORK_DIR/TARGET-corpus; a crash is written to WORK_DIR as crash-* and makes the script fail. ctest runs
# each target for a fixed count of executions from a fixed seed (deterministic); for a longer hunt:
#   tools/fuzz.sh snapshot build/fuzz -max_total_time=600
set -euo pipefail
target="$1"
work="$2"
shift 2
root="$(cd "$(dirname "$0")/.." && pwd)"
case "$target" in
  formula) sources=(host/scene/expression.cpp); libraries=() ;;
  snapshot | checkpoint)
    # The reader and the HDF5 layer under it (nn/io).
    sources=(nn/io/snapshot_layout.cpp nn/io/hdf5_file.cpp nn/io/versioned_file.cpp nn/io/atomic_file.cpp)
    [ "$target" = snapshot ] && sources+=(nn/io/snapshot_reader.cpp) || sources+=(nn/io/checkpoint.cpp)
    read -r -a libraries <<< "$(pkg-config --cflags --libs hdf5)" ;;
  *) echo "fuzz: unknown target '$target' (formula, snapshot, checkpoint)" >&2; exit 2 ;;
esac
# ROMP_FUZZ_FRESH=1 (ctest): start from the seeds alone, so that a run is the same every time.
[ "${ROMP_FUZZ_FRESH:-0}" = 1 ] && rm -rf "$work/$target-corpus"
mkdir -p "$work/$target-corpus"
binary="$work/${target}_fuzzer"
(cd "$root" && clang++ -std=c++17 -O1 -g -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=undefined \
  -I. "tests/fuzz/${target}_fuzzer.cpp" "${sources[@]}" kernels/core/error.cpp "${libraries[@]}" -lfmt \
  -o "$binary")
cd "$work"
export LSAN_OPTIONS="suppressions=$root/tests/fuzz/lsan.supp:print_suppressions=0${LSAN_OPTIONS:+:$LSAN_OPTIONS}"
exec "$binary" -artifact_prefix="$work/${target}-" -print_final_stats=1 "$@" "$work/$target-corpus" \
  "$root/tests/fuzz/corpus/$target"
