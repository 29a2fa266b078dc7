#!/usr/bin/env bash
# ./shore memcheck [scene...]: Valgrind memcheck on the smoke run of every scene (or the
# named ones), one scene at a time: `shore-demo pin --scene <s>` runs the scene's smoke run
# and checks its pinned hash, so the run under Valgrind is also checked for determinism.
# Then the couplings' misuse and lifetime tests (CouplingMisuse.*: deleted bodies, detached
# couplings, changed shapes) under memcheck too, unless scenes are named. Two runs at a time
# (the machine's cores). Fails on any memcheck error (invalid read or write, use of
# uninitialised values, a definite leak) or a hash that differs. Logs go to
# build/memcheck/<name>.log. CI (.ci/run) runs it whole: 1-2 minutes on 2 cores.
# scripts/memcheck.supp holds the suppressions (each outside Shore, with its reproduction).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh build memcheck
cmake -S . -B build/release -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
jobs=$(nproc 2>/dev/null || echo 2)
cmake --build build/release -j "$jobs" --target shore-demo shore_bullet_tests
demo=build/release/demos/shore-demo
mkdir -p build/memcheck
tests=0
if [[ $# -gt 0 ]]; then scenes=("$@"); else
  mapfile -t scenes < <("$demo" list | sed -n 's/^\([a-z0-9_-]\+\)$/\1/p')
  tests=1
fi

memcheck() {  # <name> <command...>: one run under memcheck, its verdict on stdout
  local name=$1 start; shift
  start=$(date +%s)
  if OMP_NUM_THREADS=1 valgrind --tool=memcheck --error-exitcode=99 --leak-check=full --errors-for-leak-kinds=definite \
      --suppressions=scripts/memcheck.supp \
      --log-file="build/memcheck/$name.log" "$@" >"build/memcheck/$name.out" 2>&1; then
    echo "memcheck: $name clean ($(($(date +%s) - start)) s)"
  else
    echo "memcheck: $name FAILED (build/memcheck/$name.log, build/memcheck/$name.out)"
    grep -E "ERROR SUMMARY|definitely lost|Invalid|uninitialised" "build/memcheck/$name.log" | head -10 || true
    tail -5 "build/memcheck/$name.out"
    return 1
  fi
}

runs=()
for s in "${scenes[@]}"; do runs+=("scene_$s"); done
[[ $tests -eq 1 ]] && runs+=(coupling_misuse)
run_one() {
  case $1 in
    scene_*) memcheck "$1" "$demo" pin tests/scenes/pinned_hashes.json --scene "${1#scene_}" ;;
    coupling_misuse) memcheck "$1" build/release/tests/bullet/shore_bullet_tests --gtest_filter='CouplingMisuse.*' ;;
  esac
}
failed=0 pids=()
for r in "${runs[@]}"; do
  while [[ $(jobs -rp | wc -l) -ge $jobs ]]; do sleep 1; done
  run_one "$r" &
  pids+=($!)
done
for p in "${pids[@]}"; do wait "$p" || failed=1; done
exit $failed
