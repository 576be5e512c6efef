# Sourced by the command-line checks (tests/cli/*.sh): a named check, and a tool's run with a
# deadline. `bounded SECONDS LOG COMMAND...` runs COMMAND through bop-deadline (ctest sets
# BOP_DEADLINE), its output into LOG: past SECONDS, bop-deadline prints the process tree and the
# last lines, kills every process of it, and the run's exit code is 124. A signal sent to the
# bounded run is passed on to COMMAND. `work` is a scratch folder removed when the script exits;
# MPI may run as root.
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
fail=0
check() { if eval "$2"; then echo "ok   $1"; else echo "FAIL $1"; fail=1; fi; }
# `first_match LOG SED_SCRIPT`: what sed -n SED_SCRIPT prints first from LOG, waiting up to 30 s
# for a process to write it (a server's endpoint, a port); empty if it never does.
first_match() {
  local found=""
  for _ in $(seq 1 300); do
    found=$(sed -n "$2" "$1" | head -1)
    [[ -n $found ]] && break
    sleep 0.1
  done
  echo "$found"
}
bounded() {
  local seconds=$1 log=$2
  shift 2
  "${BOP_DEADLINE:?the ctest entry sets BOP_DEADLINE to bop-deadline}" --log "$log" "$seconds" -- "$@"
}
