#!/usr/bin/env bash
# Two builds of bop-server against each other, alternately in one run, on the workloads of
# bag.sh and step.sh: the torus bag at scales 1 and 2 (1,363 and 9,208 particles) stepped 2,000
# steps from its built state at 1 rank x 1 thread and at 2 ranks x 1 thread, and bulk fcc with the
# switched cutoff (step.sh's workload) at 10,976 and 108,000 particles. Each run is repeated
# BOP_COMPARE_REPEATS times (default 3), old and new in turn, so that both meet the same load;
# median and best of each, and new/old of the medians. A refactoring is within noise when the
# ratios are within the spread of the repeats.
#   scripts/bench/compare.sh OLD_SERVER NEW_SERVER   (CSV in out/bench/compare.csv)
# e.g. build a commit apart: git worktree add /tmp/old COMMIT && cmake -S /tmp/old -B /tmp/old/build
# -G Ninja -DCMAKE_BUILD_TYPE=Release && cmake --build /tmp/old/build --target bop-server
set -euo pipefail
if [[ $# -ne 2 || $1 == -h || $1 == --help ]]; then sed -n '2,11p' "$0" | cut -c3-; [[ $# -eq 2 ]]; exit; fi
old=$(realpath "$1") new=$(realpath "$2")
for exe in "$old" "$new"; do [[ -x $exe ]] || { echo "compare.sh: $exe is not an executable bop-server" >&2; exit 2; }; done
cd "$(dirname "$0")/../.."
repeats=${BOP_COMPARE_REPEATS:-3}
out=out/bench/compare; rm -rf "$out"; mkdir -p "$out"
csv=out/bench/compare.csv
echo "workload,particles,layout,old_median,old_best,new_median,new_best,new_over_old" >"$csv"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMP_NUM_THREADS=1
echo "CPU:$(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2)"
echo "old: $old"; echo "new: $new"
# The rates of a run's summary line: steps/s ($6) and particle-steps/s ($7) (BatchReport.cpp).
rate() { awk -v f="$2" '/^this run/ {print $f}' "$1"; }
stats() { sort -g | awk '{a[NR] = $1} END {printf "%.4g %.4g\n", a[int((NR + 1) / 2)], a[NR]}'; }
report() {  # WORKLOAD PARTICLES LAYOUT UNIT
  read -r om ob < <(stats <"$out/old"); read -r nm nb < <(stats <"$out/new")
  local ratio; ratio=$(awk -v a="$om" -v b="$nm" 'BEGIN {printf "%.3f", b / a}')
  printf "%-10s %8s particles, %-16s %s: old median %s best %s, new median %s best %s, new/old %s\n" \
    "$1" "$2" "$3" "$4" "$om" "$ob" "$nm" "$nb" "$ratio"
  echo "$1,$2,$3,$om,$ob,$nm,$nb,$ratio" >>"$csv"
}
for s in 1 2; do
  scene=$out/torus-$s.toml
  sed -e "s|file = \"../models/torus.obj\"|file = \"$PWD/config/models/torus.obj\"|" \
      -e "s|^scale_mm = 1.0 |scale_mm = $s |" config/scenes/torus.toml >"$scene"
  "$new" "$scene" --no-listen -o "$out/built-$s" --cache "$out/torus-$s.bopgm" >"$out/built-$s.log" 2>&1
  particles=$(head -1 "$out/built-$s/final.xyz")
  for layout in "1 rank" "2 ranks"; do
    : >"$out/old"; : >"$out/new"
    for ((r = 0; r < repeats; ++r)); do
      for which in old new; do
        exe=$old; [[ $which == new ]] && exe=$new
        run=("$exe"); [[ $layout == "2 ranks" ]] && run=(mpirun -np 2 --oversubscribe "$exe")
        "${run[@]}" "$scene" --restart "$out/built-$s/final.xyz" --steps 2000 --no-listen -o "$out/step" \
          --cache "$out/torus-$s.bopgm" --report-every 2000 >"$out/log" 2>&1
        rate "$out/log" 6 >>"$out/$which"
      done
    done
    report "torus-$s" "$particles" "$layout" steps/s
  done
done
source scripts/bench/bulk-workload.sh
for cells in 14 30; do
  particles=$((4 * cells * cells * cells))
  steps=$(awk -v n=$particles 'BEGIN {s = int(3e7 / n); if (s > 300) s = 300; print s}')
  write_bulk_inputs switched "$cells" "$steps" "$out/table.txt" "$out/bulk-$particles.toml" "$out/in-$particles.lmp"
  : >"$out/old"; : >"$out/new"
  for ((r = 0; r < repeats; ++r)); do
    for which in old new; do
      exe=$old; [[ $which == new ]] && exe=$new
      "$exe" "$out/bulk-$particles.toml" --no-listen --steps "$steps" -o "$out/bulk" --report-every "$steps" \
        >"$out/log" 2>&1
      rate "$out/log" 7 >>"$out/$which"
    done
  done
  report bulk-fcc "$particles" "1 rank" particle-steps/s
done
