#!/usr/bin/env bash
# bop-haptic from the command line: --help, the device loop alone (its summary line, a trace of
# one line per tick), and clear errors with a non-zero exit for a bad device, a missing
# spacenavd, a missing endpoint and a bad point.
# Usage: bop_haptic_cli.sh PATH/TO/bop-haptic
set -u
exe=$1
source "$(dirname "$0")/cli-checks.sh"

bounded 30 "$work/help.txt" "$exe" --help
check "--help exits 0 and lists the devices" "grep -q 'sim:finger' '$work/help.txt'"

bounded 30 "$work/loop.txt" "$exe" --loop-only --seconds 2 --out "$work/loop"
rc=$?
cat "$work/loop.txt"
check "the loop alone exits 0 and reports its rate" "[ $rc -eq 0 ] && grep -q '^loop: [0-9]* ticks at [0-9.]* Hz' '$work/loop.txt'"
# Every 1 ms deadline to the last tick's is a tick or counted as missed, however busy the machine
# (how many are missed is the machine's; the rate is scripts/bench/haptic.sh's to report).
ticks=$(sed -n 's/^loop: \([0-9]*\) ticks.*/\1/p' "$work/loop.txt")
missed=$(sed -n 's/^loop: .* \([0-9]*\) missed deadlines.*/\1/p' "$work/loop.txt")
last=$(awk -F, 'END {printf "%d", $1 * 1000 + 0.5}' "$work/loop/haptic-trace.csv")
check "the loop ran to its 2 s (last deadline at ${last:-none} ms)" "[ \"${last:-0}\" -ge 1999 ]"
check "ticks ($ticks) and missed deadlines ($missed) account for every deadline to the last (${last:-none} ms)" \
  "[ -n \"$ticks\" ] && [ -n \"$missed\" ] && [ \$((ticks + missed)) -eq \$((last + 1)) ]"
lines=$(($(wc -l <"$work/loop/haptic-trace.csv") - 1))
check "the trace has a line per tick ($lines lines)" "[ \"$lines\" = \"${ticks:-x}\" ]"

bounded 30 "$work/e1.txt" "$exe" --loop-only --device sim:nope
rc=$?
check "an unknown device exits non-zero naming --device" "[ $rc -ne 0 ] && grep -q -- \"--device: unknown device 'sim:nope'\" '$work/e1.txt'"
bounded 30 "$work/e2.txt" "$exe" --loop-only --device spnav --seconds 1
rc=$?
check "spnav without spacenavd exits non-zero saying so" "[ $rc -ne 0 ] && grep -q 'spnav: ' '$work/e2.txt'"
bounded 30 "$work/e3.txt" "$exe" --seconds 1
rc=$?
check "no endpoint exits non-zero asking for it" "[ $rc -ne 0 ] && grep -q 'endpoint' '$work/e3.txt'"
bounded 30 "$work/e4.txt" "$exe" tcp://127.0.0.1:9 --target 1,2
rc=$?
check "a bad --target exits non-zero naming it" "[ $rc -ne 0 ] && grep -q -- '--target: expected x,y,z' '$work/e4.txt'"
exit $fail
