#!/usr/bin/env python3
"""One particle's path through a run, beside a reference run of the same scene: its position, velocity
and speed frame by frame in both, and the run's fastest particle. Meant for the particle a non-finite
stop names ("stage p2g: particle N"); reads partial outputs (RUN.h5.partial of a run that stopped).

    /usr/bin/python3 tools/particle_track.py RUN.h5 PARTICLE [--reference REFERENCE.h5] [--every N]
"""
import argparse

import h5py
import numpy as np


def vector(values):
    return "(" + ", ".join(f"{value:7.3f}" for value in values) + ")"


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("run")
    parser.add_argument("particle", type=int)
    parser.add_argument("--reference", help="a run of the same scene and particles, e.g. the ground truth")
    parser.add_argument("--every", type=int, default=10, help="print every Nth frame (and the last five)")
    args = parser.parse_args()
    with h5py.File(args.run, "r") as run:
        reference = h5py.File(args.reference, "r") if args.reference else None
        count = int(run.attrs["particle_count"])
        if not 0 <= args.particle < count:
            raise SystemExit(f"{args.run}: particle {args.particle} is not in [0, {count})")
        frames = sorted(run["frames"].keys())
        shown = sorted(set(frames[:: args.every] + frames[-5:]))
        header = "frame   x run                        v run                        speed"
        if reference is not None:
            header += "   x reference                  speed reference"
        print(header + "   fastest in run (particle: speed)")
        for k in shown:
            x, v = run["frames"][k]["x"][:], run["frames"][k]["v"][:]
            speed = np.linalg.norm(v, axis=1)
            line = f"{k}  {vector(x[args.particle])}  {vector(v[args.particle])}  {speed[args.particle]:6.3f}"
            if reference is not None:
                if k not in reference["frames"]:
                    raise SystemExit(f"{args.reference} lacks frame {k} of {args.run}")
                x_reference = reference["frames"][k]["x"][args.particle]
                speed_reference = np.linalg.norm(reference["frames"][k]["v"][args.particle])
                line += f"   {vector(x_reference)}  {speed_reference:6.3f}"
            fastest = int(np.argmax(speed))
            print(line + f"   {fastest}: {speed[fastest]:.3f}")
        if reference is not None:
            reference.close()


if __name__ == "__main__":
    main()
