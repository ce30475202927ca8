#!/usr/bin/env python3
"""Shape measures of a romp snapshot's body at chosen frames: its extent along an axis, the largest
empty slab between consecutive particles along that axis (a torn body shows a gap of many particle
spacings, an intact one about its stretch times the spacing), its smallest principal stretch and its
range of det F.

    tools/body_extent.py runs/scene.h5 [--axis y] [--frames 0 20 -1] [--slabs MM]

--slabs MM also prints, per slab of MM millimetres across the axis (from the body's lowest point), the mean
stretch along the axis (F's diagonal entry): whether a body stretches evenly or necks before it tears.

Needs Debian's python3-h5py and python3-numpy; run it with /usr/bin/python3.
"""
import argparse
import sys

import h5py
import numpy as np


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("snapshot")
    parser.add_argument("--axis", choices="xyz", default="y")
    parser.add_argument("--frames", type=int, nargs="+", default=[0, -1], help="frame indices (negative: from the end)")
    parser.add_argument("--slabs", type=float, help="also the mean stretch along the axis per slab this many mm thick")
    args = parser.parse_args()
    if args.slabs is not None and not args.slabs > 0:
        sys.exit(f"--slabs: a thickness in mm > 0, got {args.slabs}")
    axis = "xyz".index(args.axis)
    with h5py.File(args.snapshot, "r") as snapshot:
        names = sorted(snapshot["frames"].keys())
        for frame in args.frames:
            if not -len(names) <= frame < len(names):
                sys.exit(f"{args.snapshot}: frame {frame} outside the {len(names)} frames written")
            group = snapshot["frames"][names[frame]]
            along = np.sort(np.asarray(group["x"])[:, axis])
            F = np.asarray(group["F"], dtype=np.float64)
            stretches = np.linalg.svd(F, compute_uv=False)
            J = np.linalg.det(F)
            print(f"frame {names[frame]}: extent along {args.axis} {1e3 * (along[-1] - along[0]):.2f} mm, largest gap "
                  f"{1e3 * np.diff(along).max():.2f} mm, smallest stretch {stretches.min():.3f}, "
                  f"det F in [{J.min():.3f}, {J.max():.3f}]")
            if args.slabs is not None:
                position = np.asarray(group["x"])[:, axis]
                slab = np.floor((position - position.min()) / (1e-3 * args.slabs)).astype(int)
                means = [F[slab == k, axis, axis].mean() for k in range(slab.max() + 1) if (slab == k).any()]
                print(f"  mean F_{args.axis}{args.axis} by {args.slabs:g} mm slab: " + " ".join(f"{m:.3f}" for m in means))


if __name__ == "__main__":
    main()
