#!/usr/bin/env python3
"""How a run's deformation gradients drift from a reference run of the same scene, frame by frame: the
range of J = det F in both, the largest stretch anisotropy sigma_max / sigma_min of any particle's F in
both (rotation-free: 1 for F = J^(1/3) R), the smallest and largest singular values of the run's F, the
particle with the largest anisotropy, and the position MSE (m^2) against the reference. For a fluid the
reference resets F to J^(1/3) I, so an anisotropy that grows in the run says its (learned) plastic law
does not return F to its volume part. Reads partial outputs too (RUN.h5.partial of a run that stopped
non-finite).

    /usr/bin/python3 tools/deformation_drift.py RUN.h5 REFERENCE.h5 [--every N]
"""
import argparse

import h5py
import numpy as np


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("run")
    parser.add_argument("reference")
    parser.add_argument("--every", type=int, default=25, help="print every Nth frame (and the last five)")
    args = parser.parse_args()
    with h5py.File(args.run, "r") as run, h5py.File(args.reference, "r") as reference:
        frames = sorted(run["frames"].keys())
        missing = [k for k in frames if k not in reference["frames"]]
        if missing:
            raise SystemExit(f"{args.reference} lacks frame {missing[0]} of {args.run}")
        shown = sorted(set(frames[:: args.every] + frames[-5:]))
        print("frame   position MSE  J run [min, max]        J reference [min, max]  anisotropy run, reference  "
              "sigma [min, max]      particle")
        for k in shown:
            F, F_reference = run["frames"][k]["F"][:], reference["frames"][k]["F"][:]
            J, J_reference = np.linalg.det(F), np.linalg.det(F_reference)
            sigma = np.linalg.svd(F, compute_uv=False)
            sigma_reference = np.linalg.svd(F_reference, compute_uv=False)
            anisotropy = sigma[:, 0] / np.maximum(sigma[:, 2], 1e-30)
            anisotropy_reference = sigma_reference[:, 0] / np.maximum(sigma_reference[:, 2], 1e-30)
            mse = ((run["frames"][k]["x"][:] - reference["frames"][k]["x"][:]) ** 2).mean()
            print(f"{k}  {mse:10.3e}   [{J.min():9.3g}, {J.max():9.3g}]   [{J_reference.min():9.3g}, "
                  f"{J_reference.max():9.3g}]   {anisotropy.max():10.4g}, {anisotropy_reference.max():10.4g}   "
                  f"[{sigma.min():8.3g}, {sigma.max():8.3g}]  {anisotropy.argmax()}")


if __name__ == "__main__":
    main()
