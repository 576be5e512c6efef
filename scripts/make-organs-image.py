#!/usr/bin/env python3
"""Writes config/data/organs.raw: a small synthetic multi-label image (uint8, 56 x 40 x 36 voxels
of 1 mm, x fastest) for config/scenes/organs.toml. Label 1 (liver): a flattened ellipsoid; 2
(stomach) and 3 (spleen): ellipsoids pressed against it, sharing faces with it and each other;
4 (tumour): a ball inside the liver. Later labels win where shapes overlap, so organs touch."""
import sys

import numpy as np

nx, ny, nz = 56, 40, 36
z, y, x = np.mgrid[0:nz, 0:ny, 0:nx] + 0.5
img = np.zeros((nz, ny, nx), np.uint8)


def ellipsoid(c, r):
    return ((x - c[0]) / r[0]) ** 2 + ((y - c[1]) / r[1]) ** 2 + ((z - c[2]) / r[2]) ** 2 < 1


img[ellipsoid((20, 20, 18), (16, 14, 11))] = 1
img[ellipsoid((38, 20, 18), (10, 10, 9)) & (img == 0) | ellipsoid((38, 20, 18), (10, 10, 9)) & (x > 33)] = 2
img[ellipsoid((46, 26, 18), (7, 8, 8)) & (x > 42)] = 3
img[ellipsoid((16, 18, 18), (5, 5, 5))] = 4
out = sys.argv[1] if len(sys.argv) > 1 else "config/data/organs.raw"
img.tofile(out)
for label in range(1, 5):
    print(f"label {label}: {int((img == label).sum())} voxels")
