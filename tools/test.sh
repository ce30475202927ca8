#!/usr/bin/env bash
# The README's test command: installs what is missing, builds, and runs every test with ctest.
# Tests labelled `gpu` run on a CUDA device when one answers and report "skipped" otherwise.
#
#   tools/test.sh [--torch-wheel] [CMake arguments...]
#
# --torch-wheel (what CI runs) builds and tests a second time, in build-torch-wheel/, against
# PyPI's CUDA build of LibTorch (tools/torch_wheel.sh), the LibTorch GPU machines use: it brings
# its own fmt headers, OpenMP runtime and CUDA libraries, which Debian's LibTorch does not.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build_dir="${ROMP_BUILD_DIR:-$root/build}"
torch_wheel=false
if [ "${1:-}" = "--torch-wheel" ]; then
  torch_wheel=true
  shift
fi

"$root/tools/setup.sh"
# A SASS reader for build.kernel_resources where the CUDA backend is built (found by CMake at configure).
if command -v nvcc >/dev/null 2>&1 || [ -x /usr/local/cuda/bin/nvcc ]; then
  ROMP_CUDA_BINUTILS="$("$root/tools/cuda_binutils.sh")"
  export ROMP_CUDA_BINUTILS
fi
"$root/tools/build.sh" "$@"
status=0
ctest --test-dir "$build_dir" --output-on-failure -j "$(nproc)" || status=$?

if $torch_wheel; then
  torch_dir="$("$root/tools/torch_wheel.sh")"
  wheel_build="$build_dir-torch-wheel"
  # sm_90 alone, as on the H200: this build checks LibTorch's wheel, not the architecture list.
  ROMP_BUILD_DIR="$wheel_build" "$root/tools/build.sh" -DTorch_DIR="$torch_dir" -DROMP_CUDA_ARCHITECTURES=90 "$@"
  echo "test: the suite against PyPI's LibTorch ($torch_dir)"
  # The README's example block (label docs) tests the command line, not LibTorch: the Debian build ran it.
  ctest --test-dir "$wheel_build" --output-on-failure -j "$(nproc)" -LE docs || status=$?
fi
exit "$status"
