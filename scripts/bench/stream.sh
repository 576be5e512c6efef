#!/usr/bin/env bash
# Streaming from bop-server to one client on loopback (docs/protocol.md):
#  1. frames/s and MB/s at 10k, 100k and 1M particles (bulk fcc boxes), float, 16-bit
#     quantised and compact frames, with the server paused so that the stream alone is measured (the server
#     keeps publishing the same state at --publish-hz 240);
#  2. probe -> feedback round trip p50/p99/max at 1 kHz against a running 10k-particle server,
#     over ZeroMQ and as datagrams, beside its step time (target: p99 <= 2 ms + one step);
#  3. the server's step rate (2 ranks, 10k particles) without and with a subscriber that never
#     reads, alternating (target: < 5% lower).
#   scripts/bench/stream.sh            (CSV in out/bench/stream.csv)
#   BOP_STREAM_SIZES="10000 100000"    particle counts of part 1
set -euo pipefail
cd "$(dirname "$0")/../.."
scripts/install-deps.sh >/dev/null
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j "${BOP_JOBS:-2}" --target bop-server bop-stream-bench >/dev/null
out=out/bench/stream; mkdir -p "$out"
csv=out/bench/stream.csv
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
bench=build/protocol/bop-stream-bench

scene_of() {  # scene_of N FILE: a bulk fcc box of about N particles
  local cells side; cells=$(awk -v n="$1" 'BEGIN {c = int((n / 4) ^ (1 / 3) + 0.5); print (c < 6 ? 6 : c)}')
  side=$(awk -v c="$cells" 'BEGIN {printf "%.17g", c * sqrt(2)}')  # fcc cube edge sqrt(2) r0
  cat >"$2" <<TOML
[box]
size_r0 = [$side, $side, $side]
spacing_r0 = 1.0
jitter_r0 = 0.02
periodic = true
[[species]]
name = "bulk"
kind = "volume"
drag_v = 0.5
[dynamics]
time_step = 0.005
lj_cutoff = "switched"
lj_switch_r0 = [1.2, 1.6]
TOML
}

server_pid=""
start_server() {  # start_server RANKS SCENE LOG ARGS...: sets endpoint
  local ranks=$1 scene=$2 log=$3; shift 3
  if [[ $ranks -gt 1 ]]; then
    setsid mpirun -np "$ranks" build/dynamics_server/bop-server "$scene" --port 0 -o "$out/run" "$@" >"$log" 2>&1 &
  else
    setsid build/dynamics_server/bop-server "$scene" --port 0 -o "$out/run" "$@" >"$log" 2>&1 &
  fi
  server_pid=$!
  for _ in $(seq 600); do
    endpoint=$(grep -oP 'listening on \K\S+' "$log" || true)
    [[ -n "$endpoint" ]] && return 0
    sleep 0.2
  done
  echo "stream: the server did not start; see $log" >&2; exit 1
}
stop_server() { kill -INT -- "-$server_pid" 2>/dev/null || true; wait "$server_pid" 2>/dev/null || true; }
trap stop_server EXIT
field() { grep -oP "$1 \K[0-9.]+" <<<"$2"; }

echo "part,particles,encoding,frames_per_s,mb_per_s,bytes_per_particle,rtt_p50_ms,rtt_p99_ms,rtt_max_ms,step_ms,steps_per_s" >"$csv"
printf "%9s %10s %9s %8s %12s\n" particles encoding frames/s MB/s "B/particle"
for n in ${BOP_STREAM_SIZES:-10000 100000 1000000}; do
  scene_of "$n" "$out/bulk-$n.toml"
  for enc in float quantised compact; do
    extra=(--publish-hz 240); [[ $enc == quantised ]] && extra+=(--quantised); [[ $enc == compact ]] && extra+=(--compact)
    start_server 1 "$out/bulk-$n.toml" "$out/server-$n-$enc.log" "${extra[@]}"
    line=$("$bench" frames "$endpoint" --pause --seconds 5)
    stop_server
    printf "%9s %10s %9s %8s %12s\n" "$(field particles "$line")" "$enc" "$(field frames_per_s "$line")" \
      "$(field mb_per_s "$line")" "$(field bytes_per_particle "$line")"
    echo "frames,$(field particles "$line"),$enc,$(field frames_per_s "$line"),$(field mb_per_s "$line"),$(field bytes_per_particle "$line"),,,,," >>"$csv"
  done
done

scene_of 10000 "$out/bulk-10000.toml"
start_server 1 "$out/bulk-10000.toml" "$out/server-probe.log"
steps=$(field steps_per_s "$("$bench" rate "$endpoint" --seconds 3)")
step_ms=$(awk -v s="$steps" 'BEGIN {printf "%.3f", 1000 / s}')
echo
for via in zmq udp; do
  extra=(); [[ $via == udp ]] && extra=(--udp)
  line=$("$bench" probe "$endpoint" --seconds 5 --hz 1000 "${extra[@]}")
  echo "probe -> feedback over $via at 1 kHz, 10k particles (one step: $step_ms ms): p50 $(field rtt_ms_p50 "$line") ms," \
    "p99 $(field rtt_ms_p99 "$line") ms, max $(field rtt_ms_max "$line") ms; target p99 <= $(awk -v s="$step_ms" 'BEGIN {print 2 + s}') ms"
  echo "probe-$via,10000,,,,,$(field rtt_ms_p50 "$line"),$(field rtt_ms_p99 "$line"),$(field rtt_ms_max "$line"),$step_ms,$steps" >>"$csv"
done
stop_server

start_server 2 "$out/bulk-10000.toml" "$out/server-stuck.log" --publish-hz 60
without=() with=()
for cycle in 1 2 3; do
  without+=("$(field steps_per_s "$("$bench" rate "$endpoint" --seconds 4)")")
  "$bench" stuck "$endpoint" --seconds 11 & stuck=$!
  sleep 5  # until the buffers feeding it are full
  with+=("$(field steps_per_s "$("$bench" rate "$endpoint" --seconds 4)")")
  wait "$stuck"
done
stop_server
median() { printf "%s\n" "$@" | sort -g | awk '{v[NR] = $1} END {print v[int((NR + 1) / 2)]}'; }
a=$(median "${without[@]}") b=$(median "${with[@]}")
echo "step rate at 2 ranks, 10k particles: $a steps/s without, $b with a subscriber that never reads" \
  "($(awk -v a="$a" -v b="$b" 'BEGIN {printf "%+.1f", 100 * (b - a) / a}')%; target > -5%)"
echo "stuck,10000,,,,,,,,,$a;$b" >>"$csv"
echo "stream: CSV in $csv; server logs in $out"
