#!/usr/bin/env python3
"""Warps an SM (sm_90: 65,536 registers, 64 warps, 32 blocks, registers allocated 8 a thread) of every one-element
for_each kernel in build.kernel_resources' table, at 256 threads a block and at the best block size; prints those
that gain. Run from the checkout's root after the test:

    python3 bench/results/2026-12-07-loads-in-flight-cpu/occupancy.py build/kernel_resources.txt
"""
import re
import sys


def warps_per_sm(registers, block):
    warps = block // 32
    per_warp = (max(registers, 1) + 7) // 8 * 8 * 32
    return min(min(65536 // per_warp // warps, 32) * warps, 64)


rows = []
for line in open(sys.argv[1]):
    found = re.match(r"void romp::detail::for_each_kernel<256, 1, (.*?)>\(long.*\)\s+(\d+)\s+\d+\s+\d+", line)
    if found:
        rows.append((int(found.group(2)), found.group(1)))
gains = []
for registers, name in rows:
    at_256 = warps_per_sm(registers, 256)
    best, block = max((warps_per_sm(registers, b), -b) for b in range(32, 1025, 32))
    if best > at_256:
        gains.append((registers, at_256, best, -block, name))
for registers, at_256, best, block, name in sorted(gains):
    print(f"{registers:4d} registers  {at_256:2d} -> {best:2d} warps an SM (first at {block})  {name}")
print(f"{len(gains)} of {len(rows)} one-element kernels gain warps")
