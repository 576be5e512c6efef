#!/usr/bin/env bash
# Tissue in physical units (docs/physics.md §8), from the command line:
# - the calibration reproduces its stated Young's modulus: bop-material presses the scene's sphere
#   into config/scenes/tissue-block.toml (5 kPa, r0_voxels 2) and Hertz fitted to the forces over
#   depths up to 0.2 R gives E within 15% of 5 kPa (the indentation target's bound);
# - its CSV opens in Python with the columns and units it names, the Hertz column is Hertz's formula;
# - a batch run's final.xyz carries the units (ASE reads LengthUnitMm, TimeUnitS, ForceUnitN, TimeS);
# - a served run with mass scaling fast enough for real time keeps to the wall clock: it takes at
#   least the simulated time and says a real-time factor within 0.8 and 1.05.
# Usage: bop_material_cli.sh PATH/TO/bop-material PATH/TO/bop-server SOURCE_DIR
set -u
material=$1 server=$2 src=$3
source "$(dirname "$0")/cli-checks.sh"
py=/usr/bin/python3
scene=$src/config/scenes/tissue-block.toml

bounded 300 "$work/indent.log" "$material" "$scene" --out "$work/indent.csv" --depths-mm 0.4,0.8,1.2,1.6
rc=$?
tail -8 "$work/indent.log"
check "bop-material indents the block (exit $rc)" "[ $rc -eq 0 ] && [ -s '$work/indent.csv' ]"
fit=$(sed -n 's/.*Hertz fit over depths up to 0.2 R: E \([0-9.]*\) kPa.*/\1/p' "$work/indent.log")
check "Hertz's E fitted to the forces is within 15% of the stated 5 kPa (got ${fit:-none} kPa)" \
  "[ -n '$fit' ] && awk -v e='$fit' 'BEGIN { exit !(e > 4.25 && e < 5.75) }'"
bounded 60 "$work/csv.txt" "$py" - "$work/indent.csv" <<'PY'
import csv, math, sys
rows = list(csv.DictReader(open(sys.argv[1])))
assert [r["depth_mm"] for r in rows] == ["0.4", "0.8", "1.2", "1.6"], rows
for r in rows:  # Hertz: 4/3 E/(1 - nu^2) sqrt(R) d^1.5 at 5 kPa, nu 0.3, R 8 mm, in N
    d, hertz = float(r["depth_mm"]) * 1e-3, float(r["hertz_n"])
    assert abs(hertz - 4 / 3 * 5e3 / (1 - 0.09) * math.sqrt(8e-3) * d ** 1.5) < 1e-5 * hertz, r
    assert float(r["force_n"]) > 0 and abs(float(r["ratio"]) - float(r["force_n"]) / hertz) < 1e-4, r
print(f"{len(rows)} rows: force_n from {rows[0]['force_n']} to {rows[-1]['force_n']} N")
PY
check "the CSV opens, in mm and N, its Hertz column Hertz's formula" "[ $? -eq 0 ]"
cat "$work/csv.txt"

bounded 120 "$work/batch.log" "$server" "$scene" --no-listen --cache "$work/map.bopgm" -o "$work/b"
check "a batch run settles the block (exit $?) and prints its units" \
  "grep -q 'units: length 1.155 mm' '$work/batch.log' && grep -q 'real-time factor' '$work/batch.log'"
bounded 60 "$work/ase.txt" "$py" - "$work/b/final.xyz" <<'PY'
import sys
import ase.io
a = ase.io.read(sys.argv[1])
info = a.info
assert abs(info["LengthUnitMm"] - 2 / 3 ** 0.5) < 1e-12, info
assert abs(info["ForceUnitN"] - info["MassUnitKg"] * info["LengthUnitMm"] * 1e-3 / info["TimeUnitS"] ** 2) < 1e-12 * info["ForceUnitN"]
assert abs(info["TimeS"] - info["Time"] * info["TimeUnitS"]) < 1e-9 * info["TimeS"], info
print(f"ASE: {len(a)} particles, {info['TimeS']:.4g} s simulated, force unit {info['ForceUnitN']:.4g} N")
PY
check "ASE reads the units from final.xyz" "[ $? -eq 0 ]"
cat "$work/ase.txt"

# Mass scaling 10^6: a step is 1,000 times longer in s (29 ms), so any machine keeps up with the wall
# clock, under load too.
(cat "$scene"; printf '[units]\nmass_scaling = 1000000\n') >"$work/paced.toml"
start=$(date +%s%N)
bounded 120 "$work/paced.log" "$server" "$work/paced.toml" --port 0 --steps 100 --cache "$work/map.bopgm" \
  -o "$work/p"
rc=$?
wall=$(awk -v ns=$(($(date +%s%N) - start)) 'BEGIN { printf "%.3f", ns / 1e9 }')
line=$(grep 'real-time factor' "$work/paced.log")
echo "$line (wall $wall s in all)"
simulated=$(echo "$line" | sed -n 's/^simulated \([0-9.e+-]*\) s at a real-time factor of \([0-9.e+-]*\).*/\1/p')
factor=$(echo "$line" | sed -n 's/^simulated \([0-9.e+-]*\) s at a real-time factor of \([0-9.e+-]*\).*/\2/p')
check "the paced served run ends (exit $rc) and takes at least its simulated ${simulated:-?} s (wall $wall s)" \
  "[ $rc -eq 0 ] && [ -n '$simulated' ] && awk -v s='$simulated' -v w='$wall' 'BEGIN { exit !(w >= s) }'"
check "... at a real-time factor within 0.8 and 1.05 (got ${factor:-none})" \
  "[ -n '$factor' ] && awk -v f='$factor' 'BEGIN { exit !(f > 0.8 && f <= 1.05) }'"
exit $fail
