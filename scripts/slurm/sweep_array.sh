#!/bin/bash
# The machinery of study_array.sbatch and compare_array.sbatch (sourced by them; not a job script itself): a sweep of
# `wobble study KIND` or `wobble compare` cut into PIECES with --piece I/N, one array task each, then one job that
# gathers them (--gather) into the report, plots and video a one-machine run writes.
#
#   1. wobble-<sweep>        an array of PIECES tasks: wobble <COMMAND...> --out OUT --piece i/PIECES. Re-queued (a
#                            node failure, preemption, `scontrol requeue`), a task resumes: the rows or variants it
#                            had finished are kept (OUT/pieces/<sweep>/).
#   2. wobble-<sweep>-gather one job, after every task of 1 succeeded: wobble <COMMAND...> --out OUT --gather
# Prints the two job ids (also in OUT/slurm/jobs). Logs: OUT/slurm/<job name>-<job id>[_<task>].out.
# Environment: WOBBLE (the binary; default `wobble` on PATH, else build/wobble), CPUS_PER_TASK (default 4: a piece
# runs its rows or variants on as many threads (--jobs), a render study's renders on them; an accuracy study's runs
# are timed one at a time), and sbatch's own (SBATCH_PARTITION, SBATCH_TIMELIMIT, ...).
set -euo pipefail

sweep_stage() {  # inside a job: sweep_stage piece|gather OUT PIECES COMMAND...
  local stage=$1 out=$2 pieces=$3
  shift 3
  case $stage in
    piece)
      local jobs=(--jobs "$(nproc)")  # the commands that run several items at once
      [[ "$1 ${2:-}" == "study accuracy" || "$1 ${2:-}" == "study render" ]] && jobs=()
      echo "wobble $1 ${2:-} piece $SLURM_ARRAY_TASK_ID of $pieces on $(hostname), $(nproc) CPU(s)"
      exec "$WOBBLE" "$@" --out "$out" "${jobs[@]}" --piece "$SLURM_ARRAY_TASK_ID/$pieces" ;;
    gather)
      exec "$WOBBLE" "$@" --out "$out" --gather ;;
  esac
  echo "sweep_array: unknown stage '$stage'" >&2
  exit 2
}

sweep_submit() {  # on the login node: sweep_submit SELF SWEEP OUT PIECES COMMAND...
  local self=$1 sweep=$2 out=$3 pieces=$4
  shift 4
  WOBBLE=$(realpath "${WOBBLE:-$(command -v wobble || echo build/wobble)}")
  export WOBBLE  # sbatch passes the environment on (--export=ALL, its default)
  [[ -x $WOBBLE ]] || { echo "$(basename "$self"): no wobble binary at $WOBBLE (set WOBBLE=path)" >&2; exit 2; }
  [[ $pieces =~ ^[1-9][0-9]*$ ]] || { echo "$(basename "$self"): PIECES '$pieces': a whole number >= 1" >&2; exit 2; }
  local logs=$out/slurm
  mkdir -p "$logs"
  submit() { sbatch --parsable --cpus-per-task="${CPUS_PER_TASK:-4}" "$@" | cut -d';' -f1; }
  local pieces_job gather_job
  pieces_job=$(submit --job-name="wobble-$sweep" --array="1-$pieces" --output="$logs/%x-%A_%a.out" \
    "$self" --stage piece "$out" "$pieces" "$@")
  gather_job=$(submit --job-name="wobble-$sweep-gather" --dependency="afterok:$pieces_job" \
    --output="$logs/%x-%j.out" "$self" --stage gather "$out" "$pieces" "$@")
  echo "submitted: $sweep pieces $pieces_job (array 1-$pieces), gather $gather_job; logs in $logs"
  echo "$pieces_job $gather_job" >"$logs/jobs"
}
