#!/usr/bin/env python3
"""Plots scripts/bench/bag.sh's CSV: steps per second and ns per particle-step against the bag's
particle count, one line per layout (ranks x threads), log-log.

    plot-bag.py out/bench/bag.csv out/bench/bag.png
"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")  # no display: write the file only
import matplotlib.pyplot as plt  # noqa: E402


def main() -> int:
    if len(sys.argv) != 3 or sys.argv[1] in ("-h", "--help"):
        print(__doc__.strip())
        return 0 if len(sys.argv) == 2 else 2
    source, target = sys.argv[1], sys.argv[2]
    by_layout: dict[str, list[tuple[int, float, float]]] = {}
    with open(source, newline="") as f:
        for row in csv.DictReader(f):
            try:
                point = (int(row["particles"]), float(row["steps_per_s"]), float(row["ns_per_particle_step"]))
            except (KeyError, ValueError) as e:
                print(f"plot-bag: {source}: a row without particles, steps_per_s or ns_per_particle_step ({e})",
                      file=sys.stderr)
                return 1
            by_layout.setdefault(row["layout"], []).append(point)
    if not by_layout:
        print(f"plot-bag: {source}: no rows", file=sys.stderr)
        return 1
    fig, (rate, cost) = plt.subplots(1, 2, figsize=(11, 4.5))
    for layout, points in by_layout.items():
        points.sort()
        n = [p[0] for p in points]
        rate.plot(n, [p[1] for p in points], "o-", label=layout)
        cost.plot(n, [p[2] for p in points], "o-", label=layout)
    for ax, what in ((rate, "steps per second"), (cost, "ns per particle-step")):
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("particles in the built bag")
        ax.set_ylabel(what)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend()
    rate.set_title("torus bag, stepped from its built state")
    cost.set_title("cost per particle-step")
    fig.tight_layout()
    fig.savefig(target, dpi=100)
    print(f"plot-bag: {target}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
