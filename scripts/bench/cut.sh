#!/usr/bin/env bash
# Cutting (docs/physics.md §9, issue "cutting and lasting deformation"):
#  1. the map edit of a cut on one core: bop-map-cut sweeps a blade of 1 r0 into the placed torus
#     (24 strokes, 0 to 5 r0 long), times each windowed edit and checks it against a whole-grid
#     rebuild; the windows of at most 32^3 voxels against the 5 ms target;
#  2. the demo with a cut: the torus served (one rank), bop-haptic's scripted poke with --cut for
#     5 s: missed deadlines at 1 kHz (target 0), the strokes, the server's cut lines;
#  3. the torus cut in two from Python (python/examples/cut.py: one stroke of 3.2 r0 through the
#     box's middle crosses the tube twice) while bop-viewer --headless draws the run: pieces and
#     their distance, and the picture sequence (out/bench/cut/frames/*.png).
#   scripts/bench/cut.sh            (tables in out/bench/cut/)
set -euo pipefail
cd "$(dirname "$0")/../.."
scripts/install-deps.sh >/dev/null
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j "${BOP_JOBS:-2}" --target bop-map-cut bop-server bop-haptic bop-viewer >/dev/null
out=out/bench/cut
rm -rf "$out" && mkdir -p "$out"
echo "CPU: $(sed -n 's/^model name\s*: //p' /proc/cpuinfo | head -1), $(nproc) cores; $(date -u +%F)"
scene=config/scenes/torus-cut.toml

echo "== 1. the map edit of a cut, one core =="
OMP_NUM_THREADS=1 build/dynamics_server/bop-map-cut "$scene" --cache "$out/map.bopgm" --strokes 24 --check \
  --csv "$out/map-cut.csv" | tee "$out/map-cut.log"
/usr/bin/python3 - "$out/map-cut.csv" <<'PY'
import csv, sys, statistics
rows = list(csv.DictReader(open(sys.argv[1])))
small = [r for r in rows if int(r["window_voxels"]) <= 32 ** 3]
ms = [float(r["patch_ms"]) for r in small]
print(f"map edit: {len(rows)} strokes, all equal to a whole-grid rebuild: {all(r['equal'] == 'yes' for r in rows)}; "
      f"windows up to 32^3 voxels: {len(small)}, patch p50 {statistics.median(ms):.2f} ms, max {max(ms):.2f} ms "
      f"(target <= 5 ms: {'met' if max(ms) <= 5 else 'missed'}); rebuild of the whole grid p50 "
      f"{statistics.median(float(r['rebuild_ms']) for r in rows):.2f} ms")
PY

serve() {  # the placed torus, served at one rank; prints its endpoint
  local log=$1
  build/dynamics_server/bop-server "$scene" --restart "$out/settled/final.xyz" --cache "$out/map.bopgm" --port 0 \
    --steps 1000000000 --publish-hz 30 -o "$out/served" >"$log" 2>&1 &
  echo $! >"$log.pid"
  for _ in $(seq 1 300); do
    endpoint=$(sed -n 's/^listening on \(tcp:[^ ]*\).*/\1/p' "$log" | head -1)
    [[ -n $endpoint ]] && return 0
    sleep 0.1
  done
  echo "the server did not listen: $log" >&2
  exit 1
}
stop() { kill -INT "$(cat "$1.pid")" && wait "$(cat "$1.pid")" || true; }

build/dynamics_server/bop-server "$scene" --no-listen --cache "$out/map.bopgm" -o "$out/settled" >"$out/settle.log" 2>&1
grep -E "settled at step" "$out/settle.log" || true

echo "== 2. the haptic demo with a cut: bop-haptic sim:poke --cut, 5 s at 1 kHz =="
serve "$out/server-haptic.log"
build/haptic_client/bop-haptic "$endpoint" --device sim:poke --cut --seconds 5 --out "$out/haptic" | tee "$out/haptic.log"
stop "$out/server-haptic.log"
grep -E "^loop:|^cutting:" "$out/haptic.log"
echo "server: $(grep -c 'cut [0-9]* at step' "$out/server-haptic.log") cuts; the slowest map edit $(sed -n 's/.*map edited in \([0-9.]*\) ms/\1/p' "$out/server-haptic.log" | sort -g | tail -1) ms"

echo "== 3. the torus cut in two from Python, drawn by the headless viewer =="
serve "$out/server-two.log"
build/viz_client/bop-viewer "$endpoint" --headless --frames 24 --fps 3 --no-panel --width 640 --height 400 \
  --out "$out/frames" >"$out/viewer.log" 2>&1 &
viewer=$!
sleep 2
/usr/bin/python3 python/examples/cut.py "$endpoint" --radius-r0 3.2 --seconds 6 | tee "$out/two-pieces.log"
wait "$viewer" || true
stop "$out/server-two.log"
grep 'cut [0-9]* at step' "$out/server-two.log" || true
echo "pictures: $(ls "$out/frames"/*.png | wc -l) in $out/frames"
