#!/usr/bin/env bash
# Tissue in physical units (docs/physics.md §8), from the command line:
# - the calibration reproduces its stated Young's modulus: bop-material presses the scene's sphere
#   into config/scenes/tissue-block.toml (5 kPa, r0_voxels 2) and Hertz fitted to the forces over
#   depths up to 0.2 R gives E within 15% of 5 kPa (the indentation target's bound);
# - its CSV opens in Python with the columns and units it names, the Hertz column is Hertz's formula;
# - a batch run's final.xyz carries the units (ASE reads LengthUnitMm, TimeUnitS, ForceUnitN, TimeS);
# - compression of a cylinder (nu 0.45) between plates gives its stated E within 10% and its
#   Poisson ratio within 0.05 (the compression target's bounds);
# - a served run with mass scaling fast enough for real time keeps to the wall clock: it takes at
#   least the simulated time and says a real-time factor within 0.8 and 1.05;
# - the bonded block at 3 ranks moves as at 1 rank (bonds across subdomains, the ghosts'
#   dilatations from their owners), and a run stopped at a checkpoint and restarted from it ends bit
#   for bit as the uninterrupted one (the bonds placed again);
# - bop-haptic pokes the served block with no force scale given: the stiffness it fits to its
#   curve (N against mm) is within 20% of Hertz's at the same depths (the target's bound).
# Usage: bop_material_cli.sh PATH/TO/bop-material PATH/TO/bop-server PATH/TO/mpiexec PATH/TO/bop-haptic SOURCE_DIR
set -u
material=$1 server=$2 mpi=$3 haptic=$4 src=$5
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

# Mass scaling 10^6: a step is 1,000 times longer in s (42 ms), so any machine keeps up with the wall
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

printf '[grid]\nvoxel_size_mm = 1.0\nr0_voxels = 2.0\n[[shape.bag]]\nname = "cylinder"\nsource = "superellipsoid"\nradii_mm = [10, 10, 15]\nexponents = [0.1, 1.0]\n[[material]]\nyoung_kpa = 5\npoisson = 0.45\n' >"$work/cylinder.toml"
bounded 300 "$work/compress.log" "$material" "$work/cylinder.toml" --test compress --strains 0.02,0.05 \
  --out "$work/compress.csv"
check "bop-material compresses the cylinder (exit $?)" "[ -s '$work/compress.csv' ]"
cat "$work/compress.csv"
bounded 60 "$work/compress.txt" "$py" - "$work/compress.csv" <<'PY'
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
for r in rows:
    e, nu = float(r["apparent_e_kpa"]), float(r["poisson"])
    print(f"strain {r['strain']}: E {e:.3f} kPa (stated 5), Poisson {nu:.3f} (stated 0.45)")
    assert 4.5 < e < 5.5 and abs(nu - 0.45) < 0.05, r
PY
check "compression: E within 10% of 5 kPa and Poisson within 0.05 of 0.45" "[ $? -eq 0 ]"
cat "$work/compress.txt"

# The bonded block stepped 200 times from its placement (no settling rule: a fixed step count).
(cat "$scene"; printf '[construction]\nuntil_settled = false\n') >"$work/steps.toml"
run() { local n=$1 log=$2; shift 2
  if [[ $n == 1 ]]; then bounded 150 "$log" "$server" "$work/steps.toml" --no-listen --cache "$work/map.bopgm" "$@"
  else bounded 150 "$log" "$mpi" --oversubscribe -np "$n" "$server" "$work/steps.toml" --no-listen \
    --cache "$work/map.bopgm" "$@"; fi; }
run 1 "$work/s0.log" --steps 0 -o "$work/s0"
# Every run checkpoints at the same steps (each checkpoint reseats the run on the file's values).
run 1 "$work/a1.log" --steps 200 --checkpoint-every 100 -o "$work/a1"
run 3 "$work/a3.log" --steps 200 --checkpoint-every 100 -o "$work/a3"
run 1 "$work/b1.log" --steps 100 --checkpoint-every 100 -o "$work/b1"
run 1 "$work/c1.log" --steps 100 --checkpoint-every 100 -o "$work/c1" --restart "$work/b1/checkpoint.xyz"
grep -m1 'bonded:' "$work/a1.log"
check "3 ranks say how the block was split" "grep -q 'decomposed over 3 ranks' '$work/a3.log'"
bounded 60 "$work/ranks.txt" "$py" - "$work/s0/final.xyz" "$work/a1/final.xyz" "$work/a3/final.xyz" <<'PY'
import sys
import ase.io
import numpy as np
def by_id(path):
    a = ase.io.read(path)
    return dict(zip(a.arrays["id"].tolist(), a.get_positions()))
s0, a1, a3 = (by_id(p) for p in sys.argv[1:])
assert set(a1) == set(a3) == set(s0), "the same particles"
moved = max(np.linalg.norm(a1[i] - s0[i]) for i in a1)
worst = max(np.linalg.norm(a1[i] - a3[i]) for i in a1)
print(f"{len(a1)} particles: moved up to {moved:.3g} from their placement; 3 ranks against 1 differ by {worst:.3g}")
assert moved > 1e-3 and worst < 1e-8
PY
check "the bonded block moves as at 1 rank at 3 ranks (positions within 1e-8)" "[ $? -eq 0 ]"
cat "$work/ranks.txt"
check "stopped at step 100 and restarted, the bonded run ends bit for bit as the uninterrupted one" \
  "[ -s '$work/a1/final.xyz' ] && cmp -s '$work/a1/final.xyz' '$work/c1/final.xyz'"

# Felt: the served block (mass scaling 100) poked from the sphere resting on its top's mean plane
# (from the batch run's final.xyz) to 1.6 mm, no force scale and no coupling given.
target=$("$py" "$src/scripts/poke-target.py" "$work/b/final.xyz" --radius-mm 8 --depth-mm 1.6 --standoff-mm 0.5)
read -r at depth standoff <<<"$target"
(cat "$scene"; printf '[units]\nmass_scaling = 100\n') >"$work/felt.toml"
"$server" "$work/felt.toml" --port 0 --steps 100000000 --cache "$work/map.bopgm" -o "$work/felt-server" \
  >"$work/felt-server.log" 2>&1 &
served=$!
endpoint=
for _ in $(seq 300); do
  endpoint=$(grep -o 'listening on tcp://[0-9.:]*' "$work/felt-server.log" | sed 's/listening on //') && [[ -n $endpoint ]] && break
  sleep 0.1
done
bounded 60 "$work/felt.log" "$haptic" "$endpoint" --device sim:poke --target "$at" --depth "$depth" \
  --standoff "$standoff" --speed 0.3 --hold 1 --out "$work/felt"
rc=$?
kill -INT $served; wait $served
grep -E 'coupling|largest' "$work/felt.log"
check "bop-haptic pokes the served block (exit $rc) with the device's stiffest coupling" \
  "[ $rc -eq 0 ] && grep -q \"the device's stiffest\" '$work/felt.log'"
bounded 60 "$work/felt.txt" "$py" - "$work/felt/stiffness.csv" <<'PY'
import csv, sys
import numpy as np
rows = list(csv.DictReader(open(sys.argv[1])))
d = np.array([float(r["depth_mm"]) for r in rows])
f = np.array([float(r["force_n"]) for r in rows])
hertz = 4 / 3 * 5e3 / (1 - 0.3 ** 2) * np.sqrt(8e-3) * (d * 1e-3) ** 1.5
k, kh = np.dot(d, f) / np.dot(d, d), np.dot(d, hertz) / np.dot(d, d)
print(f"felt {k:.4g} N/mm over 0-{d.max():.2f} mm against Hertz's {kh:.4g} N/mm: ratio {k / kh:.3f}")
assert d.max() > 1.4 and abs(k / kh - 1) <= 0.2
PY
check "the felt stiffness is within 20% of Hertz's at the same depths" "[ $? -eq 0 ]"
cat "$work/felt.txt"
exit $fail
