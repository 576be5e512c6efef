#!/usr/bin/env bash
# The haptic client's timing (docs/haptics.md):
#  1. the device loop alone for 10 s (bop-haptic --loop-only): rate, period error p50/p99/max,
#     missed deadlines;
#  2. probe -> feedback round trip against the torus served at 2 ranks on loopback, probes over
#     TCP (DEALER) and over UDP, a sim:poke of 10 s each;
#  3. the same over two hosts (scripts/two-host.sh: namespaces and a veth pair) with 2 ms added
#     each way (netem, or bop-netdelay without it); skipped with the script's reason where the
#     machine cannot.
#   scripts/bench/haptic.sh          (CSV in out/bench/haptic.csv)
#   BOP_HAPTIC_SECONDS=10            seconds per case
set -euo pipefail
cd "$(dirname "$0")/../.."
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
seconds=${BOP_HAPTIC_SECONDS:-10}
scripts/install-deps.sh >/dev/null
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j "${BOP_JOBS:-2}" --target bop-haptic bop-server >/dev/null
cmake --build build -j "${BOP_JOBS:-2}" --target bop-netdelay >/dev/null 2>&1 || true  # where libnetfilter-queue is
out=out/bench/haptic
mkdir -p "$out"
csv=out/bench/haptic.csv
echo "case,rate_hz,p50_us,p99_us,max_us,missed,rtt_p50_ms,rtt_p99_ms,rtt_max_ms" >"$csv"

# "loop: N ticks at R Hz; period error p50 A us, p99 B us, max C us; M missed ..." and
# "probe round trip: p50 X ms, p99 Y ms, max Z ms ..." -> one CSV row.
row() {
  local name=$1 log=$2
  local loop rtt
  loop=$(sed -n 's/^loop: [0-9]* ticks at \([0-9.]*\) Hz; period error p50 \([0-9.]*\) us, p99 \([0-9.]*\) us, max \([0-9.]*\) us; \([0-9]*\) missed.*/\1,\2,\3,\4,\5/p' "$log")
  rtt=$(sed -n 's/^probe round trip: p50 \([0-9.]*\) ms, p99 \([0-9.]*\) ms, max \([0-9.]*\) ms.*/\1,\2,\3/p' "$log")
  echo "$name,${loop:-,,,,},${rtt:-,,}" >>"$csv"
  echo "haptic: $name: $(grep -E '^(loop|probe round trip):' "$log" | tr '\n' ' ')"
}

echo "== 1. the device loop alone, ${seconds} s =="
build/haptic_client/bop-haptic --loop-only --seconds "$seconds" --out "$out/loop" | tee "$out/loop.log"
row loop-only "$out/loop.log"

echo "== the torus, built once =="
build/dynamics_server/bop-server config/scenes/torus.toml --no-listen -o "$out/torus" >"$out/torus.log" 2>&1
start="$out/torus/final.xyz"

server_pid=""
trap '[[ -n $server_pid ]] && kill -INT "$server_pid" 2>/dev/null || true' EXIT
# serve NAMESPACE_PREFIX BIND: starts the server, prints its endpoint; PID in $server_pid.
serve() {
  local prefix=$1 bind=$2 log=$3
  $prefix mpirun -np 2 --oversubscribe build/dynamics_server/bop-server config/scenes/torus.toml --restart "$start" \
    --bind "$bind" --port 0 --publish-hz 30 -o "$out/run" >"$log" 2>&1 &
  server_pid=$!
  for _ in $(seq 300); do
    endpoint=$(sed -n 's/^listening on \(tcp:[^ ]*\).*/\1/p' "$log")
    [[ -n $endpoint ]] && return 0
    sleep 0.1
  done
  echo "haptic: the server did not start; see $log" >&2
  exit 1
}

echo "== 2. round trip on loopback, ${seconds} s per transport =="
serve "" 127.0.0.1 "$out/server-loopback.log"
for transport in tcp udp; do
  flag=""; [[ $transport == udp ]] && flag="--udp"
  build/haptic_client/bop-haptic "$endpoint" --device sim:poke --seconds "$seconds" $flag --out "$out/$transport" \
    | tee "$out/loopback-$transport.log"
  row "loopback-$transport" "$out/loopback-$transport.log"
done
kill -INT "$server_pid"; wait "$server_pid" || true; server_pid=""

echo "== 3. round trip with 2 ms each way between two hosts (scripts/two-host.sh) =="
hosts=bophap$$
trap '[[ -n $server_pid ]] && kill -INT "$server_pid" 2>/dev/null; scripts/two-host.sh down '"$hosts"' 2>/dev/null || true' EXIT
set +e
why=$(scripts/two-host.sh up "$hosts" --delay 2 2>&1)
code=$?
set -e
[[ $code == 0 || $code == 77 ]] || { echo "$why" >&2; exit "$code"; }
if [[ $code == 0 ]]; then
  serve "ip netns exec $hosts-dyn" 10.213.0.1 "$out/server-netns.log"
  ip netns exec "$hosts-gfx" build/haptic_client/bop-haptic "$endpoint" --device sim:poke --seconds "$seconds" \
    --out "$out/netns" | tee "$out/netns.log"
  row "netns-2ms-tcp" "$out/netns.log"
  kill -INT "$server_pid"; wait "$server_pid" || true; server_pid=""
else
  echo "haptic: skipped the 2 ms case: $(echo "$why" | tail -1)"
  echo "netns-2ms-tcp,skipped,,,,,,," >>"$csv"
fi
echo "haptic: CSV in $csv"
