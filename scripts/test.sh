#!/usr/bin/env bash
# Installs what is missing, checks the sources' format and include graph, builds with warnings
# as errors and runs every test with ctest: the unit tests in a build with AddressSanitizer +
# UndefinedBehaviorSanitizer (with the MPI tests at 2 ranks again), the rest in Release.
#   scripts/test.sh                 everything (what CI runs): the unit tests run in the sanitizer
#                                   build only (built once, CI's 25 minutes), the rest in Release
#   scripts/test.sh --no-sanitize   everything in Release, no sanitizer build and no fuzzing
# Last, every decoder of untrusted input is fuzzed for BOP_FUZZ_SECONDS (default 3; scripts/fuzz.sh alone: 30) each.
set -euo pipefail
cd "$(dirname "$0")/.."
jobs=${BOP_JOBS:-2}
sanitize=1
case "${1:-}" in
  "") ;;
  --no-sanitize) sanitize=0 ;;
  *) echo "test.sh: unknown option '$1' (expected nothing or --no-sanitize)" >&2; exit 2 ;;
esac

# Each stage says when it starts, in seconds since the start: CI's budget is 25 minutes on 2 cores.
stage() { echo "== $* (at ${SECONDS} s) =="; }
scripts/install-deps.sh

stage "format (.clang-format)"
# Every C++ file as clang-format writes it: `clang-format -i FILE` fixes one.
mapfile -t sources < <(git ls-files '*.cpp' '*.hpp' '*.h' 2>/dev/null || find common dynamics_server protocol viz_client haptic_client tests scripts -name '*.[ch]pp')
clang-format --dry-run --Werror --style=file "${sources[@]}"
echo "format: ${#sources[@]} files as .clang-format writes them"

stage "include graph (scripts/include-graph.py)"
# Parts (common/, dynamics_server/core, protocol/server, ...) include one another one way only.
python3 scripts/include-graph.py --quiet

stage "build (Release, -Werror)"
unit_in_release=$([[ $sanitize -eq 1 ]] && echo OFF || echo ON)
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release -DBOP_WERROR=ON -DBOP_BUILD_VIEWER=ON \
  -DBOP_UNIT_TESTS="$unit_in_release" >/dev/null
cmake --build build -j "$jobs"
stage "tests"
# ctest runs $jobs tests side by side: each takes one thread unless a test sets its own count
# (the thread tests do), so that the haptic tests' 1 kHz loops keep a core.
export OMP_NUM_THREADS=${OMP_NUM_THREADS:-1}
ctest --test-dir build -j "$jobs" --output-on-failure

if [[ $sanitize -eq 1 ]]; then
  stage "unit and MPI tests under AddressSanitizer + UndefinedBehaviorSanitizer"
  # -O1 and line tables only: half the compile time of -O2 -g, stack traces still name the lines.
  cmake -S . -B build-asan -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1 -DNDEBUG" \
    -DBOP_SANITIZE=ON -DBOP_WERROR=ON >/dev/null
  cmake --build build-asan -j "$jobs" --target bop_unit_tests bop_mpi_tests bop-deadline
  ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 LSAN_OPTIONS=suppressions=$PWD/tests/lsan-suppressions.txt \
    ctest --test-dir build-asan -L unit -j "$jobs" --output-on-failure
  # Open MPI keeps its allocations until exit by design: leak checks off for the MPI tests only.
  # Under the sanitizers at 2 ranks (halo, migration, gathers); 1 to 4 ranks run in the Release
  # build above (more here would take CI past its 25 minutes: 4 ranks took 78 s).
  ASAN_OPTIONS=detect_leaks=0 UBSAN_OPTIONS=print_stacktrace=1 \
    ctest --test-dir build-asan -R '^mpi[.]np2$' --output-on-failure
  stage "fuzzing the decoders (libFuzzer, ${BOP_FUZZ_SECONDS:-3} s each)"
  BOP_FUZZ_SECONDS=${BOP_FUZZ_SECONDS:-3} scripts/fuzz.sh
fi
echo "test.sh: everything passed in ${SECONDS} s"
