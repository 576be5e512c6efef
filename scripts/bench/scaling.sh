#!/usr/bin/env bash
# Parallel scaling of the decomposed run: particle-steps per second at 1 and 2 ranks (mpirun)
# for the bulk box of scripts/bench/step.sh (displaced fcc lattice at nearest distance r0,
# switched cutoff [1.2, 1.6] r0, periodic, undamped, dt 0.005) at 100k and 1M particles, the
# parallel efficiency (rate at N ranks / (N x rate at 1 rank)), halo bytes per step, and LAMMPS
# at the same rank counts on the identical workload in the same run, as ratios. Best of
# BOP_BENCH_REPEATS (default 2) alternating runs of each code.
#   scripts/bench/scaling.sh [N ...]     (default 100000 1000000; CSV in out/bench/scaling.csv)
#   BOP_BENCH_RANKS="1 2"                 rank counts
set -euo pipefail
cd "$(dirname "$0")/../.."
sizes=("$@"); [[ ${#sizes[@]} -gt 0 ]] || sizes=(100000 1000000)
scripts/install-deps.sh --bench >/dev/null
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j "${BOP_JOBS:-2}" --target bop-server bop-lj-table >/dev/null
out=out/bench/scaling; mkdir -p "$out"
csv=out/bench/scaling.csv
echo "particles,ranks,steps,bop_particle_steps_per_s,lammps_atom_steps_per_s,ratio,bop_efficiency,lammps_efficiency,halo_bytes_per_step" >"$csv"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMP_NUM_THREADS=1
mpi=(mpirun --oversubscribe --bind-to core)
source scripts/bench/bulk-workload.sh
write_lj_table switched "$out/table.txt"

printf "%9s %5s %6s %14s %14s %6s %8s %8s %12s\n" particles ranks steps "BoP p-steps/s" "LAMMPS a-s/s" ratio "BoP eff" "LMP eff" "halo B/step"
for n in "${sizes[@]}"; do
  cells=$(awk -v n="$n" 'BEGIN {c = int((n / 4) ^ (1 / 3) + 0.5); print (c < 6 ? 6 : c)}')
  particles=$((4 * cells * cells * cells))
  steps=$(awk -v n="$particles" 'BEGIN {s = int(6e7 / n); if (s > 300) s = 300; if (s < 20) s = 20; print s}')
  scene=$out/bulk-$particles.toml
  write_bulk_inputs switched "$cells" "$steps" "$out/table.txt" "$scene" "$out/in-$particles.lmp"
  bop1="" lmp1=""
  for ranks in ${BOP_BENCH_RANKS:-1 2}; do
    bop=0 lmp_rate=0
    for ((rep = 1; rep <= ${BOP_BENCH_REPEATS:-2}; rep++)); do
      "${mpi[@]}" -np "$ranks" build/dynamics_server/bop-server "$scene" --no-listen --steps "$steps" \
        -o "$out/run-$particles-$ranks" --report-every "$steps" >"$out/bop-$particles-$ranks.log" 2>&1
      bop=$(best "$bop" "$(rate_of_bop "$out/bop-$particles-$ranks.log")")
      "${mpi[@]}" -np "$ranks" lmp -in "$out/in-$particles.lmp" -log none -screen "$out/lammps-$particles-$ranks.log" >/dev/null 2>&1 || true
      lmp_rate=$(best "$lmp_rate" "$(rate_of_lammps "$out/lammps-$particles-$ranks.log")")
    done
    halo=$(awk '/ranks: halo/ {print $4}' "$out/bop-$particles-$ranks.log"); halo=${halo:-0}
    [[ -n $bop1 ]] || { bop1=$bop; lmp1=$lmp_rate; }
    ratio=$(awk -v a="$bop" -v b="$lmp_rate" 'BEGIN {if (b > 0) printf "%.2f", a / b; else print "n/a"}')
    effb=$(awk -v a="$bop" -v b="$bop1" -v r="$ranks" 'BEGIN {printf "%.0f%%", 100 * a / (r * b)}')
    effl=$(awk -v a="$lmp_rate" -v b="$lmp1" -v r="$ranks" 'BEGIN {if (b > 0) printf "%.0f%%", 100 * a / (r * b); else print "n/a"}')
    printf "%9d %5d %6d %14.0f %14.0f %6s %8s %8s %12s\n" "$particles" "$ranks" "$steps" "$bop" "$lmp_rate" "$ratio" "$effb" "$effl" "$halo"
    echo "$particles,$ranks,$steps,$bop,$lmp_rate,$ratio,${effb%\%},${effl%\%},$halo" >>"$csv"
  done
done
echo "CSV: $csv"
