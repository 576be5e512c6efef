#!/usr/bin/env bash
# The cluster-pair prototype (bop-cluster-proto, dynamics_server/app/tools/ClusterPairProto.hpp)
# against BoP's pair loops in one run, one core: the bulk box of step.sh (fcc at r0, periodic) at
# 10,976 and 97,556 particles and the torus built by placement (scripts/bench/bag.sh at scale 1,
# run first if its state is missing). Per workload and loop (LJ at 1.6 r0, oriented at 3 r0): the
# cluster pairs' useful share, the prototype's ns per pair computed and per pair in range, BoP's
# loops' ns per pair in range in double and mixed, and the gains. The layout is worth building
# when it gains 1.5x on the pair phase of the bulk box and of the torus (issue 53's rule): those
# gains are printed at the end from the CSV. Then the LJ loop of the layout as built in the core's
# form (bop-cluster-proto --help) against the core's LJ loop on the same pruned list, its forces
# checked against it: the measure that decided (docs/dynamics.md, "A cluster-pair layout").
#   scripts/bench/cluster-proto.sh    (CSV in out/bench/cluster-proto.csv)
set -euo pipefail
cd "$(dirname "$0")/../.."
case "${1:-}" in
  "") ;;
  -h|--help) sed -n '2,13p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
  *) echo "cluster-proto.sh: no arguments expected, not '$1' (--help)" >&2; exit 2 ;;
esac
scripts/install-deps.sh --bench >/dev/null
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j "${BOP_JOBS:-2}" --target bop-cluster-proto bop-server >/dev/null
bag=out/bench/bag
if [[ ! -s $bag/build-1/final.xyz || ! -s $bag/step-torus-1.toml ]]; then
  echo "cluster-proto.sh: building the torus first (scripts/bench/bag.sh 1)..." >&2
  BOP_BAG_REPEATS=1 scripts/bench/bag.sh 1 >/dev/null
fi
mkdir -p out/bench
csv=out/bench/cluster-proto.csv
echo "CPU: $(sed -n 's/^model name[[:space:]]*: *//p' /proc/cpuinfo | head -1)"
OMP_NUM_THREADS=1 build/dynamics_server/bop-cluster-proto --cells 14 29 --steps 300 --repeats 5 --csv "$csv" \
  --scene "$bag/step-torus-1.toml" --restart "$bag/build-1/final.xyz" --cache "$bag/build-1/gradient-map.bopgm"
# The pair phase per workload: the loops' time at the prototype's ns per pair against BoP's. The
# bulk box's is its LJ loop alone (step.sh's box has no surface); the lattice's oriented rows
# measure that loop on more pairs than the torus has. Then the LJ loop as built ("LJ built": double
# differences and sums, the list's pairs) against the core's LJ loop on the same list.
awk -F, 'NR > 1 && $3 != "LJ built" && !($1 == "fcc box" && $3 != "LJ") {
    w = ($1 == "fcc box" ? "bulk box, LJ" : $1 ", LJ and oriented") " (" $2 " particles)"
    proto[w] += $6 * $9; dbl[w] += $6 * $10; mix[w] += $6 * $11
  }
  NR > 1 && $3 == "LJ built" {
    printf "LJ loop as built, %s (%s particles): %.2fx BoP double, %.2fx BoP mixed on the same list (build at >= 1.5x)\n",
      $1, $2, $12, $13
  }
  END {for (w in proto) printf "pair phase, %s: prototype %.2fx BoP double, %.2fx BoP mixed (build at >= 1.5x)\n",
       w, dbl[w] / proto[w], mix[w] / proto[w]}' "$csv"
echo "CSV: $csv"
