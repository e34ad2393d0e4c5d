#!/usr/bin/env bash
# Fuzz every parser of outside input with libFuzzer under ASan+UBSan (clang from Debian).
#   bash scripts/fuzz.sh                  # each target for 60 s
#   bash scripts/fuzz.sh --seconds 300    # each target for 300 s
#   bash scripts/fuzz.sh --runs 1000000   # each target for 1e6 executions
#   bash scripts/fuzz.sh --smoke          # the test command's short run (10 s each, fixed seed)
#   bash scripts/fuzz.sh --seed 7         # a fixed libFuzzer seed (default: random, smoke: 1)
#   bash scripts/fuzz.sh fuzz_can_frame   # only the named targets
# Builds into build-fuzz/ (AMB_FUZZ_BUILD_DIR), replays tests/fuzz/regressions/<target>/*
# (every crash ever found), then fuzzes from the seeds (tests/fuzz/corpus/<target>/, seeds made
# by the project's own encoders, boards/ for the board-file target). Prints a table of
# executions and executions/s; exits non-zero on any crash, leak or sanitizer report (the
# reproducer is kept in build-fuzz/findings/).
set -euo pipefail
cd "$(dirname "$0")/.."
ROOT=$PWD
BUILD=${AMB_FUZZ_BUILD_DIR:-$ROOT/build-fuzz}
SECONDS_EACH=60
RUNS=-1
SEED=0
FRESH=0
TARGETS=()
while [ $# -gt 0 ]; do
  case "$1" in
    # The smoke run gates every commit: a fixed seed makes it the same search on every
    # machine (a slower machine runs a prefix of it), so it cannot fail by luck.
    --smoke) SECONDS_EACH=10; SEED=1; FRESH=1 ;;
    --seed) SEED=$2; shift ;;
    --seconds) SECONDS_EACH=$2; shift ;;
    --runs) RUNS=$2; SECONDS_EACH=0; shift ;;
    -h|--help) sed -n 2,14p "$0"; exit 0 ;;
    fuzz_*) TARGETS+=("$1") ;;
    *) echo "fuzz.sh: unknown argument '$1' (see --help)" >&2; exit 2 ;;
  esac
  shift
done
ALL=(fuzz_board_toml fuzz_event_ambe fuzz_wear_ambw fuzz_generation_store fuzz_can_frame
     fuzz_modbus_registers fuzz_measured_event fuzz_mat_file)
[ ${#TARGETS[@]} -eq 0 ] && TARGETS=("${ALL[@]}")

export CCACHE_BASEDIR="$ROOT" CCACHE_NOHASHDIR=1
SAN="-fsanitize=address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer"
echo "== fuzz build ($BUILD)" >&2
CC=clang CXX=clang++ cmake -S . -B "$BUILD" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DAMB_FUZZ=ON -DAMB_BUILD_TESTS=OFF -DAMB_BUILD_BENCH=OFF -DAMB_WERROR=OFF \
  "-DCMAKE_CXX_FLAGS=$SAN -fsanitize=fuzzer-no-link" "-DCMAKE_C_FLAGS=$SAN -fsanitize=fuzzer-no-link" \
  "-DCMAKE_EXE_LINKER_FLAGS=$SAN" "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -g" >/dev/null
cmake --build "$BUILD" -j"${AMB_JOBS:-2}" --target amb_fuzzers >&2

SEEDS=$BUILD/seeds
rm -rf "$SEEDS" && mkdir -p "$SEEDS" "$BUILD/findings"
"$BUILD/tests/fuzz/fuzz_make_seeds" "$SEEDS"
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1:symbolize=1
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1

status=0
printf "%-24s %12s %8s %10s  %s\n" target executions seconds execs/s result
for t in "${TARGETS[@]}"; do
  bin=$BUILD/tests/fuzz/$t
  [ -x "$bin" ] || { echo "fuzz.sh: no target $t" >&2; status=1; continue; }
  # 1. Regressions: every input that once crashed a target must now pass.
  if compgen -G "tests/fuzz/regressions/$t/*" >/dev/null; then
    if ! "$bin" tests/fuzz/regressions/"$t"/* > "$BUILD/findings/$t.regressions.log" 2>&1; then
      printf "%-24s %12s %8s %10s  %s\n" "$t" - - - "REGRESSION (see $BUILD/findings/$t.regressions.log)"
      status=1; continue
    fi
  fi
  # 2. Fuzz from the seeds into a scratch corpus (the repo's corpus is never modified).
  work=$BUILD/corpus/$t
  [ "$FRESH" = 1 ] && rm -rf "$work"   # smoke: the same start on every machine
  mkdir -p "$work"
  seeds=()
  for d in "tests/fuzz/corpus/$t" "$SEEDS/$t"; do [ -d "$d" ] && seeds+=("$d"); done
  [ "$t" = fuzz_board_toml ] && seeds+=(boards)
  extra=()
  [ "$SEED" != 0 ] && extra+=(-seed="$SEED")
  log=$BUILD/findings/$t.log
  start=$(date +%s.%N)
  set +e
  "$bin" -max_total_time="$SECONDS_EACH" -runs="$RUNS" -print_final_stats=1 -rss_limit_mb=2048 -timeout=10 \
    -artifact_prefix="$BUILD/findings/$t-" "${extra[@]}" "$work" "${seeds[@]}" > "$log" 2>&1
  rc=$?
  set -e
  end=$(date +%s.%N)
  execs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$' | tail -1)
  execs=${execs:-0}
  secs=$(awk -v a="$start" -v b="$end" 'BEGIN{printf "%.1f", b-a}')
  rate=$(awk -v n="$execs" -v s="$secs" 'BEGIN{printf "%.0f", (s>0)?n/s:0}')
  if [ $rc -eq 0 ]; then result=clean; else result="FAIL rc=$rc (see $log)"; status=1; fi
  printf "%-24s %12s %8s %10s  %s\n" "$t" "$execs" "$secs" "$rate" "$result"
done
exit $status
