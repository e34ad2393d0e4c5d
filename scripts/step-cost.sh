#!/usr/bin/env bash
# Instructions per control step, counted by callgrind: deterministic where amb-bench's medians
# move with the machine's load (docs/sweep.md "Cost in the loop").
#   bash scripts/step-cost.sh                         # the three cases, 20000 steps each
#   bash scripts/step-cost.sh --steps 50000 levitated # one case, more steps
#   bash scripts/step-cost.sh --build build-old       # another build tree (its amb-step-cost)
# Cases (tests/bench/step_cost_main.cpp): start (levitate posted, from lift-off on, as amb-bench
# BM_ControlStep), levitated (generator idle, BM_ControlStepLevitated), sweep (generator
# recording axis 0, BM_ControlStepSweep). Runs build/tests/bench/amb-step-cost under
# valgrind --tool=callgrind, counting only measured_steps() (the set-up is not counted), and
# prints per case: instructions per step of Supervisor::step (inclusive) and of the whole
# measured loop (the step plus the benchmark's moving input, one sin()). Needs valgrind and a
# build with -DAMB_BUILD_BENCH=ON. Exit 0 ok, 1 bad arguments, 2 a run failed.
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD=build
STEPS=20000
CASES=()
while [ $# -gt 0 ]; do
  case "$1" in
    --build) [ $# -ge 2 ] || { echo "step-cost.sh: --build needs a directory" >&2; exit 1; }; BUILD=$2; shift ;;
    --steps) [ $# -ge 2 ] || { echo "step-cost.sh: --steps needs a count" >&2; exit 1; }; STEPS=$2; shift ;;
    -h|--help) sed -n 2,14p "$0"; exit 0 ;;
    start|levitated|sweep) CASES+=("$1") ;;
    *) echo "step-cost.sh: unknown argument '$1' (see --help)" >&2; exit 1 ;;
  esac
  shift
done
[[ "$STEPS" =~ ^[1-9][0-9]*$ ]] || { echo "step-cost.sh: --steps '$STEPS' is not a positive integer" >&2; exit 1; }
[ ${#CASES[@]} -eq 0 ] && CASES=(start levitated sweep)
EXE=$BUILD/tests/bench/amb-step-cost
[ -x "$EXE" ] || { echo "step-cost.sh: $EXE not found (configure with -DAMB_BUILD_BENCH=ON, build target amb-step-cost)" >&2; exit 1; }
command -v valgrind >/dev/null || { echo "step-cost.sh: valgrind not found (apt-get install valgrind)" >&2; exit 1; }

TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
printf '%-10s %8s %14s %14s\n' case steps step_instr loop_instr
for c in "${CASES[@]}"; do
  out=$TMP/$c.callgrind
  if ! valgrind --tool=callgrind --callgrind-out-file="$out" --toggle-collect='*measured_steps*' \
      "$EXE" "$c" "$STEPS" >"$TMP/$c.json" 2>"$TMP/$c.log"; then
    echo "step-cost.sh: case $c failed:" >&2
    cat "$TMP/$c.log" >&2
    exit 2
  fi
  ann=$(callgrind_annotate --inclusive=yes --threshold=100 "$out")
  total=$(awk '/PROGRAM TOTALS/ {gsub(",", "", $1); print $1; exit}' <<<"$ann")
  step=$(awk '/amb::fw::Supervisor::step\(/ {gsub(",", "", $1); print $1; exit}' <<<"$ann")
  if [ -z "$total" ] || [ -z "$step" ]; then
    echo "step-cost.sh: case $c: no counts in callgrind's output" >&2
    exit 2
  fi
  awk -v c="$c" -v n="$STEPS" -v s="$step" -v t="$total" 'BEGIN { printf "%-10s %8d %14.1f %14.1f\n", c, n, s / n, t / n }'
done
