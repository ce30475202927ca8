#!/usr/bin/env python3
"""Markdown table of romp-bench's rom suite: per setup (quadrature x projection x sample points) the wall
seconds per simulated second, the speed-up over the full-order run, the accumulated position error and
the milliseconds per substep of each stage of the reduced step.

    tools/rom_bench_table.py romp-bench-results/rom-XXXX.json [--place cpu1]
"""
import argparse
import json
import re

CASE = re.compile(r"^rom\.(lagrangian|eulerian)_(velocity|position)_(\w+?)\.(\w+?)\.(.+)$")
# ReducedSim's stages in the order a substep runs them; others follow in the order found.
PIPELINE = ["samples", "kinematics", "grid_build", "p2g", "grid_update", "g2p", "projection"]


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("json")
    parser.add_argument("--place", help="backend and threads as recorded, e.g. cpu1 (default: the first found)")
    args = parser.parse_args()
    records = json.load(open(args.json))["records"]
    cases, stages = {}, []
    for key, value in records.items():
        match = CASE.match(key)
        if not match:
            continue
        quadrature, projection, samples, place, quantity = match.groups()
        args.place = args.place or place
        if place != args.place:
            continue
        case = cases.setdefault((quadrature, projection, samples), {})
        if quantity.startswith("stage."):
            stage = quantity.split(".")[1]
            case.setdefault("stages", {})[stage] = value
            if stage not in stages:
                stages.append(stage)
        else:
            case[quantity] = value
    stages.sort(key=lambda stage: PIPELINE.index(stage) if stage in PIPELINE else len(PIPELINE))
    full = records.get(f"rom.full_order.{args.place}.wall_per_simulated_second")
    print(f"Full-order run: {full:.3g} wall s per simulated s ({args.place}).\n" if full else "", end="")
    columns = ["quadrature", "projection", "samples", "wall s per simulated s", "speed-up", "position error"]
    columns += [f"{s} (ms/substep)" for s in stages]
    print("| " + " | ".join(columns) + " |")
    print("|" + "---|" * len(columns))
    order = {"10": 0, "50": 1, "all": 2}
    for (quadrature, projection, samples), case in sorted(
            cases.items(), key=lambda item: (item[0][0] != "lagrangian", item[0][1] != "position",
                                             order.get(item[0][2], 9))):
        cells = [f"{case.get('stages', {}).get(s, float('nan')):.3g}" for s in stages]
        cells = [quadrature, projection, samples, f"{case['wall_per_simulated_second']:.3g}", f"{case['speedup']:.3g}",
                 f"{case['position_error_percent']:.3g} %"] + cells
        print("| " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
