#!/usr/bin/env bash
# Several objects in one scene, against the targets of the several-objects issue:
#   - the shipped organs scene (three touching organs and a tumour inside one) and a scene of four
#     objects side by side (a ball, an ellipsoid, a box and a cylinder: bags.py), each placed and
#     run until settled: per bag, % of surface particles in its surface voxels (target >= 95),
#     % of volume particles in its volume voxels (>= 98), % of its particles inside the bag
#     (>= 99.5);
#   - the four objects built as four bags against the same voxels built as one bag: wall time of
#     the whole build (map, placement, relaxation until settled), median of 3 runs each, ratio
#     within 1 +- 0.2;
#   - the organs scene served and drawn by bop-viewer --headless with its bag panel
#     (out/bench/bags-organs.png).
# Rows in out/bench/bags.csv (case, wall_s of its first run, ready_s, settled_step, particles, steps_per_s, bag,
# surface, volume, surface_pct, volume_pct, inside_pct, targets).
#   scripts/bench/bags.sh
set -euo pipefail
cd "$(dirname "$0")/../.."
source scripts/bench/served.sh
scripts/install-deps.sh --bench >/dev/null
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j "${BOP_JOBS:-2}" --target bop-server bop-viewer >/dev/null
out=out/bench/bags; rm -rf "$out"; mkdir -p "$out"
csv=out/bench/bags.csv
echo "bags: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ //'), $(nproc) cores" >&2
python3 scripts/bench/bags.py scenes "$out"
cp config/scenes/organs.toml "$out/organs.toml"
sed -i 's|\.\./data/|'"$PWD"'/config/data/|' "$out/organs.toml"

build() {  # scene name, run number: a batch build until settled; prints its wall time, s
  local scene=$1 k=$2 t0
  t0=$(date +%s.%N)
  build/dynamics_server/bop-server "$out/$scene.toml" --no-listen -o "$out/$scene-$k" \
    >"$out/$scene-$k.log" 2>&1 || { cat "$out/$scene-$k.log" >&2; echo "bags: $scene failed" >&2; exit 1; }
  awk -v a="$t0" -v b="$(date +%s.%N)" 'BEGIN {printf "%.2f", b - a}'
}

echo "case,wall_s,ready_s,settled_step,particles,steps_per_s,bag,surface,volume,surface_pct,volume_pct,inside_pct,targets" >"$csv"
declare -A walls
for scene in organs four one; do
  for k in 1 2 3; do
    w=$(build "$scene" "$k")
    walls[$scene]+="$w "
    [[ $k == 1 ]] && first=$w
    [[ $scene == organs ]] && break
  done
  python3 scripts/bench/bags.py row "$scene" "$out/$scene-1.log" "$first" >>"$csv"
done
printf "%-8s %-12s %9s %9s %9s %9s %9s  %s\n" case bag surface volume "surf %" "vol %" "inside %" targets
awk -F, 'NR > 1 {printf "%-8s %-12s %9s %9s %9s %9s %9s  %s\n", $1, $7, $8, $9, $10, $11, $12, $13}' "$csv"
median() { tr ' ' '\n' <<<"$1" | grep . | sort -g | sed -n 2p; }
four=$(median "${walls[four]}") one=$(median "${walls[one]}")
awk -v a="$four" -v b="$one" -v la="${walls[four]}" -v lb="${walls[one]}" 'BEGIN {
  r = a / b
  printf "build until settled: four bags %.2f s (runs %s), the same voxels as one bag %.2f s (runs %s): ratio %.2f, %s (target 0.8 to 1.2)\n",
    a, la, b, lb, r, (r >= 0.8 && r <= 1.2) ? "met" : "missed" }'

# The organs scene served from its settled state and drawn with the panel listing its bags.
log=$out/serve.log
build/dynamics_server/bop-server "$out/organs.toml" --restart "$out/organs-1/final.xyz" --port 0 --publish-hz 10 \
  -o "$out/served" >"$log" 2>&1 &
server=$!
trap 'kill $server 2>/dev/null || true' EXIT
endpoint=$(served_endpoint "$log" "$server")
[[ -n $endpoint ]] || { cat "$log" >&2; echo "bags: the served organs scene did not start" >&2; exit 1; }
timeout 60 build/viz_client/bop-viewer "$endpoint" --headless --frames 3 --width 1100 --height 620 \
  --out "$out/viewer" --screenshot out/bench/bags-organs.png >"$out/viewer.log" 2>&1
echo "bags: rows in $csv, the organs scene drawn in out/bench/bags-organs.png" >&2
