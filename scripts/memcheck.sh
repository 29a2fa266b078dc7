#!/usr/bin/env bash
# ./shore memcheck [scene...]: Valgrind memcheck on the smoke run of every scene (or the
# named ones), one scene at a time: `shore-demo pin --scene <s>` runs the scene's smoke run
# and checks its pinned hash, so the run under Valgrind is also checked for determinism.
# Fails on any memcheck error (invalid read or write, use of uninitialised values, a
# definite leak) or a hash that differs. Logs go to build/memcheck/<scene>.log.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh build memcheck
cmake -S . -B build/release -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
cmake --build build/release -j "$(nproc 2>/dev/null || echo 2)" --target shore-demo
demo=build/release/demos/shore-demo
mkdir -p build/memcheck
if [[ $# -gt 0 ]]; then scenes=("$@"); else mapfile -t scenes < <("$demo" list | sed -n 's/^\([a-z0-9_-]\+\)$/\1/p'); fi
failed=0
for s in "${scenes[@]}"; do
  start=$(date +%s)
  if OMP_NUM_THREADS=1 valgrind --tool=memcheck --error-exitcode=99 --leak-check=full --errors-for-leak-kinds=definite \
      --log-file="build/memcheck/$s.log" "$demo" pin --scene "$s" tests/scenes/pinned_hashes.json >/dev/null; then
    echo "memcheck: $s clean ($(($(date +%s) - start)) s)"
  else
    failed=1
    echo "memcheck: $s FAILED (build/memcheck/$s.log)" >&2
    grep -E "ERROR SUMMARY|definitely lost|Invalid|uninitialised" "build/memcheck/$s.log" | head -10 >&2 || true
  fi
done
exit $failed
