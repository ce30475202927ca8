#!/usr/bin/env python3
"""Measures of the starter scenes (scenes/starter/) from a run's per-frame PLY point clouds.

    build/romp run scenes/starter/dam_break.toml -o /tmp/db.h5 --ply
    tools/starter_scene_check.py dam_break /tmp/db_ply [--set a=0.1 ...]

KIND is one of dam_break, granular_column_collapse, cantilever, colliding_bodies; PLY_DIR is the
`<output stem>_ply/` folder `romp run --ply` writes beside the snapshot (frame_NNNNNN.ply, binary, with
x, v and the material index of every particle, the frame's time in its header comment). The scene's
geometry is given by the same parameters the scene declares (--set NAME=VALUE, defaults as shipped).
Python 3 standard library only (the snapshot's HDF5 needs h5py, which this machine may not have).
Prints the measure and its reference, and with --csv FILE writes the per-frame series.
"""
import argparse
import math
import os
import re
import struct
import sys

G = 9.81


def read_ply(path):
    """(time, rows): rows are tuples (x, y, z[, vx, vy, vz][, material])."""
    with open(path, "rb") as f:
        data = f.read()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    header = data[:end].decode("ascii").splitlines()
    count, props, time = 0, [], float("nan")
    for line in header:
        parts = line.split()
        if parts[:2] == ["element", "vertex"]:
            count = int(parts[2])
        elif parts[0] == "property":
            props.append((parts[1], parts[2]))
        elif parts[0] == "comment":
            m = re.search(r"time (\S+)", line)
            if m:
                time = float(m.group(1))
    fmt = "<" + "".join("f" if t == "float" else "i" for t, _ in props)
    size = struct.calcsize(fmt)
    rows = [struct.unpack_from(fmt, data, end + i * size) for i in range(count)]
    return time, [name for _, name in props], rows


def frames(folder):
    names = sorted(n for n in os.listdir(folder) if re.fullmatch(r"frame_\d{6}\.ply", n))
    if not names:
        sys.exit(f"{folder}: no frame_NNNNNN.ply files (run with --ply)")
    for name in names:
        yield read_ply(os.path.join(folder, name))


def interp(table, t):
    for (t0, z0), (t1, z1) in zip(table, table[1:]):
        if t0 <= t <= t1:
            return z0 + (z1 - z0) * (t - t0) / (t1 - t0)
    return float("nan")


# Martin & Moyce 1952, Fig. 3, n^2 = 2, a = 2.25 in: (T = t sqrt(2g/a), Z = x/a), as digitised in
# PySPH (pysph/examples/db_exp_data.py, mm_data_2).
MARTIN_MOYCE = [(0.0, 1.0), (0.832, 1.217), (1.219, 1.474), (1.997, 2.292), (2.547, 2.995), (3.345, 4.134),
                (4.034, 4.944), (4.418, 5.881)]


def dam_break(folder, p, out):
    a, dx = p["a"], p["dx"]
    x0 = 3 * dx
    print(f"{'t s':>8} {'T':>6} {'Z romp':>7} {'Z M&M':>7} {'diff':>7}")
    out.append("t_s,T,Z_romp,Z_martin_moyce")
    for time, _, rows in frames(folder):
        # The front: the 99.9th percentile of x among particles (a few stray splash particles ignored).
        xs = sorted(r[0] for r in rows)
        front = xs[int(0.999 * (len(xs) - 1))]
        T = time * math.sqrt(2 * G / a)
        Z = (front - x0) / a
        ref = interp(MARTIN_MOYCE, T)
        print(f"{time:8.3f} {T:6.2f} {Z:7.3f} {ref:7.3f} {Z - ref:+7.3f}")
        out.append(f"{time:.4f},{T:.4f},{Z:.4f},{ref:.4f}")


def granular_column_collapse(folder, p, out):
    L0, H0, dx = p["L0"], p["H0"], p["dx"]
    x0 = 3 * dx
    last = None
    out.append("t_s,L_over_L0,H_over_L0,max_speed")
    print(f"{'t s':>8} {'L/L0':>7} {'H/L0':>7} {'max |v|':>8}")
    for time, names, rows in frames(folder):
        xs = sorted(r[0] for r in rows)
        ys = sorted(r[1] for r in rows)
        L = xs[int(0.999 * (len(xs) - 1))] - x0
        H = ys[-1] - 4 * dx  # the floor: the column's base, y = 4 dx
        vmax = max(math.sqrt(r[3] ** 2 + r[4] ** 2 + r[5] ** 2) for r in rows) if "vx" in names else float("nan")
        print(f"{time:8.3f} {L / L0:7.3f} {H / L0:7.3f} {vmax:8.4f}")
        out.append(f"{time:.4f},{L / L0:.4f},{H / L0:.4f},{vmax:.5f}")
        last = (L, H)
    a = H0 / L0
    runout = (last[0] - L0) / L0
    print(f"aspect ratio a = H0/L0 = {a:.3f}; final run-out (Linf - L0)/L0 = {runout:.3f}, final height Hinf/L0 = {last[1] / L0:.3f}")
    law = 1.2 * a if a < 1.8 else 1.9 * a ** (2 / 3)
    print(f"Lube et al. 2005 (2D): {'1.2 a' if a < 1.8 else '1.9 a^(2/3)'} = {law:.3f};  "
          f"band of channel experiments for small a: 1.2 a .. 1.6 a = {1.2 * a:.3f} .. {1.6 * a:.3f}")
    print(f"ratio romp / Lube = {runout / law:.3f}")


def cantilever(folder, p, out):
    L, h, dx, E, rho = p["L"], p["h"], p["dx"], p["E"], p["rho"]
    x_wall = p["x_wall"]
    delta_eb = 1.5 * rho * G * L ** 4 / (E * h ** 2)  # q L^4 / (8 E I), q = rho g b h, I = b h^3 / 12
    tip, y_init, series = None, None, []
    out.append("t_s,tip_deflection_m,tip_over_delta_EB")
    for time, _, rows in frames(folder):
        if tip is None:
            # The tip: the particles of the last particle layer (within half a particle spacing of the end).
            xmax = max(r[0] for r in rows)
            tip = [i for i, r in enumerate(rows) if r[0] > xmax - dx / 4]
            y_init = sum(rows[i][1] for i in tip) / len(tip)
        y = sum(rows[i][1] for i in tip) / len(tip)
        d = y_init - y
        series.append((time, d))
        out.append(f"{time:.5f},{d:.6e},{d / delta_eb:.4f}")
    print(f"{'t s':>8} {'tip mm':>8} {'/ EB':>6}")
    for time, d in series:
        print(f"{time:8.4f} {1e3 * d:8.3f} {d / delta_eb:6.3f}")
    # The mean over whole periods of the oscillation between rest and about twice the sag: from the
    # start (at rest, a turning point) to the last minimum, the final frame counting as one when the
    # deflection is still falling there (the scene ends on one). Trapezoidal in time.
    ds = [d for _, d in series]
    minima = [0] + [i for i in range(1, len(ds) - 1) if ds[i] <= ds[i - 1] and ds[i] < ds[i + 1]]
    if len(ds) > 1 and ds[-1] < ds[-2]:
        minima.append(len(ds) - 1)
    maxima = [i for i in range(1, len(ds) - 1) if ds[i] >= ds[i - 1] and ds[i] > ds[i + 1]]
    print(f"Euler-Bernoulli static tip deflection q L^4 / (8 E I) = {1e3 * delta_eb:.3f} mm ({100 * delta_eb / L:.2f} % of L)")
    period_eb = 2 * math.pi / (1.8751 ** 2 * math.sqrt(E * h * h / (12 * rho * L ** 4)))
    if len(minima) >= 2:
        i0, i1 = minima[0], minima[-1]
        area = sum((series[i + 1][0] - series[i][0]) * (ds[i] + ds[i + 1]) / 2 for i in range(i0, i1))
        mean = area / (series[i1][0] - series[i0][0])
        periods = len(minima) - 1
        period = (series[i1][0] - series[i0][0]) / periods
        print(f"mean tip deflection over {periods} period(s) (t = {series[i0][0]:.3f}..{series[i1][0]:.3f} s): "
              f"{1e3 * mean:.3f} mm = {mean / delta_eb:.3f} x EB")
        print(f"measured period {period:.4f} s; EB first mode {period_eb:.4f} s (ratio {period / period_eb:.3f})")
    print(f"maxima {', '.join(f'{1e3 * ds[i]:.3f}' for i in maxima)} mm; minima "
          f"{', '.join(f'{1e3 * ds[i]:.3f}' for i in minima)} mm")


def colliding_bodies(folder, p, out):
    rho = [p["rho_left"], p["rho_right"]]
    first = None
    out.append("t_s,px,py,pz,py_expected,v_left_x,v_right_x,gap_m")
    print(f"{'t s':>7} {'px':>10} {'py':>10} {'py exp':>10} {'vL x':>8} {'vR x':>8} {'gap mm':>8}")
    for time, names, rows in frames(folder):
        if "vx" not in names:
            sys.exit("colliding_bodies needs v in the snapshot's fields")
        # Equal volumes and particle counts: every particle of body k has mass rho_k V / N; report the
        # momentum per unit (V / N), i.e. in kg/m^3 * m/s summed over particles, then normalise by the
        # initial |px|.
        p_ = [0.0, 0.0, 0.0]
        mom = [[0.0, 0.0], [0.0, 0.0]]  # per body: sum m vx, sum m
        xs = [[], []]
        for r in rows:
            k = r[6]
            for c in range(3):
                p_[c] += rho[k] * r[3 + c]
            mom[k][0] += rho[k] * r[3]
            mom[k][1] += rho[k]
            xs[k].append(r[0])
        mass = mom[0][1] + mom[1][1]
        if first is None:
            first = (time, p_[:], mass)
        py_exp = first[1][1] - mass * G * (time - first[0])
        gap = min(xs[1]) - max(xs[0])
        vl, vr = mom[0][0] / mom[0][1], mom[1][0] / mom[1][1]
        print(f"{time:7.3f} {p_[0]:10.1f} {p_[1]:10.1f} {py_exp:10.1f} {vl:8.4f} {vr:8.4f} {1e3 * gap:8.2f}")
        out.append(f"{time:.4f},{p_[0]:.6e},{p_[1]:.6e},{p_[2]:.6e},{py_exp:.6e},{vl:.6f},{vr:.6f},{gap:.6f}")
        last = (p_, py_exp, vl, vr, gap)
    p0 = first[1]
    scale = abs(p0[0])
    print(f"x momentum: first {p0[0]:.2f}, last {last[0][0]:.2f}: relative change {(last[0][0] - p0[0]) / scale:+.2e}")
    print(f"y momentum vs p0 - M g t: last {last[0][1]:.2f} vs {last[1]:.2f}: difference / |px0| {(last[0][1] - last[1]) / scale:+.2e}")
    print(f"z momentum: last {last[0][2]:.3e} (/|px0| {last[0][2] / scale:+.2e})")
    print(f"after: left body vx {last[2]:+.4f} m/s, right body vx {last[3]:+.4f} m/s, gap {1e3 * last[4]:.1f} mm "
          f"({'apart' if last[4] > 0 and last[3] > last[2] else 'NOT apart'})")


DEFAULTS = {
    "dam_break": {"a": 0.1, "dx": 0.005},
    "granular_column_collapse": {"L0": 0.1, "H0": 0.1, "dx": 0.005},
    "cantilever": {"L": 0.15, "h": 0.015, "dx": 0.0025, "E": 1.1e7, "rho": 1000.0, "x_wall": 0.02},
    "colliding_bodies": {"rho_left": 1000.0, "rho_right": 1000.0},
}


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("kind", choices=sorted(DEFAULTS))
    parser.add_argument("ply_dir")
    parser.add_argument("--set", action="append", default=[], metavar="NAME=VALUE")
    parser.add_argument("--csv", help="write the per-frame series here")
    args = parser.parse_args()
    params = dict(DEFAULTS[args.kind])
    for item in args.set:
        name, value = item.split("=", 1)
        if name not in params:
            sys.exit(f"--set {name}: {args.kind} takes {', '.join(params)}")
        params[name] = float(value)
    out = []
    globals()[args.kind](args.ply_dir, params, out)
    if args.csv:
        with open(args.csv, "w") as f:
            f.write("\n".join(out) + "\n")


if __name__ == "__main__":
    main()
