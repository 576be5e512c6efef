#!/usr/bin/env python3
"""Cuts a served bag in two from Python: connects, sends a blade swept along a line through the
box's middle (along x at mid-height, crossing a ring-shaped bag's tube twice), lets the run go on,
then takes a frame and finds its pieces: particles closer than 1.2 r0 joined, the two largest
pieces' particle counts and the least distance between them (in r0).

    build/dynamics_server/bop-server config/scenes/torus-cut.toml --port 5555 &
    python3 python/examples/cut.py tcp://127.0.0.1:5555 --radius-r0 3.2 --seconds 8
"""
import argparse
import os
import sys
import time

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
import bop  # noqa: E402


def pieces(positions, link):
    """Connected pieces of points closer than `link`: a label per point (union-find over a grid)."""
    n = len(positions)
    parent = np.arange(n)

    def find(i):
        while parent[i] != i:
            parent[i] = parent[parent[i]]
            i = parent[i]
        return i

    cells = {}
    for i, key in enumerate(map(tuple, np.floor(positions / link).astype(np.int64))):
        cells.setdefault(key, []).append(i)
    for (cx, cy, cz), members in cells.items():
        near = [j for dx in (-1, 0, 1) for dy in (-1, 0, 1) for dz in (-1, 0, 1)
                for j in cells.get((cx + dx, cy + dy, cz + dz), [])]
        near = np.array(near)
        for i in members:
            d = np.linalg.norm(positions[near] - positions[i], axis=1)
            for j in near[d < link]:
                a, b = find(i), find(j)
                if a != b:
                    parent[a] = b
    return np.array([find(i) for i in range(n)])


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("endpoint", help="the server's control endpoint, tcp://HOST:PORT")
    ap.add_argument("--radius-r0", type=float, default=3.2, help="the blade's radius, r0")
    ap.add_argument("--seconds", type=float, default=8.0, help="how long the run goes on after the cut (s)")
    a = ap.parse_args()

    with bop.Client(a.endpoint, role="control") as c:
        s = c.scene
        lo, hi = np.asarray(s.box_lo, float), np.asarray(s.box_hi, float)
        mid = 0.5 * (lo + hi)
        start, end = np.array([lo[0], mid[1], mid[2]]), np.array([hi[0], mid[1], mid[2]])
        before = c.latest_frame()
        r = c.command("cut", start=start, end=end, radius=a.radius_r0 * s.r0)
        print(f"cut at step {r.step}: a blade of {a.radius_r0} r0 from {np.round(start, 3)} to {np.round(end, 3)}")
        t0 = time.monotonic()
        f = c.latest_frame()
        while time.monotonic() - t0 < a.seconds:  # the run goes on; frames are taken as they come
            f = c.latest_frame()
        labels = pieces(f.positions.astype(float), 1.2 * s.r0)
        names, counts = np.unique(labels, return_counts=True)
        order = np.argsort(counts)[::-1]
        print(f"before: {len(before)} particles; after {f.step - r.step} steps: {len(f)} particles in "
              f"{len(names)} pieces, the largest {counts[order[:4]].tolist()}")
        if len(names) >= 2:
            p0 = f.positions[labels == names[order[0]]].astype(float)
            p1 = f.positions[labels == names[order[1]]].astype(float)
            gap = min(np.linalg.norm(p1 - x, axis=1).min() for x in p0)
            print(f"the two largest pieces: {len(p0)} and {len(p1)} particles, {gap / s.r0:.3f} r0 apart at the closest")


if __name__ == "__main__":
    main()
