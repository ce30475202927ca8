#!/usr/bin/env bash
# The README's first command: installs what is missing, builds, and runs romp's main job.
# Until scene files exist the main job is `romp info` and the built-in thrown-cube MPM demo.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build_dir="${ROMP_BUILD_DIR:-$root/build}"

"$root/tools/setup.sh"
"$root/tools/build.sh" "$@"
"$build_dir/romp" info
"$build_dir/romp" demo
