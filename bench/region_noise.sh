#!/usr/bin/env bash
# region_noise.sh: the noise of wobble's default picture where it is hardest, against Cycles. On frames 20 and 60 of
# the default scene (jelly_slope, at its shipped resolution) the RMSE inside the jelly, and on a frame of cloth_drop
# the RMSE in the shade under the draped cloth; each renderer against its own converged picture (256 samples a pixel,
# no adaptive stop, no denoiser), with the render times.
#
#   bench/region_noise.sh                                   # wobble's default, and Cycles 16 and 256 from the .blend
#   CYCLES= LABEL=spp4 bench/region_noise.sh --spp 4        # another wobble setting (flags for `wobble render`)
#
# Steps (per scene; the run, the mask, the converged pictures and Cycles' renders are kept in OUT and reused; every
# wobble picture renders the run's meshes with the repository's scene file, so a kept run follows its render keys):
#   1. `wobble run SCENE --frames 1:LAST --render none` (the meshes), then `wobble blend` of that run.
#   2. The mask: the frame with the body drawn pure green (a green texture: the jelly's print covering all of it, the
#      cloth diffuse; 1 sample, no denoiser).
#   3. wobble converged; Cycles at each of CYCLES' sample counts (no adaptive stop, no denoiser, seed 1, THREADS).
#   4. wobble with the given flags (none: the scene's own settings), timed.
#   5. bench/region_error of each picture against its renderer's converged one (the jelly: --region body; the cloth:
#      --region shadow, the pixels darker than 0.35 that are not the cloth).
# Prints one Markdown row per picture: scene, frame, renderer/setting, time, RMSE in the region, RMSE outside it.
# Time: wobble's own "rendered ... (T s)" (render and denoise of one frame, with its start-up) and Blender's wall time
# of the one-frame render (scene load included); quote ratios from one run.
#
# Environment (all optional): OUT (default out/region-noise), LABEL (default "default"; names wobble's folder),
# JELLY_FRAMES ("20 60"; "" skips the jelly), CLOTH_FRAME (35: draped over the sphere; "" skips the cloth), CLOTH_RESOLUTION (640x360; "" for the scene's), REF_SPP (256),
# CYCLES ("16 256"; "" skips Cycles), THREADS (Cycles' threads, 2), BUILD_DIR (<repo>/build), BLENDER (blender).
# Exit status: 0 done; 1 a step failed (its log is named); 2 no wobble/region_error build.
set -euo pipefail

script_dir="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
repo="$(cd "$script_dir/.." && pwd)"
die() {
  echo "region_noise.sh: $2" >&2
  exit "$1"
}
[[ "${1:-}" == "-h" || "${1:-}" == "--help" ]] && { sed -n '2,/^set -euo/p' "$0" | sed -e '/^set -euo/d' -e 's/^# \{0,1\}//'; exit 0; }
flags=("$@")
out="${OUT:-out/region-noise}"
label="${LABEL:-default}"
jelly_frames="${JELLY_FRAMES-20 60}"
cloth_frame="${CLOTH_FRAME-35}"
cloth_resolution="${CLOTH_RESOLUTION-640x360}"
ref_spp="${REF_SPP:-256}"
cycles="${CYCLES-16 256}"
threads="${THREADS:-2}"
build_dir="${BUILD_DIR:-$repo/build}"
wobble="$build_dir/wobble"
region_error="$build_dir/region_error"
blender="${BLENDER:-blender}"
[[ -x "$wobble" ]] || die 2 "$wobble: not built (cmake --build $build_dir --target wobble)"
[[ -x "$region_error" ]] || die 2 "$region_error: not built (cmake --build $build_dir --target region_error)"
if [[ -n "$cycles" ]] && ! command -v "$blender" >/dev/null 2>&1; then
  echo "region_noise.sh: no '$blender' on PATH: Cycles skipped" >&2
  cycles=""
fi
mkdir -p "$out/logs"
out="$(cd "$out" && pwd)"
green="$out/green.png"
[[ -f "$green" ]] || printf 'P3\n1 1\n255\n0 255 0\n' >"$out/green.ppm"
if [[ ! -f "$green" ]]; then
  # A 1 x 1 green PNG (wobble reads textures with stb); through ffmpeg, which the video needs anyway.
  ffmpeg -v error -y -i "$out/green.ppm" "$green" || die 1 "ffmpeg could not write $green"
fi
step() { echo "== $*" >&2; }
run() {  # run LOG COMMAND...
  "${@:2}" >"$out/logs/$1" 2>&1 || die 1 "$(basename "$2") failed: see $out/logs/$1"
}
seconds() { sed -n 's/.*rendered .*(\([0-9.]*\) s).*/\1/p' "$1" | tail -1; }

echo "| scene | frame | picture | time (s) | RMSE in region | RMSE outside |"
echo "|---|---|---|---|---|---|"
# measure SCENE BODY REGION FRAMES RESOLUTION [MASK_SETTING...]
measure() {
  local scene="$1" body="$2" region="$3" frames="$4" resolution="$5"
  local mask_sets=()
  for s in "${@:6}"; do mask_sets+=(--set "bodies.$body.$s"); done
  local name last=0 dir res=()
  name="$(basename "$scene" .toml)"
  dir="$out/$name"
  for f in $frames; do ((f > last)) && last=$f; done
  [[ -n "$resolution" ]] && res=(--resolution "$resolution")
  if [[ ! -f "$dir/run/run.json" ]]; then
    step "$name: simulating to frame $last"
    run "$name-run.log" "$wobble" run "$repo/$scene" --frames "1:$last" --render none --pc2 --out "$dir/run" "${res[@]}"
  fi
  for f in $frames; do
    local png
    png="$(printf '%s_%04d.png' "$name" "$f")"
    local common=(--scene "$repo/$scene" --frames "$f" --render png --set render.video=false "${res[@]}")
    if [[ ! -f "$dir/mask/frames/$png" ]]; then
      step "$name $f: mask"
      run "$name-mask-$f.log" "$wobble" render "$dir/run/mesh" "${common[@]}" --out "$dir/mask" --spp 1 --denoise off \
        --set "bodies.$body.texture=$green" --set "bodies.$body.color=[1,1,1]" "${mask_sets[@]}"
    fi
    if [[ ! -f "$dir/converged/frames/$png" ]]; then
      step "$name $f: wobble converged ($ref_spp spp)"
      run "$name-converged-$f.log" nice "$wobble" render "$dir/run/mesh" "${common[@]}" --out "$dir/converged" \
        --spp "$ref_spp" --set render.noise_threshold=0 --denoise off
    fi
    step "$name $f: wobble $label"
    run "$name-$label-$f.log" "$wobble" render "$dir/run/mesh" "${common[@]}" --out "$dir/$label" "${flags[@]}"
    local t errors
    t="$(seconds "$out/logs/$name-$label-$f.log")"
    errors="$("$region_error" "$dir/$label/frames/$png" "$dir/converged/frames/$png" "$dir/mask/frames/$png" --region "$region")"
    echo "| $name | $f | wobble $label | $t | $(sed -n 's/rmse_in=//p' <<<"$errors") | $(sed -n 's/rmse_out=//p' <<<"$errors") |"
    [[ -z "$cycles" ]] && continue
    if [[ ! -f "$dir/run/$name.blend" ]]; then
      step "$name: wobble blend"
      run "$name-blend.log" "$wobble" blend "$dir/run"
    fi
    local spp reference=""
    for spp in $(tr ' ' '\n' <<<"$cycles" | sort -n -r); do  # the largest first: the reference
      local cpng="$dir/cycles$spp/$png"
      if [[ ! -f "$cpng" ]]; then
        step "$name $f: Cycles $spp spp"
        local settings="import bpy; s = bpy.context.scene; s.cycles.samples = $spp; s.cycles.use_adaptive_sampling = False"
        settings+="; s.cycles.use_denoising = False; s.cycles.seed = 1; s.cycles.use_animated_seed = False"
        settings+="; s.render.threads_mode = 'FIXED'; s.render.threads = $threads"
        [[ -n "$resolution" ]] && settings+="; s.render.resolution_x = ${resolution%x*}; s.render.resolution_y = ${resolution#*x}; s.render.resolution_percentage = 100"
        local start
        start=$(date +%s.%N)
        run "$name-cycles$spp-$f.log" nice "$blender" -b "$dir/run/$name.blend" --python-expr "$settings" \
          -o "$dir/cycles$spp/${name}_####" -F PNG -f "$f"
        echo "$(date +%s.%N) - $start" | bc >"$dir/cycles$spp/${png%.png}.seconds"
      fi
      if [[ -z "$reference" ]]; then
        reference="$cpng"
        continue
      fi
      errors="$("$region_error" "$cpng" "$reference" "$dir/mask/frames/$png" --region "$region")"
      echo "| $name | $f | Cycles $spp spp | $(printf '%.1f' "$(cat "$dir/cycles$spp/${png%.png}.seconds")") |" \
        "$(sed -n 's/rmse_in=//p' <<<"$errors") | $(sed -n 's/rmse_out=//p' <<<"$errors") |"
    done
  done
}

[[ -n "$jelly_frames" ]] && measure scenes/jelly_slope.toml jelly body "$jelly_frames" "" print=1  # the print all over
[[ -n "$cloth_frame" ]] && measure scenes/cloth_drop.toml cloth shadow "$cloth_frame" "$cloth_resolution" material=diffuse
exit 0
