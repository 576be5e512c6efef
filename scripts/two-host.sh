#!/usr/bin/env bash
# Two hosts on one machine: the dynamics host and the graphics host as two network namespaces,
# NAME-dyn (10.213.0.1) and NAME-gfx (10.213.0.2), joined by a veth pair; delay and jitter with
# tc netem and datagram loss with nftables, each way. Runs as root.
#   scripts/two-host.sh run [IMPAIRMENTS] [--ranks N] [--seconds S] [--udp] [--out DIR]
#       builds the torus bag (a batch run), serves it under mpirun on the dynamics host, and runs a
#       headless bop-viewer and bop-haptic sim:poke on the graphics host; prints what they measured
#   scripts/two-host.sh up NAME [IMPAIRMENTS]    makes the two hosts and leaves them up
#   scripts/two-host.sh down NAME                removes them (and whatever still runs in them)
#   scripts/two-host.sh check [IMPAIRMENTS]      exit 0 when this machine can make them, else 77 and why
# IMPAIRMENTS, each way (a round trip meets each twice):
#   --delay MS    added latency                 --jitter MS  its spread, with --delay
#                 (tc netem; on a kernel without it, bop-netdelay (scripts/netdelay/) holding the packets
#                 an iptables NFQUEUE rule hands it)
#   --loss PCT    UDP datagrams dropped at random on arrival (nftables); TCP is left whole, as its
#                 losses would only show as delay
# Processes in a host: ip netns exec NAME-dyn COMMAND (or NAME-gfx). Exit code 77: not possible
# here (no root, namespaces not permitted, neither netem nor bop-netdelay for a delay, nftables
# missing), with the reason on stderr. BOP_BUILD_DIR: where bop-netdelay is built (build).
# Every step has a deadline: one that does not finish is stopped, and the script says which one
# and exits 124.
set -euo pipefail
cd "$(dirname "$0")/.."
readonly dynAddr=10.213.0.1 gfxAddr=10.213.0.2
readonly netdelay=${BOP_BUILD_DIR:-build}/scripts/netdelay/bop-netdelay
netem=1  # check() finds out

usage() { sed -n '2,21p' "$0" | sed 's/^# \{0,1\}//'; }
skip() { echo "two-host: skipped: $*" >&2; exit 77; }
die() { echo "two-host: $*" >&2; exit 2; }

# bounded SECONDS COMMAND...: COMMAND, stopped after SECONDS (KILL 5 s later if TERM is not
# enough); a step stopped so is named on stderr and the script ends with 124.
bounded() {
  local seconds=$1 rc=0
  shift
  timeout --kill-after=5 "$seconds" "$@" || rc=$?
  if [[ $rc == 124 || $rc == 137 ]]; then
    echo "two-host: step '$*' did not finish in $seconds s; stopped" >&2
    exit 124
  fi
  return $rc
}

# waitBounded PID SECONDS WHAT: waits for a background process; past SECONDS it is stopped and
# named. Its exit code (124 when stopped).
waitBounded() {
  local pid=$1 seconds=$2 what=$3
  for _ in $(seq 1 $((seconds * 10))); do
    kill -0 "$pid" 2>/dev/null || { wait "$pid"; return; }
    sleep 0.1
  done
  echo "two-host: $what did not finish in $seconds s; stopped" >&2
  kill -TERM "$pid" 2>/dev/null
  sleep 2
  kill -KILL "$pid" 2>/dev/null
  wait "$pid" 2>/dev/null
  return 124
}

delay="" jitter="" loss="" ranks=2 seconds=20 udp=0 out=out/two-host
parseImpairments() {
  while [[ $# -gt 0 ]]; do
    case $1 in
      --delay) delay=${2:?--delay expects milliseconds}; shift 2 ;;
      --jitter) jitter=${2:?--jitter expects milliseconds}; shift 2 ;;
      --loss) loss=${2:?--loss expects a percentage}; shift 2 ;;
      --ranks) ranks=${2:?--ranks expects a count}; shift 2 ;;
      --seconds) seconds=${2:?--seconds expects seconds}; shift 2 ;;
      --udp) udp=1; shift ;;
      --out) out=${2:?--out expects a folder}; shift 2 ;;
      -h|--help) usage; exit 0 ;;
      *) die "unknown option '$1' (expected --delay, --jitter, --loss, --ranks, --seconds, --udp, --out; see --help)" ;;
    esac
  done
  for v in "$delay" "$jitter" "$loss"; do
    [[ -z $v || $v =~ ^[0-9]+([.][0-9]+)?$ ]] || die "expected a non-negative number, got '$v'"
  done
  [[ -z $jitter || -n $delay ]] || die "--jitter needs --delay"
  [[ $seconds =~ ^[0-9]+$ && $ranks =~ ^[1-9][0-9]*$ ]] || die "--seconds and --ranks expect whole numbers"
  [[ -z $loss ]] || awk -v l="$loss" 'BEGIN {exit !(l <= 100)}' || die "--loss is a percentage, 0 to 100; got $loss"
}

# Whether this machine permits what is asked: a throwaway namespace tries each piece.
check() {
  [[ $(id -u) == 0 ]] || skip "network namespaces need root (run as root, or with sudo)"
  command -v ip >/dev/null || skip "ip (iproute2) is not installed: scripts/install-deps.sh installs it"
  [[ -z $loss ]] || command -v nft >/dev/null || skip "nft (nftables) is not installed: scripts/install-deps.sh installs it"
  local probe=bop-check-$$ err rc why=""
  # try COMMAND...: its output in err and its exit code in rc; a step that did not finish (124)
  # fails the check rather than skipping it.
  try() {
    err=$(bounded 10 "$@" 2>&1) && rc=0 || rc=$?
    [[ $rc != 124 ]] || die "$err"
  }
  try ip netns add "$probe"
  [[ $rc == 0 ]] || skip "network namespaces are not permitted here: ip netns add: $err"
  bounded 10 ip -n "$probe" link set lo up
  try ip -n "$probe" link add vcheck0 type veth peer name vcheck1
  if [[ $rc != 0 ]]; then
    why="veth pairs are not permitted here: $err"
  else
    if [[ -n $delay ]]; then
      try ip netns exec "$probe" tc qdisc add dev vcheck0 root netem delay 1ms
      if [[ $rc != 0 ]]; then
        netem=0
        [[ -x $netdelay ]] && command -v iptables >/dev/null ||
          why="tc netem is not available on this kernel (no sch_netem: $err), and $netdelay (with iptables) is not there to stand in, so no --delay or --jitter"
      fi
    fi
    if [[ -z $why && -n $loss ]]; then
      try ip netns exec "$probe" nft add table inet bop
      [[ $rc == 0 ]] || why="nftables is not permitted here: $err"
    fi
    if [[ -z $why && $netem == 0 ]]; then  # the stand-in: an NFQUEUE rule and a process bound to the queue
      try ip netns exec "$probe" iptables -A OUTPUT -o vcheck0 -j NFQUEUE --queue-num 0 --queue-bypass
      if [[ $rc != 0 ]]; then
        why="tc netem is not available on this kernel, and its stand-in needs iptables' NFQUEUE, which is not: $err"
      else
        err=$(timeout 0.5 ip netns exec "$probe" "$netdelay" --delay-ms 1 2>&1) && true
        [[ $? == 124 ]] || why="tc netem is not available on this kernel, and its stand-in bop-netdelay cannot run: $err"
      fi
    fi
  fi
  bounded 10 ip netns del "$probe"
  [[ -z $why ]] || skip "$why"
}

impair() {  # namespace, interface
  local ns=$1 dev=$2
  if [[ -n $delay && $netem == 1 ]]; then
    bounded 10 ip netns exec "$ns" tc qdisc add dev "$dev" root netem delay "${delay}ms" ${jitter:+"${jitter}ms" distribution normal}
  elif [[ -n $delay ]]; then  # every packet out through bop-netdelay, which lets each go late
    local log pid
    log=$(mktemp /tmp/two-host-netdelay.XXXXXX)
    ip netns exec "$ns" "$netdelay" --delay-ms "$delay" --jitter-ms "${jitter:-0}" >"$log" 2>&1 &
    pid=$!
    for _ in $(seq 1 100); do
      grep -q ready "$log" && break
      kill -0 "$pid" 2>/dev/null || break
      sleep 0.05
    done
    grep -q ready "$log" || die "bop-netdelay did not start within 5 s: $(cat "$log")"
    rm -f "$log"
    # xt's NFQUEUE (iptables): nftables' own queue statement needs nft_queue, which kernels
    # without netem tend to lack too. bypass: with nobody on the queue, packets pass at once.
    bounded 10 ip netns exec "$ns" iptables -A OUTPUT -o "$dev" -j NFQUEUE --queue-num 0 --queue-bypass
  fi
  if [[ -n $loss ]]; then
    # On arrival, as a wire loses them: the sender is told nothing (a drop on the way out would
    # fail its send with EPERM). numgen gives 0..9999.
    local cut
    cut=$(awk -v l="$loss" 'BEGIN {printf "%d", l * 100 + 0.5}')
    bounded 10 ip netns exec "$ns" nft -f - <<EOF
table inet bop {
  chain in {
    type filter hook input priority 0;
    meta l4proto udp iifname "$dev" numgen random mod 10000 < $cut counter drop
  }
}
EOF
  fi
}

up() {
  local name=$1
  check
  down "$name" 2>/dev/null || true
  trap 'down "'"$name"'" 2>/dev/null' EXIT  # half-made hosts go; lifted once they are up
  bounded 10 ip netns add "$name-dyn"
  bounded 10 ip netns add "$name-gfx"
  bounded 10 ip -n "$name-dyn" link add eth0 type veth peer name eth0 netns "$name-gfx"
  bounded 10 ip -n "$name-dyn" addr add "$dynAddr/24" dev eth0
  bounded 10 ip -n "$name-gfx" addr add "$gfxAddr/24" dev eth0
  for ns in "$name-dyn" "$name-gfx"; do
    bounded 10 ip -n "$ns" link set lo up
    bounded 10 ip -n "$ns" link set eth0 up
    impair "$ns" eth0
  done
  trap - EXIT
  echo "two-host: $name-dyn ($dynAddr) and $name-gfx ($gfxAddr) up;" \
       "delay ${delay:-0} ms, jitter ${jitter:-0} ms$([[ -n $delay && $netem == 0 ]] && echo " (bop-netdelay)")," \
       "datagram loss ${loss:-0}% each way"
}

down() {
  local name=$1 ns
  for ns in "$name-dyn" "$name-gfx"; do
    (bounded 10 ip netns pids "$ns" 2>/dev/null || true) | xargs -r kill -TERM 2>/dev/null || true
  done
  sleep 0.2  # a moment to let go: bop-netdelay hands back what it holds
  for ns in "$name-dyn" "$name-gfx"; do
    (bounded 10 ip netns pids "$ns" 2>/dev/null || true) | xargs -r kill -KILL 2>/dev/null || true
    bounded 10 ip netns del "$ns" 2>/dev/null || true
  done
}

run() {
  local name=bop-run-$$ bin=${BOP_BUILD_DIR:-build}
  for t in dynamics_server/bop-server viz_client/bop-viewer haptic_client/bop-haptic; do
    [[ -x $bin/$t ]] || die "$bin/$t is not built (cmake --build build; scripts/demo.sh builds everything)"
  done
  export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
  mkdir -p "$out"
  echo "== the torus bag: construction (a batch run) =="
  bounded 600 $bin/dynamics_server/bop-server config/scenes/torus.toml --no-listen -o "$out/torus" | tail -2
  up "$name"
  trap 'down '"$name" EXIT
  echo "== served at $ranks ranks on $name-dyn; viewer and haptic device on $name-gfx for ${seconds} s =="
  ip netns exec "$name-dyn" mpirun --oversubscribe -np "$ranks" $bin/dynamics_server/bop-server \
    config/scenes/torus.toml --restart "$out/torus/final.xyz" --cache "$out/torus/gradient-map.bopgm" \
    --bind "$dynAddr" --port 7300 --publish-hz 30 -o "$out/served" >"$out/server.log" 2>&1 &
  local server=$! endpoint=tcp://$dynAddr:7300
  for _ in $(seq 1 600); do
    grep -q '^listening on' "$out/server.log" && break
    kill -0 "$server" 2>/dev/null || { cat "$out/server.log"; die "the server stopped"; }
    sleep 0.1
  done
  grep -q '^listening on' "$out/server.log" ||
    { tail -20 "$out/server.log"; die "the server was not listening after 60 s (its last lines above)"; }
  local udpArgs=() hapticUdp=()
  [[ $udp == 1 ]] && udpArgs=(--udp-port 7400) hapticUdp=(--udp)
  ip netns exec "$name-gfx" $bin/haptic_client/bop-haptic "$endpoint" --device sim:poke --seconds "$seconds" \
    "${hapticUdp[@]}" --out "$out/haptic" >"$out/haptic.log" 2>&1 &
  local haptic=$!
  ip netns exec "$name-gfx" $bin/viz_client/bop-viewer "$endpoint" --headless --fps 5 --frames $((seconds * 5)) \
    "${udpArgs[@]}" --connect-timeout 60 --out "$out/viewer" >"$out/viewer.log" 2>&1 &
  local viewer=$!
  waitBounded "$haptic" $((seconds + 60)) "bop-haptic" ||
    echo "two-host: bop-haptic ended with an error (see $out/haptic.log)" >&2
  # Heavy loss can keep the viewer from its frames for long: 10 s more, then it is stopped.
  waitBounded "$viewer" 10 "bop-viewer (still waiting for frames)" ||
    echo "two-host: bop-viewer ended with an error or was stopped (see $out/viewer.log)" >&2
  kill -INT "$server" 2>/dev/null || true  # as Ctrl-C: it writes its final state and checkpoint
  waitBounded "$server" 60 "the server's stop after SIGINT" || true
  echo "== what the graphics host measured (logs in $out) =="
  grep -h -E '^(loop|probe round trip|largest force)' "$out/haptic.log" || true
  grep -h -E '^bop-viewer: frames received' "$out/viewer.log" || true
  grep -h -E '^served ' "$out/server.log" || true
}

command=${1:-}
case $command in
  run) shift; parseImpairments "$@"; run ;;
  up) [[ -n ${2:-} ]] || die "up expects a NAME"; name=$2; shift 2; parseImpairments "$@"; up "$name" ;;
  down) [[ -n ${2:-} ]] || die "down expects a NAME"; down "$2" ;;
  check) shift; parseImpairments "$@"; check; echo "two-host: possible here" ;;
  -h|--help|"") usage ;;
  *) die "unknown command '$command' (expected run, up, down or check; see --help)" ;;
esac
