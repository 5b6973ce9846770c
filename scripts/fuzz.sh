#!/usr/bin/env bash
# Builds the libFuzzer targets of every reader (clang, ASan+UBSan, fuzz/) and runs each one after
# the other for RUNS executions (default 1000000), printing executions and time per target.
#
#   bash scripts/fuzz.sh [RUNS] [TARGET...]
#
# Environment: VOLTS_FUZZ_BUILD_DIR (default build-fuzz), VOLTS_FUZZ_OUT (default
# $VOLTS_FUZZ_BUILD_DIR/fuzz-out: grown corpora, logs, crash artifacts), VOLTS_FUZZ_TIMEOUT
# (seconds per input before it counts as a hang, default 10), VOLTS_FUZZ_MAX_TIME (seconds per target,
# stops a target earlier than RUNS; default 0 = no limit), VOLTS_FUZZ_JOBS (build jobs, default 2).
# Exits non-zero if any target found a crash, leak, uncaught exception or hang; the input is then in
# $VOLTS_FUZZ_OUT/artifacts/TARGET/ (reproduce: build-fuzz/fuzz/TARGET FILE).
set -euo pipefail
cd "$(dirname "$0")/.."
RUNS=${1:-1000000}
shift || true
TARGETS=("$@")
if [ ${#TARGETS[@]} -eq 0 ]; then
  TARGETS=(fuzz_off fuzz_obj fuzz_stl fuzz_ply fuzz_config fuzz_stage_classify fuzz_stage_split
           fuzz_stage_polycube fuzz_stage_tmesh fuzz_vtu)
fi
BUILD=${VOLTS_FUZZ_BUILD_DIR:-build-fuzz}
OUT=${VOLTS_FUZZ_OUT:-$BUILD/fuzz-out}
TIMEOUT=${VOLTS_FUZZ_TIMEOUT:-10}
MAX_TIME=${VOLTS_FUZZ_MAX_TIME:-0}

CC=clang CXX=clang++ cmake -S . -B "$BUILD" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g" \
  -DVOLTS_BUILD_FUZZERS=ON -DVOLTS_BUILD_TESTS=OFF -DVOLTS_BUILD_BENCH=OFF >/dev/null
cmake --build "$BUILD" -j"${VOLTS_FUZZ_JOBS:-2}" --target "${TARGETS[@]}"

# A huge allocation (a size read from garbage by a third-party reader) returns null, i.e. throws
# std::bad_alloc, which volts turns into an invalid-input error, instead of aborting the fuzzer.
export ASAN_OPTIONS=${ASAN_OPTIONS:-allocator_may_return_null=1}
status=0
printf '%-22s %12s %10s %10s  %s\n' target executions seconds exec/s result
for t in "${TARGETS[@]}"; do
  seeds=fuzz/corpus/${t#fuzz_}
  corpus=$OUT/corpus/$t
  artifacts=$OUT/artifacts/$t
  log=$OUT/logs/$t.log
  mkdir -p "$corpus" "$artifacts" "$(dirname "$log")"
  # VTK's own failure-path leaks (see the file) are suppressed for the .vtu reader only.
  supp=""
  [ "$t" = fuzz_vtu ] && supp="suppressions=$PWD/fuzz/lsan-vtk.supp"
  start=$(date +%s.%N)
  # New inputs go to the first directory (the grown corpus), never into the repository's seeds.
  if LSAN_OPTIONS="${LSAN_OPTIONS:-$supp}" "$BUILD/fuzz/$t" -runs="$RUNS" -max_total_time="$MAX_TIME" -timeout="$TIMEOUT" -rss_limit_mb=2048 -print_final_stats=1 \
       -artifact_prefix="$artifacts/" "$corpus" "$seeds" >"$log" 2>&1; then
    result=ok
  else
    result="FAILED (see $log)"
    status=1
  fi
  end=$(date +%s.%N)
  execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -n 1)
  secs=$(echo "$end - $start" | bc)
  rate=$( [ -n "$execs" ] && echo "scale=0; $execs / $secs" | bc || echo "?")
  printf '%-22s %12s %10.1f %10s  %s\n' "$t" "${execs:-?}" "$secs" "$rate" "$result"
done
exit $status
