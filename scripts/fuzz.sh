#!/usr/bin/env bash
# ./shore fuzz [seconds]: builds the libFuzzer targets (clang, ASan + UBSan, SHORE_FUZZ=ON)
# in build/fuzz and runs each for `seconds` (default 60; SHORE_FUZZ_SECONDS too), all at
# once, from the seeds of fuzz/corpus/<target>. New inputs go to build/fuzz/corpus/<target>
# (not the repository); a crash is written to build/fuzz/crashes/<target>/ and fails the
# run. Executions per target go to build/fuzz/fuzz_stats.json (shore-bench's reliability
# sweep reports them as reliability.fuzz_execs_per_target), marked as a CI run if
# SHORE_FUZZ_RUN=ci (.ci/run sets it), else as a local one. fuzz/README.md says what to do
# with a crash.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-${SHORE_FUZZ_SECONDS:-60}}
[[ $seconds =~ ^[0-9]+$ && $seconds -gt 0 ]] || { echo "fuzz: seconds must be a positive integer, got '$seconds'" >&2; exit 2; }
jobs=$(nproc 2>/dev/null || echo 2)
run_kind=${SHORE_FUZZ_RUN:-local}
[[ $run_kind == ci || $run_kind == local ]] || { echo "fuzz: SHORE_FUZZ_RUN must be 'ci' or 'local', got '$run_kind'" >&2; exit 2; }
targets=(coupled_checkpoint heightmap_png heightmap_raw material_map recording soil_delta terrain_state)

scripts/install-deps.sh build fuzz
cmake -S . -B build/fuzz -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_COMPILER=clang++ \
  -DSHORE_FUZZ=ON -DSHORE_BUILD_TESTS=OFF -DSHORE_BUILD_DEMOS=OFF -DSHORE_BUILD_BENCH=OFF \
  -DSHORE_BUILD_VIEWER=OFF >/dev/null
cmake --build build/fuzz -j "$jobs" --target "${targets[@]/#/fuzz_}"

export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1}
pids=()
for t in "${targets[@]}"; do
  mkdir -p "build/fuzz/corpus/$t" "build/fuzz/crashes/$t"
  # -timeout: an input taking over 10 s is a hang; -rss_limit_mb: more than 2 GB is a leak
  # or an unbounded allocation (both are bugs of the loader).
  "build/fuzz/fuzz/fuzz_$t" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 \
    -artifact_prefix="build/fuzz/crashes/$t/" "build/fuzz/corpus/$t" "fuzz/corpus/$t" \
    >"build/fuzz/$t.log" 2>&1 &
  pids+=($!)
done
failed=0 crashed=()
for k in "${!targets[@]}"; do
  crashed+=(false)
  if ! wait "${pids[$k]}"; then failed=1 crashed[$k]=true; echo "fuzz: fuzz_${targets[$k]} FAILED (build/fuzz/${targets[$k]}.log):" >&2
    # The crash's own report (the exception or sanitizer message and its stack), without
    # libFuzzer's progress lines, so a CI log says what failed.
    grep -v -E "^#[0-9]+|NEW_FUNC|^stat::" "build/fuzz/${targets[$k]}.log" | tail -60 >&2
  fi
done

runs=() rates=()
for t in "${targets[@]}"; do
  r=$(sed -n 's/^stat::number_of_executed_units: *//p' "build/fuzz/$t.log" | tail -1)
  s=$(sed -n 's/^stat::average_exec_per_sec: *//p' "build/fuzz/$t.log" | tail -1)
  runs+=("${r:-0}") rates+=("${s:-0}")
  printf 'fuzz_%-14s %12s executions in %s s (%s per second)\n' "$t" "${r:-0}" "$seconds" "${s:-0}"
done
{
  echo "{"
  echo "  \"seconds_per_target\": $seconds,"
  echo "  \"run\": \"$run_kind\","
  echo "  \"source\": \"./shore fuzz $seconds on $(hostname), $jobs cores, all targets at once, $(date -u +%Y-%m-%dT%H:%MZ)\","
  echo "  \"targets\": {"
  for k in "${!targets[@]}"; do
    sep=$([[ $k -lt $((${#targets[@]} - 1)) ]] && echo "," || true)
    echo "    \"${targets[$k]}\": {\"executions\": ${runs[$k]}, \"executions_per_second\": ${rates[$k]}, \"crashed\": ${crashed[$k]}}$sep"
  done
  echo "  }"
  echo "}"
} >build/fuzz/fuzz_stats.json
if [[ $failed -ne 0 ]]; then
  echo "fuzz: crashes kept in build/fuzz/crashes/; fix them and copy each input to fuzz/regressions/<target>/" >&2
  exit 1
fi
echo "fuzz: no crash; statistics in build/fuzz/fuzz_stats.json"
