#!/usr/bin/env python3
"""The Python client's frame decoding (python/bop/frames.py) against the C++ encoder: DIR holds
one frame encoded by the C++ codec as Float32 (f32.bin), Quantised16 (q16.bin) and Compact8
(c8.bin) chunks, with ids, and bounds.txt the stated bounds (per-axis position error, the two
normal angles in rad). Every particle is matched by id: species equal, Float32 positions and
normals exact (as float32), the quantised ones within their bounds. Prints 'decode ok' and
exits 0, or says what differs and exits 1.
Usage: decode_check.py DIR SOURCE_DIR"""
import os
import sys

import numpy as np

d, src = sys.argv[1], sys.argv[2]
sys.path.insert(0, os.path.join(src, "python"))
import bop  # noqa: E402

bound = [float(x) for x in open(os.path.join(d, "bounds.txt")).read().split()]
pos_bound, angle16, angle8 = np.array(bound[:3]), bound[3], bound[4]
raw = np.fromfile(os.path.join(d, "raw.f32"), dtype=np.float32).reshape(-1, 6)  # C++'s own float32 arrays


def frame(name):
    assembler, whole = bop.FrameAssembler(), None
    with open(os.path.join(d, name), "rb") as f:
        blob = f.read()
    at = 0
    while at < len(blob):
        n = int.from_bytes(blob[at:at + 4], "little")
        whole = assembler.add(bop.decode_frame(blob[at + 4:at + 4 + n])) or whole
        at += 4 + n
    return whole


f32, q16, c8 = frame("f32.bin"), frame("q16.bin"), frame("c8.bin")
fails = []
order = np.argsort(f32.ids)
if not np.array_equal(f32.positions, raw[:, :3]) or not np.array_equal(f32.normals, raw[:, 3:]):
    fails.append("Float32 arrays differ from the encoder's")
for name, g, angle in (("Quantised16", q16, angle16), ("Compact8", c8, angle8)):
    o = np.argsort(g.ids)
    if not np.array_equal(g.ids[o], f32.ids[order]):
        fails.append(f"{name}: other ids")
        continue
    if not np.array_equal(g.species[o], f32.species[order]):
        fails.append(f"{name}: species differ")
    err = np.abs(g.positions[o].astype(float) - f32.positions[order].astype(float)).max(axis=0)
    if np.any(err > pos_bound):
        fails.append(f"{name}: position error {err} beyond {pos_bound}")
    a, b = g.normals[o].astype(float), f32.normals[order].astype(float)
    worst = np.arctan2(np.linalg.norm(np.cross(a, b), axis=1), np.sum(a * b, axis=1)).max()  # arccos loses small angles
    if worst > angle:
        fails.append(f"{name}: normal off by {worst} rad, bound {angle}")
    print(f"{name}: {len(g)} particles, worst position error {err}, worst normal angle {worst:.3g} rad")
if fails:
    print("\n".join(fails))
    sys.exit(1)
print("decode ok")
