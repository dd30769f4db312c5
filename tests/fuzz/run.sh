#!/usr/bin/env bash
# Builds the libFuzzer targets with clang (build/fuzz) and runs them on the corpora in
# tests/fuzz/corpus. New inputs go to a scratch folder, so the checked-in corpus changes only when
# someone copies an input there on purpose (crashes found: add them as regression inputs).
#   tests/fuzz/run.sh --ci        deterministic: seed 1, 100000 inputs per target (what CI runs)
#   tests/fuzz/run.sh [SECONDS]   exploratory: SECONDS per target (default 300)
set -euo pipefail
cd "$(dirname "$0")/../.."
jobs="${CAUSTICA_JOBS:-2}"
CXX=clang++ cmake -S . -B build/fuzz -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCAUSTICA_FUZZ=ON -DCAUSTICA_BUILD_TESTS=OFF \
  -DCAUSTICA_WERROR=ON -DCMAKE_UNITY_BUILD=ON > /dev/null
cmake --build build/fuzz -j "$jobs" --target fuzz_graph fuzz_scene fuzz_model
if [ "${1:-}" = "--ci" ]; then
  limits=(-seed=1 -runs=100000)
else
  limits=(-max_total_time="${1:-300}")
fi
# Each target runs on one core: up to CAUSTICA_JOBS of them at once, the longest (model) first,
# so that the other two share the second core while it runs. Each one's output is shown when it ends.
fuzz_one() {  # fuzz_one TARGET: runs it, prints its last lines, exits with its status
  local target="$1" scratch status=0
  scratch="$(mktemp -d)"
  # Artifacts (a crashing input) land in build/fuzz so that a failure can be reproduced.
  build/fuzz/tests/fuzz/fuzz_$target "$scratch" "tests/fuzz/corpus/$target" "${limits[@]}" -max_len=8192 -timeout=20 \
    -artifact_prefix=build/fuzz/crash-$target- -print_final_stats=1 > "build/fuzz/$target.log" 2>&1 || status=$?
  rm -rf "$scratch"
  echo "fuzz_$target: ${limits[*]}"
  tail -n 12 "build/fuzz/$target.log"
  [ "$status" -eq 0 ] || echo "fuzz_$target failed (status $status); the input is in build/fuzz/crash-$target-*" >&2
  return "$status"
}
pids=()
for target in model graph scene; do
  while [ "$(jobs -rp | wc -l)" -ge "$jobs" ]; do wait -n || true; done
  fuzz_one "$target" &
  pids+=($!)
done
failed=0
for pid in "${pids[@]}"; do wait "$pid" || failed=1; done
[ "$failed" -eq 0 ] || exit 1
