#!/usr/bin/env bash
# Whether a change kept the runs' results bit for bit: bop-server of this tree and of a base
# revision (built apart in a git worktree) run the torus (2,000 steps: surface and volume built),
# the ventricle (600 steps: built, then beating), the bulk box (300 steps) and the organs scene
# (placed and settled), each at 1, 2 and 3 ranks, and every final state (final.xyz) must be the
# same bytes; then a session the base server recorded (a scripted haptic finger probing the torus
# at 2 ranks) must replay bit for bit on this tree's server (bop-replay check).
#   scripts/same-states.sh BASE_REVISION [BUILD_DIR]   (BUILD_DIR: this tree's build, default build)
# Exit 0 when every state and the replay are the same; the differing cases are named otherwise.
set -uo pipefail
if [[ $# -lt 1 || $1 == -h || $1 == --help ]]; then sed -n '2,9p' "$0" | cut -c3-; [[ $# -ge 1 ]]; exit; fi
cd "$(dirname "$0")/.."
base=$1 build=$(realpath "${2:-build}")
rev=$(git rev-parse --verify "$base^{commit}") || { echo "same-states.sh: no revision '$base'" >&2; exit 2; }
out=$PWD/out/same-states; rm -rf "$out"; mkdir -p "$out"
tree=/tmp/bop-base-${rev:0:12}
if [[ ! -x $tree/build/dynamics_server/bop-server ]]; then
  echo "building bop-server of $base (${rev:0:12}) in $tree"
  rm -rf "$tree"; git worktree prune; git worktree add --detach "$tree" "$rev" >/dev/null || exit 2
  cmake -S "$tree" -B "$tree/build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DBOP_UNIT_TESTS=OFF \
    -DBOP_BUILD_VIEWER=OFF >"$out/base-configure.log" || exit 2
  cmake --build "$tree/build" --target bop-server bop-haptic >"$out/base-build.log" || { tail "$out/base-build.log"; exit 2; }
fi
cmake --build "$build" --target bop-server bop-replay >"$out/build.log" || { tail "$out/build.log"; exit 2; }
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMP_NUM_THREADS=1
declare -A steps=([torus]=2000 [ventricle]=600 [bulk-box]=300 [organs]=)
failed=()
for scene in torus ventricle bulk-box organs; do
  for np in 1 2 3; do
    for which in base new; do
      exe=$build/dynamics_server/bop-server; [[ $which == base ]] && exe=$tree/build/dynamics_server/bop-server
      dir=$out/$scene-$np-$which
      args=(config/scenes/$scene.toml --no-listen -o "$dir" --report-every 100000)
      [[ -n ${steps[$scene]} ]] && args+=(--steps "${steps[$scene]}")
      mpirun -np "$np" --oversubscribe "$exe" "${args[@]}" >"$dir.log" 2>&1 ||
        { echo "$scene at $np ranks: the $which server failed (see $dir.log)"; failed+=("$scene-$np"); }
    done
    if cmp -s "$out/$scene-$np-base/final.xyz" "$out/$scene-$np-new/final.xyz"; then
      echo "$scene at $np ranks: final states the same ($(head -1 "$out/$scene-$np-new/final.xyz") particles)"
    else
      echo "$scene at $np ranks: final states DIFFER"; failed+=("$scene-$np")
    fi
  done
done
# A session recorded by the base server, replayed by this tree's.
rec=$out/session.mcap
mpirun -np 2 "$tree/build/dynamics_server/bop-server" config/scenes/torus.toml --port 0 --steps 900 \
  --wait-for-client --record "$rec" -o "$out/recorded" >"$out/recorded.log" 2>&1 &
server=$!
for _ in $(seq 100); do grep -q '^listening on' "$out/recorded.log" && break; sleep 0.2; done
endpoint=$(sed -n 's/^listening on \([^ ]*\) .*/\1/p' "$out/recorded.log")
"$tree/build/haptic_client/bop-haptic" "$endpoint" --device sim:finger --seconds 4 --out "$out/haptic" \
  >"$out/haptic.log" 2>&1
wait $server
if "$build/protocol/bop-replay" check "$rec" -o "$out/replay" >"$out/replay.log" 2>&1; then
  echo "the base server's recording replays bit for bit: $(grep -m1 'bit for bit' "$out/replay.log")"
else
  echo "the base server's recording does NOT replay bit for bit (see $out/replay.log)"; failed+=(replay)
fi
if ((${#failed[@]})); then echo "differ or failed: ${failed[*]}"; exit 1; fi
echo "every final state and the replay are the same as ${rev:0:12}'s"
