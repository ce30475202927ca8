#!/usr/bin/env bash
# The README's test command: installs what is missing, builds, and runs every test with ctest.
# Tests labelled `gpu` run on a CUDA device when one answers and report "skipped" otherwise.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build_dir="${ROMP_BUILD_DIR:-$root/build}"

"$root/tools/setup.sh"
"$root/tools/build.sh" "$@"
ctest --test-dir "$build_dir" --output-on-failure -j "$(nproc)"
