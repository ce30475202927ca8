#!/usr/bin/env python3
"""The neural-law paper's metric per material: mean over the frames after the first of the position MSE
(m^2, over the material's particles and the three axes) of a run against a reference run of the same
scene (same particles, same frame times), as `romp compare` computes it over all particles.

    /usr/bin/python3 tools/position_mse_by_material.py RUN.h5 REFERENCE.h5
"""
import sys

import h5py
import numpy as np


def main(run_path, reference_path):
    with h5py.File(run_path, "r") as run, h5py.File(reference_path, "r") as reference:
        material = run["particles"]["material"][:]
        if not np.array_equal(material, reference["particles"]["material"][:]):
            sys.exit(f"{run_path} and {reference_path} hold different particles")
        frames = sorted(run["frames"].keys())
        if frames != sorted(reference["frames"].keys()):
            sys.exit(f"{run_path} and {reference_path} hold different frames")
        for m in np.unique(material):
            chosen = material == m
            mse = [((run["frames"][k]["x"][:][chosen] - reference["frames"][k]["x"][:][chosen]) ** 2).mean()
                   for k in frames[1:]]
            print(f"material {m}: {chosen.sum()} particles, mean position MSE {np.mean(mse):.4g} m^2 "
                  f"over {len(mse)} frames (last frame {mse[-1]:.4g} m^2)")


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2])
