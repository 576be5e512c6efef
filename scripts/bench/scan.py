#!/usr/bin/python3
"""Reads a bop-server log of scripts/bench/scan.sh and prints its CSV rows, one per bag, with the
run's figures in front and each bag's verdict against the real-scans targets:
  - an organ that is not thin: >= 95% of surface and >= 98% of volume particles in their own
    voxels, median normal angle <= 6 deg;
  - a thin organ (a quarter or more of its voxels in parts thinner than 2 r0, as the run's
    warning says): >= 99% of its particles inside it;
  - the ball nested in another bag (case "nested", bag "ball"): >= 95% of its surface particles in
    its surface voxels and >= 99% of its particles inside it;
  - many bags at the cost of one: the scan's particle-steps per second at most 1.3 times fewer than
    those of one bag of its particle count and surface share (case "slab", the reference).
  scan.py row CASE LOG WALL_S      rows for one run
  scan.py targets CSV [RATES]       the run targets, met or missed, and the bags that miss theirs;
                                    RATES: lines "CASE PARTICLE_STEPS_PER_S" of more runs
"""
import csv
import re
import sys

THIN_SHARE = 25.0  # % of a bag's voxels in thin parts that make it a thin organ
HEADER = ("case,wall_s,map_s,ready_s,settled_step,minimiser_steps,particles,surface_share,steps_per_s,"
          "particle_steps_per_s,bag,surface,volume,surface_pct,volume_pct,inside_pct,normal_deg,thin_pct,kind,verdict")


def rows(case, log, wall):
    text = open(log).read()
    num = lambda pattern, group=1: (m.group(group) if (m := re.search(pattern, text)) else "")
    mapped = num(r"frame 1/1 done: .*?; ([0-9.]+) s")
    ready = num(r"ready in ([0-9.]+) s")
    settled = num(r"settled at step ([0-9]+)") or "not settled"
    fire = num(r"the FIRE minimiser's first ([0-9]+) steps") or "0"
    rate = re.search(r"this run\s+(\d+)\s+(\d+)\s+(\d+)\s+([0-9.]+)\s+(\d+)", text)
    surface, volume, particles, steps, psteps = rate.groups() if rate else ("0", "0", "0", "", "")
    share = f"{int(surface) / max(1, int(particles)):.3f}"
    thin = {m.group(1): m.group(2) for m in re.finditer(r"bag '([^']+)': \d+ of its \d+ voxels \(([0-9.]+)%\) lie in "
                                                        r"parts thinner", text)}
    common = [case, wall, mapped, ready, settled, fire, particles, share, steps, psteps]
    bag = re.compile(r"bag '([^']+)': ([0-9.]+)% of its (\d+) surface particles in its surface voxels, "
                     r"([0-9.]+)% of its (\d+) volume particles in its volume voxels, ([0-9.]+)% of its particles "
                     r"inside it, median normal angle ([0-9.]+) deg")
    found = bag.findall(text)
    if not found:  # one bag: the run's own line, and its particles inside it from the voxel counts
        m = re.search(r"shape fidelity: ([0-9.]+)% of surface particles in their surface voxels, ([0-9.]+)% of "
                      r"volume particles in their volume voxels, median normal angle ([0-9.]+) deg", text)
        name = next(iter(thin), case)
        found = [(name, m.group(1), surface, m.group(2), volume, "", m.group(3))] if m else []
    for name, surf, ns, vol, nv, inside, angle in found:
        thin_pct = float(thin.get(name, 0))
        if case == "slab":  # the cost reference, not an organ
            print(",".join(common + [name, ns, nv, surf, vol, inside, angle, f"{thin_pct:g}", "reference", "n/a"]))
            continue
        if case == "nested" and name == "ball":
            kind = "nested"
            met = float(surf) >= 95 and inside != "" and float(inside) >= 99
        elif thin_pct >= THIN_SHARE:
            kind = "thin"
            met = inside != "" and float(inside) >= 99
        else:
            kind = "organ"
            met = float(surf) >= 95 and float(vol) >= 98 and float(angle) <= 6
        print(",".join(common + [name, ns, nv, surf, vol, inside, angle, f"{thin_pct:g}", kind,
                                 "met" if met else "missed"]))


def targets(path, rates_path=None):
    table = list(csv.DictReader(open(path)))
    best = {}  # each case's fastest run, particle-steps/s
    for line in open(rates_path) if rates_path else []:
        case, rate = line.split()
        best[case] = max(best.get(case, 0.0), float(rate))
    runs = {r["case"]: r for r in table}
    lines = []

    def verdict(ok):
        return "met" if ok else "missed"

    if "scan" in runs:
        r = runs["scan"]
        ok = r["settled_step"].isdigit() and float(r["wall_s"]) <= 60
        lines.append(f"whole scan ({r['particles']} particles, {sum(1 for t in table if t['case'] == 'scan')} bags) "
                     f"placed and settled in {r['wall_s']} s (target <= 60): {verdict(ok)}")
    for case, r in runs.items():
        ok = r["settled_step"].isdigit() and int(r["settled_step"]) <= 500
        lines.append(f"{case}: settled at step {r['settled_step']} ({r['minimiser_steps']} by the minimiser; "
                     f"target <= 500): {verdict(ok)}")
    if "thin" in runs or "stomach" in runs:
        r = runs.get("thin", runs.get("stomach"))
        ok = r["settled_step"].isdigit() and float(r["wall_s"]) <= 15
        sized = 30000 <= int(r["particles"]) <= 60000  # the target is for an organ of about 45,000
        lines.append(f"thin-walled organ alone ({r['particles']} particles; the target's is about 45,000) ready in "
                     f"{r['wall_s']} s (target <= 15): "
                     + (verdict(ok) if sized else "not shown (the organ is too small to judge it)"))
    if "scan" in runs and "slab" in runs:
        many, one = runs["scan"], runs["slab"]
        rate = {c: best.get(c, float(runs[c]["particle_steps_per_s"])) for c in ("scan", "slab")}
        runs_each = "the faster of 2 runs each" if best else "one run each"
        ratio = rate["slab"] / max(1.0, rate["scan"])
        lines.append(f"many bags against one ({runs_each}): the scan ({many['particles']} particles in "
                     f"{sum(1 for t in table if t['case'] == 'scan')} bags, {many['surface_share']} surface) "
                     f"{rate['scan'] / 1e6:.2f} M particle-steps/s, one slab ({one['particles']} particles, "
                     f"{one['surface_share']} surface) {rate['slab'] / 1e6:.2f} M: cost per particle-step "
                     f"{ratio:.2f} x one bag's (target <= 1.3): {verdict(ratio <= 1.3)}")
    judged = [t for t in table if t["verdict"] in ("met", "missed")]
    missed = [f"{t['case']}/{t['bag']} ({t['kind']})" for t in judged if t["verdict"] == "missed"]
    lines.append(f"bags within their fidelity targets: {sum(t['verdict'] == 'met' for t in judged)} of {len(judged)}"
                 + (f"; missed: {', '.join(missed)}" if missed else ""))
    print("\n".join(lines))


if __name__ == "__main__":
    if len(sys.argv) > 1 and sys.argv[1] == "row" and len(sys.argv) == 5:
        rows(*sys.argv[2:5])
    elif len(sys.argv) > 1 and sys.argv[1] == "header":
        print(HEADER)
    elif len(sys.argv) in (3, 4) and sys.argv[1] == "targets":
        targets(*sys.argv[2:])
    else:
        sys.exit(__doc__)
