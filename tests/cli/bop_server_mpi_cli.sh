#!/usr/bin/env bash
# bop-server under mpirun: the bulk box at 2 ranks reports the same particles and energies as at
# 1 rank and writes one final.xyz with every particle once; a scene with a construction timeline
# at 2 ranks stops with a non-zero exit and says how to run it.
# Usage: bop_server_mpi_cli.sh PATH/TO/bop-server MPIEXEC REPO_ROOT
set -u
exe=$1 mpiexec=$2 repo=$3
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail=0
check() { if eval "$2"; then echo "ok   $1"; else echo "FAIL $1"; fail=1; fi; }
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1

scene=$repo/config/scenes/bulk-box.toml
"$exe" "$scene" --no-listen --steps 200 --report-every 200 -o "$work/np1" >"$work/np1.txt" 2>&1
check "1 rank exits 0" "[ $? -eq 0 ]"
"$mpiexec" -np 2 --oversubscribe "$exe" "$scene" --no-listen --steps 200 --report-every 200 -o "$work/np2" >"$work/np2.txt" 2>&1
check "2 ranks exit 0" "[ $? -eq 0 ]"
check "2 ranks say how the box was split" "grep -q 'decomposed over 2 ranks' '$work/np2.txt'"
# Energies after 200 steps agree to the printed digits (pair sums differ only in order).
e1=$(awk '/E_pair/ && /^births/ {sub(/.*E_pair /, ""); sub(/,.*/, ""); print}' "$work/np1.txt")
e2=$(awk '/^E_kin/ {sub(/.*E_pair /, ""); sub(/,.*/, ""); print}' "$work/np2.txt")
check "E_pair at 2 ranks ($e2) equals 1 rank ($e1)" "[ -n '$e1' ] && [ '$e1' = '$e2' ]"
n1=$(head -1 "$work/np1/final.xyz") n2=$(head -1 "$work/np2/final.xyz")
check "final.xyz holds every particle once ($n2 of $n1)" "[ '$n1' = '$n2' ] && [ \$(tail -n +3 '$work/np2/final.xyz' | awk '{print \$(NF-1)}' | sort -u | wc -l) -eq $n1 ]"

"$mpiexec" -np 2 --oversubscribe "$exe" "$repo/config/scenes/star.toml" --no-listen --steps 10 -o "$work/star" >"$work/star.txt" 2>&1
rc=$?
check "a construction timeline at 2 ranks exits non-zero (got $rc)" "[ $rc -ne 0 ]"
check "and names the scene and the limit" "grep -q 'star.toml.*construction timelines run on one rank' '$work/star.txt'"
check "and says to build at one rank and restart" "grep -q 'restart' '$work/star.txt'"
exit $fail
