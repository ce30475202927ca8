#!/usr/bin/env bash
# Run on the lent GPU machine (device tool, carry [".device"]): builds romp against PyTorch's
# LibTorch and the packages tools/device_prepare.sh unpacked, runs the gpu-labelled tests and the
# benchmarks, and copies logs and benchmark records to $OUT.
#   tools/device_run.sh [romp-bench arguments...]     (default: all suites)
set -uo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
prefix="$root/.device/root/usr"
lib="$prefix/lib/x86_64-linux-gnu"
out="${OUT:-$root/device-out}"
build_dir="$root/build-device"
mkdir -p "$out"

if [ ! -d "$prefix" ]; then
  echo "device_run: $prefix is missing: run tools/device_prepare.sh here and carry .device" >&2
  exit 1
fi

# Symlinks made by device_prepare.sh point at the checkout path of the machine that made them.
find "$root/.device/root" -type l | while read -r link; do
  target="$(readlink "$link")"
  case "$target" in
    */.device/root/*) ln -sfn "$root/.device/root/${target#*/.device/root/}" "$link" ;;
  esac
done

export LD_LIBRARY_PATH="$lib:$lib/hdf5/serial${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
export PATH="/usr/local/cuda/bin:$PATH"
nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv | tee "$out/device.txt"

{
  cmake -S "$root" -B "$build_dir" -G Ninja -DCMAKE_BUILD_TYPE=Release \
    -DCMAKE_PREFIX_PATH="$prefix;$lib/cmake" \
    -DEigen3_DIR="$prefix/share/eigen3/cmake" \
    -DHDF5_C_COMPILER_EXECUTABLE= \
    -DHDF5_C_INCLUDE_DIR="$prefix/include/hdf5/serial" \
    -DHDF5_C_LIBRARY_hdf5="$lib/hdf5/serial/libhdf5.so" \
    && cmake --build "$build_dir" -j "$(nproc)"
} 2>&1 | tee "$out/build.log"
[ "${PIPESTATUS[0]}" -eq 0 ] || { echo "device_run: build failed (see build.log)"; exit 1; }

"$build_dir/romp" info 2>&1 | tee "$out/info.txt"
ctest --test-dir "$build_dir" -L gpu --output-on-failure 2>&1 | tee "$out/ctest-gpu.log"
tests_status=${PIPESTATUS[0]}
"$build_dir/romp-bench" --out "$out" --name bench-gpu "$@" 2>&1 | tee "$out/bench.log"
bench_status=${PIPESTATUS[0]}
exit $(( tests_status != 0 || bench_status != 0 ))
