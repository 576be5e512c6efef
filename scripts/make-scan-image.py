#!/usr/bin/python3
"""Writes a synthetic multi-label abdominal scan with the difficulties of a real segmentation:
a NIfTI-1 label image (uint8) at 1 x 1 x 1.5 mm and its ITK-SNAP label table.

  scripts/make-scan-image.py [OUT_DIR] [--scale S]

writes OUT_DIR/scan.nii.gz and OUT_DIR/scan-labels.txt (OUT_DIR defaults to out/scan). --scale
(default 1.4, a scan of about 2.4e5 particles at r0 = 2 voxels) multiplies every length, and so
the particle count by about S^3.

What it holds, each as a segmentation tool leaves it (labels never share a voxel; later organs
win where shapes overlap, so organs touch along shared faces):
- 21 labels: liver, a hollow stomach whose wall is 1-3 voxels thick, spleen with a detached
  splenule, two kidneys with a notch, pancreas, gallbladder pressed into the liver, aorta
  branching into the iliac arteries, vena cava, four vertebrae, a thin branching vessel tree
  (tubes 1.5-2.5 mm in radius), two thin adrenal plates, the bases of both lungs and of the heart
  cut by the scan's top, the bladder, and specks (a lymph-node label of four blobs of about
  20-400 voxels);
- a label of a handful of voxels (label 23), too small for a bag;
- bumpy, staircase boundaries: each voxel takes the label at its centre, in slices 1.5 mm apart,
  every shape seen through a smooth displacement of about 1 mm.
"""
import argparse
import gzip
import os
import struct

import numpy as np

LABELS = [  # index, name, colour
    (1, "liver", (170, 70, 50)), (2, "stomach", (230, 190, 110)), (3, "spleen", (150, 60, 150)),
    (4, "kidney_right", (200, 120, 60)), (5, "kidney_left", (190, 110, 70)),
    (6, "pancreas", (240, 200, 120)), (7, "gallbladder", (90, 160, 60)), (8, "aorta", (220, 40, 40)),
    (9, "vena_cava", (60, 80, 200)), (10, "vertebra_L1", (235, 230, 210)),
    (11, "vertebra_L2", (225, 220, 200)), (12, "vertebra_L3", (215, 210, 190)),
    (13, "vertebra_L4", (205, 200, 180)), (14, "mesenteric_vessels", (180, 30, 90)),
    (15, "adrenal_right", (250, 160, 40)), (16, "adrenal_left", (240, 150, 30)),
    (17, "lung_right", (170, 200, 230)), (18, "lung_left", (160, 190, 220)),
    (19, "bladder", (230, 220, 90)), (20, "heart", (200, 60, 80)), (21, "lymph_nodes", (120, 200, 120)),
    (23, "marker", (255, 255, 255)),
]


# The stomach's box in unscaled mm (x, y, z), with room for the warp.
STOMACH_BOX = ((88, 148), (34, 78), (60, 108))


def build(scale, stomach_only=False):
    spacing = (1.0, 1.0, 1.5)  # mm: x, y, z (slices)
    size = [int(round(n * scale / s)) for n, s in zip((168, 136, 120), spacing)]
    # Voxel indices along x, y, z: the whole scan, or the stomach's box of it (the same voxels).
    index = [np.arange(n) for n in size]
    if stomach_only:
        index = [np.arange(int(lo * scale / s), min(n, int(np.ceil(hi * scale / s))))
                 for (lo, hi), n, s in zip(STOMACH_BOX, size, spacing)]
    z, y, x = np.meshgrid(*[(i + 0.5) * s / scale for i, s in zip(index[::-1], spacing[::-1])],
                          indexing="ij")  # voxel centres in unscaled mm
    # Bumpy boundaries, as a segmentation draws them: every organ sampled through one smooth
    # displacement of up to about 1 mm (waves 5-9 mm long before scaling, fixed phases), so organs
    # that touch still touch.
    rng = np.random.default_rng(7)
    warp = []
    for _ in range(3):
        d = np.zeros_like(x)
        for _ in range(4):
            k = rng.normal(size=3)
            k *= 2 * np.pi / rng.uniform(5, 9) / np.linalg.norm(k)
            d += 0.3 / scale * np.sin(k[0] * x + k[1] * y + k[2] * z + rng.uniform(0, 2 * np.pi))
        warp.append(d)
    x, y, z = x + warp[0], y + warp[1], z + warp[2]
    img = np.zeros(x.shape, np.uint8)

    def ellipsoid(c, r):
        return ((x - c[0]) / r[0]) ** 2 + ((y - c[1]) / r[1]) ** 2 + ((z - c[2]) / r[2]) ** 2 < 1

    def tube(a, b, r):  # a capsule from a to b of radius r
        a, b = np.array(a, float), np.array(b, float)
        d = b - a
        t = np.clip(((x - a[0]) * d[0] + (y - a[1]) * d[1] + (z - a[2]) * d[2]) / d.dot(d), 0, 1)
        return (x - a[0] - t * d[0]) ** 2 + (y - a[1] - t * d[1]) ** 2 + (z - a[2] - t * d[2]) ** 2 < r * r

    def paint(label, mask):
        img[mask] = label

    # The bases of the lungs and the heart, cut by the scan's top; the liver and stomach under them.
    paint(17, ellipsoid((50, 88, 150), (40, 38, 48)))
    paint(18, ellipsoid((120, 88, 152), (36, 38, 48)))
    paint(20, ellipsoid((92, 48, 142), (34, 28, 30)))
    paint(1, ellipsoid((52, 62, 82), (40, 34, 26)) | ellipsoid((88, 50, 90), (22, 18, 14)))
    # The stomach: a shell whose wall is 1.5-3.5 mm thick around the body's axis, empty inside.
    outer = ellipsoid((118, 56, 84), (26, 20, 22))
    t = (2.5 + 1.0 * np.sin(3 * np.arctan2(y - 56, x - 118))) / scale
    inner = ((x - 118) / (26 - t)) ** 2 + ((y - 56) / (20 - t)) ** 2 + ((z - 84) / (22 - t)) ** 2 < 1
    paint(2, outer & ~inner)
    if stomach_only:
        img[img != 2] = 0
        return img, list(spacing)
    paint(3, ellipsoid((142, 90, 80), (14, 20, 24)) | ellipsoid((150, 62, 66), (5, 5, 5)))  # a splenule
    notch = lambda cx: ellipsoid((cx, 98, 52), (5, 6, 8))
    paint(4, ellipsoid((44, 104, 52), (12, 14, 22)) & ~notch(56))
    paint(5, ellipsoid((132, 104, 54), (12, 14, 22)) & ~notch(120))
    paint(6, tube((68, 74, 62), (100, 78, 66), 8) | tube((100, 78, 66), (136, 84, 72), 6))
    paint(7, ellipsoid((62, 36, 68), (9, 9, 16)))
    paint(8, tube((92, 88, 34), (92, 88, 118), 8) | tube((92, 88, 34), (72, 84, 0), 5) | tube((92, 88, 34), (112, 84, 0), 5))
    paint(9, tube((74, 90, 10), (74, 90, 118), 9))
    for k, (lo, hi) in enumerate([(12, 34), (38, 60), (64, 86), (90, 112)]):
        body = (((x - 92) / 15) ** 2 + ((y - 114) / 12) ** 2 < 1) & (z > lo) & (z < hi)
        spine = (np.abs(x - 92) < 3) & (y > 122) & (y < 134) & (z > lo + 4) & (z < hi - 4)
        paint(10 + k, body | spine)
    mm = lambda v: v / scale  # thin parts keep their thickness at any scale
    paint(14, tube((88, 66, 30), (88, 66, 64), mm(2.5)) | tube((88, 66, 40), (66, 52, 28), mm(1.6))
          | tube((88, 66, 48), (112, 50, 36), mm(1.6)) | tube((88, 66, 56), (70, 46, 54), mm(1.5))
          | tube((88, 66, 40), (102, 40, 46), mm(2.0)) | tube((102, 40, 46), (118, 32, 40), mm(1.5)))
    paint(15, ellipsoid((54, 98, 80), (9, mm(1.6), 12)))
    paint(16, ellipsoid((124, 98, 82), (8, mm(1.6), 11)))
    paint(19, ellipsoid((92, 40, 16), (24, 20, 14)))
    for c, r in [((40, 40, 30), 2.0), ((140, 40, 28), 2.4), ((100, 120, 6), 3.0), ((60, 28, 40), 4.2)]:
        paint(21, ellipsoid(c, (mm(r), mm(r), mm(r))))
    paint(23, ellipsoid((20, 20, 10), (mm(1.2), mm(1.2), mm(1.2))))
    return img, list(spacing)


def write_nifti(path, img, spacing):
    nz, ny, nx = img.shape
    hdr = bytearray(348)
    struct.pack_into("<i", hdr, 0, 348)
    struct.pack_into("<8h", hdr, 40, 3, nx, ny, nz, 1, 1, 1, 1)
    struct.pack_into("<hh", hdr, 70, 2, 8)  # datatype: unsigned char, 8 bits
    struct.pack_into("<8f", hdr, 76, 1.0, *spacing, 1, 1, 1, 1)
    struct.pack_into("<fff", hdr, 108, 352.0, 1.0, 0.0)  # vox_offset, scl_slope, scl_inter
    hdr[123] = 2  # xyzt_units: mm
    hdr[148:148 + 40] = b"BoP synthetic scan (make-scan-image.py)".ljust(40, b"\0")
    struct.pack_into("<hh", hdr, 252, 0, 1)  # qform_code, sform_code: scanner
    for row, values in enumerate([(spacing[0], 0, 0, 0), (0, spacing[1], 0, 0), (0, 0, spacing[2], 0)]):
        struct.pack_into("<4f", hdr, 280 + 16 * row, *values)
    hdr[344:348] = b"n+1\0"
    with open(path, "wb") as raw, gzip.GzipFile(fileobj=raw, mode="wb", compresslevel=6, mtime=0) as f:
        f.write(bytes(hdr) + b"\0\0\0\0" + img.tobytes())  # x fastest, as NIfTI stores it


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("out_dir", nargs="?", default="out/scan")
    parser.add_argument("--scale", type=float, default=1.4, help="multiplies every length (default 1.4)")
    parser.add_argument("--stomach-only", action="store_true",
                        help="only the stomach, in its own box: a thin-walled organ whose walls keep their "
                             "1.5-3.5 mm at any scale")
    a = parser.parse_args()
    if not a.scale > 0:
        parser.error(f"--scale: expected a positive number, got {a.scale}")
    os.makedirs(a.out_dir, exist_ok=True)
    img, spacing = build(a.scale, a.stomach_only)
    write_nifti(os.path.join(a.out_dir, "scan.nii.gz"), img, spacing)
    with open(os.path.join(a.out_dir, "scan-labels.txt"), "w") as f:
        f.write("# ITK-SNAP Label Description File for scan.nii.gz (scripts/make-scan-image.py)\n")
        f.write('    0     0    0    0     0   0   0   "Clear Label"\n')
        for idx, name, (r, g, b) in LABELS:
            f.write(f'{idx:5d} {r:5d} {g:4d} {b:4d}     1   1   1   "{name}"\n')
    counts = np.bincount(img.ravel(), minlength=24)
    nz, ny, nx = img.shape
    print(f"scan.nii.gz: {nx} x {ny} x {nz} voxels of {spacing[0]:g} x {spacing[1]:g} x {spacing[2]:g} mm, "
          f"{sum(1 for k in range(1, 24) if counts[k])} labels")
    for idx, name, _ in LABELS:
        print(f"  label {idx:2d} {name:20s} {counts[idx]:8d} voxels")


if __name__ == "__main__":
    main()
