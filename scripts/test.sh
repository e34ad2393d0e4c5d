#!/usr/bin/env bash
# The README's test command: install dependencies, build for the host and run every test,
# cross-build for the aarch64 board and run the unit tests under qemu-user, then run the
# target test on an emulated ARM board; in between, a short fuzz run of every outside-input parser
# and the sanitizer smoke runs (ASan+UBSan, TSan).
set -euo pipefail
cd "$(dirname "$0")/.."
ROOT=$PWD
JOBS=${AMB_JOBS:-2}
BUILD=${AMB_BUILD_DIR:-$ROOT/build}
BUILD_ARM=${AMB_BUILD_ARM_DIR:-$ROOT/build-aarch64}

# Each stage's wall time is printed as it ends and summed up at the end (also on failure), so a
# slow CI run says where its time went.
T_START=$(date +%s); T_STAGE=$T_START; STAGE="setup"; TIMES=""
stage() {
  local now; now=$(date +%s)
  TIMES+="$(printf '  %-28s %5d s' "$STAGE" $((now - T_STAGE)))"$'\n'
  echo "== [$STAGE took $((now - T_STAGE)) s; $((now - T_START)) s so far]"
  STAGE=$1; T_STAGE=$now
}
summary() {
  local rc=$? now; now=$(date +%s)
  TIMES+="$(printf '  %-28s %5d s%s' "$STAGE" $((now - T_STAGE)) "$([ $rc = 0 ] || echo ' (failed here)')")"
  printf '== test.sh stage times (total %d s, exit %d):\n%s\n' $((now - T_START)) $rc "$TIMES"
}
trap summary EXIT

bash scripts/setup-debian.sh
# ccache keys on paths relative to the checkout, so any clone of the repo hits the cache.
export CCACHE_BASEDIR="$ROOT"
export CCACHE_NOHASHDIR=1

stage "host build"; echo "== host build ($BUILD)"
cmake -S . -B "$BUILD" -G Ninja -DCMAKE_BUILD_TYPE=Release -DAMB_BUILD_BENCH=OFF
cmake --build "$BUILD" -j"$JOBS"
stage "host tests"; echo "== host tests"
# Tests labelled `long` (validation sweeps, documented in docs/) run with: ctest --test-dir build -L long
ctest --test-dir "$BUILD" -j"$JOBS" --output-on-failure --timeout 900 -LE long

if [ "${AMB_SKIP_FUZZ:-0}" != 1 ]; then
  stage "fuzz smoke"; echo "== fuzz smoke: every outside-input parser, 10 s each under ASan+UBSan (scripts/fuzz.sh)"
  AMB_FUZZ_BUILD_DIR="$ROOT/build-fuzz" bash scripts/fuzz.sh --smoke
fi

if [ "${AMB_SKIP_SANITIZERS:-0}" != 1 ]; then
  # Full runs (every host test folder): bash scripts/sanitizers.sh asan|tsan (docs/hardening.md)
  echo "== sanitizer smoke: ASan+UBSan on the firmware and linux tests, TSan on the threaded parts"
  stage "ASan smoke"; AMB_SAN_BUILD_DIR="$ROOT/build-asan" bash scripts/sanitizers.sh asan --smoke
  stage "TSan smoke"; AMB_SAN_BUILD_DIR="$ROOT/build-tsan" bash scripts/sanitizers.sh tsan --smoke
fi

if [ "${AMB_SKIP_ARM:-0}" != 1 ]; then
  stage "aarch64 build"; echo "== aarch64 cross build ($BUILD_ARM)"
  cmake -S . -B "$BUILD_ARM" -G Ninja -DCMAKE_BUILD_TYPE=Release \
    -DCMAKE_TOOLCHAIN_FILE="$ROOT/cmake/aarch64-linux-gnu.cmake" \
    -DAMB_BUILD_HOST_TOOLS=OFF -DAMB_BUILD_BENCH=OFF \
    "-DAMB_TEST_DIRS=firmware;linux;rt;plant" -DAMB_BUILD_PLANT=ON
  cmake --build "$BUILD_ARM" -j"$JOBS"
  stage "aarch64 tests (qemu)"; echo "== aarch64 unit tests under qemu-user"
  ctest --test-dir "$BUILD_ARM" -j"$JOBS" --output-on-failure --timeout 1800 -LE host_only
fi

[ "${AMB_SKIP_ARM:-0}" = 1 ] || { stage "packages"; echo "== Debian packages: build, Depends and lintian check (scripts/package.sh)"; bash scripts/package.sh "$BUILD" "$BUILD_ARM"; }

if [ -x tests/target/run-target-test.sh ] && [ "${AMB_SKIP_TARGET:-0}" != 1 ]; then
  stage "target test"; echo "== target test: emulated ARM board"
  bash tests/target/run-target-test.sh "$BUILD" "$BUILD_ARM"
fi
