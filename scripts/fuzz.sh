#!/usr/bin/env bash
# Fuzzes what reads untrusted input (tests/fuzz) with libFuzzer + AddressSanitizer +
# UndefinedBehaviorSanitizer: installs what is missing, configures build-fuzz with Clang and
# BOP_FUZZ=ON, builds only the fuzz targets and the seed generator, writes the seeds, then runs
# each target for a bounded time (or number of runs) and prints its executions per second. Exits
# non-zero if any target crashed (sanitizer report, broken contract, timeout, out of memory or
# leak); the reproducer is build-fuzz/fuzz/artifacts/<target>-crash-<sha1> (also leak-, timeout-, oom-).
#   scripts/fuzz.sh                      every decoder (hello scene frame probe feedback command reply
#                                        maprequest mapchunk mapedits refusal mcap igtl; igtl: bop-igtl's
#                                        OpenIGTLink reader); what scripts/test.sh runs
#   scripts/fuzz.sh front mcap           only these; front: message sequences through the server's front
#                                        and served loop (FuzzFront.cpp; builds the server's libraries)
#   scripts/fuzz.sh --campaign [T...]    every target (decoders and front), each for BOP_FUZZ_RUNS
#                                        executions (default 10,000,000; hours); a log per target in
#                                        build-fuzz/fuzz/logs and the figures at the end
# Ctrl-C (or TERM) stops the running target with libFuzzer's figures, skips the rest and exits 130;
# the summary says "stopped".
# Environment:
#   BOP_FUZZ_SECONDS   seconds per target (default 30; not with --campaign)
#   BOP_FUZZ_RUNS      executions per target with --campaign (default 10000000)
#   BOP_FUZZ_WORKERS   processes per target with --campaign, sharing its corpus, the executions
#                      split between them (default 1; the front target is slow: one per core)
#   BOP_FUZZ_TIMEOUT   seconds one input may take before it counts as a hang (default 10)
#   BOP_JOBS           build jobs (default 2)
#   BOP_FUZZ_CXX       the Clang C++ compiler (default clang++)
#   BOP_FUZZ_BUILD     the build folder (default build-fuzz; a campaign may run in its own)
# The corpus grows across runs in build-fuzz/fuzz/corpus/<target>. To replay one reproducer:
#   build-fuzz/tests/fuzz/bop_fuzz_<target> build-fuzz/fuzz/artifacts/<target>-crash-...
set -euo pipefail
if [[ ${1:-} == -h || ${1:-} == --help ]]; then  # the comment above is the help
  sed -n '2,/^set -euo/{/^#/s/^# \{0,1\}//p}' "$0"
  exit 0
fi
cd "$(dirname "$0")/.."
jobs=${BOP_JOBS:-2}
seconds=${BOP_FUZZ_SECONDS:-30}
timeout=${BOP_FUZZ_TIMEOUT:-10}
cxx=${BOP_FUZZ_CXX:-clang++}
dir=${BOP_FUZZ_BUILD:-build-fuzz}
campaign=0
if [[ "${1:-}" == "--campaign" ]]; then
  campaign=1
  shift
fi
runs=${BOP_FUZZ_RUNS:-10000000}
workers=${BOP_FUZZ_WORKERS:-1}
stopped=0
[[ $workers =~ ^[1-9][0-9]*$ ]] || { echo "fuzz: BOP_FUZZ_WORKERS must be a whole number from 1 (got '$workers')" >&2; exit 2; }
[[ $campaign -eq 1 ]] || workers=1
decoders=(hello scene frame probe feedback command reply maprequest mapchunk mapedits refusal mcap igtl)
all_targets=("${decoders[@]}" front)
targets=("$@")
if [[ ${#targets[@]} -eq 0 ]]; then
  if [[ $campaign -eq 1 ]]; then targets=("${all_targets[@]}"); else targets=("${decoders[@]}"); fi
fi
for t in "${targets[@]}"; do
  [[ " ${all_targets[*]} " == *" $t "* ]] || { echo "fuzz: unknown target '$t' (${all_targets[*]})" >&2; exit 2; }
done

scripts/install-deps.sh --fuzz
command -v "$cxx" >/dev/null || { echo "fuzz: $cxx not found (scripts/install-deps.sh --fuzz installs clang)" >&2; exit 1; }

echo "== configure $dir ($cxx, BOP_FUZZ=ON) =="
cmake -S . -B "$dir" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_COMPILER="$cxx" -DBOP_FUZZ=ON >/dev/null
build_targets=(bop_fuzz_seeds)
for t in "${targets[@]}"; do build_targets+=("bop_fuzz_$t"); done
echo "== build ${build_targets[*]} =="
cmake --build "$dir" -j "$jobs" --target "${build_targets[@]}"

work=$dir/fuzz
bin=$dir/tests/fuzz
rm -rf "$work/seeds" "$work/logs"
mkdir -p "$work/corpus" "$work/artifacts" "$work/logs"
echo "== seeds =="
"$bin/bop_fuzz_seeds" "$work/seeds"

# Symbolised stack traces when llvm-symbolizer is there (Debian: package llvm).
if [[ -z "${ASAN_SYMBOLIZER_PATH:-}" ]]; then
  for s in llvm-symbolizer /usr/lib/llvm-*/bin/llvm-symbolizer; do
    if command -v "$s" >/dev/null 2>&1; then export ASAN_SYMBOLIZER_PATH=$(command -v "$s"); break; fi
  done
fi
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}

# A libFuzzer -print_final_stats value from a log.
final_stat() { sed -n "s/^stat::$1: *//p" "$2" | tail -1; }

failed=()
summary=()
for t in "${targets[@]}"; do
  max_len=65536
  [[ $t == frame ]] && max_len=$((1 << 20))  # frame chunks are large: a 1 MiB buffer holds ~50k particles
  mkdir -p "$work/corpus/$t"
  log="$work/logs/$t.log"
  # Artifacts of earlier runs stay; only the ones this run writes count.
  before=$(find "$work/artifacts" -maxdepth 1 -name "$t-*" -type f | sort)
  budget=(-max_total_time="$seconds")
  [[ $campaign -eq 1 ]] && budget=(-runs="$(((runs + workers - 1) / workers))")
  extra=()
  leaks=$ASAN_OPTIONS
  # The front runs MPI and ZeroMQ threads that keep their allocations to the end: no leak checks.
  [[ $t == front ]] && extra=(-detect_leaks=0) && leaks=detect_leaks=0
  echo "== fuzz $t (${budget[*]}, -max_len=$max_len$([[ $workers -gt 1 ]] && echo ", $workers processes")) =="
  rc=0
  start=$(date +%s)
  cmd=(env ASAN_OPTIONS="$leaks" OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
    "$bin/bop_fuzz_$t" -max_len="$max_len" -rss_limit_mb=2048 -timeout="$timeout" "${budget[@]}" "${extra[@]}"
    -print_final_stats=1 -artifact_prefix="$work/artifacts/$t-" "$work/corpus/$t" "$work/seeds/$t")
  # One log per worker ($t.1.log ...), gathered into $t.log at the end; one worker writes $t.log.
  logs=("$log") pids=()
  [[ $workers -eq 1 ]] || mapfile -t logs < <(for w in $(seq "$workers"); do echo "$work/logs/$t.$w.log"; done)
  # Ctrl-C or TERM: libFuzzer stops with its figures (exit 72); the summary says "stopped".
  trap 'stopped=1; [[ ${#pids[@]} -eq 0 ]] || kill -INT "${pids[@]}" 2>/dev/null || true' INT TERM
  for l in "${logs[@]}"; do
    "${cmd[@]}" >"$l" 2>&1 &  # in the background, so that a signal reaches the trap
    pids+=($!)
  done
  for p in "${pids[@]}"; do wait "$p" || rc=$?; done
  wait  # the workers a signal took the loop past
  [[ $workers -eq 1 ]] || cat "${logs[@]}" >"$log"
  trap - INT TERM
  took=$(( $(date +%s) - start ))
  after=$(find "$work/artifacts" -maxdepth 1 -name "$t-*" -type f | sort)
  new_artifacts=$(comm -13 <(echo "$before") <(echo "$after") | sed '/^$/d' || true)
  execs=0 rate=0
  for l in "${logs[@]}"; do  # summed over the workers; "?" where a log has no final figures
    e=$(final_stat number_of_executed_units "$l") r=$(final_stat average_exec_per_sec "$l")
    [[ $e =~ ^[0-9]+$ && $execs != "?" ]] && execs=$((execs + e)) || execs="?"
    [[ $r =~ ^[0-9]+$ && $rate != "?" ]] && rate=$((rate + r)) || rate="?"
  done
  corpus=$(find "$work/corpus/$t" -type f | wc -l)
  if [[ $stopped -eq 1 && -z "$new_artifacts" ]]; then
    summary+=("$(printf '%-10s stopped  %s exec/s  %s execs  %s s  corpus %s' "$t" "${rate:-?}" "${execs:-?}" "$took" "$corpus")")
    echo "fuzz: $t stopped: ${execs:-?} executions, no failure"
    break
  elif [[ $rc -ne 0 || -n "$new_artifacts" ]]; then
    failed+=("$t")
    summary+=("$(printf '%-9s CRASH (exit %s)  %s exec/s' "$t" "$rc" "${rate:-?}")")
    echo "fuzz: $t FAILED (exit $rc); log: $log"
    grep -E "^(==[0-9]+==ERROR|SUMMARY|FUZZ CONTRACT BROKEN)|runtime error" "$log" | head -5 || true
    echo "--- last lines of the log ---"
    tail -n 40 "$log"
    for a in $new_artifacts; do echo "fuzz: reproducer $a ($(wc -c <"$a") bytes)"; done
  else
    summary+=("$(printf '%-10s ok  %8s exec/s  %10s execs  %6s s  corpus %s' "$t" "${rate:-?}" "${execs:-?}" "$took" "$corpus")")
    echo "fuzz: $t ok: ${rate:-?} exec/s, ${execs:-?} executions, corpus $corpus inputs"
  fi
done

if [[ $campaign -eq 1 ]]; then echo "== summary ($runs executions per target) =="; else echo "== summary (${seconds} s per target) =="; fi
printf '%s\n' "${summary[@]}"
if [[ ${#failed[@]} -gt 0 ]]; then
  echo "fuzz: crashes in: ${failed[*]} (reproducers in $work/artifacts)" >&2
  exit 1
fi
[[ $stopped -eq 0 ]] || { echo "fuzz: stopped before the end" >&2; exit 130; }
