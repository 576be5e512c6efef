#!/usr/bin/env bash
# Gradient-map memory per rank: a 256^3-voxel map (the star bag of config/scenes/star.toml at
# 0.29 mm voxels) loaded by bop-server at 1, 2, 8 and 64 ranks (oversubscribed on small
# machines). At one rank the process holds the whole map; at more, each rank holds the window of
# its subdomain plus a margin, read straight from the cache file. Reports the largest window
# per rank in MB, from the servers' own summaries.
#   scripts/bench/map-memory.sh           (CSV in out/bench/map-memory.csv)
#   BOP_BENCH_RANKS="1 2 8 64"            rank counts
set -euo pipefail
cd "$(dirname "$0")/../.."
scripts/install-deps.sh >/dev/null
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j "${BOP_JOBS:-2}" --target bop-server >/dev/null
out=out/bench/map-memory; mkdir -p "$out"
scene=$out/star-256.toml
# Star of radius 36 mm with 4 voxels of padding: 72 / 0.2903 + 8 = 256 voxels per side.
sed -e 's/^voxel_size_mm = .*/voxel_size_mm = 0.2903/' config/scenes/star.toml >"$scene"
# No construction timeline: the map alone.
awk '/^\[\[construction.event\]\]/ {skip = 1; next} /^\[/ {skip = 0} !skip' "$scene" >"$scene.tmp" && mv "$scene.tmp" "$scene"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMP_NUM_THREADS=1
csv=out/bench/map-memory.csv
echo "ranks,rank_grid,map_mb_per_rank_max" >"$csv"
echo "map-memory: building the 256^3 map once (cached in $out/gradient-map.bopgm)"
printf "%6s %18s %14s\n" ranks "MB per rank (max)" "of the whole"
whole=""
for ranks in ${BOP_BENCH_RANKS:-1 2 8 64}; do
  log=$out/ranks-$ranks.log
  start=$(date +%s)
  mpirun --oversubscribe -np "$ranks" build/dynamics_server/bop-server "$scene" --no-listen --steps 1 \
    -o "$out" --cache "$out/gradient-map.bopgm" --report-every 1 >"$log" 2>&1 || { tail -20 "$log"; exit 1; }
  mb=$(grep -oP 'gradient map: (at most )?\K[0-9.]+(?= MB)' "$log" | tail -1)
  grid=$(grep -oP 'grid \K[0-9]+ x [0-9]+ x [0-9]+(?=;)' "$log" | head -1 || true)
  [[ -n "$whole" ]] || whole=$mb
  printf "%6s %18s %13.1f%%   (%s s)\n" "$ranks" "$mb" "$(awk -v a="$mb" -v b="$whole" 'BEGIN {print 100 * a / b}')" "$(( $(date +%s) - start ))"
  echo "$ranks,${grid:-1 x 1 x 1},$mb" >>"$csv"
done
echo "map-memory: CSV in $csv; logs in $out"
