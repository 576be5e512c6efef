#!/usr/bin/env python3
"""The targets of issue 35 checked on scripts/bench/bag.sh's CSV: each printed with its figure as
met or MISSED, or "not measured" where the CSV has no bag of that size. The default layout is
bop-server's without mpirun on two cores: 1 rank x 2 threads.

    bag_targets.py out/bench/bag.csv
"""
import csv
import math
import sys

DEFAULT = "1 rank x 2 threads"


def rows_by_size(path):
    sizes = {}
    with open(path, newline="") as f:
        for row in csv.DictReader(f):
            try:
                n = int(row["particles"])
                sizes.setdefault(n, {"built": float(row["construction_s"]), "rates": {}})
                sizes[n]["rates"][row["layout"]] = float(row["steps_per_s"])
                sizes[n]["settle"] = row.get("settle_steps", "")
            except (KeyError, ValueError) as e:
                raise SystemExit(f"{path}: a row without particles, construction_s, layout or steps_per_s ({e})")
    if not sizes:
        raise SystemExit(f"{path}: no rows")
    return sizes


def near(sizes, n, factor=1.5):
    """The bag nearest n particles (log scale) within `factor`, or None."""
    best = min(sizes, key=lambda k: abs(math.log(k / n)))
    return best if abs(math.log(best / n)) <= math.log(factor) else None


def verdict(ok):
    return "met" if ok else "MISSED"


def main(path):
    sizes = rows_by_size(path)
    lines = []
    for n, limit in ((10**6, 60.0), (10**5, 10.0)):
        k = near(sizes, n)
        if k is None:
            lines.append(f"built and settled, {n:.0e} particles, <= {limit:.0f} s: not measured")
            continue
        t = sizes[k]["built"]
        lines.append(f"built and settled, {k:,} particles, <= {limit:.0f} s: {t:.1f} s "
                     f"(settled at step {sizes[k]['settle']}) {verdict(t <= limit)}")
    for n, limit in ((10**6, 10.0), (10**5, 100.0)):
        k = near(sizes, n)
        if k is None or DEFAULT not in sizes[k]["rates"]:
            lines.append(f"steps/s, {n:.0e} particles, >= {limit:.0f}: not measured")
            continue
        rates = sizes[k]["rates"]
        r = rates[DEFAULT]
        best = max(rates, key=rates.get)
        lines.append(f"steps/s, {k:,} particles, >= {limit:.0f} ({DEFAULT}): {r:.1f} {verdict(r >= limit)}"
                     f" (fastest layout: {best}, {rates[best]:.1f})")
    one = {k: 1e9 / (v["rates"]["1 rank x 1 thread"] * k) for k, v in sizes.items() if "1 rank x 1 thread" in v["rates"]}
    if len(one) >= 2:
        lo, hi = min(one, key=one.get), max(one, key=one.get)
        spread = one[hi] / one[lo]
        lines.append(f"ns per particle-step at 1 thread within 1.3x over {min(one):,}..{max(one):,} particles: "
                     f"{one[lo]:.0f} ({lo:,}) to {one[hi]:.0f} ({hi:,}), {spread:.2f}x {verdict(spread <= 1.3)}")
    for k in sorted(sizes):
        rates = sizes[k]["rates"]
        if not {"1 rank x 1 thread", DEFAULT, "2 ranks x 1 thread"} <= rates.keys():
            continue
        gain = rates[DEFAULT] / rates["1 rank x 1 thread"]
        versus = rates[DEFAULT] / rates["2 ranks x 1 thread"]
        text = f"{k:,} particles: 2 threads / 1 thread {gain:.2f}x"
        if k >= 10**4:
            text += f" (>= 1.8: {verdict(gain >= 1.8)})"
        lines.append(text + f", 2 threads / 2 ranks {versus:.2f}x (>= 1: {verdict(versus >= 1.0)})")
    small = min(sizes)
    if DEFAULT in sizes[small]["rates"]:
        r = sizes[small]["rates"][DEFAULT]
        lines.append(f"smallest torus ({small:,} particles) >= 8,000 steps/s ({DEFAULT}): {r:.0f} {verdict(r >= 8000)}")
    print("targets (issue 35):")
    for line in lines:
        print("  " + line)


if __name__ == "__main__":
    if len(sys.argv) != 2 or sys.argv[1] in ("-h", "--help"):
        print(__doc__.strip())
        sys.exit(0 if len(sys.argv) == 2 else 2)
    main(sys.argv[1])
