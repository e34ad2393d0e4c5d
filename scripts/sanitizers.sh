#!/usr/bin/env bash
# Sanitizer builds of the tests (issue 19), each in its own build directory:
#   bash scripts/sanitizers.sh asan [--smoke|--resume] [DIRS]  # ASan+UBSan (gcc), host tests of DIRS (default: all)
#   bash scripts/sanitizers.sh tsan [--smoke|--resume] [DIRS]  # TSan, the threaded parts (default: capture firmware linux rt sil)
# DIRS is a ;-separated list of tests/ folders (AMB_TEST_DIRS). Any sanitizer report fails
# the test that produced it (halt_on_error / abort_on_error), so a green ctest means a clean run.
# --smoke: a subset that runs in about 3 minutes on 2 cores once the build directory is warm
#   asan: the firmware and linux tests (board file, wear record, register map and write access,
#         field-bus codec, storage faults, persistence; not the 110 s torn-write sweep);
#   tsan: the SeqLock and SPSC ring under contention, the Modbus server with the register map
#         and the event writer, and three fault-rig scenarios (flood, storage EIO, silent node)
#         with every thread of the board running (loop, Modbus server, event writer, analysis).
# --resume: the full run takes longer than a working session on a shared 2-core machine (the
#   residual loop's record generation and fits run 10-20x slower under ASan+UBSan); every test
#   that passed is noted in $BUILD/sanitizer-passed-<commit>.txt, and --resume runs only the
#   tests not yet passed on the same commit and the same uncommitted changes, so the full set
#   is reached over several runs. Without --resume the list starts afresh.
# ASan keeps 10 frames of each allocation's stack (malloc_context_size; default 30): reports
#   name the same errors with shorter allocation stacks; an allocation-bound loop 40 calls deep
#   runs 1.5x faster (docs/hardening.md).
# AMB_SAN_TIMEOUT_SCALE: every test's own TIMEOUT is multiplied by it (default 8: the
#   sanitizers' slowdown; the 2026-11-28 run timed out a 120 s CLI test and two 600 s fits).
# AMB_SAN_TIMEOUT_S: the limit of a test without its own (default 1800 s).
# Run times on this project's 2-core machine: docs/hardening.md.
set -euo pipefail
cd "$(dirname "$0")/.."
ROOT=$PWD
KIND=${1:-}
shift || true
SMOKE=0
RESUME=0
if [ "${1:-}" = --smoke ]; then SMOKE=1; shift; fi
if [ "${1:-}" = --resume ]; then RESUME=1; shift; fi
FILTER=()
case "$KIND" in
  asan) FLAGS="-fsanitize=address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer"
        if [ $SMOKE = 1 ]; then
          DIRS=${1:-"firmware;linux"}
          # The torn-write sweep (every byte of a record, ~110 s under ASan) runs in the full run only.
          FILTER=(-E '^Persistence\.WriterInterruptedAtEveryByte')
        else DIRS=${1:-}; fi
        export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1:strict_string_checks=1:malloc_context_size=10 \
               UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 ;;
  tsan) FLAGS="-fsanitize=thread -fno-omit-frame-pointer"
        if [ $SMOKE = 1 ]; then
          DIRS=${1:-"firmware;linux;sil"}
          FILTER=(-R '^(Concurrency\.|RegisterMap\.|Link\.WriteBack|Faults\.(ModbusFlood|StorageEio|SilentSensor))')
        else DIRS=${1:-"capture;firmware;linux;rt;sil"}; fi
        # second_deadlock_stack: both stacks of a lock-order report. The loop thread asks for
        # SCHED_FIFO; under TSan it simply runs slower.
        export TSAN_OPTIONS=halt_on_error=1:second_deadlock_stack=1 ;;
  *) sed -n 2,13p "$0"; exit 2 ;;
esac
BUILD=${AMB_SAN_BUILD_DIR:-$ROOT/build-$KIND}
export CCACHE_BASEDIR="$ROOT" CCACHE_NOHASHDIR=1
T0=$(date +%s)
# The smoke runs need no host tool (amb-host, amb-plant, their core): not built, much shorter.
HOST_TOOLS=ON; [ $SMOKE = 1 ] && HOST_TOOLS=OFF
cmake -S . -B "$BUILD" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DAMB_BUILD_BENCH=OFF -DAMB_WERROR=OFF \
  -DAMB_BUILD_HOST_TOOLS=$HOST_TOOLS \
  "-DCMAKE_CXX_FLAGS=$FLAGS" "-DCMAKE_C_FLAGS=$FLAGS" "-DCMAKE_EXE_LINKER_FLAGS=$FLAGS" \
  "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -g" "-DAMB_TEST_DIRS=$DIRS" "-DAMB_TEST_TIMEOUT_SCALE=${AMB_SAN_TIMEOUT_SCALE:-8}" >/dev/null
cmake --build "$BUILD" -j"${AMB_JOBS:-2}"
T1=$(date +%s)
# Sanitized code runs several times slower: long validation sweeps stay out (-LE long).
# The tests that passed on this source state (commit + uncommitted changes), for --resume.
STATE=$(git rev-parse --short HEAD 2>/dev/null || echo nogit)-$( (git diff HEAD 2>/dev/null || true) | sha256sum | cut -c1-12)
PASSED="$BUILD/sanitizer-passed-$STATE.txt"
[ $RESUME = 1 ] || rm -f "$BUILD"/sanitizer-passed-*.txt "$BUILD"/sanitizer-ctest-*.log
touch "$PASSED"
# A run stopped part-way (the session's end, a kill) still counts what passed: every run's
# log is kept per source state and its "Passed" lines are read before the list is made.
passed_from_logs() {
  for log in "$BUILD"/sanitizer-ctest-"$STATE"-*.log; do
    [ -e "$log" ] || continue
    # ctest's result lines: " 12/80 Test #34: Suite.Case ......   Passed    1.23 sec".
    sed -n 's/^ *[0-9]*\/[0-9]* Test *#[0-9]*: \([^ ]*\) .*  Passed .*/\1/p' "$log"
  done
}
passed_from_logs >> "$PASSED"
# "number name", the name up to its first blank: a value-parameterised case is listed as
# "Suite.Case/param  # GetParam() = <bytes>" (the bytes differ from build to build), while
# ctest's result line, which the passes are read from, starts with the same first word.
LISTED=$(ctest --test-dir "$BUILD" -N -LE long "${FILTER[@]}" | sed -n 's/^ *Test *#\([0-9]*\): \([^ ]*\).*$/\1 \2/p')
ALL=$(echo "$LISTED" | cut -d' ' -f2 | sort -u)
TODO=$(comm -23 <(echo "$ALL") <(sort -u "$PASSED") | sed '/^$/d')
echo "sanitizers $KIND: $(echo "$ALL" | sed '/^$/d' | wc -l) tests, $(sort -u "$PASSED" | sed '/^$/d' | wc -l) passed before on this source state, $(echo "$TODO" | sed '/^$/d' | wc -l) to run"
STATUS=0
if [ -n "$TODO" ]; then
  # The tests to run by number (ctest -I 0,0,0,N,N,...), not as a regex of a few hundred names.
  NUMBERS=$(awk 'NR == FNR { todo[$0] = 1; next } ($2 in todo) { print $1 }' \
              <(echo "$TODO") <(echo "$LISTED") | paste -sd,)
  LOG="$BUILD/sanitizer-ctest-$STATE-$(date +%Y%m%dT%H%M%S).log"
  # Longest first: without a cost record of its own, ctest is given the plain build's (same test
  # names, each roughly 5-15x faster there), so the slow fits start first and -j2 stays full.
  COSTS="$BUILD/Testing/Temporary/CTestCostData.txt"
  if [ ! -s "$COSTS" ] && [ -s "$ROOT/build/Testing/Temporary/CTestCostData.txt" ]; then
    mkdir -p "$(dirname "$COSTS")" && cp "$ROOT/build/Testing/Temporary/CTestCostData.txt" "$COSTS"
  fi
  set +e
  ctest --test-dir "$BUILD" -j"${AMB_JOBS:-2}" --output-on-failure --timeout "${AMB_SAN_TIMEOUT_S:-1800}" \
    -I "0,0,0,$NUMBERS" 2>&1 | tee "$LOG"
  STATUS=${PIPESTATUS[0]}
  set -e
  passed_from_logs >> "$PASSED"
fi
T2=$(date +%s)
echo "sanitizers $KIND$([ $SMOKE = 1 ] && echo ' --smoke')$([ $RESUME = 1 ] && echo ' --resume'): build $((T1 - T0)) s, tests $((T2 - T1)) s (DIRS: ${DIRS:-all}); passed so far on this source state: $(sort -u "$PASSED" | sed '/^$/d' | wc -l) of $(echo "$ALL" | sed '/^$/d' | wc -l)$([ $STATUS = 0 ] || echo ': FAILED')"
exit $STATUS
