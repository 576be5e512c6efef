"""Tables and plots of scripts/bench/material.sh's virtual tests (out/bench/material/): each
target measured, met or missed, and indent.png, compress.png with labelled axes."""
import csv
import glob
import os
import re
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

out = sys.argv[1]


def rows(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def col(rs, name):
    return np.array([float(r[name]) for r in rs])


def verdict(ok):
    return "met" if ok else "MISSED"


summary = []
# Indentation against Hertz, and the two resolutions against each other.
indent = {}
for path in sorted(glob.glob(os.path.join(out, "indent-r*-e*.csv"))):
    r0, e = re.search(r"indent-r([0-9.]+)-e([0-9.]+)\.csv", path).groups()
    indent[(float(r0), float(e))] = rows(path)
fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(12, 4.8))
for (r0, e), rs in sorted(indent.items()):
    d, f, h, ratio = col(rs, "depth_mm"), col(rs, "force_n"), col(rs, "hertz_n"), col(rs, "ratio")
    style = "-o" if r0 == 2.0 else "--s"
    ax1.plot(d, f, style, ms=3, label=f"{e:g} kPa, r0 = {r0:g} voxels")
    ax2.plot(d, ratio, style, ms=3, label=f"{e:g} kPa, r0 = {r0:g} voxels")
    worst = float(np.max(np.abs(ratio - 1)))
    summary.append(f"indentation {e:g} kPa, r0 {r0:g} voxels: force / Hertz {ratio.min():.3f}..{ratio.max():.3f} "
                   f"(target within 0.85..1.15: {verdict(worst <= 0.15)})")
    if r0 == 2.0:
        ax1.plot(d, h, ":", color="#555555", lw=1)
ax1.set_yscale("log")
ax1.set_xlabel("depth past first contact (mm)")
ax1.set_ylabel("force on the sphere (N)")
ax1.set_title("Indentation by a sphere of 8 mm (dotted: Hertz)")
ax1.legend(fontsize=7)
ax2.axhspan(0.85, 1.15, color="#d0ecd0", label="target: within 15% of Hertz")
ax2.axhline(1, color="#555555", lw=0.8)
ax2.set_xlabel("depth past first contact (mm)")
ax2.set_ylabel("force / Hertz's (dimensionless)")
ax2.set_title("Against Hertz, F = 4/3 E/(1-nu^2) sqrt(R) d^1.5")
ax2.legend(fontsize=7)
for ax in (ax1, ax2):
    ax.grid(True, alpha=0.3)
fig.tight_layout()
fig.savefig(os.path.join(out, "indent.png"), dpi=100)
for e in (1.0, 10.0, 100.0):
    if (2.0, e) in indent and (1.4, e) in indent:
        a, b = col(indent[(2.0, e)], "force_n"), col(indent[(1.4, e)], "force_n")
        dev = float(np.max(np.abs(a / b - 1)))
        summary.append(f"resolutions at {e:g} kPa: force at r0 2 over r0 1.4 voxels {np.min(a / b):.3f}.."
                       f"{np.max(a / b):.3f} (target within 10%: {verdict(dev <= 0.10)})")
if (2.0, 1.0) in indent and (2.0, 100.0) in indent:
    lin = col(indent[(2.0, 100.0)], "force_n") / col(indent[(2.0, 1.0)], "force_n")
    summary.append(f"linear in E: force at 100 kPa over 1 kPa {lin.min():.4f}..{lin.max():.4f} (100 expected)")

# Compression: apparent E at 2-5% strain and Poisson ratio.
fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(12, 4.8))
for path in sorted(glob.glob(os.path.join(out, "compress-r*-nu*.csv"))):
    r0, nu = re.search(r"compress-r([0-9.]+)-nu([0-9.]+)\.csv", path).groups()
    rs = rows(path)
    strain, stress, lateral = col(rs, "strain"), col(rs, "stress_kpa"), col(rs, "lateral_strain")
    band = (strain >= 0.02 - 1e-9) & (strain <= 0.05 + 1e-9)
    e_app = float(np.dot(strain[band], stress[band]) / np.dot(strain[band], strain[band]))
    # strain counts compression positive, lateral strain expansion positive: nu = lateral / axial
    nu_app = float(np.dot(strain[band], lateral[band]) / np.dot(strain[band], strain[band]))
    summary.append(f"compression r0 {float(r0):g} voxels, stated nu {nu}: apparent E {e_app:.3g} kPa (stated 5; "
                   f"within 10%: {verdict(abs(e_app / 5 - 1) <= 0.10)}), Poisson ratio {nu_app:.3f} "
                   f"(within 0.05: {verdict(abs(nu_app - float(nu)) <= 0.05)})")
    ax1.plot(strain * 100, stress, "-o", ms=3, label=f"r0 = {float(r0):g} voxels, stated nu {nu}")
    ax2.plot(strain * 100, lateral * 100, "-o", ms=3, label=f"r0 = {float(r0):g} voxels, stated nu {nu}")
s = np.linspace(0, 5, 6)
ax1.plot(s, 5 * s / 100, ":", color="#555555", label="E = 5 kPa")
for nu in (0.3, 0.45):
    ax2.plot(s, nu * s, ":", lw=1, label=f"lateral = {nu} x axial")
ax1.set_xlabel("axial strain (%)")
ax1.set_ylabel("stress on the plates (kPa)")
ax1.set_title("Cylinder between frictionless plates")
ax2.set_xlabel("axial strain (%)")
ax2.set_ylabel("lateral strain at mid-height (%)")
ax2.set_title("Lateral expansion (Poisson ratio)")
for ax in (ax1, ax2):
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=7)
fig.tight_layout()
fig.savefig(os.path.join(out, "compress.png"), dpi=100)



def boussinesq_uz(z_mm, a_mm, nu=0.3):
    """Vertical displacement on the axis at depth z under Hertz's pressure p0 sqrt(1 - s^2/a^2) over
    a circle of radius a on a half-space (Boussinesq's point load summed over rings), in units of
    p0 / E mm."""
    s = (np.arange(4000) + 0.5) / 4000 * a_mm
    p = np.sqrt(1 - (s / a_mm) ** 2)
    r = np.sqrt(s * s + z_mm * z_mm)
    return float(np.sum(p * s * (a_mm / 4000) * (1 + nu) / r * (2 * (1 - nu) + z_mm * z_mm / r ** 2)))


def palpation_estimate(depth_mm, radius_mm=8.0, top_mm=4.0, bottom_mm=12.0, factor=5.0):
    """Force above a stiffer ball over the force beside it at one depth: the contact's compliance on
    the axis, the vertical strain between the ball's top and bottom divided by `factor` (springs in
    series along the axis; the lateral spread of the ball's stiffness is left out)."""
    a = np.sqrt(radius_mm * depth_mm)
    u0 = boussinesq_uz(1e-6, a)
    return u0 / (u0 - (1 - 1 / factor) * (boussinesq_uz(top_mm, a) - boussinesq_uz(bottom_mm, a)))


# Palpation: above the inclusion against beside it, at equal depth.
for path in sorted(glob.glob(os.path.join(out, "palpate-r*-at0_0.csv"))):
    r0 = re.search(r"palpate-r([0-9.]+)-", path).group(1)
    above, aside = rows(path), rows(path.replace("at0_0", "at12_0"))
    for a, b in zip(above, aside):
        ratio = float(a["force_n"]) / float(b["force_n"])
        est = palpation_estimate(float(a["depth_mm"]))
        summary.append(f"palpation r0 {float(r0):g} voxels at {a['depth_mm']} mm: force above the 5x inclusion over "
                       f"beside it {ratio:.3f} (Boussinesq series estimate {est:.3f}; bounds 1 and 5)")

# Felt: bop-haptic's stiffness curve on the served block against Hertz at the same depths.
felt = os.path.join(out, "felt", "stiffness.csv")
if os.path.exists(felt):
    rs = rows(felt)
    d, f = col(rs, "depth_mm"), col(rs, "force_n")
    hertz = 4 / 3 * 5e3 / (1 - 0.3 ** 2) * np.sqrt(8e-3) * (d * 1e-3) ** 1.5
    k, kh = float(np.dot(d, f) / np.dot(d, d)), float(np.dot(d, hertz) / np.dot(d, d))
    summary.append(f"felt: bop-haptic on the served 5 kPa block, stiffness fitted over 0-{d.max():.2f} mm "
                   f"{k:.4g} N/mm against Hertz's {kh:.4g} N/mm, ratio {k / kh:.3f} "
                   f"(target within 20%: {verdict(abs(k / kh - 1) <= 0.2)})")

rt = os.path.join(out, "real-time.txt")
if os.path.exists(rt):
    summary += [line.strip() for line in open(rt) if "real-time factor" in line]
with open(os.path.join(out, "summary.txt"), "w") as f:
    f.write("\n".join(summary) + "\n")
print("\n".join(summary))
print(f"plots: {out}/indent.png, {out}/compress.png")
