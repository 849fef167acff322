#!/bin/bash
# End-to-end test of scripts/slurm/render_array.sbatch, study_array.sbatch and compare_array.sbatch on a real
# scheduler, outside CI: starts a one-node Slurm
# cluster on this machine (munge, slurmctld and slurmd from Debian's slurm-wlm, started directly: no systemd needed),
# with a temporary slurm.conf (this host, its CPUs) and state folder, then
#   1. submits the sbatch script with 1 piece and with 4 pieces (2 CPUs a piece, then 1: two run at once on a
#      2-CPU machine) and waits for each video job;
#   2. checks each video (ffprobe frame count = the frames the run wrote) and that the pieces' frames are the bytes
#      of the one-piece render and their video decodes to the same frames (ffmpeg framemd5);
#   3. re-queues a running piece (scontrol requeue) and checks that it resumes: its log says it skipped the frames
#      it had written;
#   4. splits a stability, an accuracy and a render study (3 pieces each) and a comparison (2 pieces) through
#      study_array.sbatch and compare_array.sbatch and checks that what each gathering job wrote is the bytes of the
#      same command run on one machine (stability.csv, .md and plots; accuracy.csv and render.csv but for their time
#      columns, the render study's images, reference and frame/; the comparison's frames and the frames its video
#      decodes to);
#   5. submits a study whose pieces fail (a bad flag) and checks that the wait for its gathering job stops at once
#      (Slurm keeps it pending as DependencyNeverSatisfied), naming the failed tasks and their logs' last line;
# prints the wall times, and stops the daemons and removes the temporary folder (kept on failure). Every wait for a
# job gives up after WAIT_TIMEOUT seconds (default 1800), naming the jobs that did not complete.
#
#   apt-get install -y slurm-wlm ffmpeg               # once (root); munge comes with slurm-wlm
#   scripts/slurm/test_local_cluster.sh [SCENE [FLAGS...]]
# Default: scenes/jelly_slope.toml, its first 2 s (60 frames) at 640 x 360. Run as root from the project root, with
# build/wobble built (or WOBBLE=path); about 5 to 10 minutes on 2 cores. Exit status 0 when every check passed; on a
# failure it says which check and keeps the temporary folder (logs, outputs) for a look.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."

scene=${1:-scenes/jelly_slope.toml}
if (($# > 1)); then flags=("${@:2}"); else flags=(--set simulation.duration=2 --resolution 640x360); fi
wobble=$(realpath "${WOBBLE:-build/wobble}")
[[ $(id -u) == 0 ]] || { echo "test_local_cluster: run as root (slurmd starts jobs as their user)" >&2; exit 2; }
for program in munged slurmctld slurmd sbatch ffprobe; do
  command -v "$program" >/dev/null || { echo "test_local_cluster: $program missing (apt-get install -y slurm-wlm ffmpeg)" >&2; exit 2; }
done
[[ -x $wobble ]] || { echo "test_local_cluster: build/wobble missing (./setup.sh)" >&2; exit 2; }

tmp=$(mktemp -d /tmp/wobble-slurm.XXXXXX)
pids=()
ok=0
finish() {
  for ((i = ${#pids[@]} - 1; i >= 0; --i)); do kill "${pids[i]}" 2>/dev/null || true; done
  for pid in "${pids[@]}"; do wait "$pid" 2>/dev/null || true; done
  if ((ok)); then rm -rf "$tmp"; else echo "test_local_cluster: FAILED; logs and outputs kept in $tmp" >&2; fi
}
trap finish EXIT
fail() { echo "test_local_cluster: $*" >&2; exit 1; }
now() { date +%s.%N; }

# munge: a fresh key, its socket in the temporary folder.
mkdir -m 700 "$tmp/munge"
dd if=/dev/urandom of="$tmp/munge/munge.key" bs=1024 count=1 status=none
chmod 400 "$tmp/munge/munge.key"
munged --foreground --force --key-file="$tmp/munge/munge.key" --socket="$tmp/munge/munge.socket" \
  --pid-file="$tmp/munge/munged.pid" --log-file="$tmp/munge/munged.log" --seed-file="$tmp/munge/munged.seed" &
pids+=($!)

host=$(hostname -s)
cpus=$(nproc)
mkdir -p "$tmp/state" "$tmp/spool"
export SLURM_CONF=$tmp/slurm.conf  # for the daemons, sbatch, squeue and scontrol alike
cat >"$SLURM_CONF" <<EOF
ClusterName=wobbletest
SlurmctldHost=$host
SlurmUser=root
SlurmctldPort=16817
SlurmdPort=16818
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$tmp/munge/munge.socket
StateSaveLocation=$tmp/state
SlurmdSpoolDir=$tmp/spool
SlurmctldPidFile=$tmp/slurmctld.pid
SlurmdPidFile=$tmp/slurmd.pid
SlurmctldLogFile=$tmp/slurmctld.log
SlurmdLogFile=$tmp/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/affinity
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
SchedulerParameters=sched_interval=2,bf_interval=2
ReturnToService=2
MpiDefault=none
JobCompType=jobcomp/none
AccountingStorageType=accounting_storage/none
JobAcctGatherType=jobacct_gather/none
NodeName=$host CPUs=$cpus State=UNKNOWN
PartitionName=debug Nodes=$host Default=YES MaxTime=INFINITE State=UP
EOF
slurmctld -D -i >"$tmp/slurmctld.out" 2>&1 &
pids+=($!)
slurmd -D -N "$host" >"$tmp/slurmd.out" 2>&1 &
pids+=($!)
for ((i = 0; ; ++i)); do
  state=$(sinfo -h -o %t 2>/dev/null || true)
  [[ $state == idle ]] && break
  ((i < 120)) || fail "the node did not come up (state '$state'; see $tmp/slurmctld.log, $tmp/slurmd.log)"
  sleep 0.5
done
echo "cluster up: node $host, $cpus CPUs, $(sinfo -V)"

# Every job of a submission (the ids in OUT/slurm/jobs; an array's tasks one by one) that did not complete: its
# state, exit code, reason and the last line of its log.
unfinished_jobs() {
  local out=$1 job line
  for job in $(cat "$out/slurm/jobs"); do
    scontrol -o show job "$job" 2>/dev/null | while read -r line; do
      local id state code reason log
      [[ $line =~ ^JobId=([0-9]+) ]] && id=${BASH_REMATCH[1]}
      [[ $line =~ ArrayJobId=([0-9]+)\ ArrayTaskId=([0-9]+) ]] && id="${BASH_REMATCH[1]}_${BASH_REMATCH[2]}"
      state=$(grep -o 'JobState=[A-Z_]*' <<<"$line" | cut -d= -f2)
      [[ $state == COMPLETED ]] && continue
      code=$(grep -o ' ExitCode=[0-9:]*' <<<"$line" | cut -d= -f2)
      reason=$(grep -o ' Reason=[^ ]*' <<<"$line" | cut -d= -f2)
      log=$(grep -o ' StdOut=[^ ]*' <<<"$line" | cut -d= -f2)
      echo "  job $id: $state, exit $code, reason $reason; log $log${log:+: $(tail -n 1 "$log" 2>/dev/null)}"
    done
  done
}
# Waits for the last job of a submission (the last id in OUT/slurm/jobs: the video or gathering job, which runs after
# all the others succeeded) to end; it must have completed. A job whose dependency can never be satisfied (a job it
# waits for failed: Slurm keeps it pending as DependencyNeverSatisfied) fails at once, naming the failed jobs and
# their logs; waiting longer than WAIT_TIMEOUT seconds (default 1800) fails too. Both cancel the submission's jobs.
wait_last_job() {
  local out=$1 timeout=${WAIT_TIMEOUT:-1800} start=$SECONDS job info state reason
  job=$(awk '{ print $NF }' "$out/slurm/jobs")
  while :; do
    info=$(scontrol show job "$job" 2>/dev/null || true)
    state=$(grep -o 'JobState=[A-Z_]*' <<<"$info" | cut -d= -f2 || true)
    reason=$(grep -o ' Reason=[^ ]*' <<<"$info" | cut -d= -f2 || true)
    if [[ $reason == DependencyNeverSatisfied ]]; then
      local failed
      failed=$(unfinished_jobs "$out" | grep -v "job $job: ")
      scancel $(cat "$out/slurm/jobs") 2>/dev/null || true
      fail "$out: job $job can never start: a job it depends on failed (DependencyNeverSatisfied):"$'\n'"$failed"
    fi
    [[ $state =~ ^(PENDING|CONFIGURING|RUNNING|COMPLETING|REQUEUED|SUSPENDED)$ ]] || break
    if ((SECONDS - start > timeout)); then
      local left
      left=$(unfinished_jobs "$out")
      scancel $(cat "$out/slurm/jobs") 2>/dev/null || true
      fail "$out: job $job still $state ($reason) after ${timeout} s (WAIT_TIMEOUT); cancelled:"$'\n'"$left"
    fi
    sleep 0.25
  done
  [[ $state == COMPLETED ]] || fail "$out: the last job ($job) ended $state ($reason):"$'\n'"$(unfinished_jobs "$out")"
}
# Runs the sbatch script: OUT PIECES CPUS_PER_TASK; prints the wall time from submission to the video.
pipeline() {
  local out=$tmp/$1 start
  start=$(now)
  CPUS_PER_TASK=$3 WOBBLE=$wobble scripts/slurm/render_array.sbatch "$scene" "$out" "$2" "${flags[@]}" >&2
  wait_last_job "$out"
  awk "BEGIN { printf \"%.1f\", $(now) - $start }"
}
# The render stage's own seconds per piece, from the pieces' logs ("rendered N frame(s) ... (S s)").
piece_seconds() { cat "$tmp/$1"/slurm/wobble-render-*.out | sed -n 's/^rendered .*(\([0-9.]*\) s).*/\1/p' | paste -sd' '; }
# The render stage's wall time: the first piece's start to the last one's end (Slurm's times, whole seconds).
stage_seconds() {
  local simulate render video
  read -r simulate render video <"$tmp/$1/slurm/jobs"
  scontrol show job "$render" | grep -o '\(Start\|End\)Time=[0-9T:-]*' | while IFS== read -r what when; do
    echo "$what $(date -d "$when" +%s)"
  done | awk '$1 == "StartTime" && (!s || $2 < s) { s = $2 } $1 == "EndTime" && $2 > e { e = $2 } END { print e - s }'
}
frame_md5() { ffmpeg -nostdin -loglevel error -i "$1" -f framemd5 - | grep -v '^#'; }

one=$(pipeline one 1 "$cpus") && one_stage=$(stage_seconds one)
four=$(pipeline four 4 "$cpus") && four_stage=$(stage_seconds four)
four_single=$(pipeline four_1cpu 4 1) && four_single_stage=$(stage_seconds four_1cpu)

frames=$(python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['frames']['written'])" "$tmp/one/run.json")
name=$(basename "$scene" .toml)
for run in one four four_1cpu; do
  count=$(ffprobe -v error -select_streams v:0 -count_frames -show_entries stream=nb_read_frames \
    -of default=nw=1:nk=1 "$tmp/$run/$name.mp4")
  [[ $count == "$frames" ]] || fail "$run/$name.mp4 has $count frames, the run wrote $frames"
done
for run in four four_1cpu; do
  for png in "$tmp/one/frames/"*.png; do
    cmp -s "$png" "$tmp/$run/frames/$(basename "$png")" || fail "$run: $(basename "$png") differs from the one-piece render"
  done
  [[ $(frame_md5 "$tmp/$run/$name.mp4") == "$(frame_md5 "$tmp/one/$name.mp4")" ]] ||
    fail "$run/$name.mp4 decodes to other frames than the one-piece video"
done
grep -h "wobble-render task" "$tmp/four_1cpu/slurm/"wobble-render-*.out | sed 's/^/  /'
echo "videos: $frames frames each; the 4-piece frames and videos are the one-piece render's, byte for byte / frame for frame"

# A piece re-queued while it renders resumes: --skip-existing keeps what it had written.
out=$tmp/requeue
CPUS_PER_TASK=1 WOBBLE=$wobble scripts/slurm/render_array.sbatch "$scene" "$out" 4 "${flags[@]}" >/dev/null
read -r simulate render video <"$out/slurm/jobs"
for ((i = 0; ; ++i)); do  # the simulation's run.json, then piece 1's third frame
  if [[ -f $out/run.json ]]; then
    first_piece=$("$wobble" frames "$out" --chunks 4 --chunk 1)
    [[ -f $(printf '%s/frames/%s_%04d.png' "$out" "$name" $((${first_piece%%:*} + 2))) ]] && break
  fi
  ((i < 1200)) || fail "requeue: piece 1 wrote no frame in 2 minutes"
  sleep 0.1
done
scontrol requeue "${render}_1" || fail "requeue: scontrol requeue ${render}_1 failed"
requeued=$(now)
# Slurm holds a re-queued job back two minutes (its begin time); once it is pending again, let it start at once.
for ((i = 0; i < 120; ++i)); do
  scontrol show job "${render}_1" 2>/dev/null | grep -q 'Reason=BeginTime' &&
    scontrol update JobId="${render}_1" StartTime=now && break
  sleep 0.25
done
wait_last_job "$out"
requeue_wait=$(awk "BEGIN { printf \"%.0f\", $(now) - $requeued }")
log=$out/slurm/wobble-render-${render}_1.out
skipped=$(sed -n 's/^skipped \([0-9]*\) frame.*/\1/p' "$log" | tail -1)
((${skipped:-0} > 0)) || fail "requeue: the re-queued piece did not skip its frames (see $log)"
[[ $(frame_md5 "$out/$name.mp4") == "$(frame_md5 "$tmp/one/$name.mp4")" ]] || fail "requeue: the video differs"
echo "requeue: piece 1 (frames $first_piece) was re-queued after some frames; it resumed and skipped $skipped," \
  "the video is the same ($requeue_wait s from the requeue to the video)"

# Sweeps in pieces: every study kind and a comparison, each split on the cluster and gathered, against the same
# command run here on one machine.
csv_without() {  # FILE COLUMN...: the CSV without the named columns (times: each run's where it ran)
  awk -F, -v drop="${*:2}" 'BEGIN { n = split(drop, d, " ") }
    NR == 1 { for (i = 1; i <= NF; ++i) for (j = 1; j <= n; ++j) if ($i == d[j]) skip[i] = 1 }
    { line = ""; for (i = 1; i <= NF; ++i) if (!skip[i]) line = line $i ","; print line }' "$1"
}
sweep() {  # NAME PIECES KIND COMMAND...: runs COMMAND here into NAME_one and through KIND's sbatch into NAME_split
  local name=$1 pieces=$2 kind=$3 start
  shift 3
  "$wobble" "$@" --out "$tmp/${name}_one" >/dev/null
  start=$(now)
  if [[ $kind == compare ]]; then
    CPUS_PER_TASK=1 WOBBLE=$wobble scripts/slurm/compare_array.sbatch "$tmp/${name}_split" "$pieces" "${@:2}" >&2
  else
    CPUS_PER_TASK=1 WOBBLE=$wobble scripts/slurm/study_array.sbatch "$tmp/${name}_split" "$pieces" "$kind" "${@:3}" >&2
  fi
  wait_last_job "$tmp/${name}_split"
  awk "BEGIN { printf \"%.1f\", $(now) - $start }" >"$tmp/${name}_seconds"
}
same() {  # NAME FILE...: each file (relative) of NAME_split is the bytes of NAME_one's
  local name=$1 file
  for file in "${@:2}"; do
    [[ -f $tmp/${name}_one/$file ]] || fail "$name: the one-machine run wrote no $file"
    cmp -s "$tmp/${name}_one/$file" "$tmp/${name}_split/$file" ||
      fail "$name: $file of the pieces differs from the one-machine run's"
  done
}

sweep stability 3 stability study stability scenes/jelly_impact.toml --integrators explicit-euler,midpoint,rk4 \
  --ks-points 3 --dt-points 3 --duration 0.2 --no-contact
same stability $(cd "$tmp/stability_one" && ls stability*)
echo "study stability: 3 pieces gathered into the one-machine study's files, byte for byte:" \
  "$(cd "$tmp/stability_one" && ls stability* | paste -sd' ') ($(cat "$tmp/stability_seconds") s)"

sweep accuracy 3 accuracy study accuracy scenes/cloth_swing.toml --integrators explicit-euler,midpoint,rk4 \
  --duration 0.25 --kmin 4 --kmax 7 --samples 4 --repeats 0
[[ $(csv_without "$tmp/accuracy_one/accuracy.csv" seconds) == "$(csv_without "$tmp/accuracy_split/accuracy.csv" seconds)" ]] ||
  fail "accuracy: accuracy.csv of the 3 pieces differs from the one-machine study's (but for run times)"
echo "study accuracy: 3 pieces gathered into the one-machine study's accuracy.csv ($(($(wc -l <"$tmp/accuracy_one/accuracy.csv") - 1))" \
  "points: errors, steps, evaluations the same bytes; run times are each run's) ($(cat "$tmp/accuracy_seconds") s)"

sweep render 3 render study render scenes/jelly_slope.toml --frame 20 --resolution 96x54 --reference-spp 64 \
  --max-spp 8 --variants sobol,sobol+denoise,adaptive --thresholds 0.1,0.05
same render reference.png $(cd "$tmp/render_one" && ls images/* frame/* reference-*.pfm)
[[ $(csv_without "$tmp/render_one/render.csv" seconds denoise_seconds) == \
  "$(csv_without "$tmp/render_split/render.csv" seconds denoise_seconds)" ]] ||
  fail "render: render.csv of the 3 pieces differs from the one-machine study's (but for render times)"
echo "study render: 3 pieces gathered into the one-machine study's render.csv (but for times) and its" \
  "$(ls "$tmp/render_one/images" | wc -l) images, reference and frame/, byte for byte ($(cat "$tmp/render_seconds") s)"

sweep compare 2 compare compare scenes/jelly_slope.toml --vary integrator=pc-euler,midpoint,rk4 \
  --set simulation.duration=0.5 --resolution 192x108 --quality preview
same compare $(cd "$tmp/compare_one" && ls frames/*)
[[ $(frame_md5 "$tmp/compare_split/compare.mp4") == "$(frame_md5 "$tmp/compare_one/compare.mp4")" ]] ||
  fail "compare: the gathered video decodes to other frames than the one-machine comparison's"
grep -q "gathered from 2 pieces" "$tmp/compare_split/compare.md" || fail "compare: compare.md does not say it gathered 2 pieces"
echo "compare: 2 pieces gathered into the one-machine comparison's $(ls "$tmp/compare_one/frames" | wc -l) frames" \
  "(byte for byte) and video (frame for frame) ($(cat "$tmp/compare_seconds") s)"

# A failed piece: the gathering job can never start; the wait names the failed task and its log, and does not hang.
CPUS_PER_TASK=1 WOBBLE=$wobble scripts/slurm/study_array.sbatch "$tmp/failing" 2 stability scenes/jelly_impact.toml \
  --integrators explicit-euler --ks-points 2 --dt-points 2 --duration 0.05 --no-contact --strain-bound -1 >&2
message=$( (wait_last_job "$tmp/failing") 2>&1) && fail "failing: a sweep whose pieces failed was waited for as done"
grep -q DependencyNeverSatisfied <<<"$message" && grep -q "strain-bound" <<<"$message" ||
  fail "failing: the wait did not name the failed dependency and the piece's error: $message"
echo "a failed piece: the wait stops with"
sed 's/^/  /' <<<"$message"

echo "wall time ($frames frames, ${flags[*]}; load average $(cut -d' ' -f1-3 /proc/loadavg)):"
echo "                         submission to video   render stage   each piece's render"
printf '  %-22s %8s s %14s s   %s s\n' "1 piece, $cpus CPUs" "$one" "$one_stage" "$(piece_seconds one)" \
  "4 pieces, $cpus CPUs each" "$four" "$four_stage" "$(piece_seconds four)" \
  "4 pieces, 1 CPU each" "$four_single" "$four_single_stage" "$(piece_seconds four_1cpu)"
ok=1
