#!/usr/bin/env python3
"""Plots romp-bench's rom suite as the ROM paper's Fig. 20: position error (%) against wall-clock seconds
per simulated second, one marker per quadrature x projection pair and sample count, with the real-time
line (1 s per simulated second) and the full-order run's line. Writes PNG and SVG beside each other.

    tools/plot_rom_bench.py romp-bench-results/bench-XXXX.json -o rom-tower [--place cpu2]

Needs Debian's python3-matplotlib (apt-get install python3-matplotlib); run it with /usr/bin/python3.
"""
import argparse
import json
import re
import sys

CASE = re.compile(r"^rom\.(lagrangian|eulerian)_(velocity|position)_(\w+)\.(\w+?)\.(wall_per_simulated_second|position_error_percent)$")
FULL = re.compile(r"^rom\.full_order\.(\w+?)\.wall_per_simulated_second$")
MARKERS = {("lagrangian", "position"): "o", ("lagrangian", "velocity"): "s",
           ("eulerian", "position"): "p", ("eulerian", "velocity"): "X"}


def read_cases(records, place):
    """{(quadrature, projection, samples): {"wall": s, "error": %}} and the full-order wall time, for `place`."""
    cases, full = {}, None
    for key, value in records.items():
        match = FULL.match(key)
        if match and match.group(1) == place:
            full = value
        match = CASE.match(key)
        if match and match.group(4) == place:
            quadrature, projection, samples, _, quantity = match.groups()
            entry = cases.setdefault((quadrature, projection, samples), {})
            entry["wall" if quantity == "wall_per_simulated_second" else "error"] = value
    return cases, full


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("report", help="romp-bench JSON report with a rom suite run")
    parser.add_argument("-o", "--output", required=True, help="output path without extension")
    parser.add_argument("--place", help="backend and threads as the records name them (cpu2, cuda0); default: the first")
    args = parser.parse_args()
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        sys.exit("plot_rom_bench: needs matplotlib: apt-get install python3-matplotlib, then run with /usr/bin/python3")

    with open(args.report) as f:
        records = json.load(f)["records"]
    places = sorted({m.group(1) for m in map(FULL.match, records) if m})
    if not places:
        sys.exit(f"plot_rom_bench: {args.report} holds no rom suite records (rom.full_order.*)")
    place = args.place or places[0]
    if place not in places:
        sys.exit(f"plot_rom_bench: no rom records for {place}; the report has {', '.join(places)}")
    cases, full = read_cases(records, place)

    figure, axes = plt.subplots(figsize=(6.4, 4.4))
    for (quadrature, projection), marker in MARKERS.items():
        points = sorted((v["wall"], v["error"], samples) for (q, p, samples), v in cases.items()
                        if q == quadrature and p == projection and "wall" in v and "error" in v)
        if not points:
            continue
        axes.scatter([w for w, _, _ in points], [e for _, e, _ in points], marker=marker, s=50,
                     label=f"{quadrature} quadrature, {projection} projection")
        for wall, error, samples in points:
            axes.annotate(samples, (wall, error), textcoords="offset points", xytext=(5, 4), fontsize=7)
    axes.axvline(1.0, color="green", linewidth=1.2, label="real time")
    axes.axvline(full, color="red", linewidth=1.2, label="full-order run")
    axes.set_xscale("log")
    axes.set_xlabel("wall-clock seconds per simulated second")
    axes.set_ylabel("accumulated position error (%)")
    axes.set_title(f"ROM error against run time ({place}); labels: sample points")
    axes.legend(fontsize=7)
    figure.tight_layout()
    for extension in ("png", "svg"):
        figure.savefig(f"{args.output}.{extension}", dpi=150)
    print(f"wrote {args.output}.png and {args.output}.svg")


if __name__ == "__main__":
    main()
