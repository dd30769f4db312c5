#!/usr/bin/env bash
# Builds the libFuzzer targets with clang (build/fuzz) and runs them on the corpora in
# tests/fuzz/corpus. New inputs go to a scratch folder, so the checked-in corpus changes only when
# someone copies an input there on purpose (crashes found: add them as regression inputs).
#   tests/fuzz/run.sh --ci        deterministic: 32768 inputs per target from fixed seeds (what CI runs)
#   tests/fuzz/run.sh [SECONDS]   exploratory: SECONDS per target (default 300)
#   --build-dir DIR               with either: the targets of a build configured with -DCAUSTICA_FUZZ=ON
#                                 and clang instead (tools/setup.sh test: its sanitizer build)
set -euo pipefail
cd "$(dirname "$0")/../.."
jobs="${CAUSTICA_JOBS:-2}"
dir=""
args=()
while [ $# -gt 0 ]; do
  if [ "$1" = "--build-dir" ]; then
    dir="${2:?--build-dir needs a folder}"
    shift 2
  else
    args+=("$1")
    shift
  fi
done
set -- "${args[@]+"${args[@]}"}"
if [ -z "$dir" ]; then
  dir=build/fuzz
  CXX=clang++ cmake -S . -B "$dir" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCAUSTICA_FUZZ=ON \
    -DCAUSTICA_BUILD_TESTS=OFF -DCAUSTICA_WERROR=ON -DCMAKE_UNITY_BUILD=ON > /dev/null
fi
cmake --build "$dir" -j "$jobs" --target fuzz_graph fuzz_scene fuzz_model
# Each run takes one core: up to CAUSTICA_JOBS at once, the longest first. In --ci mode the model
# target (in the sanitizer build, whose libraries are at -O1 with assertions, 66 s for 50,000
# inputs against 35 and 17 s for the others) runs as two halves with seeds 1 and 2, so that neither
# core waits on it alone at the end. (Halving the others too took 66 s against 69: each run first
# replays the whole corpus.) The input counts were halved twice for a test command at its budget:
# 50,000 inputs reached all but about 1% of the edges that 100,000 did (graph 1990 of 2007, scene
# 1665 of 1683, model about 3000 of 3048), and 32,768 all but 1 to 2% of what 50,000 did (2026-11-29,
# two runs' DONE lines: graph 3398 of 3444, scene 2450 of 2469, the model's halves 3689 and 3669 of
# 3710 and 3735 at 16,384 of 25,000), the run 55 s -> 37 s; tests/fuzz/run.sh SECONDS explores further.
if [ "${1:-}" = "--ci" ]; then
  runs=("model 1 16384" "model 2 16384" "graph 1 32768" "scene 1 32768")
else
  runs=("model" "graph" "scene")
  seconds="${1:-300}"
fi
fuzz_one() {  # fuzz_one TARGET [SEED RUNS]: runs it, prints its last lines, exits with its status
  local target="$1" scratch status=0 limits
  if [ $# -eq 3 ]; then limits=(-seed="$2" -runs="$3"); else limits=(-max_total_time="$seconds"); fi
  scratch="$(mktemp -d)"
  # Artifacts (a crashing input) land in the build folder so that a failure can be reproduced.
  "$dir/tests/fuzz/fuzz_$target" "$scratch" "tests/fuzz/corpus/$target" "${limits[@]}" -max_len=8192 -timeout=20 \
    -artifact_prefix="$dir/crash-$target-" -print_final_stats=1 > "$dir/$target-${2:-run}.log" 2>&1 || status=$?
  rm -rf "$scratch"
  echo "fuzz_$target: ${limits[*]}"
  tail -n 12 "$dir/$target-${2:-run}.log"
  [ "$status" -eq 0 ] || echo "fuzz_$target failed (status $status); the input is in $dir/crash-$target-*" >&2
  return "$status"
}
pids=()
for run in "${runs[@]}"; do
  while [ "$(jobs -rp | wc -l)" -ge "$jobs" ]; do wait -n || true; done
  # shellcheck disable=SC2086 # a run is its target and, in --ci mode, its seed and input count
  fuzz_one $run &
  pids+=($!)
done
failed=0
for pid in "${pids[@]}"; do wait "$pid" || failed=1; done
[ "$failed" -eq 0 ] || exit 1
