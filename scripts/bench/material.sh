#!/usr/bin/env bash
# Tissue in physical units, measured (docs/physics.md §8): virtual tests of bop-material on shapes
# the tree builds (superellipsoids), CSV and plots in out/bench/material/.
# - Indentation: the block of config/scenes/tissue-block.toml (40 x 40 x 20 mm, held at its base)
#   pressed by a sphere of R = 8 mm to 0.2 R, at E = 1, 10 and 100 kPa and r0_voxels 2 and 1.4,
#   against Hertz F = 4/3 E/(1 - nu^2) sqrt(R) d^1.5 (nu 0.3). Targets: within 15% of Hertz at
#   every depth; the two resolutions within 10% of each other.
# - Compression: a cylinder 20 mm across and 30 mm high between frictionless plates, strains 1-5%,
#   at both resolutions, stated nu 0.3 and 0.45: apparent E (stress over strain at 2-5%) within
#   10% of the stated E, Poisson ratio (lateral over axial strain) within 0.05 of the stated one.
# - Palpation: the block with a ball of 5 times its modulus (radius 4 mm) one radius below its top,
#   the sphere pressed 0.4-1.2 mm above the ball and 12 mm aside: the force's ratio, against an
#   estimate from Boussinesq's solution (material.py) and the bounds 1 and 5.
# - Felt: bop-haptic's sim:poke on the served 5 kPa block (config/scenes/tissue-block.toml, on its
#   support), the sphere from touching its top to 0.2 R: the stiffness fitted to the curve it
#   writes (N against mm, no force scale given) against Hertz's at the same depths, within 20%.
# - Real time: the torus of config/scenes/torus.toml at 5 kPa served for 1,500 steps, without mass
#   scaling and with the scaling that its step rate asks for (the factor stated): the real-time
#   factor each reports.
#   scripts/bench/material.sh   (BOP_MATERIAL_QUICK=1: r0_voxels 2 only)
set -euo pipefail
cd "$(dirname "$0")/../.."
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j "${BOP_JOBS:-2}" --target bop-server bop-material bop-haptic >/dev/null
out=out/bench/material; rm -rf "$out"; mkdir -p "$out"
echo "material: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ //'), $(nproc) cores" | tee "$out/cpu.txt"
resolutions=(2.0 1.4); [[ ${BOP_MATERIAL_QUICK:-0} == 1 ]] && resolutions=(2.0)
bin=build/dynamics_server

# scene NAME R0_VOXELS BODY: a scene file of the tissue block's grid with BODY after it.
scene() {
  printf '[grid]\nvoxel_size_mm = 1.0\nr0_voxels = %s\n%b' "$2" "$3" >"$out/$1.toml"
  echo "$out/$1.toml"
}
block='[[shape.bag]]\nname = "block"\nsource = "superellipsoid"\nradii_mm = [20, 20, 10]\nexponents = [0.1, 0.1]\n'
probe='[probe]\nradius_mm = 8.0\n'

for r0 in "${resolutions[@]}"; do
  for e in 1 10 100; do
    f=$(scene "indent-r$r0-e$e" "$r0" "$block[[material]]\nyoung_kpa = $e\npoisson = 0.3\ndensity_kg_m3 = 1000\nrelaxation_s = 0.05\n$probe")
    "$bin/bop-material" "$f" --out "$out/indent-r$r0-e$e.csv" --depths-mm 0.2,0.4,0.6,0.8,1.0,1.2,1.4,1.6 \
      | grep -E "settled|Hertz fit" | sed "s/^/indent r0 $r0 voxels, $e kPa: /"
  done
  for nu in 0.3 0.45; do
    f=$(scene "compress-r$r0-nu$nu" "$r0" '[[shape.bag]]\nname = "cylinder"\nsource = "superellipsoid"\nradii_mm = [10, 10, 15]\nexponents = [0.1, 1.0]\n'"[[material]]\nyoung_kpa = 5\npoisson = $nu\n")
    "$bin/bop-material" "$f" --test compress --out "$out/compress-r$r0-nu$nu.csv" | grep -E "settled" \
      | sed "s/^/compress r0 $r0 voxels, nu $nu: /"
  done
  f=$(scene "palpate-r$r0" "$r0" "$block"'[[shape.bag]]\nname = "inclusion"\nsource = "sphere"\nradius_mm = 4\ncenter_mm = [0, 0, 2]\n[[material]]\nbags = ["block"]\nyoung_kpa = 5\n[[material]]\nbags = ["inclusion"]\nyoung_kpa = 25\n'"$probe")
  for at in "0 0" "12 0"; do
    name=palpate-r$r0-at$(echo $at | tr ' ' '_')
    "$bin/bop-material" "$f" --out "$out/$name.csv" --at-mm $at --depths-mm 0.4,0.8,1.2 | grep -E "Hertz fit" \
      | sed "s/^/palpate r0 $r0 voxels at $at mm: /"
  done
done

# Felt: the served block (mass scaling 100, so the machine keeps up or nearly) poked by bop-haptic
# from the sphere resting on the top's mean plane (from a batch run's final.xyz) to 1.6 mm.
"$bin/bop-server" config/scenes/tissue-block.toml --no-listen -o "$out/block" --cache "$out/block.bopgm" >/dev/null 2>&1
target=$(scripts/poke-target.py "$out/block/final.xyz" --radius-mm 8 --depth-mm 1.6 --standoff-mm 0.5)
read -r at depth standoff <<<"$target"
(cat config/scenes/tissue-block.toml; printf '[units]\nmass_scaling = 100\n') >"$out/felt.toml"
"$bin/bop-server" "$out/felt.toml" --port 0 --steps 100000000 -o "$out/felt-server" --cache "$out/block.bopgm" \
  >"$out/felt-server.log" 2>&1 &
server=$!
endpoint=
for _ in $(seq 300); do
  endpoint=$(grep -o 'listening on tcp://[0-9.:]*' "$out/felt-server.log" | sed 's/listening on //') && [[ -n $endpoint ]] && break
  sleep 0.1
done
build/haptic_client/bop-haptic "$endpoint" --device sim:poke --target "$at" \
  --depth "$depth" --standoff "$standoff" --speed 0.3 --hold 1 --out "$out/felt" | tee "$out/felt.log" \
  | grep -E "coupling|largest"
kill -INT $server; wait $server || true
grep 'real-time factor' "$out/felt-server.log" | sed 's/^/felt block served: /'

# Real time: the served torus at 5 kPa, then with the mass scaling its step rate asks for.
# The torus's own construction timeline and [interactions] give way: a material's bag is placed and
# sets its own weights.
torus() { (sed -e "s|\.\./models/|$PWD/config/models/|" -e '/^\[construction\]/,/^\[run\]/{/^\[run\]/!d}' config/scenes/torus.toml
  printf '[[material]]\nyoung_kpa = 5\ndensity_kg_m3 = 1000\n%b' "$1") >"$out/torus-$2.toml"; echo "$out/torus-$2.toml"; }
run_torus() {
  "$bin/bop-server" "$1" --port 0 --steps 1500 -o "$out/served-$2" 2>&1 | grep -E "time step|real-time factor" \
    | sed "s/^/torus, $2: /" | tee -a "$out/real-time.txt"
}
: >"$out/real-time.txt"
run_torus "$(torus '' plain)" plain
factor=$(sed -n 's/.*torus, plain: simulated .* real-time factor of \([0-9.e+-]*\).*/\1/p' "$out/real-time.txt")
scaling=$(/usr/bin/python3 -c "import math; print(max(1, math.ceil((1.25 / $factor) ** 2)))")
run_torus "$(torus "[units]\nmass_scaling = $scaling\n" scaled)" "mass scaling $scaling"

/usr/bin/python3 scripts/bench/material.py "$out"
