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
#   4. splits a stability study (3 pieces) and a comparison (2 pieces) through study_array.sbatch and
#      compare_array.sbatch and checks that what each gathering job wrote is the bytes of the same command run on one
#      machine (stability.csv, .md and plots; the comparison's frames and the frames its video decodes to);
# prints the wall times, and stops the daemons and removes the temporary folder (kept on failure).
#
#   apt-get install -y slurm-wlm                      # once (root); munge comes with it
#   scripts/slurm/test_local_cluster.sh [SCENE [FLAGS...]]
# Default: scenes/jelly_slope.toml, its first 2 s (60 frames) at 640 x 360. Run as root from the project root, with
# build/wobble built. Exit status 0 when every check passed.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."

scene=${1:-scenes/jelly_slope.toml}
if (($# > 1)); then flags=("${@:2}"); else flags=(--set simulation.duration=2 --resolution 640x360); fi
wobble=$(realpath build/wobble)
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
SchedulerParameters=kill_invalid_depend,sched_interval=2,bf_interval=2
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

# Waits for the last job of a submission (the last id in OUT/slurm/jobs: the video or gathering job, which runs after
# all the others succeeded, and kill_invalid_depend cancels it when one failed) to end; it must have completed.
wait_last_job() {
  local out=$1 job state
  job=$(awk '{ print $NF }' "$out/slurm/jobs")
  while :; do
    state=$(scontrol show job "$job" 2>/dev/null | grep -o 'JobState=[A-Z_]*' || true)
    [[ $state =~ =(PENDING|CONFIGURING|RUNNING|COMPLETING|REQUEUED|SUSPENDED)$ ]] || break
    sleep 0.25
  done
  [[ $state == JobState=COMPLETED ]] || fail "$out: the last job ($job) did not complete: $(
    scontrol show job "$job" | grep -o 'JobState=[A-Z_]* Reason=[^ ]*')"
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

# Sweeps in pieces: a stability study and a comparison, each split on the cluster and gathered, against the same
# command run here on one machine.
study=(scenes/jelly_impact.toml --integrators explicit-euler,midpoint,rk4 --ks-points 3 --dt-points 3 --duration 0.2
  --no-contact)
"$wobble" study stability "${study[@]}" --out "$tmp/study_one" >/dev/null
CPUS_PER_TASK=1 WOBBLE=$wobble scripts/slurm/study_array.sbatch "$tmp/study_split" 3 stability "${study[@]}" >&2
wait_last_job "$tmp/study_split"
for file in "$tmp/study_one/"stability*; do
  cmp -s "$file" "$tmp/study_split/$(basename "$file")" ||
    fail "study: $(basename "$file") of the 3 pieces differs from the one-machine study's"
done
echo "study: 3 pieces gathered into the one-machine study's files, byte for byte: $(cd "$tmp/study_one" && ls stability*)"
compare=(scenes/jelly_slope.toml --vary integrator=pc-euler,midpoint,rk4 --set simulation.duration=0.5
  --resolution 192x108 --quality preview)
"$wobble" compare "${compare[@]}" --out "$tmp/compare_one" >/dev/null
CPUS_PER_TASK=1 WOBBLE=$wobble scripts/slurm/compare_array.sbatch "$tmp/compare_split" 2 "${compare[@]}" >&2
wait_last_job "$tmp/compare_split"
for png in "$tmp/compare_one/frames/"*.png; do
  cmp -s "$png" "$tmp/compare_split/frames/$(basename "$png")" ||
    fail "compare: $(basename "$png") of the 2 pieces differs from the one-machine comparison's"
done
[[ $(frame_md5 "$tmp/compare_split/compare.mp4") == "$(frame_md5 "$tmp/compare_one/compare.mp4")" ]] ||
  fail "compare: the gathered video decodes to other frames than the one-machine comparison's"
echo "compare: 2 pieces gathered into the one-machine comparison's $(ls "$tmp/compare_one/frames" | wc -l) frames" \
  "(byte for byte) and video (frame for frame)"

echo "wall time ($frames frames, ${flags[*]}; load average $(cut -d' ' -f1-3 /proc/loadavg)):"
echo "                         submission to video   render stage   each piece's render"
printf '  %-22s %8s s %14s s   %s s\n' "1 piece, $cpus CPUs" "$one" "$one_stage" "$(piece_seconds one)" \
  "4 pieces, $cpus CPUs each" "$four" "$four_stage" "$(piece_seconds four)" \
  "4 pieces, 1 CPU each" "$four_single" "$four_single_stage" "$(piece_seconds four_1cpu)"
ok=1
