# Sourced by step.sh and scaling.sh: the bulk workload both codes run, and how their rates are
# read. Material at nearest distance r0 = sqrt(3) (fcc cube edge sqrt(2) r0, LAMMPS lattice
# density 0.2722), every site displaced uniformly by up to 0.05 r0 = 0.0866 per axis, periodic,
# undamped, dt 0.005, neighbour skin 0.3 r0 = 0.5196 in LAMMPS (BoP's default).

# write_lj_table MODE FILE: our LJ form as a LAMMPS table (switched [1.2, 1.6] r0, or paper at 2.99 r0).
write_lj_table() {
  build/dynamics_server/bop-lj-table "$2" --mode "$1" \
    $([[ $1 == switched ]] && echo "--switch-r0 1.2 --cutoff-r0 1.6" || echo "--cutoff-r0 2.99") >/dev/null
}

# write_bulk_inputs MODE CELLS STEPS TABLE SCENE LAMMPS_INPUT: a box of CELLS^3 fcc cells as a
# BoP scene and as a LAMMPS input running STEPS steps with the table.
write_bulk_inputs() {
  local mode=$1 cells=$2 steps=$3 table=$4 scene=$5 lammps=$6 side cutoff
  side=$(awk -v c="$cells" 'BEGIN {printf "%.17g", c * sqrt(2)}')
  cutoff=$([[ $mode == switched ]] && echo 2.7712812921102037 || echo 5.178831647964295)
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
lj_cutoff = "$mode"
$([[ $mode == switched ]] && echo 'lj_switch_r0 = [1.2, 1.6]' || echo 'lj_cutoff_r0 = 2.99')
TOML
  cat >"$lammps" <<LMP
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
pair_coeff 1 1 $table LJ $cutoff
neighbor 0.5196152422706632 bin
neigh_modify every 1 delay 0 check yes
timestep 0.005
fix 1 all nve
thermo $steps
run $steps
LMP
}

# Rates from the logs: BoP's "this run" particle-steps/s, LAMMPS's atoms x steps / loop time.
rate_of_bop() { awk '/^this run/ {print $7}' "$1"; }
rate_of_lammps() { awk '/^Loop time of/ {t=$4; s=$9; n=$12} END {if (t > 0) printf "%.0f", n*s/t}' "$1"; }
best() { awk -v a="$1" -v b="${2:-0}" 'BEGIN {print (b > a ? b : a)}'; }
