#!/usr/bin/env bash
# bop-haptic from the command line: --help, the device loop alone (its summary line, a trace of
# one line per tick), and clear errors with a non-zero exit for a bad device, a missing
# spacenavd, a missing endpoint and a bad point.
# Usage: bop_haptic_cli.sh PATH/TO/bop-haptic
set -u
exe=$1
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail=0
check() { if eval "$2"; then echo "ok   $1"; else echo "FAIL $1"; fail=1; fi; }

"$exe" --help >"$work/help.txt" 2>&1
check "--help exits 0 and lists the devices" "grep -q 'sim:finger' '$work/help.txt'"

"$exe" --loop-only --seconds 2 --out "$work/loop" >"$work/loop.txt" 2>&1
rc=$?
cat "$work/loop.txt"
check "the loop alone exits 0 and reports its rate" "[ $rc -eq 0 ] && grep -q '^loop: [0-9]* ticks at [0-9.]* Hz' '$work/loop.txt'"
# Loose: a loaded machine may be late; 2 s at 1 kHz is about 2,000 ticks.
ticks=$(sed -n 's/^loop: \([0-9]*\) ticks.*/\1/p' "$work/loop.txt")
check "about 2,000 ticks in 2 s (got ${ticks:-none})" "[ \"${ticks:-0}\" -gt 1000 ] && [ \"${ticks:-0}\" -le 2001 ]"
lines=$(($(wc -l <"$work/loop/haptic-trace.csv") - 1))
check "the trace has a line per tick ($lines lines)" "[ \"$lines\" = \"${ticks:-x}\" ]"

"$exe" --loop-only --device sim:nope >"$work/e1.txt" 2>&1
rc=$?
check "an unknown device exits non-zero naming --device" "[ $rc -ne 0 ] && grep -q -- \"--device: unknown device 'sim:nope'\" '$work/e1.txt'"
"$exe" --loop-only --device spnav --seconds 1 >"$work/e2.txt" 2>&1
rc=$?
check "spnav without spacenavd exits non-zero saying so" "[ $rc -ne 0 ] && grep -q 'spnav: ' '$work/e2.txt'"
"$exe" --seconds 1 >"$work/e3.txt" 2>&1
rc=$?
check "no endpoint exits non-zero asking for it" "[ $rc -ne 0 ] && grep -q 'endpoint' '$work/e3.txt'"
"$exe" tcp://127.0.0.1:9 --target 1,2 >"$work/e4.txt" 2>&1
rc=$?
check "a bad --target exits non-zero naming it" "[ $rc -ne 0 ] && grep -q -- '--target: expected x,y,z' '$work/e4.txt'"
exit $fail
