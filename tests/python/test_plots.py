#!/usr/bin/env python3
"""Every plot BoP draws (python/bop/plots.py: the haptic stiffness curve, the ventricle's
pressure cycle, the bag benchmark) has, on every panel, tick labels with values on both axes,
axis labels naming their unit in parentheses, and a legend; its PNG opens and is not blank.
The same checker must refuse a panel drawn without ticks. Prints one line per plot; exit 1 on a
failure. Usage: test_plots.py SOURCE_DIR OUT_DIR"""
import os
import sys

import matplotlib.image as mpimg
import numpy as np

src, out = sys.argv[1], sys.argv[2]
sys.path.insert(0, os.path.join(src, "python"))
from bop import plots  # noqa: E402

os.makedirs(out, exist_ok=True)


def write(name, text):
    path = os.path.join(out, name)
    with open(path, "w") as f:
        f.write(text)
    return path


def problems(fig, png):
    fig.canvas.draw()
    found = []
    for k, ax in enumerate(fig.axes):
        for axis, labels, name in (("x", ax.get_xticklabels(), ax.get_xlabel()), ("y", ax.get_yticklabels(), ax.get_ylabel())):
            values = [t.get_text() for t in labels if t.get_text().strip()]
            if len(values) < 2 or not any(any(ch.isdigit() for ch in v) for v in values):
                found.append(f"panel {k}: {axis} axis has no tick values ({values})")
            if "(" not in name or ")" not in name:
                found.append(f"panel {k}: {axis} label '{name}' names no unit in parentheses")
        legend = ax.get_legend()
        if legend is None or not [t for t in legend.get_texts() if t.get_text()]:
            found.append(f"panel {k}: no legend")
    image = mpimg.imread(png)
    if image.ndim != 3 or np.mean(image[..., :3].min(axis=2) < 0.9) < 0.01:
        found.append(f"{png}: blank or unreadable")
    return found


depth = np.linspace(0.025, 1.5, 30)
stiffness_csv = write("stiffness.csv", "depth,force,samples\n" + "".join(f"{d},{3 * d - 0.2 * d * d},{50}\n" for d in depth))
phase = np.linspace(0, 1, 101)
cycle_csv = write("pressure-cycle.csv", "phase,pressure_fit_mmhg,typical_mmhg\n" +
                  "".join(f"{p},{120 * np.sin(np.pi * p) ** 4},{110 * np.sin(np.pi * p) ** 2}\n" for p in phase))
vphase = np.linspace(1 / 64, 1 - 1 / 64, 32)
volume_csv = write("volume-cycle.csv", "phase,cavity_ml,particle_ml,ef_voxels,ef_particles\n" +
                   "".join(f"{p},{120 - 60 * np.sin(np.pi * p)},{-1 if k % 4 == 3 else 118 - 55 * np.sin(np.pi * p)},0.5,0.466\n"
                           for k, p in enumerate(vphase)))
bag_csv = write("bag.csv", "layout,particles,steps_per_s,ns_per_particle_step,construction_s,build,cpu,clone\n" +
                "".join(f"{layout},{n},{1e9 / (200 * n)},{200 + 10 * k},{2 + n / 2e4},place,AMD EPYC,x86-64-v4\n"
                        for layout in ("1x1", "1x2", "2x1") for k, n in enumerate((1363, 9208, 139703))))

failures = 0
for name, fig, png in (
        ("stiffness", plots.stiffness(stiffness_csv, os.path.join(out, "stiffness.png")), os.path.join(out, "stiffness.png")),
        ("pressure", plots.pressure(cycle_csv, volume_csv, os.path.join(out, "pressure.png")), os.path.join(out, "pressure.png")),
        ("bag", plots.bag(bag_csv, os.path.join(out, "bag.png")), os.path.join(out, "bag.png"))):
    found = problems(fig, png)
    failures += bool(found)
    print(f"{name}: {len(fig.axes)} panel(s), " + ("ticks, units and legends on every panel" if not found else "; ".join(found)))

# The checker can fail: the stiffness plot with its ticks and legend taken away.
fig = plots.stiffness(stiffness_csv, os.path.join(out, "bare.png"))
fig.axes[0].set_xticks([])
fig.axes[0].get_legend().remove()
bare = problems(fig, os.path.join(out, "bare.png"))
print(f"bare: {'; '.join(bare)}")
failures += len(bare) != 2
print("plots ok" if failures == 0 else f"plots: {failures} failure(s)")
sys.exit(1 if failures else 0)
