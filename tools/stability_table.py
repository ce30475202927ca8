#!/usr/bin/env python3
"""Markdown tables from the console output of `romp-bench --suite stability`: one row per model, E, nu
and scenario with a cell per variant (explicit or implicit, plain or enriched) that the output holds,
then the counts per variant.

    tools/stability_table.py bench/results/<session>/stability-output.txt

A cell reads "ok xr" (finished finite, largest energy after the reference r times the reference),
"budget at p" (the case's budget ran out at share p of its duration) or "stopped" (a NonFiniteError or
other error, with its step and stage).
"""
import collections
import re
import sys

CASE = re.compile(r"^(\S+)/E([^/]+)/nu([^/]+)/([^/]+)/(plain|enriched)/(explicit|implicit)\s+"
                  r"(finished|non-finite|error|substep budget|time budget)\s+t ([\d.]+)/([\d.]+) s\s+(\d+) substeps\s+"
                  r"energy x(\S+)\s+(?:enriched [\d.]+\s+)?([\d.]+) s\s+(ok|NOT OK)(.*)$")
ALL_VARIANTS = ["explicit plain", "explicit enriched", "implicit plain", "implicit enriched"]


def cell(status, simulated, duration, energy, acceptable, message):
    if status == "finished":
        return f"ok ×{float(energy):.2g}" if acceptable == "ok" else f"**energy ×{float(energy):.3g}**"
    if status in ("non-finite", "error"):
        step, stage = re.search(r"step (\d+)", message), re.search(r"stage (\w+)", message)
        return f"**stopped**: {status} at step {step.group(1) if step else '?'}, {stage.group(1) if stage else ''}"
    return f"budget at {float(simulated) / float(duration):.0%}"


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    rows, counts = collections.OrderedDict(), collections.Counter()
    with open(sys.argv[1]) as output:
        for line in output:
            match = CASE.match(line.rstrip("\n"))
            if not match:
                continue
            model, youngs, poisson, scenario, particles, integrator, status, t, end, _, energy, _, ok, message = match.groups()
            variant = f"{integrator} {particles}"
            rows.setdefault((model, youngs, poisson, scenario), {})[variant] = cell(status, t, end, energy, ok, message)
            kind = "finished" if status == "finished" else "stopped" if status in ("non-finite", "error") else "budget"
            counts[(variant, kind, ok)] += 1
    seen = {variant for cells in rows.values() for variant in cells}
    VARIANTS = [v for v in ALL_VARIANTS if v in seen]
    print("| model | E (Pa) | ν | scenario | " + " | ".join(VARIANTS) + " |")
    print("|---|---|---|---|" + "---|" * len(VARIANTS))
    for (model, youngs, poisson, scenario), cells in rows.items():
        print(f"| {model} | {youngs} | {poisson} | {scenario} | " + " | ".join(cells.get(v, "—") for v in VARIANTS) + " |")
    print()
    print("| variant | finished, energy ≤ 2× | finished, energy > 2× | stopped with a message | budget spent |")
    print("|---|---|---|---|---|")
    for v in VARIANTS:
        stopped = counts[(v, "stopped", "ok")] + counts[(v, "stopped", "NOT OK")]
        print(f"| {v} | {counts[(v, 'finished', 'ok')]} | {counts[(v, 'finished', 'NOT OK')]} | {stopped} | "
              f"{counts[(v, 'budget', 'ok')]} |")


if __name__ == "__main__":
    main()
