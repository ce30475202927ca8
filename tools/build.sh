#!/usr/bin/env bash
# Configures and builds romp in build/ (or $ROMP_BUILD_DIR). Extra arguments go to CMake's
# configure step, e.g. tools/build.sh -DROMP_CUDA=OFF.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build_dir="${ROMP_BUILD_DIR:-$root/build}"

cmake -S "$root" -B "$build_dir" -G Ninja "$@"
cmake --build "$build_dir" -j "$(nproc)"
