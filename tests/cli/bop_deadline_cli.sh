#!/usr/bin/env bash
# bop-deadline, which bounds the tests that are scripts or mpirun lines: --help; a command that
# ends passes its exit code and output through; one that hangs (a shell waiting on a child that
# never ends) is stopped at its deadline with exit 124, the process tree and its last lines, and
# none of its processes is left; a signal sent to bop-deadline reaches the command.
# Usage: bop_deadline_cli.sh (BOP_DEADLINE set by ctest)
set -u
source "$(dirname "$0")/cli-checks.sh"

"$BOP_DEADLINE" --help >"$work/help.txt" 2>&1
check "--help exits 0 and explains the deadline" "grep -q 'exits 124' '$work/help.txt'"
"$BOP_DEADLINE" 30 -- sh -c 'echo through; exit 3' >"$work/pass.txt" 2>&1
rc=$?
check "a command that ends: its exit code (got $rc) and output pass through" "[ $rc -eq 3 ] && grep -q '^through' '$work/pass.txt'"

start=$SECONDS
"$BOP_DEADLINE" --log "$work/hang.log" 2 -- sh -c 'echo waiting on a server that never answers; sleep 1000 & wait' \
  >"$work/out.txt" 2>"$work/report.txt"
rc=$? took=$((SECONDS - start))
cat "$work/report.txt"
check "a hung command is stopped at its deadline: exit 124 (got $rc) within seconds (took $took s)" "[ $rc -eq 124 ] && [ $took -lt 12 ]"
check "... saying what it waited for" "grep -q 'DEADLINE: pid [0-9]* did not end within 2.0 s' '$work/report.txt'"
check "... with the process tree, each process's state and wait channel" \
  "grep -q 'sleep 1000' '$work/report.txt' && grep -q ' S in \\| S,' '$work/report.txt' && grep -q 'threads: ' '$work/report.txt'"
check "... and its last lines" "grep -q 'waiting on a server that never answers' '$work/report.txt'"
check "... and its whole tree killed (the shell's child too)" "! pgrep -f '^sleep 1000$' >/dev/null"

"$BOP_DEADLINE" 30 -- sh -c 'trap "echo got TERM; exit 5" TERM; while :; do sleep 0.1; done' >"$work/sig.txt" 2>&1 &
pid=$!
sleep 1
kill -TERM "$pid"
wait "$pid"
rc=$?
check "a signal to bop-deadline reaches the command (exit $rc)" "[ $rc -eq 5 ] && grep -q 'got TERM' '$work/sig.txt'"
exit $fail
