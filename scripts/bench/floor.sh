#!/usr/bin/env bash
# The arithmetic floor of the pair loops on this machine's CPU (bop-kernel-floor): ns per element
# of a division, a square root, both side by side (every LJ and oriented pair needs them), the
# loops' e^x (every oriented pair) and the LJ loop's own f(r)/r, each over an array in the L1
# cache, in the x86-64-v3 clone the loops run, best of 5 timings. Beside them, the bag's speed
# targets: an LJ pair in 1 ns and an oriented pair in 3 ns of one core. A floor above a target
# means no layout of the loops meets it in double precision here. The first row, a dependent
# chain of integer additions, reads the clock period, so ns can be turned into cycles.
#   scripts/bench/floor.sh    (CSV in out/bench/floor.csv)
set -euo pipefail
cd "$(dirname "$0")/../.."
scripts/install-deps.sh >/dev/null
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j "${BOP_JOBS:-2}" --target bop-kernel-floor >/dev/null
mkdir -p out/bench
build/dynamics_server/bop-kernel-floor --csv out/bench/floor.csv
awk -F, 'NR > 1 {gsub("\"", "", $1); ns[$1] = $2}
  END {
    clock = ns["integer add (clock period)"]; both = ns["division and square root"]
    printf "clock about %.2f GHz; a division and a square root: %.2f ns (%.1f cycles) per lane\n", 1 / clock, both, both / clock
    printf "LJ pair floor (f(r)/r alone): %.2f ns against the 1 ns target: %s\n", ns["LJ f(r)/r (forceOverR)"],
      (ns["LJ f(r)/r (forceOverR)"] > 1 ? "above it" : "below it")
    o = both + ns["e^x (simdExp)"]
    printf "oriented pair floor (division, root and e^x alone): %.2f ns against the 3 ns target: %s\n", o, (o > 3 ? "above it" : "below it")
  }' out/bench/floor.csv
echo "CSV: out/bench/floor.csv"
