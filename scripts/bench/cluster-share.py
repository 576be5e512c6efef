#!/usr/bin/python3
"""Useful share of a cluster-pair list on BoP's workloads: what a cluster-pair layout (GROMACS's
kind: clusters of M particles against clusters of N, every M x N pair computed in SIMD lanes, no
gathers) would compute for each pair in range, against BoP's Verlet list.

Clusters are made as GROMACS makes them: the box's x-y plane cut into columns holding about M
particles per unit of height, each column's particles sorted by z and taken M at a time (and N at
a time for the j side). A cluster pair is listed when the clusters' bounding boxes come within
the list range (cutoff + skin); a listed pair computes M x N pairs (a cluster with itself half of
them). The share is the pairs within the cutoff over the pairs computed, at the list range and
at the cutoff plus a small inner skin (GROMACS's dynamic pruning). The workloads: the bulk box of
step.sh (displaced fcc at r0, periodic) with the switched LJ cutoff 1.6 r0, and the oriented
terms' 3 r0 on the same lattice. Prints a table; writes out/bench/cluster-share.csv.

  scripts/bench/cluster-share.py [CELLS]   (fcc cells per edge, default 14: 10,976 particles)
"""
import csv
import math
import os
import sys

import numpy as np
from scipy.spatial import cKDTree

R0 = math.sqrt(3.0)  # BoP's length unit: r0 = sqrt(3)


def fcc_box(cells, seed=4242):
    a = math.sqrt(2.0) * R0
    basis = np.array([[0, 0, 0], [0.5, 0.5, 0], [0.5, 0, 0.5], [0, 0.5, 0.5]])
    g = np.stack(np.meshgrid(*[np.arange(cells)] * 3, indexing="ij"), -1).reshape(-1, 3)
    x = ((g[:, None, :] + basis[None, :, :]).reshape(-1, 3)) * a
    rng = np.random.default_rng(seed)
    x += rng.uniform(-0.05 * R0, 0.05 * R0, x.shape)
    side = cells * a
    return np.mod(x, side), side


def clusters(x, side, size):
    """Particle indices grouped size at a time: columns in x-y of about `size` particles per
    column cross-section's worth of height, sorted by z within each column."""
    n = len(x)
    density = n / side**3
    width = (size / density) ** (1.0 / 3.0)  # a cluster's edge, roughly cubic
    cols = max(1, int(side / width))
    cx = np.minimum((x[:, 0] / side * cols).astype(int), cols - 1)
    cy = np.minimum((x[:, 1] / side * cols).astype(int), cols - 1)
    order = np.lexsort((x[:, 2], cy, cx))
    col = (cx * cols + cy)[order]
    groups = []
    for c in np.unique(col):  # each column's particles, size at a time (its last cluster may be short)
        idx = order[col == c]
        groups += [idx[k:k + size] for k in range(0, len(idx), size)]
    return groups


def share(x, side, m, n, cutoff, rlist):
    ci, cj = clusters(x, side, m), clusters(x, side, n)
    lo_j = np.array([x[g].min(0) for g in cj])
    hi_j = np.array([x[g].max(0) for g in cj])
    centre_j = 0.5 * (lo_j + hi_j)
    reach_j = np.linalg.norm(hi_j - lo_j, axis=1).max() / 2
    tree = cKDTree(centre_j, boxsize=side)
    computed = in_range = 0
    for g in ci:
        lo, hi = x[g].min(0), x[g].max(0)
        c = 0.5 * (lo + hi)
        reach = np.linalg.norm(hi - lo) / 2
        for j in tree.query_ball_point(c, rlist + reach + reach_j):
            # bounding-box distance under the periodic box: the nearest image of j's box
            shift = np.round((centre_j[j] - c) / side) * side
            d = np.maximum(0, np.maximum(lo_j[j] - shift - hi, lo - (hi_j[j] - shift)))
            if np.linalg.norm(d) >= rlist:
                continue
            r = x[cj[j]][None, :, :] - x[g][:, None, :]
            r -= np.round(r / side) * side
            r2 = (r**2).sum(-1)
            same = np.equal.outer(g, cj[j])
            computed += m * n  # lanes, every ordered cluster pair (a half list halves both counts)
            in_range += int(((r2 < cutoff**2) & ~same).sum())
    return in_range / computed, computed, in_range


def main():
    if len(sys.argv) > 1 and sys.argv[1] in ("-h", "--help"):
        print(__doc__)
        return
    if len(sys.argv) > 1 and not sys.argv[1].isdigit():
        sys.exit(f"cluster-share: CELLS must be a whole number of fcc cells per edge (got '{sys.argv[1]}')")
    cells = int(sys.argv[1]) if len(sys.argv) > 1 else 14
    x, side = fcc_box(cells)
    rows = []
    print(f"{len(x)} particles, fcc at r0, displaced 0.05 r0; share = pairs within the cutoff / pairs computed")
    print(f"{'loop':<10} {'cutoff':>7} {'list':>7} {'M x N':>6} {'share':>7} {'computed per particle':>22}")
    for loop, cut in (("LJ", 1.6), ("oriented", 3.0)):
        for rlist, what in ((cut + 0.3, "+0.3"), (cut + 0.05, "+0.05")):
            for m, n in ((4, 4), (4, 8)):
                s, computed, inr = share(x, side, m, n, cut * R0, rlist * R0)
                rows.append([loop, cut, rlist, f"{m}x{n}", f"{s:.3f}", computed / len(x), inr / len(x)])
                print(f"{loop:<10} {cut:>5.2f}r0 {what:>7} {m}x{n:<4} {s:>7.3f} {computed / len(x):>22.1f}")
    os.makedirs("out/bench", exist_ok=True)
    with open("out/bench/cluster-share.csv", "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["loop", "cutoff_r0", "list_range_r0", "cluster", "useful_share", "computed_per_particle",
                    "in_range_per_particle"])
        w.writerows(rows)
    print("CSV: out/bench/cluster-share.csv")


if __name__ == "__main__":
    main()
