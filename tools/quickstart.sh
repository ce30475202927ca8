#!/usr/bin/env bash
# The README's first command: installs what is missing, builds, and runs romp's main job: the
# default scene (scenes/default.toml), written to runs/default.h5 with a ParaView sidecar.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build_dir="${ROMP_BUILD_DIR:-$root/build}"

"$root/tools/setup.sh"
"$root/tools/build.sh" "$@"
"$build_dir/romp" info
cd "$root"
"$build_dir/romp" run
