#!/usr/bin/env bash
# The Python client (python/bop) against a served run: the torus served in Compact8 frames with
# ids while recording, python/examples/poke.py connects, takes frames as NumPy arrays, presses the
# probe onto the topmost surface particle (which must move more than 5 times its unprobed
# wander), reads the force, pauses and resumes; after the server stops, bop.read_recording takes
# the recording, and its whole frames are those the server recorded (one /bop/stats row each, as
# the C++ side assembled them) with the steps of the frames, rising but at the paused step.
# Usage: python_client_cli.sh BOP_SERVER SOURCE_DIR
set -u
server=$1 src=$2
source "$(dirname "$0")/cli-checks.sh"
py=/usr/bin/python3

bounded 200 "$work/build.log" "$server" "$src/config/scenes/torus.toml" --no-listen --cache "$work/map.bopgm" -o "$work/t"
check "the torus is built" "[ -s '$work/t/final.xyz' ]"
"$server" "$src/config/scenes/torus.toml" --restart "$work/t/final.xyz" --cache "$work/map.bopgm" --port 0 \
  --publish-hz 30 --compact --frame-ids --steps 1000000000 --record "$work/s.mcap" -o "$work/served" \
  >"$work/server.log" 2>&1 &
pid=$!
endpoint=""
for _ in $(seq 1 300); do
  endpoint=$(sed -n 's/^listening on \(tcp:[^ ]*\).*/\1/p' "$work/server.log" | head -1)
  [[ -n $endpoint ]] && break
  sleep 0.1
done
check "the server listens" "[ -n '$endpoint' ]"
bounded 60 "$work/poke.txt" "$py" "$src/python/examples/poke.py" "$endpoint" --seconds 2
rc=$?
cat "$work/poke.txt"
check "poke.py moves the particle with the probe (exit $rc)" "[ $rc -eq 0 ] && grep -q 'the probe moved the particle' '$work/poke.txt'"
check "... with frames of the scene's particles as NumPy arrays, ids included" \
  "grep -qE '^frame [0-9]+: step [0-9]+, [0-9]+ particles, positions \\([0-9]+, 3\\) float32, normals \\([0-9]+, 3\\), ids yes' '$work/poke.txt'"
check "... the force it felt, and a pause at a step" "grep -q '^force on the probe' '$work/poke.txt' && grep -qE '^paused at step [0-9]+' '$work/poke.txt'"
kill -INT "$pid"
wait "$pid"
check "the server stops with its recording" "[ -s '$work/s.mcap' ]"

paused=$(sed -n 's/^paused at step \([0-9]*\).*/\1/p' "$work/poke.txt" | head -1)
bounded 60 "$work/rec.txt" "$py" - "$src" "$work/s.mcap" "${paused:--1}" <<'PY'
import sys
import numpy as np
sys.path.insert(0, sys.argv[1] + "/python")
import bop
from bop.recording import _messages
path = sys.argv[2]
rec = bop.read_recording(path)
rows = sum(1 for topic, _, _ in _messages(open(path, "rb").read(), path) if topic == "/bop/stats")
f = rec.frames[-1]
n = len(f)
surface = np.isin(f.species, [k + 1 for k, kind in enumerate(rec.scene.kinds) if kind == "surface"])
print(f"{len(rec.frames)} whole frames, {rows} stats rows; {n} particles, {len(np.unique(f.ids))} distinct ids")
# Frames while paused share the paused step (a paused run still publishes); elsewhere steps rise.
steps = rec.steps.astype(np.int64)
repeated = steps[1:][np.diff(steps) == 0]
print(f"steps rise: {bool(np.all(np.diff(steps) >= 0) and np.all(repeated == int(sys.argv[3])))}")
print(f"inside the box: {bool(np.all((f.positions >= rec.scene.box_lo - 1e-3) & (f.positions <= rec.scene.box_hi + 1e-3)))}")
print(f"unit normals on the surface: {bool(np.allclose(np.linalg.norm(f.normals[surface], axis=1), 1, atol=1e-5))}")
print(f"probes applied: {len(rec.probe_steps)}, active {int(rec.probe_active.sum())}")
ok = len(rec.frames) == rows > 20 and len(np.unique(f.ids)) == n and n > 1000 and len(rec.probe_steps) > 50
print("recording ok" if ok else "recording NOT ok")
PY
cat "$work/rec.txt"
check "bop.read_recording: whole frames as the server recorded them, ids unique, steps rising (but while paused)" \
  "grep -q 'recording ok' '$work/rec.txt' && grep -q 'steps rise: True' '$work/rec.txt' && grep -q 'inside the box: True' '$work/rec.txt' && grep -q 'unit normals on the surface: True' '$work/rec.txt'"
exit $fail
