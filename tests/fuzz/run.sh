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
for target in graph scene model; do
  scratch="$(mktemp -d)"
  echo "fuzz_$target: ${limits[*]}"
  # Artifacts (a crashing input) land in build/fuzz so that a failure can be reproduced.
  build/fuzz/tests/fuzz/fuzz_$target "$scratch" "tests/fuzz/corpus/$target" "${limits[@]}" -max_len=8192 -timeout=20 \
    -artifact_prefix=build/fuzz/crash-$target- -print_final_stats=1 2>&1 | tail -n 12
  status=${PIPESTATUS[0]}
  rm -rf "$scratch"
  [ "$status" -eq 0 ] || { echo "fuzz_$target failed (status $status); the input is in build/fuzz/crash-$target-*" >&2; exit 1; }
done
