#!/usr/bin/env python3
"""The rest-state error of the enriched-MPM paper's Table 1 for a romp snapshot: how far the body at a
frame (the last by default) is from its initial shape once the best rigid motion is taken out, as the
mean and the largest particle distance over the initial bounding-box diagonal.

    tools/rest_state_error.py runs/robust_twist_compress_release.h5 [--frame N] [--against M]

Alignment is Kabsch's: centroids matched, rotation U V^T from the SVD of the covariance. Needs
Debian's python3-h5py and python3-numpy; run it with /usr/bin/python3.
"""
import argparse
import sys

import h5py
import numpy as np


def positions(snapshot, frame):
    names = sorted(snapshot["frames"].keys())
    if not -len(names) <= frame < len(names):
        sys.exit(f"{snapshot.filename}: frame {frame} outside the {len(names)} frames written")
    return np.asarray(snapshot["frames"][names[frame]]["x"], dtype=np.float64), names[frame]


def rest_state_error(x, x0):
    """(mean, largest) distance of x from the rigidly best-aligned x0, over x0's bounding-box diagonal."""
    centred, centred0 = x - x.mean(axis=0), x0 - x0.mean(axis=0)
    u, _, vt = np.linalg.svd(centred.T @ centred0)
    rotation = u @ np.diag([1.0, 1.0, np.linalg.det(u @ vt)]) @ vt
    distance = np.linalg.norm(centred - centred0 @ rotation.T, axis=1)
    diagonal = np.linalg.norm(x0.max(axis=0) - x0.min(axis=0))
    return distance.mean() / diagonal, distance.max() / diagonal


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("snapshot")
    parser.add_argument("--frame", type=int, default=-1, help="the frame to measure (default: the last)")
    parser.add_argument("--against", type=int, default=0, help="the rest frame (default: the initial one)")
    args = parser.parse_args()
    with h5py.File(args.snapshot, "r") as snapshot:
        x, name = positions(snapshot, args.frame)
        x0, name0 = positions(snapshot, args.against)
    mean, largest = rest_state_error(x, x0)
    print(f"{args.snapshot}: frame {name} against frame {name0}: rest-state error {mean:.3e} (mean), "
          f"{largest:.3e} (largest), of the bounding-box diagonal")


if __name__ == "__main__":
    main()
