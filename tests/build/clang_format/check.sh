#!/usr/bin/env bash
# The tree follows .clang-format: every tracked C++ and CUDA file is as clang-format 14 (Debian 12's, the
# version the tree is formatted with; other versions format differently) leaves it. Lists the files that
# are not, and how to fix them.
#   check.sh ROOT
set -uo pipefail
root="$1"
formatter="$(command -v clang-format-14 || true)"
if [ -z "$formatter" ]; then
  echo "skipped: clang-format-14 is not installed (tools/setup.sh installs it)"
  exit 0
fi
cd "$root" || exit 1
if ! git rev-parse --is-inside-work-tree > /dev/null 2>&1; then
  echo "skipped: $root is not a git work tree (the check formats the tracked files)"
  exit 0
fi
mapfile -t files < <(git ls-files '*.h' '*.cpp' '*.cu' '*.cuh')
unformatted=()
for file in "${files[@]}"; do
  [ -f "$file" ] || continue
  "$formatter" --style=file --dry-run -Werror "$file" > /dev/null 2>&1 || unformatted+=("$file")
done
if [ ${#unformatted[@]} -ne 0 ]; then
  printf 'not formatted: %s\n' "${unformatted[@]}"
  echo "${#unformatted[@]} of ${#files[@]} files differ from .clang-format; fix with: clang-format-14 -i FILE..."
  exit 1
fi
echo "${#files[@]} files follow .clang-format"
