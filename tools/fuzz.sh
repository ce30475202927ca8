#!/usr/bin/env bash
# Builds one libFuzzer harness of tests/fuzz with clang (ASan and UBSan on) and runs it.
#   tools/fuzz.sh TARGET WORK_DIR [libFuzzer options...]
# TARGET: formula (the scene formula evaluator), scene (the scene reader of `romp check`, libtoml++ built
# in), manifest (the sweep manifest that `romp train-rom` reads), law (a learned law's file, without
# LibTorch), model (a ROM model file, without LibTorch), snapshot (the snapshot reader and libhdf5 under it) or checkpoint (the run checkpoint reader of
# --resume).
# The run starts from the seed corpus tests/fuzz/corpus/TARGET (read only) and keeps what it finds in
# WORK_DIR/TARGET-corpus; a crash is written to WORK_DIR as crash-* and makes the script fail. ctest runs
# each target for a fixed count of executions from a fixed seed (deterministic); for a longer hunt:
#   tools/fuzz.sh snapshot build/fuzz -max_total_time=600
set -euo pipefail
target="$1"
work="$2"
shift 2
root="$(cd "$(dirname "$0")/.." && pwd)"
# Each target's sources besides its harness and kernels/core/error.cpp, and its compiler flags and libraries;
# kept: third-party code that tests/fuzz/NAME.cpp (NAME up to a '-VERSION') compiles, built once into
# WORK_DIR/NAME-VERSION.o and kept while newer than this script and its source (toml++: 13 s of each build).
kept=()
hdf5_layer=(nn/io/hdf5_file.cpp nn/io/versioned_file.cpp nn/io/atomic_file.cpp)
case "$target" in
  formula) sources=(host/scene/expression.cpp); flags=() ;;
  scene)
    # The parser checks that a law a scene names is a law file (nn/io). toml++ is compiled in
    # (toml_implementation.cpp, kept), not linked, so that its parser is instrumented like the rest; with
    # its assertions off, as Debian's libtomlplusplus (which romp links) is built: its parse_key asserts
    # what its callers do not check, and reports a syntax error where the assertion is off (README.md).
    sources=(host/scene/scene_parser.cpp host/scene/toml_reader.cpp host/scene/toml_writer.cpp
      host/scene/expression.cpp host/scene/sweep.cpp host/scene/named_materials.cpp nn/io/snapshot_layout.cpp
      "${hdf5_layer[@]}")
    kept=("toml_implementation-$(pkg-config --modversion tomlplusplus)")
    read -r -a flags <<< "-DTOML_HEADER_ONLY=0 -DTOML_ASSERT(condition)=(void)0 $(pkg-config --cflags --libs hdf5)" ;;
  manifest) sources=(nn/rom/sweep_manifest.cpp); flags=() ;;
  law)
    # The HDF5 half of the neural-law reader, which read_law_file loads into LibTorch modules of fixed shapes.
    sources=(nn/nclaw/law_file_content.cpp "${hdf5_layer[@]}")
    read -r -a flags <<< "$(pkg-config --cflags --libs hdf5)" ;;
  model)
    # The HDF5 half of the ROM model reader, which read_rom_model loads into LibTorch modules of those sizes.
    sources=(nn/rom/rom_model_file_content.cpp nn/rom/map_layout.cpp nn/rom/encoder_shape.cpp
      nn/rom/training_record.cpp "${hdf5_layer[@]}")
    read -r -a flags <<< "$(pkg-config --cflags --libs hdf5)" ;;
  snapshot | checkpoint)
    # The reader and the HDF5 layer under it (nn/io).
    sources=(nn/io/snapshot_layout.cpp "${hdf5_layer[@]}")
    [ "$target" = snapshot ] && sources+=(nn/io/snapshot_reader.cpp) || sources+=(nn/io/checkpoint.cpp)
    read -r -a flags <<< "$(pkg-config --cflags --libs hdf5)" ;;
  *) echo "fuzz: unknown target '$target' (formula, scene, manifest, law, model, snapshot, checkpoint)" >&2; exit 2 ;;
esac
# ROMP_FUZZ_FRESH=1 (ctest): start from the seeds alone, so that a run is the same every time.
[ "${ROMP_FUZZ_FRESH:-0}" = 1 ] && rm -rf "$work/$target-corpus"
mkdir -p "$work/$target-corpus"
binary="$work/${target}_fuzzer"
compile=(clang++ -std=c++17 -O1 -g -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=undefined -I.)
objects=()
defines=()
for flag in "${flags[@]}"; do [[ "$flag" == -[DI]* ]] && defines+=("$flag"); done
for name in "${kept[@]}"; do
  object="$work/$name.o"
  source="tests/fuzz/${name%%-*}.cpp"
  if [ ! -f "$object" ] || [ "$object" -ot "$root/tools/fuzz.sh" ] || [ "$object" -ot "$root/$source" ]; then
    (cd "$root" && "${compile[@]}" "${defines[@]}" -c "$source" -o "$object.partial") && mv "$object.partial" "$object"
  fi
  objects+=("$object")
done
(cd "$root" && "${compile[@]}" "tests/fuzz/${target}_fuzzer.cpp" "${sources[@]}" kernels/core/error.cpp \
  "${objects[@]}" "${flags[@]}" -lfmt -o "$binary")
cd "$work"
export LSAN_OPTIONS="suppressions=$root/tests/fuzz/lsan.supp:print_suppressions=0${LSAN_OPTIONS:+:$LSAN_OPTIONS}"
exec "$binary" -artifact_prefix="$work/${target}-" -print_final_stats=1 "$@" "$work/$target-corpus" \
  "$root/tests/fuzz/corpus/$target"
