#!/bin/bash
# Two commands run at the same time, each pinned to a core of its own, then again with the cores swapped: their CPU
# times and the ratio A/B a round. Both runs meet the same load from the machine's other tenants at once, so the ratio
# holds still where whole-process times taken in turn move by 10% (docs/performance.md, "Running the benchmarks").
# Each command runs on one thread (its core); give each its own --out.
#
#   bench/paired_runs.sh [-n PAIRS] 'COMMAND A' 'COMMAND B'
#
# PAIRS (default 2) rounds of two runs each (A on core 0 and B on core 1, then swapped); prints each run's CPU seconds
# and ratio, each pair's geometric mean of its two ratios (which cancels a core that is faster than the other) and the
# median of those. Exit 1 if a command fails.
set -euo pipefail

pairs=2
if [[ ${1:-} == -n ]]; then
  pairs=$2
  shift 2
fi
if [[ $# -ne 2 ]]; then
  sed -n '2,11p' "$0" | sed 's/^# \{0,1\}//' >&2
  exit 2
fi
if (($(nproc) < 2)); then
  echo "paired_runs.sh: needs 2 cores, this machine has $(nproc)" >&2
  exit 2
fi

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# CPU seconds (user + system) of COMMAND on CORE, into FILE (bash's own `time`: no other program needed).
timed() {
  local core=$1 file=$2 command=$3 TIMEFORMAT='%U %S'
  { time taskset -c "$core" bash -c "$command" >"$file.log" 2>&1; } 2>"$file.time" ||
    { echo "paired_runs.sh: failed on core $core: $command; its output:" >&2; cat "$file.log" >&2; return 1; }
  awk '{ print $1 + $2 }' "$file.time" >"$file"
}

set -m  # each run a process group of its own, so that a failure can stop the other run whole
stop_runs() {  # and an interrupt stops both
  local job
  for job in $(jobs -p); do kill -- -"$job" 2>/dev/null || true; done
  exit 130
}
trap stop_runs INT TERM
ratios=()
for ((round = 0; round < 2 * pairs; ++round)); do
  core_a=$((round % 2)) core_b=$((1 - round % 2))
  timed "$core_a" "$work/a" "$1" &
  run_a=$!
  timed "$core_b" "$work/b" "$2" &
  run_b=$!
  # Whichever ends first; when it failed, the other is stopped rather than left to run on to its end.
  failed=0
  wait -n -p ended "$run_a" "$run_b" || failed=$?
  other=$([[ $ended == "$run_a" ]] && echo "$run_b" || echo "$run_a")
  if ((failed != 0)); then
    kill -- -"$other" 2>/dev/null || true
    exit 1
  fi
  wait "$other" || exit 1
  a=$(cat "$work/a") b=$(cat "$work/b")
  ratio=$(awk -v a="$a" -v b="$b" 'BEGIN { printf "%.3f", (b > 0 ? a / b : 0) }')
  ratios+=("$ratio")
  printf 'A on core %d: %6.2f s   B on core %d: %6.2f s   A/B %s\n' "$core_a" "$a" "$core_b" "$b" "$ratio"
done
printf '%s\n' "${ratios[@]}" |
  awk 'NR % 2 { first = $1; next } { printf "%.3f\n", sqrt(first * $1) }' |
  sort -n | awk '{ g[NR] = $1; list = list " " $1 } END {
    print "each pair (the geometric mean of its two ratios), ascending:" list
    printf "A/B median %.3f over %d pairs\n", NR % 2 ? g[(NR + 1) / 2] : (g[NR / 2] + g[NR / 2 + 1]) / 2, NR }'
