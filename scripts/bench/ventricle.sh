#!/usr/bin/env bash
# The beating ventricle (config/scenes/ventricle.toml: construction at end-diastole, then three
# cycles through the 8 gated frames) at 1 and 2 ranks: particles, steps per second over the
# whole run, and the paper's Table 1 figure beside them (1,431 particles at 6.5 frames/s on 12
# CPUs of an SGI Origin 2000; a frame there is one step), with the ratios. Also the ejection
# fractions and where the pressure peaks, from the run's summary.
#   scripts/bench/ventricle.sh            (CSV in out/bench/ventricle.csv)
#   BOP_BENCH_RANKS="1 2"                 rank counts
set -euo pipefail
cd "$(dirname "$0")/../.."
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j "${BOP_JOBS:-2}" --target bop-server >/dev/null
out=out/bench/ventricle; mkdir -p "$out"
csv=out/bench/ventricle.csv
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMP_NUM_THREADS=1
echo "ranks,surface,volume,total,steps_per_s,particle_steps_per_s,paper_particles,paper_frames_per_s,steps_ratio,particle_steps_ratio" >"$csv"
printf "%5s %8s %7s %6s %9s %15s   %s\n" ranks surface volume total "steps/s" "particle-steps/s" "vs paper (1431 at 6.5/s)"
for ranks in ${BOP_BENCH_RANKS:-1 2}; do
  log=$out/run-$ranks.log
  echo "running the ventricle at $ranks rank(s) (about a minute) ..." >&2
  mpirun --oversubscribe -np "$ranks" build/dynamics_server/bop-server config/scenes/ventricle.toml --no-listen \
    -o "$out/run-$ranks" >"$log" 2>&1
  read -r surface volume total rate prate < <(awk '/^this run/ {print $3, $4, $5, $6, $7}' "$log")
  ratio=$(awk -v r="$rate" 'BEGIN {printf "%.1f", r / 6.5}')
  pratio=$(awk -v r="$prate" 'BEGIN {printf "%.1f", r / (1431 * 6.5)}')
  printf "%5s %8s %7s %6s %9s %15s   %sx the steps/s, %sx the particle-steps/s\n" "$ranks" "$surface" "$volume" "$total" \
    "$rate" "$prate" "$ratio" "$pratio"
  echo "$ranks,$surface,$volume,$total,$rate,$prate,1431,6.5,$ratio,$pratio" >>"$csv"
  grep -E "^cycle" "$log" | sed 's/^/      /'
done
echo "CSV: $csv; pressure curves: $out/run-*/pressure.png"
