#!/usr/bin/env bash
# Clients that come, misbehave and go (docs/protocol.md, "Sessions"): the torus served at one
# rank with --session-timeout 2, a haptic client (bop-haptic sim:poke) pressing on it throughout,
# and bop-churn sending BOP_CHURN_CLIENTS (1,000) clients, 8 at a time, each saying Hello, sending
# 20 messages (valid probes and commands mixed with out-of-range values, garbage, cut buffers and
# foreign kinds) and leaving, while its own viewer session watches. Reports the server's step rate
# before, during and after the churn, its resident memory before and after (once every churned
# session is forgotten), the frames the viewer took, the haptic client's loop and round trip, and
# the server's counts of refusals. CSV in out/bench/churn.csv.
#   scripts/bench/churn.sh
#   BOP_CHURN_CLIENTS=5000 scripts/bench/churn.sh
set -euo pipefail
cd "$(dirname "$0")/../.."
clients=${BOP_CHURN_CLIENTS:-1000}
scripts/install-deps.sh >/dev/null
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j "${BOP_JOBS:-2}" --target bop-server bop-haptic bop-churn >/dev/null
out=out/bench/churn
mkdir -p "$out"

echo "== the torus, built once =="
[[ -f $out/torus/final.xyz ]] || build/dynamics_server/bop-server config/scenes/torus.toml --no-listen -o "$out/torus" >"$out/torus.log" 2>&1
server_pid=""
haptic_pid=""
trap '[[ -n $haptic_pid ]] && kill -INT "$haptic_pid" 2>/dev/null; [[ -n $server_pid ]] && kill -INT "$server_pid" 2>/dev/null || true' EXIT
build/dynamics_server/bop-server config/scenes/torus.toml --restart "$out/torus/final.xyz" --port 0 \
  --session-timeout 2 -o "$out/run" >"$out/server.log" 2>&1 &
server_pid=$!
endpoint=""
for _ in $(seq 300); do
  endpoint=$(sed -n 's/^listening on \(tcp:[^ ]*\).*/\1/p' "$out/server.log")
  [[ -n $endpoint ]] && break
  sleep 0.1
done
[[ -n $endpoint ]] || { echo "churn: the server did not start; see $out/server.log" >&2; exit 1; }

echo "== $clients clients against $endpoint, a haptic client poking throughout =="
build/haptic_client/bop-haptic "$endpoint" --device sim:poke --seconds 3600 --out "$out/haptic" >"$out/haptic.log" 2>&1 &
haptic_pid=$!
sleep 1
build/protocol/bop-churn "$endpoint" --clients "$clients" --concurrency 8 --burst 20 --baseline 5 --settle 5 \
  --server-pid "$server_pid" | tee "$out/churn.log"
kill -INT "$haptic_pid"
wait "$haptic_pid" || true
haptic_pid=""
kill -INT "$server_pid"
wait "$server_pid" || true
server_pid=""

figures=$(grep '^clients=' "$out/churn.log")
value() { sed -n "s/.*\\b$1=\\([0-9.]*\\).*/\\1/p" <<<"$figures"; }
summary=$(grep '^served ' "$out/server.log")
count() { sed -n "s/.*[^0-9]\\([0-9][0-9]*\\) $1.*/\\1/p" <<<"$summary"; }
loop=$(sed -n 's/^loop: [0-9]* ticks at \([0-9.]*\) Hz.*/\1/p' "$out/haptic.log")
rtt=$(sed -n 's/^probe round trip: p50 \([0-9.]*\) ms, p99 \([0-9.]*\) ms.*/\1,\2/p' "$out/haptic.log")
{
  echo "clients,seconds,steps_per_s_before,steps_per_s_during,steps_per_s_after,rss_before_mb,rss_after_mb,frames_during,longest_frame_gap_s,haptic_hz,rtt_p50_ms,rtt_p99_ms,sessions_expired,malformed_refused,out_of_range_refused,refusals_sent,internal_errors"
  echo "$(value clients),$(value seconds),$(value steps_per_s_before),$(value steps_per_s_during),$(value steps_per_s_after),$(value rss_before_mb),$(value rss_after_mb),$(value frames_during),$(value longest_frame_gap_s),$loop,${rtt:-,},$(count 'sessions expired'),$(count 'malformed messages refused'),$(count 'messages with values out of range refused'),$(count 'refusals sent'),$(count 'internal errors')"
} >out/bench/churn.csv
echo "== figures (out/bench/churn.csv) =="
column -s, -t out/bench/churn.csv
echo "server: $summary"
