#!/usr/bin/env bash
# A recording opened as Foxglove opens it (tests/foxglove/check.mjs, with npm's @mcap/core,
# @foxglove/schemas, flatbuffers_reflection and fzstd, pinned by tests/foxglove/package-lock.json):
# a served torus recorded for 4 s while a simulated haptic device pokes it (Compact8 frames), then
#  - the recording: @mcap/core's indexed and stream readers find every message; its Foxglove
#    schemas equal the published ones field by field; every message decodes, also with the
#    published schemas, with sensible content;
#  - the same recording written unchunked (bop-replay export --chunk-kib 0, as recordings were
#    before chunks) is refused by the check (no index: the check can fail), and
#  - exported back by bop-replay export, it passes again with the same messages.
# npm installs the check's packages once into NPM_DIR (the registry must be reachable: a missing
# package fails this test, it does not skip it; every package is checked against the sha512 in
# package-lock.json).
# Usage: foxglove_cli.sh BOP_SERVER BOP_HAPTIC BOP_REPLAY FLATC SOURCE_DIR NPM_DIR
set -u
server=$1 haptic=$2 replay=$3 flatc=$4 src=$5 npm_dir=$6
source "$(dirname "$0")/cli-checks.sh"

mkdir -p "$npm_dir"
cp "$src/tests/foxglove/package.json" "$src/tests/foxglove/package-lock.json" "$src/tests/foxglove/check.mjs" "$npm_dir/"
npm_ci() { (cd "$npm_dir" && npm ci --no-audit --no-fund --loglevel=error "$@") >"$work/npm.log" 2>&1; }
if ! cmp -s "$npm_dir/package-lock.json" "$npm_dir/node_modules/.installed-lock" 2>/dev/null; then
  npm_ci
  rc=$?
  if [[ $rc -ne 0 ]] && grep -q "CERT" "$work/npm.log"; then
    # A network whose TLS is intercepted by a proxy this machine's Node.js does not trust (seen on
    # a fresh Debian root behind such a proxy): the download goes on without checking the
    # registry's certificate, and npm ci still checks every package against the sha512 that
    # package-lock.json pins, so what is installed is what the lock file names.
    cat "$work/npm.log"
    echo "npm: the registry's certificate is not trusted here; installing with --strict-ssl=false (packages checked against package-lock.json's sha512)"
    npm_ci --strict-ssl=false
    rc=$?
  fi
  cat "$work/npm.log"
  check "npm installs the check's packages (exit $rc)" "[ $rc -eq 0 ]"
  [[ $rc -eq 0 ]] && cp "$npm_dir/package-lock.json" "$npm_dir/node_modules/.installed-lock"
fi

bounded 200 "$work/build.log" "$server" "$src/config/scenes/torus.toml" --no-listen --cache "$work/map.bopgm" -o "$work/t"
check "the torus is built" "[ -s '$work/t/final.xyz' ]"
"$server" "$src/config/scenes/torus.toml" --restart "$work/t/final.xyz" --cache "$work/map.bopgm" --port 0 \
  --publish-hz 30 --compact --steps 1000000000 --record "$work/session.mcap" -o "$work/served" >"$work/server.log" 2>&1 &
pid=$!
endpoint=""
for _ in $(seq 1 300); do
  endpoint=$(sed -n 's/^listening on \(tcp:[^ ]*\).*/\1/p' "$work/server.log" | head -1)
  [[ -n $endpoint ]] && break
  sleep 0.1
done
check "the server listens" "[ -n '$endpoint' ]"
bounded 60 "$work/haptic.log" "$haptic" "$endpoint" --device sim:poke --seconds 4 --out "$work/haptic"
kill -INT "$pid"
wait "$pid"
rc=$?
check "the served run ends on SIGINT with its recording (exit $rc)" "[ $rc -eq 0 ] && [ -s '$work/session.mcap' ]"

fox() { bounded 120 "$1" node "$npm_dir/check.mjs" "$2" --flatc "$flatc" --report "$1.json"; }
fox "$work/check.txt" "$work/session.mcap"
rc=$?
cat "$work/check.txt"
check "Foxglove's readers and schemas take the recording (exit $rc)" "[ $rc -eq 0 ]"
check "... with a point cloud, surfels, probe, transform and stats for every frame" \
  "[ \$(grep -cE '^  /(foxglove/(particles|surfels|probe|transforms)|bop/stats) +([0-9]+) +\\3 +\\3' '$work/check.txt') -eq 5 ]"
frames=$(awk '$1 == "/bop/frame" {print $2}' "$work/check.txt")
particles=$(awk '$1 == "/foxglove/particles" {print $2}' "$work/check.txt")
check "... and as many point clouds ($particles) as whole frames ($frames, one chunk each)" "[ '${particles:-0}' -gt 60 ] && [ '$particles' -eq '$frames' ]"

bounded 60 "$work/plain.log" "$replay" export "$work/session.mcap" "$work/plain.mcap" --chunk-kib 0
fox "$work/plain.txt" "$work/plain.mcap"
rc=$?
check "an unchunked copy is refused by the check (exit $rc: no index)" "[ $rc -eq 1 ] && grep -q 'not indexed' '$work/plain.txt'"
bounded 60 "$work/export.log" "$replay" export "$work/plain.mcap" "$work/export.mcap"
cat "$work/export.log"
fox "$work/export.txt" "$work/export.mcap"
rc=$?
check "bop-replay export makes it Foxglove-ready again (exit $rc)" "[ $rc -eq 0 ]"
check "... with the same messages per topic" \
  "diff <(grep -E '^  /' '$work/check.txt' | awk '{print \$1, \$2, \$5}') <(grep -E '^  /' '$work/export.txt' | awk '{print \$1, \$2, \$5}')"
exit $fail
