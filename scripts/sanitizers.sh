#!/usr/bin/env bash
# Sanitizer builds of the tests (issue 19), each in its own build directory:
#   bash scripts/sanitizers.sh asan [DIRS]   # ASan+UBSan (gcc), host tests of DIRS (default: all)
#   bash scripts/sanitizers.sh tsan [DIRS]   # TSan, the threaded parts (default: capture firmware linux rt)
# DIRS is a ;-separated list of tests/ folders (AMB_TEST_DIRS). Any sanitizer report fails
# the test that produced it (halt_on_error), so a green ctest means a clean run.
set -euo pipefail
cd "$(dirname "$0")/.."
ROOT=$PWD
KIND=${1:-}
case "$KIND" in
  asan) FLAGS="-fsanitize=address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer"
        DIRS=${2:-}
        export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 ;;
  tsan) FLAGS="-fsanitize=thread -fno-omit-frame-pointer"
        DIRS=${2:-"capture;firmware;linux;rt"}
        export TSAN_OPTIONS=halt_on_error=1:second_deadlock_stack=1 ;;
  *) sed -n 2,6p "$0"; exit 2 ;;
esac
BUILD=${AMB_SAN_BUILD_DIR:-$ROOT/build-$KIND}
export CCACHE_BASEDIR="$ROOT" CCACHE_NOHASHDIR=1
cmake -S . -B "$BUILD" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DAMB_BUILD_BENCH=OFF -DAMB_WERROR=OFF \
  "-DCMAKE_CXX_FLAGS=$FLAGS" "-DCMAKE_C_FLAGS=$FLAGS" "-DCMAKE_EXE_LINKER_FLAGS=$FLAGS" \
  "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -g" "-DAMB_TEST_DIRS=$DIRS" >/dev/null
cmake --build "$BUILD" -j"${AMB_JOBS:-2}"
# Sanitized code runs several times slower: long validation sweeps stay out (-LE long).
ctest --test-dir "$BUILD" -j"${AMB_JOBS:-2}" --output-on-failure --timeout 1800 -LE long
