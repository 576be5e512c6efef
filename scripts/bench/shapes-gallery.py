#!/usr/bin/env python3
"""Helpers of scripts/bench/shapes-gallery.sh: synthetic shapes, scene files, one CSV row, the contact sheet.

  shapes-gallery.py synth DIR                         a thin plate, a frame (a hole), two balls (two pieces)
  shapes-gallery.py scene FILE SIZE STEPS DIR         DIR/scene.toml (torus settings; placed, or the torus
                                                      timeline when BOP_GALLERY_METHOD=birth) and DIR/fine.toml
  shapes-gallery.py row NAME SIZE DIR SECONDS NOTE FILE   one CSV row from DIR's logs and map
  shapes-gallery.py sheet DIR PNG                     every DIR/*/picture.png on one labelled sheet
"""
import math
import os
import re
import struct
import sys

import numpy as np

VOXEL_MM = 2.25  # the torus scene's voxel
R0_VOXELS = 2.0


def box(lo, hi, offset):
    """A closed box [lo, hi] as OBJ lines (vertex indices from offset + 1), outward."""
    v = [(hi[0] if c & 1 else lo[0], hi[1] if c & 2 else lo[1], hi[2] if c & 4 else lo[2]) for c in range(8)]
    quads = [(0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2), (1, 3, 7, 5)]
    lines = ["v %g %g %g" % p for p in v]
    for q in quads:
        a, b, c, d = (offset + i + 1 for i in q)
        lines += ["f %d %d %d" % (a, b, c), "f %d %d %d" % (a, c, d)]
    return lines


def write_nifti(path, labels, spacing):
    nz, ny, nx = labels.shape
    hdr = bytearray(348)
    struct.pack_into("<i", hdr, 0, 348)
    struct.pack_into("<8h", hdr, 40, 3, nx, ny, nz, 1, 1, 1, 1)
    struct.pack_into("<hh", hdr, 70, 2, 8)  # uint8
    struct.pack_into("<8f", hdr, 76, 1, spacing, spacing, spacing, 1, 1, 1, 1)
    struct.pack_into("<f", hdr, 108, 352)
    struct.pack_into("<B", hdr, 123, 2)  # mm
    hdr[344:348] = b"n+1\0"
    with open(path, "wb") as f:
        f.write(bytes(hdr) + b"\0" * 4 + labels.astype(np.uint8).tobytes())


def synth(d):
    os.makedirs(d, exist_ok=True)
    with open(f"{d}/thin-plate.obj", "w") as f:  # 60 x 60 x 6: a part 1/10 as thick as it is wide
        f.write("\n".join(box((0, 0, 0), (60, 60, 6), 0)) + "\n")
    lines = []  # a square frame of four bars that touch: a hole through the solid
    for lo, hi in [((0, 0, 0), (50, 12, 12)), ((0, 38, 0), (50, 50, 12)), ((0, 12, 0), (12, 38, 12)),
                   ((38, 12, 0), (50, 38, 12))]:
        lines += box(lo, hi, len([l for l in lines if l.startswith("v ")]))
    with open(f"{d}/frame.obj", "w") as f:
        f.write("\n".join(lines) + "\n")
    z, y, x = np.mgrid[0:40, 0:40, 0:80] + 0.5  # two balls 20 voxels apart: two pieces of one label
    balls = ((x - 20) ** 2 + (y - 20) ** 2 + (z - 20) ** 2 < 14 ** 2) | ((x - 60) ** 2 + (y - 20) ** 2 + (z - 20) ** 2 < 12 ** 2)
    write_nifti(f"{d}/two-balls.nii", balls.astype(np.uint8), 1.0)


def mesh_of(path):
    vs, fs = [], []
    for line in open(path):
        p = line.split()
        if not p:
            continue
        if p[0] == "v":
            vs.append([float(t) for t in p[1:4]])
        elif p[0] == "f":
            idx = [int(t.split("/")[0]) for t in p[1:]]
            idx = [i - 1 if i > 0 else len(vs) + i for i in idx]
            fs += [(idx[0], idx[k], idx[k + 1]) for k in range(1, len(idx) - 1)]
    return np.array(vs), np.array(fs)


def closed_volume(path):
    """The mesh's own volume in file units^3 when every edge is used once each way, else None."""
    v, f = mesh_of(path)
    edges = {}
    for t in f:
        for a, b in ((t[0], t[1]), (t[1], t[2]), (t[2], t[0])):
            edges[(a, b)] = edges.get((a, b), 0) + 1
    if any(edges.get((b, a), 0) != n for (a, b), n in edges.items()):
        return None
    a, b, c = v[f[:, 0]], v[f[:, 1]], v[f[:, 2]]
    return abs(np.einsum("ij,ij->i", a, np.cross(b, c)).sum() / 6.0)


def source_lines(path, size, voxel):
    if path.endswith(".nii"):
        return ['source = "nifti"', f'file = "{os.path.abspath(path)}"', "label = 1"]
    return ['source = "mesh"', f'file = "{os.path.abspath(path)}"', f"fit_voxels = {size}"]


def grid_voxel(path, size):
    if not path.endswith(".nii"):
        return VOXEL_MM
    labels = np.fromfile(path, np.uint8, offset=352).reshape(40, 40, 80)
    nz = np.nonzero(labels)
    extent = max(a.max() - a.min() + 1 for a in nz)  # voxels of 1 mm
    return extent / size


def scene(path, size, steps, d):
    size, steps = int(size), int(steps)
    torus = open(os.path.join(os.path.dirname(__file__), "../../config/scenes/torus.toml")).read()
    voxel = grid_voxel(path, size)
    body = re.sub(r'source = "mesh"\nfile = [^\n]*\nscale_mm = [^\n]*\n', "\n".join(source_lines(path, size, voxel)) + "\n", torus)
    body = body.replace("voxel_size_mm = 2.25", f"voxel_size_mm = {voxel!r}").replace("steps = 4000", f"steps = {steps}")
    body = body.replace('name = "torus"', f'name = "{os.path.basename(path).split(".")[0]}"')
    if os.environ.get("BOP_GALLERY_METHOD", "place") == "place":
        # No timeline: the bag is placed on its map and the run ends once it has settled.
        body = re.sub(r"# Build the bag.*?(?=# Oriented-particle)", "", body, flags=re.S)
        body = re.sub(r"\[run\]\nsteps = \d+\n", "", body)
    assert "fit_voxels" in body or "nifti" in body, "could not set the source in the torus scene"
    open(f"{d}/scene.toml", "w").write(body)
    fine = "\n".join(["[grid]", f"voxel_size_mm = {voxel / 2!r}", "r0_voxels = 4.0", "[shape]", "[[shape.bag]]"]
                     + source_lines(path, 2 * size, voxel / 2)) + "\n"
    open(f"{d}/fine.toml", "w").write(fine)


def surface_area(obj):
    """Area of a voxel object's boundary, voxel^2: each face between object and outside counts
    1 / (|n_x| + |n_y| + |n_z|), n the unit gradient of the object smoothed by a Gaussian of 1
    voxels (a plane of normal n shows |n_x| + |n_y| + |n_z| faces per unit of area)."""
    from scipy import ndimage
    padded = np.pad(obj.astype(np.float64), 2)
    g = np.gradient(ndimage.gaussian_filter(padded, 1.0))
    norm = np.sqrt(g[0] ** 2 + g[1] ** 2 + g[2] ** 2) + 1e-12
    l1 = (np.abs(g[0]) + np.abs(g[1]) + np.abs(g[2])) / norm
    area = 0.0
    for a in range(3):
        lo = [slice(None)] * 3
        hi = [slice(None)] * 3
        lo[a], hi[a] = slice(0, -1), slice(1, None)
        lo, hi = tuple(lo), tuple(hi)
        face = padded[lo] != padded[hi]
        weight = 0.5 * (l1[lo] + l1[hi])  # the normal at the face, between its two voxels
        area += float(np.sum(1.0 / np.maximum(weight[face], 1.0)))
    return area


def row(name, size, d, seconds, note, path):
    run = open(f"{d}/run.log").read()
    vol = lambda log: float(re.search(r"object volume ([0-9.]+) mL", open(log).read()).group(1))
    voxel_ml, fine_ml = vol(f"{d}/shape.log"), vol(f"{d}/fine.log")
    solid_ml = fine_ml
    own = closed_volume(path) if path.endswith(".obj") else None
    if own is not None:
        v, _ = mesh_of(path)
        scale = int(size) * VOXEL_MM / (v.max(axis=0) - v.min(axis=0)).max()
        solid_ml = own * scale ** 3 / 1000.0
    fid = re.search(r"shape fidelity: ([0-9.]+)% of surface.*?, ([0-9.]+)% of volume.*?median normal angle ([0-9.]+) deg", run)
    surface, volume, total = (int(x) for x in re.search(r"^this run\s+(\d+)\s+(\d+)\s+(\d+)", run, re.M).groups())
    so_far = [(int(b), int(dd)) for b, dd in re.findall(r"construction so far: (\d+) births, (\d+) deaths", run)]
    late = (so_far[-1][0] - so_far[-2][0]) + (so_far[-1][1] - so_far[-2][1]) if len(so_far) >= 2 else 0
    labels = np.load(f"{d}/map/labels.npy")
    area = surface_area(labels > 0)
    surface_ideal = area / (math.sqrt(3) / 2 * R0_VOXELS ** 2)
    volume_ideal = np.count_nonzero(labels == 2) / (R0_VOXELS ** 3 / math.sqrt(2))
    print(",".join(str(x) for x in [
        name, size, "accepted", f"{voxel_ml:.3f}", f"{solid_ml:.3f}", f"{voxel_ml / solid_ml:.4f}",
        surface, f"{surface_ideal:.0f}", volume, f"{volume_ideal:.0f}", fid.group(1), fid.group(2), fid.group(3),
        late, total, seconds, note]))


def sheet(d, png):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    cases = sorted(c for c in os.listdir(d) if os.path.exists(f"{d}/{c}/picture.png"))
    if not cases:
        print("shapes-gallery: no pictures", file=sys.stderr)
        return
    cols = 4
    rows = (len(cases) + cols - 1) // cols
    fig, axes = plt.subplots(rows, cols, figsize=(4 * cols, 4.2 * rows), squeeze=False)
    for ax in axes.flat:
        ax.axis("off")
    for ax, c in zip(axes.flat, cases):
        ax.imshow(plt.imread(f"{d}/{c}/picture.png"))
        fid = re.search(r"shape fidelity: ([0-9.]+)% of surface.*?([0-9.]+)% of volume", open(f"{d}/{c}/run.log").read())
        ax.set_title(f"{c}\nsurface {fid.group(1)}%, volume {fid.group(2)}% in their voxels", fontsize=9)
    fig.suptitle("BoP bags built from real and synthetic shapes (torus settings, r0 = 2 voxels)")
    fig.tight_layout()
    fig.savefig(png, dpi=80)


if __name__ == "__main__":
    cmd, args = sys.argv[1], sys.argv[2:]
    {"synth": synth, "scene": scene, "row": row, "sheet": sheet}[cmd](*args)
