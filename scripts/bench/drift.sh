#!/usr/bin/env bash
# Mixed precision's energy gate at its full length: the bulk box and the torus of config/scenes
# (the torus built in double, then run without its map), 100,000 undamped steps in double and in
# mixed, the largest |E - E0| / |E0| of each printed and mixed checked to be at most twice double's
# (tests/physics/TestMixedScenes.cpp; CI runs the same check over 5,000 steps). A few minutes.
#   scripts/bench/drift.sh
set -euo pipefail
cd "$(dirname "$0")/../.."
case "${1:-}" in
  "") ;;
  -h|--help) sed -n '2,6p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
  *) echo "drift.sh: no arguments expected, not '$1' (--help)" >&2; exit 2 ;;
esac
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j "${BOP_JOBS:-2}" --target bop_physics_tests >/dev/null
echo "CPU: $(sed -n 's/^model name[[:space:]]*: *//p' /proc/cpuinfo | head -1)"
OMP_NUM_THREADS=${OMP_NUM_THREADS:-1} build/tests/bop_physics_tests "[drift-long]" | grep -E "drift over|passed|failed|FAILED"
