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

build() {  # build DIR [cmake options...]
  local dir="$1"
  shift
  cmake -S . -B "$dir" -G Ninja -DCAUSTICA_WERROR=ON "$@" > /dev/null
  cmake --build "$dir" -j "$jobs"
}

case "$mode" in
  render)
    build build/release -DCMAKE_BUILD_TYPE=Release
    ./build/release/caustica render --out caustica.png
    echo "wrote $(pwd)/caustica.png"
    ;;
  test)
    build build/release -DCMAKE_BUILD_TYPE=Release
    ctest --test-dir build/release --output-on-failure -j "$jobs"
    # The same suite under AddressSanitizer and UndefinedBehaviorSanitizer. Leak checking is off
    # because Mesa's LLVM JIT keeps allocations until exit that LeakSanitizer reports as leaks.
    build build/asan -DCMAKE_BUILD_TYPE=Debug -DCAUSTICA_SANITIZE=ON
    ASAN_OPTIONS=detect_leaks=0:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
      ctest --test-dir build/asan --output-on-failure -j "$jobs"
    # Graph and scene loading under libFuzzer (clang, ASan, UBSan): a fixed seed and input count,
    # so the run is the same every time; tests/fuzz/run.sh SECONDS explores further.
    tests/fuzz/run.sh --ci
    ;;
  *)
    echo "usage: tools/setup.sh [render|test]" >&2
    exit 2
    ;;
esac
