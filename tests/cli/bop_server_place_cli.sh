#!/usr/bin/env bash
# A bag placed on its map (the torus scene without its construction timeline): the batch run ends
# by itself once settled, well before its cap, with the placement's counts and the shape's
# fidelity in its log, stepping at its settle_time_step; the minimiser settles it sooner than the
# dynamics alone, to their rule; 1, 2 and 3 ranks place the same particles and settle at the same
# step to the same positions, and 1 and 3 threads build the same bag to the last digit (the
# particles sorted as they move); a thin shape is named before it is built.
# Usage: bop_server_place_cli.sh PATH/TO/bop-server PATH/TO/mpiexec SOURCE_DIR
set -u
exe=$1
mpi=$2
src=$3
source "$(dirname "$0")/cli-checks.sh"
# The torus scene, its timeline and its [run] table left out, its mesh found from here.
awk '/^# Build the bag/ {skip = 1} /^# Oriented-particle/ {skip = 0} /^\[run\]/ {skip = 1} !skip' \
  "$src/config/scenes/torus.toml" | sed "s|\"../models/torus.obj\"|\"$src/config/models/torus.obj\"|" >"$work/placed.toml"
check "the scene has no construction events left" "! grep -q 'construction.event' '$work/placed.toml'"

bounded 150 "$work/p1.log" "$exe" "$work/placed.toml" --no-listen --cache "$work/map.bopgm" -o "$work/p1"
rc1=$?
bounded 150 "$work/p2.log" "$mpi" --oversubscribe -np 2 "$exe" "$work/placed.toml" --no-listen \
  --cache "$work/map.bopgm" -o "$work/p2"
rc2=$?
bounded 150 "$work/p3.log" "$exe" "$work/placed.toml" --no-listen --cache "$work/map.bopgm" -o "$work/p3" --threads 1
rc3=$?
bounded 150 "$work/p4.log" "$exe" "$work/placed.toml" --no-listen --cache "$work/map.bopgm" -o "$work/p4" --threads 3
rc4=$?
bounded 150 "$work/p5.log" "$mpi" --oversubscribe -np 3 "$exe" "$work/placed.toml" --no-listen \
  --cache "$work/map.bopgm" -o "$work/p5" --threads 1
rc5=$?
# Today's damped dynamics alone, to the same rule.
{ cat "$work/placed.toml"; printf '\n[construction]\nsettle_method = "dynamics"\n'; } >"$work/dynamics.toml"
bounded 150 "$work/d1.log" "$exe" "$work/dynamics.toml" --no-listen --cache "$work/map.bopgm" -o "$work/d1"
rcd=$?
tail -4 "$work/p1.log"
check "both runs end with exit code 0 (got $rc1 and $rc2)" "[ $rc1 -eq 0 ] && [ $rc2 -eq 0 ]"
check "1 and 3 threads build the same bag to the last digit: every particle of final.xyz (exit codes $rc3, $rc4)" \
  "[ $rc3 -eq 0 ] && [ $rc4 -eq 0 ] && grep -q 'layout: 1 rank x 1 thread ' '$work/p3.log' && \
   grep -q 'layout: 1 rank x 3 threads ' '$work/p4.log' && \
   cmp -s <(tail -n +3 '$work/p3/final.xyz') <(tail -n +3 '$work/p4/final.xyz') && \
   [ \$(sed -n 's/^settled at step \\([0-9]*\\):.*/\\1/p' '$work/p3.log') = \$(sed -n 's/^settled at step \\([0-9]*\\):.*/\\1/p' '$work/p4.log') ]"
settled1=$(sed -n 's/^settled at step \([0-9]*\):.*/\1/p' "$work/p1.log")
settled2=$(sed -n 's/^settled at step \([0-9]*\):.*/\1/p' "$work/p2.log")
check "the run ends by itself once settled, before the cap of 20000 steps (step ${settled1:-none})" \
  "[ -n '$settled1' ] && [ '$settled1' -lt 20000 ] && grep -q \"Step=$settled1 \" '$work/p1/final.xyz'"
check "the run to the settled state steps at settle_time_step, by default 1.5 times the scene's 0.02: Time = 0.03 x Step" \
  "grep -q 'until settled: time step 0.03 (settle_time_step; \[dynamics\] time_step 0.02)' '$work/p1.log' && \
   awk 'NR == 2 {for (i = 1; i <= NF; ++i) {if (\$i ~ /^Time=/) t = substr(\$i, 6); if (\$i ~ /^Step=/) s = substr(\$i, 6)}}
        END {exit !(s > 0 && t / s > 0.03 - 1e-12 && t / s < 0.03 + 1e-12)}' '$work/p1/final.xyz'"
{ cat "$work/placed.toml"; printf '\n[construction]\nsettle_time_step = 0\n'; } >"$work/bad-dt.toml"
bounded 60 "$work/bad-dt.log" "$exe" "$work/bad-dt.toml" --no-listen --steps 1 --cache "$work/map.bopgm" -o "$work/bad-dt"
rcbad=$?
check "settle_time_step = 0 is refused, naming the key and what it expects (exit $rcbad)" \
  "[ $rcbad -ne 0 ] && grep -q 'settle_time_step.*expected a positive time step' '$work/bad-dt.log'"
{ cat "$work/placed.toml"; printf '\n[construction]\nsettle_calm_steps = -1\n'; } >"$work/bad-calm.toml"
bounded 60 "$work/bad-calm.log" "$exe" "$work/bad-calm.toml" --no-listen --steps 1 --cache "$work/map.bopgm" -o "$work/bad-calm"
rccalm=$?
check "settle_calm_steps = -1 is refused, naming the key and what it expects (exit $rccalm)" \
  "[ $rccalm -ne 0 ] && grep -q 'settle_calm_steps.*expected 0 steps or more' '$work/bad-calm.log'"
check "settled by checks 10 steps apart, calm over 50 steps (step ${settled1:-none})" \
  "[ -n '$settled1' ] && [ \$(( ${settled1:-1} % 10 )) -eq 0 ] && \
   grep -q 'at every check over 50 steps, 10 steps apart' '$work/p1.log'"
check "the log gives the counts placed against the ideal" \
  "grep -q 'placed on the map: torus-surface [0-9]* (1.0[0-9] of the' '$work/p1.log'"
check "no births or deaths: the bag was full from the start" "grep -q '^births 0, deaths 0' '$work/p1.log'"
check "the shape's fidelity: at least 95% of surface and 98% of volume particles in their voxels" \
  "awk '/^shape fidelity/ {s = \$3 + 0; v = \$11 + 0} END {exit !(s >= 95 && v >= 98)}' '$work/p1.log'"
check "2 ranks settle at the same step (${settled2:-none}) with the same particles" \
  "[ '$settled1' = '$settled2' ] && [ \$(head -1 '$work/p1/final.xyz') = \$(head -1 '$work/p2/final.xyz') ] && \
   diff -q <(awk 'NR > 2 {print \$(NF - 1)}' '$work/p1/final.xyz' | sort) \
           <(awk 'NR > 2 {print \$(NF - 1)}' '$work/p2/final.xyz' | sort) >/dev/null"

# The minimiser (core/Fire.hpp) settles the bag to the rule of today's dynamics: its steps first,
# then the damped dynamics' until calm over 50 steps, in fewer steps than the dynamics alone and
# to a state as deep (pair energy within 0.5%) and as faithful; 1, 2 and 3 ranks settle at the
# same step to the same particles (positions by id within 1e-9 length: the sums over ranks differ
# in their last bits).
settled5=$(sed -n 's/^settled at step \([0-9]*\):.*/\1/p' "$work/p5.log")
settledd=$(sed -n 's/^settled at step \([0-9]*\):.*/\1/p' "$work/d1.log")
fire=$(sed -n "s/.*the FIRE minimiser's first \([0-9]*\) steps, then the damped dynamics$/\1/p" "$work/p1.log")
check "the minimiser's $fire steps, then the dynamics' $(( ${settled1:-0} - ${fire:-0} )) (at least 50) settle the bag" \
  "[ -n '$fire' ] && [ \$(( ${settled1:-0} - ${fire:-0} )) -ge 50 ]"
check "the dynamics alone settle it too (exit $rcd), at step ${settledd:-none}, later than the minimiser (${settled1:-none})" \
  "[ $rcd -eq 0 ] && [ -n '$settledd' ] && [ -n '$settled1' ] && [ $settled1 -lt $settledd ] && \
   ! grep -q 'FIRE' '$work/d1.log'"
energy() { sed -n 's/^births .*E_pair \([-0-9.e+]*\),.*/\1/p' "$1"; }
check "the minimiser's state is as deep as the dynamics' (E_pair $(energy "$work/p1.log") against $(energy "$work/d1.log"))" \
  "awk -v f=\"$(energy "$work/p1.log")\" -v d=\"$(energy "$work/d1.log")\" 'BEGIN {exit !(f != \"\" && d != \"\" && f <= d + 0.005 * (d < 0 ? -d : d))}'"
check "and as faithful: at least 95% of surface particles in their voxels after both" \
  "awk '/^shape fidelity/ {s = \$3 + 0} END {exit !(s >= 95)}' '$work/d1.log'"
positions() { awk 'NR > 2 {print $(NF - 1), $2, $3, $4}' "$1" | sort -n; }
check "3 ranks (exit $rc5) settle at the same step (${settled5:-none}) as 1 and 2, to the same positions within 1e-9" \
  "[ $rc5 -eq 0 ] && [ '$settled1' = '$settled5' ] && \
   paste -d ' ' <(positions '$work/p1/final.xyz') <(positions '$work/p2/final.xyz') <(positions '$work/p5/final.xyz') |
   awk '{for (k = 2; k <= 4; ++k) {a = \$k - \$(k + 4); b = \$k - \$(k + 8); if (\$1 != \$5 || \$1 != \$9 || a * a > 1e-18 || b * b > 1e-18) bad = 1}} END {exit bad || NR == 0}'"

# A torus whose tube is 3 voxels across at r0 = 2 voxels: named before it is built.
sed -e 's|^source = "mesh"|source = "torus"\nmajor_radius_mm = 20.0\nminor_radius_mm = 3.4|' \
    -e '/^file = /d' -e '/^scale_mm = /d' "$work/placed.toml" >"$work/thin.toml"
bounded 150 "$work/thin.log" "$exe" "$work/thin.toml" --no-listen --steps 10 --cache "$work/thin.bopgm" -o "$work/thin"
check "a part thinner than 2 r0 is named before the bag is built, with the r0_voxels that would hold it" \
  "grep -q \"warning: bag 'torus': .* lie in parts thinner than 2 r0 (4 voxels).*r0_voxels = \" '$work/thin.log'"
exit $fail
