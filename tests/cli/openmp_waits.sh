#!/usr/bin/env bash
# `romp` starts its program with OpenMP's idle threads sleeping (OMP_WAIT_POLICY=passive: libgomp's spin
# count 0) unless the user set OMP_WAIT_POLICY, and `romp info` says which (host/cli/launcher.cpp).
#
#   openmp_waits.sh ROMP
set -euo pipefail
romp="$1"

spin_count() {  # the spin count libgomp started with, from its own report
  env "$@" OMP_DISPLAY_ENV=verbose "$romp" --log-level warn info 2>&1 | sed -n "s/^ *GOMP_SPINCOUNT = '\([0-9]*\)'.*/\1/p"
}

default="$(spin_count -u OMP_WAIT_POLICY)"
[ "$default" = "0" ] || { echo "with OMP_WAIT_POLICY unset, libgomp spins $default times, not 0" >&2; exit 1; }
active="$(spin_count OMP_WAIT_POLICY=active)"
[ -n "$active" ] && [ "$active" != "0" ] || { echo "OMP_WAIT_POLICY=active was not kept (spin count '$active')" >&2; exit 1; }
env -u OMP_WAIT_POLICY "$romp" info | grep -q "OpenMP waits *passive (romp's default)" ||
  { echo "romp info does not report the passive default" >&2; exit 1; }
OMP_WAIT_POLICY=active "$romp" info | grep -q "OpenMP waits *active (OMP_WAIT_POLICY)" ||
  { echo "romp info does not report the user's policy" >&2; exit 1; }
echo "OpenMP waits: passive by default (spin count 0), the user's OMP_WAIT_POLICY kept (spin count $active)"
