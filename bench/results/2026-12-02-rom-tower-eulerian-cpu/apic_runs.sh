#!/usr/bin/env bash
# APIC tower, Eulerian velocity-only, 10 samples, the 4 test members, two at a time, one thread each.
cd /work/main/runs/rom/paper-tower/apic-tower-dx0.024 || exit 1
run() {
  local m="$1" id; id=$(printf %06d "$m")
  OMP_WAIT_POLICY=passive /tmp/romp-efd --threads 1 run --no-progress "sweep/members/member_$id.toml" --rom mlp_r6.h5 \
    --quadrature eulerian --projection velocity --samples 10 -o "runs-fixed/mlp_r6-eulerian-velocity-s10-m$m.h5" \
    > "runs-fixed/mlp_r6-eulerian-velocity-s10-m$m.log" 2>&1
}
run 0 & run 5 & wait
run 11 & run 16 & wait
