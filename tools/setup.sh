#!/usr/bin/env bash
# One-command set-up on Debian 12: installs the packages, builds, then
#   tools/setup.sh render   renders the default graph to caustica.png (the default)
#   tools/setup.sh test     runs every test: the Release build, then the ASan/UBSan build, then
#                           a deterministic run of the fuzz targets
set -euo pipefail
cd "$(dirname "$0")/.."
mode="${1:-render}"
jobs="${CAUSTICA_JOBS:-2}"

bash tools/install-deps.sh

# Mesa compiles every pipeline's shaders with LLVM on first use, most of a cold suite's time (a
# test that took 10 s with its pipelines cached took 199 s without), and keeps them in its disk
# cache. The suite keeps its own under build/, so that every run from a clean clone starts alike
# and the sanitizer run reuses what the Release run compiled.
export MESA_SHADER_CACHE_DIR="$PWD/build/mesa-shader-cache"
# caustica's own cache of compiled SPIR-V (engine/shader/shader_disk_cache.h), likewise: every
# `caustica` process and test would otherwise run glslang over the same library again.
export CAUSTICA_SHADER_CACHE_DIR="$PWD/build/shader-cache"

phases=()
started=$SECONDS
phase_done() {  # phase_done NAME: records how long the phase since the previous one took
  phases+=("$(printf '%5d s  %s' $((SECONDS - started)) "$1")")
  started=$SECONDS
}
run_tests() {  # run_tests BUILD_DIR [CTEST OPTIONS]: the tests, then the ten slowest (ctest's own timings)
  local dir="$1" status=0
  shift
  ctest --test-dir "$dir" --output-on-failure -j "$jobs" "$@" || status=$?
  echo "slowest tests in $dir:"
  # awk, not head, takes the first ten: head leaves before sort has written everything once the
  # list passes sort's 4 KB buffer, and sort's SIGPIPE then fails the pipeline (pipefail) and the run.
  awk '/^---/ {exit} NF == 3 {printf "%8.1f s  %s\n", $3, $1}' "$dir/Testing/Temporary/CTestCostData.txt" | sort -rn | awk 'NR <= 10'
  return "$status"
}

# A unity build (CMake joins each target's sources into a few files) compiles the headers that every
# file includes, nlohmann's JSON and the Vulkan headers among them, once per batch instead of once
# per file: the Release build took 313 s one by one and 212 s joined, the sanitizer build 537 s and
# 294 s (docs/testing.md).
# Linked by LLVM's lld: a sanitizer build's `caustica` links in 0.8 s instead of 2.9 s with the
# default linker, and each build links about twenty programs.
build() {  # build DIR [cmake options...]
  local dir="$1"
  shift
  cmake -S . -B "$dir" -G Ninja -DCAUSTICA_WERROR=ON -DCMAKE_UNITY_BUILD=ON -DCMAKE_EXE_LINKER_FLAGS=-fuse-ld=lld "$@" > /dev/null
  cmake --build "$dir" -j "$jobs"
}

case "$mode" in
  render)
    build build/release -DCMAKE_BUILD_TYPE=Release
    ./build/release/caustica render --out caustica.png
    echo "wrote $(pwd)/caustica.png"
    ;;
  test)
    # The tiers and their times: docs/testing.md.
    phase_done "install"
    build build/release -DCMAKE_BUILD_TYPE=Release
    phase_done "Release build"
    # Each test runs once where it checks most (tests/CMakeLists.txt, docs/testing.md): here the
    # accuracy tests, the stability suite and the matrix at full size, the CPU tests, packaging and
    # Slurm; the sanitizer run below takes the rest. `ctest` alone in either build runs everything.
    run_tests build/release -L 'accuracy|release'
    phase_done "Release tests (accuracy, full size, CPU)"
    # The suite under AddressSanitizer and UndefinedBehaviorSanitizer: every test but the accuracy
    # tests, the render loops small (tests/CMakeLists.txt). Leak checking is off because Mesa's
    # LLVM JIT keeps allocations until exit that LeakSanitizer reports as leaks. An 8 MB quarantine
    # (freed memory held back from reuse, for use-after-free reports) instead of 256: lavapipe's
    # shader code allocates and frees per dispatch, and with 256 MB each such block came from fresh
    # pages: a sanitized 20-frame render took 12.1 s with the default and 6.4 s with 32 MB; from 32
    # to 8 MB the command-line tests went from 136 to 114 s and the viewer's and editor's from 75
    # to 65 s (docs/testing.md). A use after free within the last 8 MB of frees is still reported.
    # Built with clang, with the libFuzzer targets in the same build (CAUSTICA_FUZZ: the libraries
    # carry the fuzzer's coverage instrumentation), so that the sanitized libraries are compiled
    # once for both: this build and a separate fuzz build took 536 + 141 s of CPU with GCC, this one
    # 479 s. One unity file per target (batch size 0): the sanitizer build took 266 s so against
    # 304 s in batches of eight, measured one after the other. (The Release build gains nothing from
    # it: 172 s against 177 s at -O2.)
    # A build/asan made by GCC before: CMake cannot switch a build tree's compiler in place (its first
    # configure after the switch fails to generate), so it starts afresh.
    if [ -f build/asan/CMakeCache.txt ] && ! grep -q '^CMAKE_CXX_COMPILER:.*clang' build/asan/CMakeCache.txt; then rm -rf build/asan; fi
    build build/asan -DCMAKE_CXX_COMPILER="$(command -v clang++)" -DCMAKE_BUILD_TYPE=Debug -DCAUSTICA_SANITIZE=ON -DCAUSTICA_FUZZ=ON \
      -DCMAKE_UNITY_BUILD_BATCH_SIZE=0
    phase_done "ASan/UBSan build (clang, with the fuzz targets)"
    ASAN_OPTIONS=detect_leaks=0:abort_on_error=1:quarantine_size_mb=8 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 run_tests build/asan -LE accuracy
    phase_done "ASan/UBSan tests"
    # Graph and scene loading under libFuzzer (clang, ASan, UBSan): a fixed seed and input count,
    # so the run is the same every time; tests/fuzz/run.sh SECONDS explores further.
    tests/fuzz/run.sh --ci --build-dir build/asan
    phase_done "fuzz run"
    echo "tools/setup.sh test: every phase passed"
    printf '%s\n' "${phases[@]}"
    ;;
  *)
    echo "usage: tools/setup.sh [render|test]" >&2
    exit 2
    ;;
esac
