#!/usr/bin/python3
"""Where bop-haptic's scripted poke starts a sphere of R mm on a bag's top (docs/haptics.md):
prints `X,Y,Z DEPTH STANDOFF` in simulation lengths for --target, --depth and --standoff, the
target being the sphere's centre resting on the mean plane of the top sheet's particles within
R / 2 of the bag's axis (the plane Hertz's depth is measured from, as bop-material's first
contact), the depth and standoff given in mm.

  scripts/poke-target.py FINAL.xyz --radius-mm 8 --depth-mm 1.6 --standoff-mm 0.5
"""
import argparse
import sys

import ase.io
import numpy as np


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("xyz", help="extended XYZ of a run of a scene with materials (its LengthUnitMm)")
    ap.add_argument("--radius-mm", type=float, required=True, help="the probe sphere's radius, mm")
    ap.add_argument("--depth-mm", type=float, required=True, help="how far past first contact, mm")
    ap.add_argument("--standoff-mm", type=float, default=0.5, help="start this far above contact, mm")
    a = ap.parse_args()
    frame = ase.io.read(a.xyz)
    if "LengthUnitMm" not in frame.info:
        sys.exit(f"{a.xyz}: no LengthUnitMm in its header (a scene with materials writes it)")
    mm = frame.info["LengthUnitMm"]
    p = frame.get_positions()
    sheet = np.array(["surface" in t for t in frame.arrays["type"]])
    axis = p[:, :2].mean(axis=0)
    near = sheet & (np.linalg.norm(p[:, :2] - axis, axis=1) < 0.5 * a.radius_mm / mm)
    if not near.any():
        sys.exit(f"{a.xyz}: no surface particle within R / 2 of the bag's axis")
    top = p[near, 2].max()
    plane = p[near & (p[:, 2] > top - 3 ** 0.5), 2].mean()  # the top sheet: within r0 of its highest
    print(f"{axis[0]:.4f},{axis[1]:.4f},{plane + a.radius_mm / mm:.4f} {a.depth_mm / mm:.4f} {a.standoff_mm / mm:.4f}")


if __name__ == "__main__":
    main()
