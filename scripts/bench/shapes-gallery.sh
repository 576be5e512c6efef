#!/usr/bin/env bash
# Real shapes in, bags out: builds a bag from every mesh of ../shared/data/meshes (when present) and
# from synthetic shapes with a thin part, a hole and two separate pieces, at 64 and 128 voxels
# across, with the torus scene's settings (config/scenes/torus.toml: r0 = 2 voxels), each bag
# placed on its map and run until settled (BOP_GALLERY_METHOD=birth: grown on the torus scene's
# construction timeline instead), and prints one row per case:
#   accepted or refused (and why); the voxel volume against the solid (closed meshes: their own
#   volume; others: the same source voxelized at twice the resolution); surface and volume
#   particles against the ideal count at r0 spacing (hexagonal sheet over the area, the faces
#   between object and outside voxels each counted 1 / |n|_1 with n the smoothed mask's
#   gradient; fcc over the volume voxels); surface and
#   volume fidelity and the median normal angle (bop-server's last line); births + deaths over the
#   last 10% of construction against the particles; the build's wall time.
# Each built bag is then served for a moment and drawn by bop-viewer --headless; the pictures
# make one contact sheet (out/bench/shapes-gallery.png).
#   scripts/bench/shapes-gallery.sh [SIZE ...]   (default 64 128; CSV out/bench/shapes-gallery.csv)
#   BOP_GALLERY_STEPS   construction steps (default: the torus timeline's 4,000)
set -euo pipefail
cd "$(dirname "$0")/../.."
source scripts/bench/served.sh
sizes=("$@"); [[ ${#sizes[@]} -gt 0 ]] || sizes=(64 128)
scripts/install-deps.sh --bench >/dev/null
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j "${BOP_JOBS:-2}" --target bop-server bop-shape bop-viewer >/dev/null
out=out/bench/shapes-gallery; rm -rf "$out"; mkdir -p "$out"
csv=out/bench/shapes-gallery.csv
echo "case,size_voxels,status,voxel_mL,solid_mL,volume_ratio,surface,surface_ideal,volume,volume_ideal,surface_fidelity,volume_fidelity,normal_deg,late_births_deaths,particles,build_s,note" >"$csv"
echo "shapes-gallery: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ //'), $(nproc) cores" >&2
/usr/bin/python3 scripts/bench/shapes-gallery.py synth "$out/synthetic"

cases=()
for f in ../shared/data/meshes/*.obj "$out"/synthetic/*.obj "$out"/synthetic/*.nii; do [[ -e $f ]] && cases+=("$f"); done
steps=${BOP_GALLERY_STEPS:-4000}
for size in "${sizes[@]}"; do
  for file in "${cases[@]}"; do
    name=$(basename "${file%.*}")
    dir=$out/$name-$size; mkdir -p "$dir"
    /usr/bin/python3 scripts/bench/shapes-gallery.py scene "$file" "$size" "$steps" "$dir"
    # the voxel volume, then the reference solid at twice the resolution
    note=""
    if ! build/dynamics_server/bop-shape "$dir/scene.toml" -o "$dir/map" --no-png --export labels >"$dir/shape.log" 2>&1; then
      note=$(grep -m1 -i "error\|not\|flat" "$dir/shape.log" | tr ',' ';' | cut -c1-160)
      echo "$name,$size,refused,,,,,,,,,,,,,,$note" >>"$csv"
      printf "%-16s %4s  refused: %s\n" "$name" "$size" "$note"
      continue
    fi
    build/dynamics_server/bop-shape "$dir/fine.toml" -o "$dir/fine" --no-png --export none >"$dir/fine.log" 2>&1
    note=$(sed -n 's/^\[bop-shape\] shape.bag\[0\]: //p' "$dir/shape.log" | tr ',' ';' | cut -c1-160)
    start=$(date +%s.%N)
    build/dynamics_server/bop-server "$dir/scene.toml" --no-listen -o "$dir/run" --cache "$dir/run.bopgm" \
      --report-every $((steps / 10)) >"$dir/run.log" 2>&1 || { echo "$name,$size,failed,,,,,,,,,,,,,,see $dir/run.log" >>"$csv"; continue; }
    built=$(awk -v t0="$start" -v t1="$(date +%s.%N)" 'BEGIN {printf "%.1f", t1 - t0}')
    /usr/bin/python3 scripts/bench/shapes-gallery.py row "$name" "$size" "$dir" "$built" "$note" "$file" >>"$csv"
    tail -1 "$csv" | awk -F, '{printf "%-16s %4s  vol %5s  surf %5s/%-5s vol %6s/%-6s  fid %5s%% %5s%%  %4s deg  late %5s  %6s s\n", $1, $2, $6, $7, $8, $9, $10, $11, $12, $13, $14, $16}'
  done
done

# One picture of each built bag: served from its final state, drawn by the headless viewer.
for dir in "$out"/*-*/; do
  dir=${dir%/}; [[ -s $dir/run/final.xyz ]] || continue
  log=$dir/serve.log
  build/dynamics_server/bop-server "$dir/scene.toml" --restart "$dir/run/final.xyz" --cache "$dir/run.bopgm" \
    --port 0 --publish-hz 10 -o "$dir/served" >"$log" 2>&1 &
  server=$!
  endpoint=$(served_endpoint "$log" "$server")
  if [[ -n $endpoint ]]; then
    timeout 60 build/viz_client/bop-viewer "$endpoint" --headless --frames 2 --no-panel --width 480 --height 400 \
      --out "$dir/viewer" --screenshot "$dir/picture.png" >"$dir/viewer.log" 2>&1 || true
  fi
  kill "$server" 2>/dev/null || true
  wait "$server" 2>/dev/null || true
done
/usr/bin/python3 scripts/bench/shapes-gallery.py sheet "$out" out/bench/shapes-gallery.png
echo "shapes-gallery: rows in $csv, contact sheet out/bench/shapes-gallery.png" >&2
