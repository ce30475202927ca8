#!/usr/bin/env bash
# The CPU backend on a shared machine: romp-bench's step suite at small sizes on 1 and on 2 threads
# while another process keeps one core busy, then, per case, whether 2 threads were slower than 1.
# A benchmark, not a test: its numbers depend on the machine. Prints a table and leaves romp-bench's
# CSV and JSON in the output folder.
#
#   tools/cpu_contention_bench.sh [OUT_DIR] [romp-bench arguments...]
#
# Defaults: --scale 0.01 (the jelly cube and sand column at 1k and 10k particles), --repeats 5 --warmup 1.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bench="${ROMP_BENCH:-$root/build/romp-bench}"
out="${1:-runs/cpu-contention}"
shift || true
mkdir -p "$out"

# The other process: one core kept busy for as long as the benchmark runs.
sh -c 'while :; do :; done' &
busy=$!
trap 'kill "$busy" 2>/dev/null || true' EXIT INT TERM

stem="contention-$(date -u +%Y%m%d-%H%M%S)"
"$bench" --device cpu --suite step --threads 1 --threads 2 --scale 0.01 --repeats 5 --warmup 1 \
  --out "$out" --name "$stem" "$@"
kill "$busy" 2>/dev/null || true

/usr/bin/python3 - "$out/$stem.csv" <<'PY'
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
by_case = {}
for r in rows:
    by_case.setdefault(r["name"], {})[r["threads"]] = float(r["median_s"])
print(f"\n{'case (beside a busy process)':<40} {'1 thread (s)':>13} {'2 threads (s)':>14} {'2 / 1':>7}")
slower = 0
for name, t in sorted(by_case.items()):
    if "1" in t and "2" in t:
        ratio = t["2"] / t["1"]
        slower += ratio > 1.0
        print(f"{name:<40} {t['1']:>13.4g} {t['2']:>14.4g} {ratio:>7.2f}{'  slower' if ratio > 1.0 else ''}")
print(f"\n2 threads slower than 1 in {slower} of {len(by_case)} cases")
PY
