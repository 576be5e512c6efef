#!/usr/bin/env python3
"""BoP's plots, drawn with matplotlib from the CSV files the tools write: axes with ticks, values,
units and a legend. The C++ tools call this file after writing their CSV (bop-haptic's
stiffness.png, the ventricle run's pressure.png); the benchmarks call it too.

    plots.py stiffness stiffness.csv stiffness.png
    plots.py pressure pressure-cycle.csv volume-cycle.csv pressure.png
    plots.py bag bag.csv bag.png

Each function returns the matplotlib Figure it saved (tests/python/test_plots.py reads its axes).
Needs python3-matplotlib and python3-numpy.
"""
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")  # no display: files only
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.ticker import FuncFormatter  # noqa: E402

PLAIN = FuncFormatter(lambda v, _: f"{v:g}")  # 200, 1e+04: not 2 x 10^2 on a log axis


def _save(fig, png_path):
    """Writes the PNG under a temporary name and renames it: the file is whole once it exists."""
    tmp = png_path + ".partial.png"
    fig.savefig(tmp, dpi=100)
    os.replace(tmp, png_path)


def _read(path, *columns):
    """Columns of a CSV file as float arrays; ValueError naming the file and column when absent."""
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    out = []
    for c in columns:
        try:
            out.append(np.array([float(r[c]) for r in rows]))
        except (KeyError, ValueError) as e:
            raise ValueError(f"{path}: column '{c}' missing or not a number ({e})") from e
    return out


def stiffness(csv_path, png_path):
    """Force felt against depth past the surface (bop-haptic --device sim:poke), with the
    stiffness fitted as a line through the origin over the first half of the depths: in N against
    mm for a scene with materials (columns depth_mm, force_n), else in simulation units."""
    with open(csv_path, newline="") as f:
        physical = "force_n" in (f.readline().strip().split(","))
    if physical:
        depth, force, samples = _read(csv_path, "depth_mm", "force_n", "samples")
        length, force_unit, stiffness_unit = "mm", "N", "N/mm"
    else:
        depth, force, samples = _read(csv_path, "depth", "force", "samples")
        length, force_unit, stiffness_unit = "simulation length", "simulation force", "force / length"
    fig, ax = plt.subplots(figsize=(7, 4.5))
    ax.plot(depth, force, "o-", ms=3, color="#c8401e", label=f"mean force felt in each depth bin ({int(samples.sum())} ticks)")
    half = depth <= 0.5 * depth.max() if len(depth) else depth
    if np.count_nonzero(half) >= 2 and np.dot(depth[half], depth[half]) > 0:
        k = float(np.dot(depth[half], force[half]) / np.dot(depth[half], depth[half]))
        ax.plot(depth[half], k * depth[half], "--", color="#555555",
                label=f"stiffness fit: {k:.3g} {stiffness_unit} (first half of the depths)")
    ax.axhline(0, color="#999999", lw=0.8)
    ax.set_xlabel(f"depth past the surface ({length})")
    ax.set_ylabel(f"force felt along the poke ({force_unit})")
    ax.set_title("Haptic poke: force against depth")
    ax.grid(True, alpha=0.3)
    ax.legend(loc="upper left")
    fig.tight_layout()
    _save(fig, png_path)
    return fig


def pressure(cycle_csv, volume_csv, png_path):
    """One averaged cardiac cycle (the ventricle run): the blood's pressure over a typical
    left-ventricular curve, and the cavity volume from the voxels and from the particles with
    the run's ejection fractions (from every frame, not from these phase-binned means)."""
    phase, fit, typical = _read(cycle_csv, "phase", "pressure_fit_mmhg", "typical_mmhg")
    vphase, cavity, particles, ef_voxels, ef_particles = _read(volume_csv, "phase", "cavity_ml", "particle_ml",
                                                               "ef_voxels", "ef_particles")
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(8.6, 6.8), gridspec_kw={"height_ratios": [2, 1]})
    top.plot(phase, typical, color="#787878", lw=2, label="typical left ventricle")
    top.plot(phase, fit, color="#c8321e", lw=2, label="bag of particles (spline, scaled to the peak)")
    top.set_xlabel("phase of the cycle (0 .. 1)")
    top.set_ylabel("pressure (mmHg)")
    top.set_title("Pressure through one cardiac cycle (end-diastole at phase 0)")
    top.grid(True, alpha=0.3)
    top.legend(loc="upper right")
    bottom.plot(vphase, cavity, color="#285ac8", lw=2, label=f"voxels (EF {100 * ef_voxels[0]:.1f}%)" if len(ef_voxels) else "voxels")
    have = particles >= 0
    bottom.plot(vphase[have], particles[have], "s", color="#e68c14", label=f"particles (EF {100 * ef_particles[0]:.1f}%)" if len(ef_particles) else "particles")
    bottom.set_xlabel("phase of the cycle (0 .. 1)")
    bottom.set_ylabel("cavity volume (mL)")
    bottom.set_ylim(bottom=0)
    bottom.grid(True, alpha=0.3)
    bottom.legend(loc="lower right")
    fig.tight_layout()
    _save(fig, png_path)
    return fig


def bag(csv_path, png_path):
    """scripts/bench/bag.sh: the time to build each bag and its steps per second and ns per
    particle-step against its particle count, one line per layout (ranks x threads), log-log; the
    CPU and the clone of the pair loops in the title when the CSV names them."""
    by_layout, built, machine = {}, {}, set()
    with open(csv_path, newline="") as f:
        for row in csv.DictReader(f):
            try:
                n = int(row["particles"])
                point = (n, float(row["steps_per_s"]), float(row["ns_per_particle_step"]))
            except (KeyError, ValueError) as e:
                raise ValueError(f"{csv_path}: a row without particles, steps_per_s or ns_per_particle_step ({e})") from e
            by_layout.setdefault(row["layout"], []).append(point)
            if row.get("construction_s"):
                how = {"place": "placement and settling", "birth": "birth and death"}.get(row.get("build"), "built")
                built.setdefault(how, {})[n] = float(row["construction_s"])
            if row.get("cpu"):
                machine.add(f"{row['cpu']}, {row.get('clone') or '?'} clone")
    if not by_layout:
        raise ValueError(f"{csv_path}: no rows")
    fig, axes = plt.subplots(1, 3 if built else 2, figsize=(16 if built else 11, 4.5))
    rate, cost = axes[-2], axes[-1]
    for layout, points in by_layout.items():
        points.sort()
        n = [p[0] for p in points]
        rate.plot(n, [p[1] for p in points], "o-", label=layout)
        cost.plot(n, [p[2] for p in points], "o-", label=layout)
    panels = [(rate, "steps per second (1/s)", "ranks x threads"), (cost, "time per particle-step (ns)", "ranks x threads")]
    if built:
        build = axes[0]
        for how, times in built.items():
            n = sorted(times)
            build.plot(n, [times[k] for k in n], "s-", color="#555555", label=how)
        build.set_title("time to build the bag (map, placement, settling)")
        panels.insert(0, (build, "wall time (s)", "bag built by"))
    for ax, what, legend in panels:
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.yaxis.set_major_formatter(PLAIN)
        lo, hi = ax.get_ylim()
        if hi < 10 * lo:  # less than a decade: label the minor ticks too, else they crowd
            ax.yaxis.set_minor_formatter(PLAIN)
        ax.set_xlabel("size of the built bag (particles)")
        ax.set_ylabel(what)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(title=legend)
    rate.set_title("torus bag, stepped from its built state")
    cost.set_title("cost per particle-step")
    if machine:
        fig.suptitle("; ".join(sorted(machine)), fontsize=10)
    fig.tight_layout()
    _save(fig, png_path)
    return fig


KINDS = {"stiffness": (stiffness, 1), "pressure": (pressure, 2), "bag": (bag, 1)}  # function, CSV files it reads


def main(argv):
    if len(argv) < 2 or argv[1] in ("-h", "--help") or argv[1] not in KINDS:
        print(__doc__.strip())
        return 0 if len(argv) >= 2 and argv[1] in ("-h", "--help") else 2
    fn, inputs = KINDS[argv[1]]
    if len(argv) != 2 + inputs + 1:
        print(f"plots.py {argv[1]}: expected {inputs} CSV file(s) and the PNG to write", file=sys.stderr)
        return 2
    try:
        fn(*argv[2:])
    except (OSError, ValueError) as e:
        print(f"plots.py {argv[1]}: {e}", file=sys.stderr)
        return 1
    print(f"plots.py: {argv[-1]}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
