#!/usr/bin/env python3
"""Helper of scripts/bench/bags.sh.

  bags.py scenes DIR         writes DIR/four.raw (four objects side by side, labels 1-4, with a
                             3-voxel gap between neighbours) and two scenes of its voxels:
                             four.toml (one bag per label) and one.toml (one bag of all four labels)
  bags.py row CASE LOG WALL  prints CSV rows, one per bag, from a bop-server batch log
"""
import re
import sys

import numpy as np

SIZE = (72, 72, 30)  # x, y, z voxels of 1 mm
TARGETS = (95.0, 98.0, 99.5)  # % surface / volume in own voxels, % inside the bag


def four_objects():
    nx, ny, nz = SIZE
    z, y, x = np.indices((nz, ny, nx)) + 0.5
    img = np.zeros((nz, ny, nx), np.uint8)
    c = 15.0  # quadrant centres at 18 and 54 (x, y), z 15
    img[(x - 18) ** 2 + (y - 18) ** 2 + (z - c) ** 2 < 13 ** 2] = 1                      # ball
    img[((x - 54) / 15) ** 2 + ((y - 18) / 11) ** 2 + ((z - c) / 9) ** 2 < 1] = 2          # ellipsoid
    img[(abs(x - 18) < 11) & (abs(y - 54) < 13) & (abs(z - c) < 8)] = 3                    # box
    img[((x - 54) ** 2 + (y - 54) ** 2 < 12 ** 2) & (abs(z - c) < 11)] = 4                 # cylinder
    return img


def scenes(out):
    img = four_objects()
    img.tofile(f"{out}/four.raw")
    # Placed (the sheets counted over their faces, the default) and run until settled.
    dynamics = "[dynamics]\ntime_step = 0.02\nseed = 1\n[run]\nsteps = 20000\n"
    head = ("[grid]\npadding_voxels = 4\nr0_voxels = 2.0\n[shape]\nsmoothing_sigma_voxels = 1.5\n"
            "[[shape.bag]]\nsource = \"raw\"\nfile = \"four.raw\"\n"
            f"size_voxels = [{SIZE[0]}, {SIZE[1]}, {SIZE[2]}]\nspacing_mm = [1.0, 1.0, 1.0]\n")
    with open(f"{out}/four.toml", "w") as f:
        f.write(head + "labels = [1, 2, 3, 4]\nname = \"object\"\n" + dynamics)
    with open(f"{out}/one.toml", "w") as f:
        f.write(head + "label = [1, 2, 3, 4]\nname = \"all\"\n" + dynamics)
    for label in range(1, 5):
        print(f"label {label}: {int((img == label).sum())} voxels", file=sys.stderr)


def rows(case, log, wall):
    text = open(log).read()
    ready = re.search(r"ready in ([0-9.]+) s: ([0-9]+) particles", text)
    settled = re.search(r"settled at step ([0-9]+)", text)
    rate = re.search(r"this run\s+\d+\s+\d+\s+(\d+)\s+([0-9.]+)", text)
    common = [case, wall, ready.group(1) if ready else "", settled.group(1) if settled else "not settled",
              rate.group(1) if rate else "", rate.group(2) if rate else ""]
    bag = re.compile(r"bag '([^']+)': ([0-9.]+)% of its (\d+) surface particles in its surface voxels, "
                     r"([0-9.]+)% of its (\d+) volume particles in its volume voxels, ([0-9.]+)% of its particles")
    found = bag.findall(text)
    if not found:  # one bag: the run's own line
        m = re.search(r"shape fidelity: ([0-9.]+)% of surface particles in their surface voxels, "
                      r"([0-9.]+)% of volume", text)
        found = [("all", m.group(1), "", m.group(2), "", "")] if m else []
    for name, surf, ns, vol, nv, inside in found:
        met = float(surf) >= TARGETS[0] and float(vol) >= TARGETS[1] and (inside == "" or float(inside) >= TARGETS[2])
        print(",".join(common + [name, ns, nv, surf, vol, inside, "met" if met else "missed"]))


if __name__ == "__main__":
    if sys.argv[1] == "scenes":
        scenes(sys.argv[2])
    else:
        rows(*sys.argv[2:5])
