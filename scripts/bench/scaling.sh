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
build/dynamics_server/bop-lj-table "$out/table.txt" --mode switched --switch-r0 1.2 --cutoff-r0 1.6 >/dev/null
rate_of_bop() { awk '/^this run/ {print $7}' "$1"; }
rate_of_lammps() { awk '/^Loop time of/ {t=$4; s=$9; n=$12} END {if (t > 0) printf "%.0f", n*s/t}' "$1"; }
best() { awk -v a="$1" -v b="${2:-0}" 'BEGIN {print (b > a ? b : a)}'; }

printf "%9s %5s %6s %14s %14s %6s %8s %8s %12s\n" particles ranks steps "BoP p-steps/s" "LAMMPS a-s/s" ratio "BoP eff" "LMP eff" "halo B/step"
for n in "${sizes[@]}"; do
  cells=$(awk -v n="$n" 'BEGIN {c = int((n / 4) ^ (1 / 3) + 0.5); print (c < 6 ? 6 : c)}')
  particles=$((4 * cells * cells * cells))
  steps=$(awk -v n="$particles" 'BEGIN {s = int(6e7 / n); if (s > 300) s = 300; if (s < 20) s = 20; print s}')
  side=$(awk -v c="$cells" 'BEGIN {printf "%.17g", c * sqrt(2)}')
  scene=$out/bulk-$particles.toml
  cat >"$scene" <<TOML
[box]
size_r0 = [$side, $side, $side]
spacing_r0 = 1.0
jitter_r0 = 0.1
periodic = true
[[species]]
name = "bulk"
kind = "volume"
drag_v = 0.0
[dynamics]
time_step = 0.005
lj_cutoff = "switched"
lj_switch_r0 = [1.2, 1.6]
TOML
  cat >"$out/in-$particles.lmp" <<LMP
units lj
atom_style atomic
boundary p p p
lattice fcc 0.27216552697590868
region box block 0 $cells 0 $cells 0 $cells
create_box 1 box
create_atoms 1 box
displace_atoms all random 0.08660254037844387 0.08660254037844387 0.08660254037844387 4242 units box
mass 1 1.0
pair_style table linear 20000
pair_coeff 1 1 $out/table.txt LJ 2.7712812921102037
neighbor 0.5196152422706632 bin
neigh_modify every 1 delay 0 check yes
timestep 0.005
fix 1 all nve
thermo $steps
run $steps
LMP
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
