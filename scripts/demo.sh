#!/usr/bin/env bash
# The whole system on the embedded default scene (the torus) in one command: installs what is
# missing, builds, builds the torus's gradient map (slice pictures) and its bag of particles
# (a batch run), then serves the bag for about BOP_DEMO_SECONDS (30) seconds, at one rank with
# every core but one as a thread (BOP_DEMO_RANKS=2 runs it under mpirun at 2 ranks instead;
# BOP_DEMO_THREADS sets the threads per rank), with a
# scripted haptic device poking it (sim:poke) and a viewer watching: headless (PNG frames, an MP4
# when ffmpeg is present) or, when a display is present, the window. Ends with a summary of the
# measured figures and where the pictures are.
#   scripts/demo.sh                     BOP_DEMO_SECONDS=60 for longer; BOP_DEMO_HEADLESS=1 forces headless
# A bag this small steps fastest on one machine as one process whose threads share the cores (no
# halo, no messages between ranks; docs/parallel.md); the server prints the layout it took. The
# haptic client and the viewer run on the same machine, so the server leaves them a core: on a
# 2-core machine, 1 server thread stepped the torus at 1,204-1,265 steps/s with a probe round
# trip p99 of 4.0-5.0 ms, 2 threads at 540-907 steps/s and 13-16 ms (docs/parallel.md).
set -euo pipefail
cd "$(dirname "$0")/.."
jobs=${BOP_JOBS:-2}
seconds=${BOP_DEMO_SECONDS:-30}
ranks=${BOP_DEMO_RANKS:-1}
cores=$(nproc)
threads=${BOP_DEMO_THREADS:-$(((cores - 1) / ranks > 0 ? (cores - 1) / ranks : 1))}
out=out/demo

scripts/install-deps.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release -DBOP_BUILD_VIEWER=ON >/dev/null
cmake --build build -j "$jobs" --target bop-shape bop-server bop-viewer bop-haptic
if [[ $(id -u) == 0 ]]; then export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1; fi
mkdir -p "$out"

echo "== the torus's gradient map (bop-shape) =="
build/dynamics_server/bop-shape config/scenes/torus.toml -o "$out/torus" --export all
echo "== the torus bag: construction and relaxation (bop-server batch run, about 10 s) =="
build/dynamics_server/bop-server config/scenes/torus.toml --no-listen -o "$out/torus" | tail -6

echo "== several organs in one scene: liver with a tumour, stomach, spleen, touching (placed and settled, about 5 s) =="
build/dynamics_server/bop-server config/scenes/organs.toml --no-listen -o "$out/organs" | grep -E "placed|settled|fidelity"

echo "== served for ${seconds} s ($ranks rank(s) x $threads thread(s), a core left to the clients): a haptic device pokes it, a viewer watches =="
pids=()
cleanup() { for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; done; }
trap cleanup EXIT
launch=()
[[ $ranks -gt 1 ]] && launch=(mpirun --oversubscribe -np "$ranks")
"${launch[@]}" build/dynamics_server/bop-server config/scenes/torus.toml \
  --restart "$out/torus/final.xyz" --cache "$out/torus/gradient-map.bopgm" --port 0 --publish-hz 30 --threads "$threads" \
  -o "$out/served" >"$out/server.log" 2>&1 &
server=$!
pids+=("$server")
endpoint=""
for _ in $(seq 1 600); do  # up to 60 s for the map and the start
  endpoint=$(sed -n 's/^listening on \(tcp:[^ ]*\).*/\1/p' "$out/server.log" | head -1)
  [[ -n $endpoint ]] && break
  kill -0 "$server" 2>/dev/null || { cat "$out/server.log"; echo "demo: the server stopped" >&2; exit 1; }
  sleep 0.1
done
[[ -n $endpoint ]] || { cat "$out/server.log"; echo "demo: the server did not start listening" >&2; exit 1; }
echo "server listening on $endpoint (log: $out/server.log)"

build/haptic_client/bop-haptic "$endpoint" --device sim:poke --seconds "$seconds" --out "$out/haptic" \
  >"$out/haptic.log" 2>&1 &
haptic=$!
pids+=("$haptic")
fps=5
viewerStart=$(date +%s.%N)
if [[ -n ${DISPLAY:-} && -z ${BOP_DEMO_HEADLESS:-} ]]; then
  echo "a display is present: the viewer opens its window (close it to end the demo early)"
  build/viz_client/bop-viewer "$endpoint" --out "$out/viewer" >"$out/viewer.log" 2>&1 &
  viewer=$!
  headless=0
else
  build/viz_client/bop-viewer "$endpoint" --headless --fps "$fps" --frames $((seconds * fps)) --out "$out/viewer" \
    >"$out/viewer.log" 2>&1 &
  viewer=$!
  headless=1
fi
pids+=("$viewer")
wait "$haptic" || echo "demo: the haptic client ended with an error (see $out/haptic.log)" >&2
if [[ $headless == 1 ]]; then
  wait "$viewer" || echo "demo: the viewer ended with an error (see $out/viewer.log)" >&2
  viewerSeconds=$(awk -v a="$viewerStart" -v b="$(date +%s.%N)" 'BEGIN {printf "%.1f", b - a}')
else
  kill "$viewer" 2>/dev/null || true
fi
kill -INT "$server" 2>/dev/null || true
for _ in $(seq 1 300); do kill -0 "$server" 2>/dev/null || break; sleep 0.1; done  # up to 30 s to stop
if kill -0 "$server" 2>/dev/null; then
  echo "demo: the server did not stop within 30 s; killed (see $out/server.log)" >&2
  kill -KILL "$server" 2>/dev/null || true
fi
wait "$server" 2>/dev/null || true
trap - EXIT

mp4=""
if [[ $headless == 1 ]] && command -v ffmpeg >/dev/null; then
  ffmpeg -loglevel error -y -framerate "$fps" -i "$out/viewer/frame-%06d.png" -pix_fmt yuv420p \
    -vf "pad=ceil(iw/2)*2:ceil(ih/2)*2" "$out/viewer/demo.mp4" && mp4="$out/viewer/demo.mp4"
fi

# The figures, from what each process wrote.
csv=$out/viewer/frames.csv
summary=$out/summary.txt
{
  echo "BoP demo: the torus served for ${seconds} s, poked by sim:poke, watched by bop-viewer"
  sed -n 's/^\[bop-server\] \(layout: .*\)/server \1/p' "$out/server.log" | head -1
  [[ $headless == 1 ]] || echo "(the viewer had a window: its rates were on its panel)"
  if [[ -s $csv ]]; then
    awk -F, 'NR > 1 {n++; if (n == 1) {t0 = $3; s0 = $2} t1 = $3; s1 = $2; p = $8; r += $7}
             END {if (n) printf "particles: %d\nserver step rate: %.0f steps/s (mean over %d frames)\n", p, r / n, n}' "$csv"
    [[ -n ${viewerSeconds:-} ]] && awk -v n="$(($(wc -l <"$csv") - 1))" -v s="$viewerSeconds" \
      'BEGIN {printf "viewer: %d frames drawn in %.1f s, %.1f frames/s (asked for %d)\n", n, s, n / s, '"$fps"'}'
  fi
  grep -h -E '^loop: ' "$out/haptic.log" | sed 's/^loop: /haptic loop: /' || true
  grep -h -E '^probe round trip' "$out/haptic.log" || true
  grep -h -E '^largest force rendered' "$out/haptic.log" || true
  grep -h -E '^served ' "$out/server.log" || true
} | tee "$summary"

echo
echo "Summary:   $summary"
if [[ $headless == 1 ]]; then
  echo "Pictures:  $out/viewer/frame-*.png (the viewer's frames$([[ -n $mp4 ]] && echo ", and $mp4"))"
else
  echo "Pictures:  the viewer's screenshots (S in its window) in $out/viewer"
fi
echo "Force:     $out/haptic/stiffness.png (force felt against depth), $out/haptic/haptic-trace.csv (every tick)"
echo "Map:       $out/torus/slice-{xy,xz,yz}.png (labels, signed distance, co-planar weight)"
echo "Particles: $out/torus/final.xyz and $out/served/final.xyz (extended XYZ; OVITO opens them)"
