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

# write_ljcut_input SWITCHED_INPUT FILE: the switched box's LAMMPS input with 12-6 LJ in place of
# the table: its minimum at r0 (sigma = r0 / 2^(1/6)), epsilon 1, the same cutoff (1.6 r0) and so
# the same pairs per particle: a cost per pair for LAMMPS's lj/cut/opt and lj/cut/intel kernels.
write_ljcut_input() {
  sed -e 's|^pair_style table .*|pair_style lj/cut 2.7712812921102037|' \
    -e 's|^pair_coeff 1 1 .*|pair_coeff 1 1 1.0 1.5430818442170522|' "$1" >"$2"
}

# write_gromacs_inputs CELLS STEPS DIR: GROMACS's nearest equivalent of the switched box, a cost
# reference per pair, not the same potential: 12-6 LJ with its minimum at r0 (C6 = 2 r0^6,
# C12 = r0^12, epsilon 1), GROMACS's force switch on [1.2, 1.6] r0, pair list to 1.9 r0 rebuilt
# every 10 steps (its dynamic pruning on), the same lattice, displacement, box and steps; 1 length
# unit = 1 nm, mass 1 u, dt 0.005 ps. Writes DIR/conf.gro, DIR/topol.top, DIR/md.mdp.
write_gromacs_inputs() {
  local cells=$1 steps=$2 dir=$3
  mkdir -p "$dir"
  awk -v c="$cells" 'BEGIN {
    a = sqrt(6); d = 0.08660254037844387; srand(4242); n = 4 * c * c * c
    split("0 0.5 0.5 0", bx, " "); split("0 0.5 0 0.5", by, " "); split("0 0 0.5 0.5", bz, " ")
    print "bulk fcc, displaced"; print n
    k = 0
    for (i = 0; i < c; i++) for (j = 0; j < c; j++) for (l = 0; l < c; l++) for (b = 1; b <= 4; b++) {
      k++
      x = (i + bx[b]) * a + d * (2 * rand() - 1); y = (j + by[b]) * a + d * (2 * rand() - 1)
      z = (l + bz[b]) * a + d * (2 * rand() - 1)
      printf "%5d%-5s%5s%5d%8.3f%8.3f%8.3f\n", k % 100000, "LJ", "LJ", k % 100000, x, y, z
    }
    printf "%10.5f%10.5f%10.5f\n", c * a, c * a, c * a
  }' >"$dir/conf.gro"
  cat >"$dir/topol.top" <<TOP
[ defaults ]
; nbfunc comb-rule gen-pairs
1 1 no
[ atomtypes ]
; name at.num mass charge ptype C6 C12 (r0 = sqrt(3): C6 = 2 r0^6, C12 = r0^12)
LJ 0 1.0 0.0 A 54.0 729.0
[ moleculetype ]
LJ 1
[ atoms ]
1 LJ 1 LJ LJ 1 0.0 1.0
[ system ]
bulk
[ molecules ]
LJ $((4 * cells * cells * cells))
TOP
  cat >"$dir/md.mdp" <<MDP
integrator = md
dt = 0.005
nsteps = $steps
cutoff-scheme = Verlet
nstlist = 10
verlet-buffer-tolerance = -1
rlist = 3.2908965343808667
vdwtype = Cut-off
vdw-modifier = Force-switch
rvdw-switch = 2.0784609690826525
rvdw = 2.7712812921102037
coulombtype = Cut-off
rcoulomb = 2.7712812921102037
pbc = xyz
tcoupl = no
pcoupl = no
gen-vel = no
DispCorr = no
nstcalcenergy = $steps
nstenergy = 0
nstlog = 0
MDP
}

# run_gromacs DIR [GMX]: grompp and one mdrun on one core (-ntmpi 1 -ntomp 1 -nb cpu) with GMX
# (default: Debian's gmx); its log is DIR/md.log.
run_gromacs() {
  local g=${2:-gmx}
  (cd "$1" && "$g" -quiet -nobackup grompp -f md.mdp -c conf.gro -p topol.top -o run.tpr >grompp.log 2>&1 &&
    "$g" -quiet -nobackup mdrun -s run.tpr -deffnm md -ntmpi 1 -ntomp 1 -nb cpu -noconfout >mdrun.out 2>&1) || true
}

# why_gromacs_failed DIR: one line saying why GROMACS gave no rate, from its own words in DIR (the
# Debian build stops on a CPU without the rdtscp instruction, which some VMs hide).
why_gromacs_failed() {
  local log
  for log in "$1/mdrun.out" "$1/grompp.log"; do
    [[ -s $log ]] || continue
    if grep -q "rdtscp" "$log"; then
      echo "GROMACS did not run: its Debian build is compiled to use the rdtscp instruction, which this CPU or VM does not offer (grep rdtscp /proc/cpuinfo finds nothing); $log says: $(grep -m1 -i "rdtscp" "$log" | sed 's/^ *//')"
      return
    fi
    if grep -qiE "fatal error|^error" "$log"; then
      echo "GROMACS stopped: $(grep -m1 -iA3 -E "fatal error|^error" "$log" | tr -s ' \n' ' ' | cut -c1-300) ($log)"
      return
    fi
  done
  command -v gmx >/dev/null || { echo "GROMACS did not run: gmx is not installed (scripts/install-deps.sh --bench installs it)"; return; }
  echo "GROMACS gave no rate: no performance summary in $1/md.log (see $1/mdrun.out)"
}

# Rates from the logs: BoP's "this run" particle-steps/s, LAMMPS's atoms x steps / loop time.
rate_of_bop() { awk '/^this run/ {print $7}' "$1"; }
# GROMACS's atoms x steps / wall time of its performance summary ("Time:" line).
rate_of_gromacs() {
  awk '/nsteps *=/ && !s {s = $3} /^ *Time:/ {t = $3} END {if (t > 0) printf "%.0f", n * s / t}' \
    n="$(sed -n 2p "$(dirname "$1")/conf.gro")" "$1"
}
rate_of_lammps() { awk '/^Loop time of/ {t=$4; s=$9; n=$12} END {if (t > 0) printf "%.0f", n*s/t}' "$1"; }
best() { awk -v a="$1" -v b="${2:-0}" 'BEGIN {print (b > a ? b : a)}'; }
