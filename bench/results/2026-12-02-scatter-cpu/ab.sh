#!/usr/bin/env bash
# A/B: the torsion member 3 (2560 domain particles) on one thread, before (d2df90c) and after the Scatter change.
cd /work/main
for r in 1 2 3; do
  for v in before after; do
    bin=/tmp/romp-stable/romp; [ $v = after ] && bin=/tmp/romp-sr3/romp
    $bin --threads 1 run --no-progress runs/rom/paper/torsion/sweep/members/member_000003.toml -o /tmp/scatter_ab/$v-$r.h5 > /tmp/scatter_ab/$v-$r.log 2>&1
  done
done
