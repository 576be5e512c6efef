#!/usr/bin/env bash
# The bag's step rate against its size: the torus scene (config/scenes/torus.toml) scaled by
# SCALE (its mesh's mm per unit; particles grow about as SCALE^3: 1,363 at 1, 9,208 at 2,
# 139,703 at 5 and 1.1 million at 10), each built by its own construction timeline (wall time and births per
# second; the surface grows from step 0, the volume from step 1,500, 4,000 steps in all, each
# stretched by SCALE / 2 above scale 2 because the growth fronts travel farther), then stepped from
# its built state at one rank with 1 thread, with 2 threads, and at 2 ranks of 1 thread. Per run:
# steps/s, ns per particle-step, the pair phase per step (one rank) and the pairs in range of
# each kind (LJ, oriented), ns per pair in range (both kinds together, wall time of the phase),
# and each loop's CPU time per pair of its kind (summed over threads). A PNG plots steps/s and
# ns per particle-step against the particle count.
#   scripts/bench/bag.sh [SCALE ...]   (default 1 1.4 2 5; CSV in out/bench/bag.csv, plot in
#                                       out/bench/bag.png); scale 10 (10^6 particles) built for 67
#                                       minutes here with BOP_BAG_BUILD_STEPS=12500 (longer by default)
#   BOP_BAG_STEPS    most steps from the built state (default 2000; fewer above 15k particles:
#                    3e7 / particles, at least 20)
#   BOP_BAG_BUILD_STEPS  construction steps in all (default 4,000 x the stretch; the volume still
#                    starts at 1,500 x the stretch)
#   BOP_BAG_APPEND=1 add rows to an existing CSV (a large scale run on its own) instead of a new one
set -euo pipefail
cd "$(dirname "$0")/../.."
scales=("$@"); [[ ${#scales[@]} -gt 0 ]] || scales=(1 1.4 2 5)
max_steps=${BOP_BAG_STEPS:-2000}
scripts/install-deps.sh --bench >/dev/null
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j "${BOP_JOBS:-2}" --target bop-server >/dev/null
out=out/bench/bag; mkdir -p "$out"
csv=out/bench/bag.csv
[[ -n ${BOP_BAG_APPEND:-} && -s $csv ]] || echo "scale,surface,volume,particles,construction_s,births_per_s,layout,steps_per_s,ns_per_particle_step,pairs_ms_per_step,lj_pairs,oriented_pairs,ns_per_pair,cpu_ns_per_lj_pair,cpu_ns_per_oriented_pair" >"$csv"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
server=build/dynamics_server/bop-server
printf "%-6s %9s %10s %9s  %-18s %9s %11s %9s %9s %9s %8s %7s %7s\n" scale particles "build s" births/s layout steps/s ns/p-step \
  "pairs ms" "LJ pairs" oriented "ns/pair" "ns/LJ" "ns/or."
for s in "${scales[@]}"; do
  scene=$out/torus-$s.toml
  stretch=$(awk -v s="$s" 'BEGIN {print (s > 2 ? s / 2 : 1)}')
  volume_from=$(awk -v f="$stretch" 'BEGIN {printf "%d", 1500 * f}')
  build_steps=${BOP_BAG_BUILD_STEPS:-$(awk -v f="$stretch" 'BEGIN {printf "%d", 4000 * f}')}
  sed -e "s|file = \"../models/torus.obj\"|file = \"$PWD/config/models/torus.obj\"|" \
      -e "s|^scale_mm = 1.0 |scale_mm = $s |" -e "s|^step = 1500$|step = $volume_from|" \
      -e "s|^steps = 4000$|steps = $build_steps|" config/scenes/torus.toml >"$scene"
  grep -q "^scale_mm = $s " "$scene" && grep -q "^steps = $build_steps$" "$scene" &&
    [[ $(grep -c "^step = $volume_from$" "$scene") == 2 ]] ||
    { echo "bag.sh: could not set scale_mm and the timeline in $scene" >&2; exit 1; }
  echo "bag.sh: building the torus at scale $s ($build_steps construction steps, volume from step $volume_from)..." >&2
  start=$(date +%s.%N)
  "$server" "$scene" --no-listen -o "$out/build-$s" >"$out/build-$s.log" 2>&1
  built=$(awk -v t0="$start" -v t1="$(date +%s.%N)" 'BEGIN {printf "%.1f", t1 - t0}')
  read -r surface volume total < <(awk '/^this run/ {print $3, $4, $5}' "$out/build-$s.log")
  births=$(awk -v t="$built" '/^births/ {gsub(",", "", $2); printf "%.0f", $2 / t}' "$out/build-$s.log")
  steps=$(awk -v n="$total" -v m="$max_steps" 'BEGIN {s = int(3e7 / n); if (s > m) s = m; if (s < 20) s = 20; print s}')
  for layout in "1 rank x 1 thread" "1 rank x 2 threads" "2 ranks x 1 thread"; do
    log=$out/step-$s-${layout// /_}.log
    case $layout in
      "1 rank x 1 thread") run=(env OMP_NUM_THREADS=1 "$server") ;;
      "1 rank x 2 threads") run=(env OMP_NUM_THREADS=2 "$server") ;;
      *) run=(env OMP_NUM_THREADS=1 mpirun -np 2 --oversubscribe "$server") ;;
    esac
    "${run[@]}" "$scene" --restart "$out/build-$s/final.xyz" --steps "$steps" --no-listen -o "$out/step-$s" \
      --report-every "$steps" >"$log" 2>&1
    rate=$(awk '/^this run/ {print $6}' "$log")
    ns=$(awk -v r="$rate" -v n="$total" 'BEGIN {printf "%.0f", 1e9 / (r * n)}')
    pairs=$(awk '/^pairs / {print $2}' "$log")
    lj=$(sed -n 's/.*(\([0-9]*\) within the cutoff).*/\1/p' "$log")
    oriented=$(sed -n 's/.*oriented pairs within theirs (\([0-9]*\)).*/\1/p' "$log")
    read -r nslj nsor < <(sed -n 's/^pair loops.*: \([0-9.]*\) ns per LJ.*, \([0-9.]*\) ns per oriented.*/\1 \2/p' "$log") || true
    perpair=$(awk -v ms="${pairs:-0}" -v a="${lj:-0}" -v b="${oriented:-0}" 'BEGIN {if (ms > 0 && a + b > 0) printf "%.1f", ms * 1e6 / (a + b); else print ""}')
    printf "%-6s %9d %10s %9s  %-18s %9.1f %11s %9s %9s %9s %8s %7s %7s\n" "$s" "$total" "$built" "$births" "$layout" \
      "$rate" "$ns" "${pairs:--}" "${lj:--}" "${oriented:--}" "${perpair:--}" "${nslj:--}" "${nsor:--}"
    echo "$s,$surface,$volume,$total,$built,$births,$layout,$rate,$ns,${pairs:-},${lj:-},${oriented:-},${perpair:-},${nslj:-},${nsor:-}" >>"$csv"
  done
done
/usr/bin/python3 python/bop/plots.py bag "$csv" out/bench/bag.png >/dev/null
echo "CSV: $csv; plot: out/bench/bag.png; logs: $out/"
