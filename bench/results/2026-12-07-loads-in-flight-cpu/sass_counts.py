#!/usr/bin/env python3
"""Per kernel of an object's sm_90 SASS whose demangled name holds PATTERN: loads in flight (as build.kernel_resources
counts them), instructions, FP32 add/mul/FMA and MUFU instructions. Run from the checkout's root:

    python3 bench/results/2026-12-07-loads-in-flight-cpu/sass_counts.py CUOBJDUMP OBJECT PATTERN
"""
import re
import subprocess
import sys

sys.path.insert(0, "tests/kernels")
import check_kernel_resources as checker  # noqa: E402

cuobjdump, obj, pattern = sys.argv[1:4]
listing = subprocess.run([cuobjdump, "-sass", "-arch", "sm_90", obj], capture_output=True, text=True,
                         check=True).stdout
functions = checker.sass_functions(listing)
names = checker.demangle(sorted(functions))
for mangled, lines in functions.items():
    if pattern not in names[mangled]:
        continue
    ops = [line for line in lines if re.search(r"/\*[0-9a-f]{4}\*/", line)]
    fp32 = sum(1 for line in ops if re.search(r"\b(FFMA|FMUL|FADD)\b", line))
    mufu = sum(1 for line in ops if re.search(r"\bMUFU\.", line))
    print(f"loads_in_flight {checker.loads_in_flight(lines)}  instructions {len(ops)}  fp32 {fp32}  mufu {mufu}  "
          f"{names[mangled]}")
