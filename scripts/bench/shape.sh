#!/usr/bin/env bash
# Gradient-map build time against grid size: a sphere (radius 0.35 N voxels) on N^3 grids,
# N = 64, 128, 256, 384, one core (--threads 1). Prints seconds and ns per voxel for each
# stage: rasterize (the model source), label, distance (exact EDT with nearest surface) and
# geometry (normals and curvature, per surface voxel), and the gradient map proper
# (label + distance). Target (issue 2): 256^3 map in <= 1.5 s on one core, ns/voxel flat.
#   scripts/bench/shape.sh [N ...]     (results also in out/bench/shape.csv)
set -euo pipefail
cd "$(dirname "$0")/../.."
sizes=("$@"); [[ ${#sizes[@]} -gt 0 ]] || sizes=(64 128 256 384)
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j "${BOP_JOBS:-2}" --target bop-shape >/dev/null
exe=build/dynamics_server/bop-shape
out=out/bench; mkdir -p "$out"
csv=$out/shape.csv
echo "n,stage,seconds,items,ns_per_item" >"$csv"
printf "%6s %12s %10s %10s %10s %12s %14s %12s\n" N voxels rasterize label distance "map (s)" "map ns/voxel" "geometry"
for n in "${sizes[@]}"; do
  scene=$out/sphere-$n.toml
  r=$(awk "BEGIN{print 0.35*$n}")
  cat >"$scene" <<TOML
[grid]
voxel_size_mm = 1.0
r0_voxels = 2.0
size_voxels = [$n, $n, $n]
[shape]
[[shape.bag]]
source = "sphere"
radius_mm = $r
TOML
  OMP_NUM_THREADS=1 "$exe" "$scene" -o "$out/sphere-$n" --no-cache --no-png --export none --threads 1 \
         --timings-csv "$out/sphere-$n.csv" >/dev/null 2>"$out/sphere-$n.log"
  tail -n +2 "$out/sphere-$n.csv" | awk -F, -v n="$n" '{print n "," $1 "," $5 "," $6 "," $7}' >>"$csv"
  awk -F, -v n="$n" 'NR>1 {s[$1]=$5; i[$1]=$6}
    END {m=s["label"]+s["distance"];
         printf "%6d %12d %9.3fs %9.3fs %9.3fs %11.3fs %14.1f %8.3fs (%.0f ns/surface voxel)\n",
                n, i["label"], s["rasterize"], s["label"], s["distance"], m, m*1e9/i["label"], s["geometry"], s["geometry"]*1e9/i["geometry"]}' \
      "$out/sphere-$n.csv"
done
echo "CSV: $csv"
