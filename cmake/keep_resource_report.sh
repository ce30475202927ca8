#!/usr/bin/env bash
# CUDA compiler launcher (CMAKE_CUDA_COMPILER_LAUNCHER): runs the nvcc command line it is given and keeps
# ptxas's per-kernel resource report (--resource-usage: registers, stack frame, spills) beside the object,
# in OBJECT.resources, where tests/kernels/check_kernel_resources.py reads it. The report lines stay out
# of the build log; every other line nvcc writes to stderr (warnings, errors) is passed on.
set -uo pipefail
object=""
previous=""
for argument in "$@"; do
  [ "$previous" = "-o" ] && object="$argument"
  previous="$argument"
done

stderr_file="$(mktemp)"
trap 'rm -f "$stderr_file"' EXIT
"$@" 2>"$stderr_file"
status=$?
report='^ptxas info|^ +[0-9]+ bytes stack frame'
if [ -n "$object" ] && [ "$status" -eq 0 ]; then
  # Written whole under a temporary name, then renamed: a report is either complete or absent.
  grep -E "$report" "$stderr_file" >"$object.resources.tmp" || true
  mv -f "$object.resources.tmp" "$object.resources"
fi
grep -vE "$report" "$stderr_file" >&2 || true
exit "$status"
