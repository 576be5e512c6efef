#!/usr/bin/env bash
# bop-igtl's targets (docs/igtl.md): the torus of scripts/bench/bag.sh at scale 2 (about 12,000
# particles; built first if its state is missing) served at one rank; its step rate read from the
# frames' stats for 10 s alone, then for 10 s with bop-igtl bridging it to ten OpenIGTLink clients,
# nine of which never read and one that reads everything (tests/igtl/igtl_spec_client.py, written
# from the protocol's specification): that client's updates per second (target >= 30)
# and the run's step rate with the clients against without (target: at most 5% lower; without:
# the mean of a window before bop-igtl starts and one after it stops). Prints the CPU, the rates
# and the drop, met or missed; CSV in out/bench/igtl.csv.
#   scripts/bench/igtl.sh
#   BOP_IGTL_RATE   bop-igtl's --rate (default 60)
set -euo pipefail
cd "$(dirname "$0")/../.."
case "${1:-}" in
  "") ;;
  -h|--help) sed -n '2,12p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
  *) echo "igtl.sh: no arguments expected, not '$1' (--help)" >&2; exit 2 ;;
esac
scripts/install-deps.sh >/dev/null
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j "${BOP_JOBS:-2}" --target bop-server bop-igtl >/dev/null
bag=out/bench/bag
if [[ ! -s $bag/build-2/final.xyz || ! -s $bag/step-torus-2.toml ]]; then
  echo "igtl.sh: building the torus at scale 2 first (scripts/bench/bag.sh 2)..." >&2
  BOP_BAG_REPEATS=1 scripts/bench/bag.sh 2 >/dev/null
fi
out=out/bench/igtl
mkdir -p "$out"
igtl_rate=${BOP_IGTL_RATE:-60}  # what bop-igtl is asked for: above the target, to show what it reaches
py=/usr/bin/python3
OMP_NUM_THREADS=1 build/dynamics_server/bop-server "$bag/step-torus-2.toml" --restart "$bag/build-2/final.xyz" \
  --cache "$bag/build-2/gradient-map.bopgm" --port 0 --steps 1000000000 -o "$out/served" >"$out/server.log" 2>&1 &
server=$!
pids=("$server")
trap 'kill "${pids[@]}" 2>/dev/null || true' EXIT
first_match() {  # first_match LOG SED_SCRIPT: its first output, waiting up to 60 s for the process to write it
  local found=""
  for _ in $(seq 1 600); do
    found=$(sed -n "$2" "$1" | head -1)
    [[ -n $found ]] && break
    sleep 0.1
  done
  echo "$found"
}
endpoint=$(first_match "$out/server.log" 's/^listening on \(tcp:[^ ]*\).*/\1/p')
[[ -n $endpoint ]] || { echo "igtl.sh: the server did not start ($out/server.log)" >&2; exit 1; }
rate() {  # the run's mean step rate over $1 s, from its frames' stats, and its particle count
  "$py" - "$endpoint" "$1" <<'PY'
import sys, time
sys.path.insert(0, "python")
import bop
with bop.Client(sys.argv[1]) as c:
    n = len(c.latest_frame())
    end, rates = time.monotonic() + float(sys.argv[2]), []
    while time.monotonic() < end:
        rates.append(c.frame().stats["step_rate_hz"])
print(f"{sum(rates) / len(rates):.1f} {n}")
PY
}
sleep 3
read -r alone1 particles < <(rate 10)
build/protocol/bop-igtl "$endpoint" --igtl-port 0 --rate "$igtl_rate" >"$out/igtl.log" 2>&1 &
igtl=$!
pids+=("$igtl")
port=$(first_match "$out/igtl.log" 's/^OpenIGTLink listening on port \([0-9]*\).*/\1/p')
[[ -n $port ]] || { echo "igtl.sh: bop-igtl did not start ($out/igtl.log)" >&2; exit 1; }
"$py" tests/igtl/igtl_spec_client.py idle --port "$port" --count 9 --seconds 16 >"$out/idle.txt" &
idle=$!
pids+=("$idle")
"$py" tests/igtl/igtl_spec_client.py check --port "$port" --seconds 14 >"$out/check.txt" &
reader=$!
sleep 2
read -r with _ < <(rate 10)
wait "$reader" "$idle"
kill -INT "$igtl"
wait "$igtl" || true
# The run alone once more: the mean of the two windows without clients is the baseline, so that
# a drift of the machine's speed over the minute is not counted against the clients.
read -r alone2 _ < <(rate 10)
alone=$(awk -v a="$alone1" -v b="$alone2" 'BEGIN {printf "%.1f", (a + b) / 2}')
updates=$(sed -n 's/^updates_per_s=//p' "$out/check.txt")
points=$(sed -n 's/^surface_points=//p' "$out/check.txt")
drop=$(awk -v a="$alone" -v w="$with" 'BEGIN {printf "%.1f", 100 * (a - w) / a}')
echo "CPU: $(sed -n 's/^model name[[:space:]]*: *//p' /proc/cpuinfo | head -1); the torus at scale 2, ${particles:-?} particles (${points:-?} on the surface), one rank, one thread"
echo "served run alone: $alone steps/s ($alone1 before, $alone2 after); with bop-igtl and 10 clients (9 never reading): $with steps/s; drop $drop%"
echo "the reading client: $updates updates/s at --rate $igtl_rate"
echo "target, updates: $updates/s (>= 30: $(awk -v u="$updates" 'BEGIN {print (u >= 30 ? "met" : "MISSED")}'))"
echo "target, step rate drop: $drop% (<= 5%: $(awk -v d="$drop" 'BEGIN {print (d <= 5 ? "met" : "MISSED")}'))"
echo "particles,surface_points,updates_per_s,steps_per_s_alone,steps_per_s_with_clients,drop_percent" >out/bench/igtl.csv
echo "${particles:-},${points:-},$updates,$alone,$with,$drop" >>out/bench/igtl.csv
