#!/usr/bin/env python3
"""Checks the device kernels' resources, as ptxas reported them at build time, against their budgets.

Every CUDA compile of the build keeps ptxas's report beside its object (OBJECT.resources, written by
cmake/keep_resource_report.sh). This script reads those reports for one architecture, demangles the
kernel names, writes one table of every kernel (registers, stack frame, spills) to the report file, and
exits 1 when a kernel exceeds its budget or a budget names no kernel (a renamed kernel must not leave
its budget checking nothing).

    check_kernel_resources.py BUILD_DIR BUDGET_TOML REPORT [--arch sm_90] [--cuobjdump PATH]

The budget file (TOML) holds [[kernel]] tables: `match`, a substring of the demangled kernel name (every
kernel whose name holds it is checked), and the largest `registers`, `stack` (bytes of stack frame) and
`spills` (bytes of spill stores plus loads) allowed; a key left out is not checked. `loads_in_flight`, the
fewest allowed, is read from the kernel's SASS (cuobjdump, which then must be given): the longest run of
global loads with no global store or atomic between them, what a thread can have in flight at once before it
waits to store (a streaming kernel that loads one value and stores it before the next keeps one).
"""
import argparse
import pathlib
import re
import subprocess
import sys
import tomllib

ENTRY = re.compile(r"^ptxas info\s*: Compiling entry function '([^']+)' for '(sm_\d+a?)'")
FRAME = re.compile(r"^\s+(\d+) bytes stack frame, (\d+) bytes spill stores, (\d+) bytes spill loads")
REGISTERS = re.compile(r"^ptxas info\s*: Used (\d+) registers")


def parse_report(text, arch):
    """Kernels of `arch` in one report: {mangled name: {registers, stack, spills}}."""
    kernels, current = {}, None
    for line in text.splitlines():
        entry = ENTRY.match(line)
        if entry:
            current = entry.group(1) if entry.group(2) == arch else None
            if current:
                kernels[current] = {"registers": 0, "stack": 0, "spills": 0}
            continue
        if current is None:
            continue
        frame = FRAME.match(line)
        if frame:
            kernels[current]["stack"] = int(frame.group(1))
            kernels[current]["spills"] = int(frame.group(2)) + int(frame.group(3))
            continue
        registers = REGISTERS.match(line)
        if registers:
            kernels[current]["registers"] = int(registers.group(1))
            current = None  # the last line of a kernel's report
    return kernels


GLOBAL_LOAD = re.compile(r"\bLDG\.")
GLOBAL_STORE = re.compile(r"\b(STG|ATOMG|RED)\.")
FUNCTION = re.compile(r"^\s*Function : (\S+)")


def sass_functions(text):
    """{mangled name: its SASS lines} of one cuobjdump -sass listing."""
    functions, current = {}, None
    for line in text.splitlines():
        function = FUNCTION.match(line)
        if function:
            current = functions.setdefault(function.group(1), [])
        elif current is not None:
            current.append(line)
    return functions


def loads_in_flight(lines):
    """The longest run of global loads with no global store or atomic between them."""
    longest = run = 0
    for line in lines:
        if GLOBAL_STORE.search(line):
            run = 0
        elif GLOBAL_LOAD.search(line):
            run += 1
            longest = max(longest, run)
    return longest


def demangle(names):
    if not names:
        return {}
    result = subprocess.run(["c++filt"], input="\n".join(names), capture_output=True, text=True, check=True)
    return dict(zip(names, result.stdout.splitlines()))


def check(kernels, budgets):
    """The lines that say what exceeds its budget, and the budgets that match no kernel."""
    failures = []
    for budget in budgets:
        matched = [name for name in kernels if budget["match"] in name]
        if not matched:
            failures.append(f"budget '{budget['match']}' matches no kernel: update {budget['file']}")
        for name in matched:
            for key in ("registers", "stack", "spills"):
                if key in budget and kernels[name][key] > budget[key]:
                    failures.append(f"{name}: {key} {kernels[name][key]} > budget {budget[key]} "
                                    f"('{budget['match']}' in {budget['file']})")
            if "loads_in_flight" in budget and kernels[name].get("loads_in_flight", 0) < budget["loads_in_flight"]:
                failures.append(f"{name}: loads_in_flight {kernels[name].get('loads_in_flight', 0)} < budget "
                                f"{budget['loads_in_flight']} ('{budget['match']}' in {budget['file']})")
    return failures


def add_loads_in_flight(kernels, objects, budgets, cuobjdump, arch):
    """Adds `loads_in_flight` from the SASS of every kernel a budget asks it of (kernels: {demangled: usage};
    objects: {demangled: the object its report came from})."""
    asked = {name for budget in budgets if "loads_in_flight" in budget for name in kernels if budget["match"] in name}
    listings = {}
    for name in sorted(asked):
        obj = objects[name]
        if obj not in listings:
            listing = subprocess.run([cuobjdump, "-sass", "-arch", arch, str(obj)], capture_output=True, text=True,
                                     check=True).stdout
            functions = sass_functions(listing)
            demangled = demangle(sorted(functions))
            listings[obj] = {demangled[mangled]: lines for mangled, lines in functions.items()}
        kernels[name]["loads_in_flight"] = loads_in_flight(listings[obj].get(name, []))


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("build_dir", type=pathlib.Path)
    parser.add_argument("budget", type=pathlib.Path)
    parser.add_argument("report", type=pathlib.Path)
    parser.add_argument("--arch", default="sm_90")
    parser.add_argument("--cuobjdump", help="cuobjdump, for the budgets of loads_in_flight (tools/cuda_binutils.sh)")
    args = parser.parse_args()

    mangled, mangled_objects = {}, {}
    reports = sorted(args.build_dir.rglob("*.resources"))
    for path in reports:
        for name, usage in parse_report(path.read_text(), args.arch).items():
            mangled[name] = usage
            mangled_objects[name] = path.with_suffix("")
    if not mangled:
        print(f"no {args.arch} kernel in {len(reports)} resource reports under {args.build_dir}: "
              "was the build configured with the CUDA backend and that architecture?", file=sys.stderr)
        return 1
    names = demangle(sorted(mangled))
    kernels = {names[name]: usage for name, usage in mangled.items()}

    with open(args.budget, "rb") as budget_file:
        budgets = tomllib.load(budget_file).get("kernel", [])
    for budget in budgets:
        budget["file"] = str(args.budget)
    if any("loads_in_flight" in budget for budget in budgets):
        if not args.cuobjdump:
            print(f"{args.budget} budgets loads in flight, read from SASS: give --cuobjdump (tools/cuda_binutils.sh "
                  "prints where one is)", file=sys.stderr)
            return 1
        objects = {names[name]: obj for name, obj in mangled_objects.items()}
        add_loads_in_flight(kernels, objects, budgets, args.cuobjdump, args.arch)

    width = max(len(name) for name in kernels)
    lines = [f"# {args.arch}: registers, stack frame (bytes), spill stores + loads (bytes) from ptxas at build time; "
             "loads in flight from the SASS where budgeted",
             f"{'kernel':<{width}}  registers  stack  spills  loads_in_flight"]
    for name in sorted(kernels):
        usage = kernels[name]
        loads = str(usage["loads_in_flight"]) if "loads_in_flight" in usage else ""
        lines.append(f"{name:<{width}}  {usage['registers']:>9}  {usage['stack']:>5}  {usage['spills']:>6}  "
                     f"{loads:>15}")
    args.report.write_text("\n".join(lines) + "\n")

    failures = check(kernels, budgets)
    for failure in failures:
        print(failure, file=sys.stderr)
    print(f"{len(kernels)} {args.arch} kernels, {len(budgets)} budgets, {len(failures)} failures; "
          f"the table is in {args.report}")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
