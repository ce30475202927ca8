#!/bin/sh
# Seconds per epoch, 4 epochs each, one thread; sequential so the runs do not share the CPU with each other.
set -e
out=runs/rom/timing
mkdir -p $out
for case in "gravity mlp_analytic 4 --derivatives analytic" "gravity mlp_autograd 4 --derivatives autograd" "gravity linear 4 --linear" \
            "torsion mlp_analytic 7 --derivatives analytic" "torsion mlp_autograd 7 --derivatives autograd" "torsion linear 7 --linear"; do
  set -- $case
  build-cpu/romp --threads 1 train-rom runs/rom/$1 -o $out/$1_$2.h5 --latent $3 $4 $5 --epochs 4 --report-every 1 --checkpoint-every 0 > $out/$1_$2.log 2>&1
done
