#!/usr/bin/env bash
# Checkpoints of bop-server runs: a run stopped at a checkpoint and restarted from it ends bit for
# bit where an uninterrupted run ends (1 rank and 2 ranks; the torus built by births, its volume
# seeded after the restart; a served run at 2 ranks; the four bags of the organs scene, stopped while it settles);
# SIGTERM to mpirun writes a whole checkpoint and stops; a restart at 1 and at 3 ranks holds every
# particle of it.
# Usage: bop_server_checkpoint_cli.sh PATH/TO/bop-server PATH/TO/mpiexec SOURCE_DIR
set -u
exe=$1
mpi=$2
src=$3
source "$(dirname "$0")/cli-checks.sh"
scene=$src/config/scenes/torus.toml
server() {  # ranks, its log, then bop-server's options; at most 150 s
  local n=$1 log=$2
  shift 2
  if [[ $n == 1 ]]; then bounded 150 "$log" "$exe" "$scene" --no-listen --cache "$work/$(basename "$scene").bopgm" "$@"
  else bounded 150 "$log" "$mpi" --oversubscribe -np "$n" "$exe" "$scene" --no-listen \
    --cache "$work/$(basename "$scene").bopgm" "$@"; fi
}
ids() { awk 'NR > 2 {print $(NF - 1)}' "$1" | sort; }  # the id column of an extended XYZ frame

for ranks in 1 2; do
  # The volume is seeded at step 1500: after the restart at 900, so the seed count must carry over.
  server "$ranks" "$work/a$ranks.log" --steps 1800 --checkpoint-every 900 --report-every 300 -o "$work/a$ranks"
  server "$ranks" "$work/b$ranks.log" --steps 900 --report-every 300 -o "$work/b$ranks"
  server "$ranks" "$work/c$ranks.log" --steps 900 --checkpoint-every 900 --report-every 300 -o "$work/c$ranks" \
    --restart "$work/b$ranks/checkpoint.xyz"
  check "$ranks rank(s): the checkpoint at the end of a run is at step 900" \
    "grep -q 'Step=900 Births=' '$work/b$ranks/checkpoint.xyz'"
  check "$ranks rank(s): stopped at 900 and restarted, the run ends bit for bit as the uninterrupted one" \
    "cmp -s '$work/a$ranks/final.xyz' '$work/c$ranks/final.xyz'"
  check "$ranks rank(s): ... with the volume seeded after the restart" \
    "[ \$(grep -c '^torus-volume ' '$work/c$ranks/final.xyz') -gt 10 ]"
done

# A served run's checkpoints mean what a batch run's do (app/runs/RunLifecycle.hpp): stopped at one
# and restarted from it, at 2 ranks, the served run ends bit for bit as the one that went on.
served() {  # its log, then bop-server's options; at most 150 s
  local log=$1
  shift
  bounded 150 "$log" "$mpi" --oversubscribe -np 2 "$exe" "$scene" --port 0 \
    --cache "$work/$(basename "$scene").bopgm" "$@"
}
served "$work/sa.log" --steps 1800 --checkpoint-every 900 -o "$work/sa"
served "$work/sb.log" --steps 900 --checkpoint-every 900 -o "$work/sb"
served "$work/sc.log" --steps 900 --checkpoint-every 900 -o "$work/sc" --restart "$work/sb/checkpoint.xyz"
check "served, 2 ranks: the checkpoint at the end of a run is at step 900" \
  "grep -q 'Step=900 Births=' '$work/sb/checkpoint.xyz'"
check "served, 2 ranks: stopped at 900 and restarted, the run ends bit for bit as the uninterrupted one" \
  "[ -s '$work/sa/final.xyz' ] && cmp -s '$work/sa/final.xyz' '$work/sc/final.xyz'"

# Several bags (the organs scene: four bags, one inside another, placed and settled, the
# minimiser's steps first, then the dynamics' from about step 180): stopped at a checkpoint in
# either part and restarted, at 1 and 2 ranks, it ends as the uninterrupted run does, at the
# same step (the checkpoint carries the settling's state, Settle=). Every run takes its checkpoints
# at the same steps: each one starts the run afresh from the file's values (core::Run::reseat).
scene=$src/config/scenes/organs.toml
for ranks in 1 2; do
  server "$ranks" "$work/oa$ranks.log" --steps 600 --checkpoint-every 100 -o "$work/oa$ranks"
  for at in 100 200; do
    server "$ranks" "$work/ob$ranks-$at.log" --steps $at --checkpoint-every 100 -o "$work/ob$ranks-$at"
    server "$ranks" "$work/oc$ranks-$at.log" --steps 600 --checkpoint-every 100 -o "$work/oc$ranks-$at" \
      --restart "$work/ob$ranks-$at/checkpoint.xyz"
    check "organs, $ranks rank(s): the checkpoint at $at says where the settling is ($(grep -o 'Settle="[a-z]*' \
      "$work/ob$ranks-$at/checkpoint.xyz"))" "grep -q 'Settle=\"\\(fire\\|dynamics\\) ' '$work/ob$ranks-$at/checkpoint.xyz'"
    check "organs, $ranks rank(s): stopped at $at and restarted, the run ends bit for bit as the uninterrupted one" \
      "cmp -s '$work/oa$ranks/final.xyz' '$work/oc$ranks-$at/final.xyz'"
  done
  check "organs, $ranks rank(s): every bag's species in the checkpoint" \
    "[ \$(awk 'NR > 2 {print \$1}' '$work/ob$ranks-100/checkpoint.xyz' | sort -u | wc -l) -eq 8 ]"
  check "organs, $ranks rank(s): the checkpoints at 100 and 200 are in the minimiser's part and the dynamics'" \
    "grep -q 'Settle=\"fire ' '$work/ob$ranks-100/checkpoint.xyz' && grep -q 'Settle=\"dynamics ' '$work/ob$ranks-200/checkpoint.xyz'"
done
scene=$src/config/scenes/torus.toml

# SIGTERM to mpirun (through bop-deadline, which passes it on): a whole checkpoint, then a
# restart at other rank counts.
"$BOP_DEADLINE" --log "$work/t.log" 150 -- "$mpi" --oversubscribe -np 2 "$exe" "$scene" --no-listen \
  --cache "$work/map.bopgm" --steps 10000000 --report-every 200 -o "$work/t" &
pid=$!
for _ in $(seq 1 300); do grep -q '^step ' "$work/t.log" && break; sleep 0.1; done
sleep 1
kill -TERM "$pid"
wait "$pid"
cat "$work/t.log" | tail -3
check "SIGTERM stops the run and says where the checkpoint is" "grep -q 'stopped by a signal after step' '$work/t.log'"
check "the checkpoint is whole: its count line matches its rows, no temporary file left" \
  "[ -s '$work/t/checkpoint.xyz' ] && [ ! -e '$work/t/checkpoint.xyz.tmp' ] && \
   [ \$((\$(wc -l <'$work/t/checkpoint.xyz') - 2)) = \$(head -1 '$work/t/checkpoint.xyz') ]"
# SIGUSR1, which mpirun passes on without killing the ranks a second later: the same stop.
"$BOP_DEADLINE" --log "$work/u.log" 150 -- "$mpi" --oversubscribe -np 2 "$exe" "$scene" --no-listen \
  --cache "$work/map.bopgm" --steps 10000000 --report-every 200 -o "$work/u" &
pid=$!
for _ in $(seq 1 300); do grep -q '^step ' "$work/u.log" && break; sleep 0.1; done
kill -USR1 "$pid"
wait "$pid"
rc=$?
check "SIGUSR1 to mpirun stops the run with a checkpoint and exit code 0 (got $rc)" \
  "[ $rc -eq 0 ] && grep -q 'stopped by a signal after step' '$work/u.log' && [ -s '$work/u/checkpoint.xyz' ]"

for ranks in 1 3; do
  server "$ranks" "$work/r$ranks.log" --steps 0 --restart "$work/t/checkpoint.xyz" -o "$work/r$ranks"
  check "a restart at $ranks rank(s) holds every particle of the checkpoint" \
    "[ -s '$work/r$ranks/final.xyz' ] && diff -q <(ids '$work/t/checkpoint.xyz') <(ids '$work/r$ranks/final.xyz') >/dev/null"
done
exit $fail
