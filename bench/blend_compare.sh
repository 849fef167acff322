#!/usr/bin/env bash
# blend_compare.sh: does the .blend `wobble blend` writes render in Cycles as wobble renders the scene? Both renderers'
# converged pictures of the same frames, side by side, and their mean CIE76 colour difference (bench/cie76.cpp).
#
#   bench/blend_compare.sh SCENE "FRAMES" [--out DIR]
#   bench/blend_compare.sh scenes/jelly_slope.toml "20 60"
#   WOBBLE_SPP=16 CYCLES_SPP=16 RESOLUTION=352x198 bench/blend_compare.sh scenes/cloth_drop.toml 40   # a quick look
#
# Steps:
#   1. `wobble run SCENE --frames 1:LAST --render none --pc2 --out OUT/run` (LAST: the largest of FRAMES).
#   2. wobble's converged frames: `wobble render OUT/run/mesh --spp WOBBLE_SPP --denoise off` with no adaptive stop
#      (render.noise_threshold = 0), into OUT/wobble.
#   3. `wobble blend OUT/run`, then Blender renders each frame of OUT/run/<scene>.blend with CYCLES_SPP samples (no
#      adaptive stop, seed 1) into OUT/cycles: the .blend's own settings otherwise (its tone curve, bounces, sky).
#   4. cie76 of each pair; OUT/side_by_side_<frame>.png (wobble | Cycles, by ffmpeg's hstack) and a Markdown table on
#      stdout and in OUT/compare.md: frame, mean and 95th-percentile CIE76, each renderer's time.
#
# Environment (all optional): OUT (default out/blend-compare-<scene>), WOBBLE_SPP (256), CYCLES_SPP (256),
# RESOLUTION (WxH, default the scene's), THREADS (Cycles' threads, default 2), BUILD_DIR (default <repo>/build),
# BLENDER (default blender).
# Exit status: 0 done; 1 a step failed (its log is named); 2 bad arguments or no wobble/cie76 build; 3 no Blender.
set -euo pipefail

script_dir="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
repo="$(cd "$script_dir/.." && pwd)"
die() {  # die CODE MESSAGE
  echo "blend_compare.sh: $2" >&2
  exit "$1"
}
out="${OUT:-}"
positional=()
while (($#)); do
  case "$1" in
    -h | --help) sed -n '2,/^set -euo/p' "${BASH_SOURCE[0]}" | sed -e '/^set -euo/d' -e 's/^# \{0,1\}//'; exit 0 ;;
    --out) (($# >= 2)) || die 2 "--out needs a folder"; out="$2"; shift 2 ;;
    -*) die 2 "$1: unknown option (see --help)" ;;
    *) positional+=("$1"); shift ;;
  esac
done
((${#positional[@]} == 2)) || die 2 "expected SCENE \"FRAMES\" (see --help)"
scene="${positional[0]}"
frames="${positional[1]}"
[[ -f "$scene" ]] || die 2 "$scene: no such scene file"
last=0
for f in $frames; do
  [[ "$f" =~ ^[1-9][0-9]*$ ]] || die 2 "FRAMES: $f is not a frame number >= 1"
  ((f > last)) && last=$f
done
((last > 0)) || die 2 "FRAMES is empty"
wobble_spp="${WOBBLE_SPP:-256}"
cycles_spp="${CYCLES_SPP:-256}"
threads="${THREADS:-2}"
for v in "$wobble_spp" "$cycles_spp" "$threads"; do [[ "$v" =~ ^[1-9][0-9]*$ ]] || die 2 "$v: must be a whole number >= 1"; done
resolution_set=()
if [[ -n "${RESOLUTION:-}" ]]; then
  [[ "$RESOLUTION" =~ ^([1-9][0-9]*)x([1-9][0-9]*)$ ]] || die 2 "RESOLUTION $RESOLUTION: must be WxH"
  resolution_set=(--set "camera.resolution=[${BASH_REMATCH[1]},${BASH_REMATCH[2]}]")
fi
name="$(basename "$scene" .toml)"
out="${out:-out/blend-compare-$name}"
build_dir="${BUILD_DIR:-$repo/build}"
wobble="$build_dir/wobble"
cie76="$build_dir/cie76"
blender="${BLENDER:-blender}"
command -v "$blender" >/dev/null 2>&1 || die 3 "'$blender' is not on PATH (apt-get install blender gives Cycles 3.4)"
[[ -x "$wobble" ]] || die 2 "$wobble: not built (cmake --build $build_dir --target wobble)"
[[ -x "$cie76" ]] || die 2 "$cie76: not built (cmake --build $build_dir --target cie76)"
mkdir -p "$out/logs" "$out/cycles"
out="$(cd "$out" && pwd)"
step() { echo "== $*" >&2; }
run() {  # run LOG COMMAND...: the command's output into OUT/logs/LOG; fails naming the log
  "${@:2}" >"$out/logs/$1" 2>&1 || die 1 "$(basename "$2") failed: see $out/logs/$1"
}

step "simulating $scene to frame $last"
run run.log "$wobble" run "$scene" --frames "1:$last" --render none --pc2 --out "$out/run" "${resolution_set[@]}"
step "wobble blend"
run blend.log "$wobble" blend "$out/run"

table="| frame | mean CIE76 | 95th percentile | wobble ($wobble_spp spp) | Cycles ($cycles_spp spp) |
|---|---|---|---|---|"
for f in $frames; do
  step "frame $f: wobble at $wobble_spp spp"
  start=$(date +%s.%N)
  run "wobble_$f.log" "$wobble" render "$out/run/mesh" --scene "$scene" --frames "$f" --spp "$wobble_spp" \
    --denoise off --set render.noise_threshold=0 --render png --out "$out/wobble" "${resolution_set[@]}"
  wobble_s=$(echo "$(date +%s.%N) - $start" | bc)
  wobble_png="$(printf '%s/wobble/frames/%s_%04d.png' "$out" "$name" "$f")"
  step "frame $f: Cycles at $cycles_spp spp"
  settings="import bpy; s = bpy.context.scene; s.cycles.samples = $cycles_spp; s.cycles.use_adaptive_sampling = False"
  settings+="; s.cycles.seed = 1; s.cycles.use_animated_seed = False; s.render.threads_mode = 'FIXED'"
  settings+="; s.render.threads = $threads"
  start=$(date +%s.%N)
  run "cycles_$f.log" "$blender" -b "$out/run/$name.blend" --python-expr "$settings" \
    -o "$out/cycles/${name}_####" -F PNG -f "$f"
  cycles_s=$(echo "$(date +%s.%N) - $start" | bc)
  cycles_png="$(printf '%s/cycles/%s_%04d.png' "$out" "$name" "$f")"
  read -r mean p95 < <("$cie76" "$wobble_png" "$cycles_png" | awk -F= '/^mean=/{m=$2} /^p95=/{p=$2} END{print m, p}')
  if command -v ffmpeg >/dev/null 2>&1; then
    ffmpeg -v error -y -i "$wobble_png" -i "$cycles_png" -filter_complex hstack "$out/side_by_side_$f.png" ||
      echo "blend_compare.sh: ffmpeg could not put frame $f side by side" >&2
  fi
  table+="
| $f | $mean | $p95 | $(printf '%.1f s' "$wobble_s") | $(printf '%.1f s' "$cycles_s") |"
done
echo "$table" | tee "$out/compare.md"
