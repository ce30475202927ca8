#!/usr/bin/env bash
# The tracer baseline on a coarse run whose grid carries the whole body: each test member of
# `tools/rom_paper.sh super-resolution OUT` rerun with [solver] enrichment = 0 (no corner leaves the grid),
# the fine run's points carried by its grid velocity, compared with the fine run. Run from the checkout's
# root after rom_paper.sh has written OUT/torsion/superres/fine-m<index>.h5; prints "m<index> <error %>".
#   bench/results/2026-12-07-rom-superres-domains-cpu/grid_tracers_without_enrichment.sh runs/rom/paper-domain
set -euo pipefail
romp="${ROMP:-build/romp}"
torsion="$1/torsion"
mkdir -p "$torsion/superres-no-enrichment"
for m in 5 10 18 20 26 28 33; do  # the sweep's test members (sweep/test_members.txt)
  fine="$torsion/superres/fine-m$m.h5"
  scene="$torsion/superres-no-enrichment/member_$m.toml"
  sed 's/^enrichment = 0.6$/enrichment = 0.0/' "$torsion/sweep/members/$(printf 'member_%06d.toml' "$m")" > "$scene"
  grep -q '^enrichment = 0.0$' "$scene" || { echo "member $m: no enrichment line to change" >&2; exit 1; }
  out="$torsion/superres-no-enrichment/tracers-grid-m$m.h5"
  [ -f "$out" ] || "$romp" --threads 1 run --no-progress "$scene" --output-points "$fine" --tracers-by grid -o "$out" \
    > "${out%.h5}.log" 2>&1
  echo "m$m $("$romp" compare "$out" "$fine" | sed -n 's/.*accumulated position error \([^%]*\)%.*/\1/p')"
done
