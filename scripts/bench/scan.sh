#!/usr/bin/env bash
# A whole segmented scan ready to poke: the synthetic multi-label scan of
# scripts/make-scan-image.py (21 labels at 1 x 1 x 1.5 mm, organs touching, a hollow stomach with
# walls 1-3 voxels thick, a thin branching vessel tree, thin adrenal plates, specks, bumpy
# staircase boundaries) built at the defaults of config/scenes/scan.toml: every label as a bag,
# then the stomach alone (the thin-walled organ) and the liver alone, the stomach of a scan 3.9
# times larger (a thin-walled organ of about 45,000 particles), and a ball of radius 2.5 r0
# nested in another bag, and one bag of the scan's particle count and surface share (a flat slab:
# what many bags cost against one). Each is placed and settled by
# a batch run of bop-server, timed from start to its final state, and gives one row per bag:
# map and ready time, the step it settled at (and the minimiser's part), steps/s and particle-
# steps/s, each bag's surface and volume particles in their voxels, particles inside it and
# median normal angle, against the real-scans targets (scan.py). The settled scan is served and
# drawn by bop-viewer --headless (out/bench/scan.png).
#   scripts/bench/scan.sh            CSV in out/bench/scan.csv
#   BOP_SCAN_SCALE=S                 the scan's lengths times S (default 1.4: about 2.3e5 particles)
set -euo pipefail
cd "$(dirname "$0")/../.."
source scripts/bench/served.sh
scripts/install-deps.sh >/dev/null
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j "${BOP_JOBS:-2}" --target bop-server bop-viewer >/dev/null
out=out/bench/scan; rm -rf "$out"; mkdir -p "$out"
csv=out/bench/scan.csv
echo "scan: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ //'), $(nproc) cores, $(git rev-parse --short HEAD 2>/dev/null || echo 'no git')" >&2
/usr/bin/python3 scripts/make-scan-image.py "$out" --scale "${BOP_SCAN_SCALE:-1.4}" >"$out/image.txt"
head -1 "$out/image.txt" >&2
# The shipped scene on this image; one organ alone: the same with `labels` narrowed to its label.
sed -e "s|\"\\.\\./data/scan.nii.gz\"|\"$PWD/$out/scan.nii.gz\"|" -e "s|\"\\.\\./data/scan-labels.txt\"|\"$PWD/$out/scan-labels.txt\"|" \
  config/scenes/scan.toml >"$out/scan.toml"
sed 's|^labels = "all".*|labels = [2]|' "$out/scan.toml" >"$out/stomach.toml"
# A thin-walled organ of about 45,000 particles: the same stomach, its walls still 1.5-3.5 mm, in a
# scan 3.9 times the unscaled size (only the stomach's box of it is made).
/usr/bin/python3 scripts/make-scan-image.py "$out/thin-image" --stomach-only --scale "${BOP_THIN_SCALE:-3.9}" >/dev/null
sed -e "s|$PWD/$out/scan.nii.gz|$PWD/$out/thin-image/scan.nii.gz|" -e "s|$PWD/$out/scan-labels.txt|$PWD/$out/thin-image/scan-labels.txt|" \
  "$out/stomach.toml" >"$out/thin.toml"
sed 's|^labels = "all".*|labels = [1]|' "$out/scan.toml" >"$out/liver.toml"
# A ball of radius 2.5 r0 (5 voxels) nested off-centre in another, at the defaults.
cat >"$out/nested.toml" <<'EOF'
[grid]
voxel_size_mm = 1.0

[[shape.bag]]
name = "outer"
source = "sphere"
radius_mm = 16.0

[[shape.bag]]
name = "ball"
source = "sphere"
radius_mm = 5.0
center_mm = [4.0, 2.0, 1.0]
EOF

/usr/bin/python3 scripts/bench/scan.py header >"$csv"
for case in scan stomach liver nested thin slab; do
  if [ "$case" = slab ]; then
    # One bag of the scan's particle count and surface share: a flat round slab (superellipsoid of
    # radii a, a, c mm at 1 mm voxels, r0 = 2 mm), sized by a fit of such slabs' counts, surface
    # 1.9 a^2 and volume 1.08 a^2 (c - 1.1) particles per mm^2 of a^2.
    read -r n share < <(awk -F, '$1 == "scan" {print $7, $8; exit}' "$csv")
    read -r a c < <(awk -v n="$n" -v s="$share" 'BEGIN {c = 1.1 + 1.9 * (1 / s - 1) / 1.08;
      printf "%.1f %.2f\n", sqrt(n / (1.9 + 1.08 * (c - 1.1))), c}')
    printf '[grid]\nvoxel_size_mm = 1.0\n\n[[shape.bag]]\nname = "slab"\nsource = "superellipsoid"\nradii_mm = [%s, %s, %s]\nexponents = [0.2, 1.0]\n' \
      "$a" "$a" "$c" >"$out/slab.toml"
  fi
  t0=$(date +%s.%N)
  build/dynamics_server/bop-server "$out/$case.toml" --no-listen -o "$out/$case" --cache "$out/$case.bopgm" \
    >"$out/$case.log" 2>&1 || { tail -20 "$out/$case.log" >&2; echo "scan: $case failed" >&2; exit 1; }
  wall=$(awk -v a="$t0" -v b="$(date +%s.%N)" 'BEGIN {printf "%.1f", b - a}')
  /usr/bin/python3 scripts/bench/scan.py row "$case" "$out/$case.log" "$wall" >>"$csv"
  echo "scan: $case built and settled in $wall s ($(grep -m1 -o 'settled at step [0-9]*' "$out/$case.log" || echo 'not settled'))" >&2
done
# Many bags against one, again: the machine's speed wanders by 20% between runs, so each of the
# two runs once more, one after the other, and the ratio takes each one's faster run.
rates=$out/rates.txt
for case in scan slab; do
  awk -F, -v c="$case" '$1 == c {print c, $10; exit}' "$csv" >>"$rates"
done
for case in scan slab; do
  build/dynamics_server/bop-server "$out/$case.toml" --no-listen -o "$out/$case-again" --cache "$out/$case.bopgm" \
    >"$out/$case-again.log" 2>&1 || { tail -20 "$out/$case-again.log" >&2; echo "scan: $case failed" >&2; exit 1; }
  echo "$case $(awk '$1 == "this" && $2 == "run" {print $7; exit}' "$out/$case-again.log")" >>"$rates"
done
printf "%-8s %-20s %6s %7s %7s %7s %9s %6s %7s  %s\n" case bag surface volume "surf %" "vol %" "inside %" "angle" kind verdict
awk -F, 'NR > 1 {printf "%-8s %-20s %6s %7s %7s %7s %9s %6s %7s  %s\n", $1, $11, $12, $13, $14, $15, $16, $17, $19, $20}' "$csv"
awk -F, 'NR > 1 && !seen[$1]++ {printf "%-8s %8s particles (%s surface), map %s s, ready %s s, settled at step %s (%s by the minimiser), %s steps/s, %s particle-steps/s, %s s in all\n", $1, $7, $8, $3, $4, $5, $6, $9, $10, $2}' "$csv"
/usr/bin/python3 scripts/bench/scan.py targets "$csv" "$rates"

# The settled scan served from its final state and drawn with the panel listing its bags.
log=$out/serve.log
build/dynamics_server/bop-server "$out/scan.toml" --restart "$out/scan/final.xyz" --cache "$out/scan.bopgm" --port 0 \
  --publish-hz 5 -o "$out/served" >"$log" 2>&1 &
server=$!
trap 'kill $server 2>/dev/null || true' EXIT
endpoint=$(served_endpoint "$log" "$server")
[[ -n $endpoint ]] || { cat "$log" >&2; echo "scan: the served scan did not start" >&2; exit 1; }
timeout 120 build/viz_client/bop-viewer "$endpoint" --headless --frames 2 --width 1100 --height 700 \
  --out "$out/viewer" --screenshot out/bench/scan.png >"$out/viewer.log" 2>&1
echo "scan: rows in $csv, the settled scan drawn in out/bench/scan.png" >&2
