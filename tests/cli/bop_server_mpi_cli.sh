#!/usr/bin/env bash
# bop-server under mpirun: the bulk box at 2 ranks reports the same particles and energies as at
# 1 rank and writes one final.xyz with every particle once; the star bag built by its
# construction timeline at 2 ranks has the particles of a 1-rank build, and each rank holds only
# a window of its gradient map; the organs scene (four bags side by side, touching and nested)
# at 1, 2 and 4 ranks places the same particles and reports the same per-bag fidelity.
# Usage: bop_server_mpi_cli.sh PATH/TO/bop-server MPIEXEC REPO_ROOT
set -u
exe=$1 mpiexec=$2 repo=$3
source "$(dirname "$0")/cli-checks.sh"

scene=$repo/config/scenes/bulk-box.toml
bounded 120 "$work/np1.txt" "$exe" "$scene" --no-listen --steps 200 --report-every 200 -o "$work/np1"
check "1 rank exits 0" "[ $? -eq 0 ]"
bounded 120 "$work/np2.txt" "$mpiexec" -np 2 --oversubscribe "$exe" "$scene" --no-listen --steps 200 --report-every 200 -o "$work/np2"
check "2 ranks exit 0" "[ $? -eq 0 ]"
check "2 ranks say how the box was split" "grep -q 'decomposed over 2 ranks' '$work/np2.txt'"
# Energies after 200 steps agree to the printed digits (pair sums differ only in order).
energy() { awk '/E_pair/ && /^births/ {sub(/.*E_pair /, ""); sub(/,.*/, ""); print}' "$1"; }
e1=$(energy "$work/np1.txt") e2=$(energy "$work/np2.txt")
check "E_pair at 2 ranks ($e2) equals 1 rank ($e1)" "[ -n '$e1' ] && [ '$e1' = '$e2' ]"
n1=$(head -1 "$work/np1/final.xyz") n2=$(head -1 "$work/np2/final.xyz")
check "final.xyz holds every particle once ($n2 of $n1)" "[ '$n1' = '$n2' ] && [ \$(tail -n +3 '$work/np2/final.xyz' | awk '{print \$(NF-1)}' | sort -u | wc -l) -eq $n1 ]"

star=$repo/config/scenes/star.toml
bounded 120 "$work/star1.txt" "$exe" "$star" --no-listen --report-every 100000 -o "$work/star1"
check "the star builds at 1 rank" "[ $? -eq 0 ]"
bounded 120 "$work/star2.txt" "$mpiexec" -np 2 --oversubscribe "$exe" "$star" --no-listen --report-every 100000 -o "$work/star2"
check "the star builds at 2 ranks" "[ $? -eq 0 ]"
c1=$(awk '/^this run/ {print $3, $4}' "$work/star1.txt") c2=$(awk '/^this run/ {print $3, $4}' "$work/star2.txt")
check "surface and volume particles at 2 ranks ($c2) equal 1 rank ($c1)" "[ -n '$c1' ] && [ '$c1' = '$c2' ]"
whole=$(grep -oP 'gradient map: \K[0-9.]+(?= MB \(the whole)' "$work/star1.txt")
window=$(grep -oP 'gradient map: at most \K[0-9.]+' "$work/star2.txt" | tail -1)
check "a rank's map window ($window MB) is smaller than the whole map ($whole MB)" "awk -v w='$window' -v a='$whole' 'BEGIN {exit !(w > 0 && w < a)}'"
organs=$repo/config/scenes/organs.toml
for np in 1 2 4; do
  launch=("$mpiexec" -np $np --oversubscribe)
  [ $np -eq 1 ] && launch=()
  bounded 180 "$work/organs$np.txt" "${launch[@]}" "$exe" "$organs" --no-listen --steps 300 --report-every 100000 -o "$work/organs$np"
  check "the organs run at $np rank(s)" "[ $? -eq 0 ]"
done
bags() { awk '/^this run/ {print $3, $4} /^  bag / {print}' "$1"; }
check "four bags reported, each with its fidelity" "[ \$(grep -c \"^  bag '\" '$work/organs1.txt') -eq 4 ]"
for np in 2 4; do
  check "particles and per-bag fidelity at $np ranks equal 1 rank's" "[ -n \"\$(bags '$work/organs1.txt')\" ] && [ \"\$(bags '$work/organs$np.txt')\" = \"\$(bags '$work/organs1.txt')\" ]"
done
exit $fail
