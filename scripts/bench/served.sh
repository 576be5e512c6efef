# Sourced by the benchmarks that serve a run for the headless viewer. `served_endpoint LOG PID`
# prints the endpoint bop-server names in LOG ("listening on tcp://...") once it does, or nothing
# when the server (PID) ends first or 30 s pass.
served_endpoint() {
  local log=$1 pid=$2 endpoint=""
  for _ in $(seq 1 300); do
    endpoint=$(sed -n 's/^listening on \(tcp:[^ ]*\).*/\1/p' "$log" | head -1)
    [[ -n $endpoint ]] && break
    kill -0 "$pid" 2>/dev/null || break
    sleep 0.1
  done
  echo "$endpoint"
}
