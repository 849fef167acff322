#!/usr/bin/env bash
# embree_share.sh: how much of a renderer's path-tracing time is Embree's (ray traversal) and how much its own
# (shading, sampling, lights, the render loop), for wobble and for Blender Cycles on the same frame, by profiling.
#
#   bench/embree_share.sh SCENE FRAME RESOLUTION [SPP_LOW SPP_HIGH]
#   bench/embree_share.sh scenes/jelly_slope.toml 150 1280x720          # 4 and 16 samples a pixel
#
# Method: each renderer renders the frame twice, at SPP_LOW and at SPP_HIGH samples a pixel (no adaptive sampling,
# no denoising), under `perf record -e cpu-clock` (all threads). What differs between the two profiles is the path
# tracing of SPP_HIGH - SPP_LOW samples a pixel alone: start-up, wobble's simulation, Blender's Python and scene sync,
# both BVH builds and the image writing are the same in both runs and cancel. Embree's share = the difference's
# samples in libembree3 over all its samples. render_bench's "fraction of raw Embree" (the renderer's rays a second
# over raw rtcIntersect1 / rtcOccluded1 on rays of the same kind) is this share wherever Embree costs the same a ray
# inside a renderer as alone.
# Cycles renders the frame as bench/cycles_compare.sh does (bench/cycles_scene.py, from the frame `wobble study
# render` exports); wobble renders it from the scene (`wobble run --frames FRAME`). Each keeps its own sampling.
#
# Environment (optional): OUT (default out/embree-share-<scene>-<frame>), BUILD_DIR (default <repo>/build), BLENDER
# (default blender), FREQ (perf's samples a second and thread, default 999).
# Exit status: 0 done; 1 a step failed (its log is named); 2 bad arguments or no wobble build; 3 perf or Blender missing.
set -euo pipefail

script_dir="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
repo="$(cd "$script_dir/.." && pwd)"
die() {  # die CODE MESSAGE
  echo "embree_share.sh: $2" >&2
  exit "$1"
}
is_uint() { [[ "$1" =~ ^[0-9]+$ ]]; }

[[ "${1:-}" == -h || "${1:-}" == --help ]] && { sed -n '2,/^set -euo/p' "$0" | sed -e '/^set -euo/d' -e 's/^# \{0,1\}//'; exit 0; }
(($# == 3 || $# == 5)) || die 2 "expected SCENE FRAME RESOLUTION [SPP_LOW SPP_HIGH] (see --help)"
scene="$1" frame="$2" resolution="$3" low="${4:-4}" high="${5:-16}"
[[ -f "$scene" ]] || die 2 "$scene: no such scene file"
is_uint "$frame" && ((frame >= 1)) || die 2 "FRAME $frame: must be a whole number >= 1"
[[ "$resolution" =~ ^[1-9][0-9]*x[1-9][0-9]*$ ]] || die 2 "RESOLUTION $resolution: must be WxH, e.g. 1280x720"
is_uint "$low" && is_uint "$high" && ((low >= 1 && high > low)) || die 2 "SPP_LOW $low, SPP_HIGH $high: need 1 <= SPP_LOW < SPP_HIGH"
freq="${FREQ:-999}"
is_uint "$freq" && ((freq >= 1)) || die 2 "FREQ $freq: must be a whole number >= 1"

wobble="${BUILD_DIR:-$repo/build}/wobble"
blender="${BLENDER:-blender}"
[[ -x "$wobble" ]] || die 2 "$wobble: not built (cmake --build build --target wobble; or set BUILD_DIR)"
command -v perf >/dev/null 2>&1 || die 3 "perf is missing (Debian 12: apt-get install linux-perf)"
command -v "$blender" >/dev/null 2>&1 || die 3 "Blender is missing: '$blender' is not on PATH (Debian 12: apt-get install blender)"
out="${OUT:-out/embree-share-$(basename "$scene" .toml)-$frame}"
mkdir -p "$out/logs" || die 1 "$out: cannot create the output folder"

# profile KEY COMMAND...: runs COMMAND under perf (log: OUT/logs/KEY.log) and sets embree[KEY] and all[KEY], its
# samples in libembree3 and in all. In this shell, not a subshell, so that die ends the script.
declare -A embree all
profile() {
  local key="$1"
  shift
  perf record -q -e cpu-clock -F "$freq" -o "$out/$key.perf" -- "$@" >"$out/logs/$key.log" 2>&1 ||
    die 1 "$key failed (log: $out/logs/$key.log)"
  read -r "embree[$key]" "all[$key]" < <(perf script -i "$out/$key.perf" -F ip,dso 2>/dev/null |
    awk '{ n++; if ($2 ~ /libembree3/) e++ } END { print e + 0, n + 0 }')
}

echo "== exporting frame $frame for Cycles (wobble study render)" >&2
"$wobble" study render "$scene" --frame "$frame" --resolution "$resolution" --reference-spp 2 --max-spp 1 \
  --variants independent --out "$out/export" >"$out/logs/export.log" 2>&1 || die 1 "the export failed (log: $out/logs/export.log)"

for spp in "$low" "$high"; do
  echo "== wobble at $spp spp" >&2
  profile "wobble-$spp" "$wobble" run "$scene" --frames "$frame" --resolution "$resolution" --spp "$spp" \
    --set render.noise_threshold=0 --denoise off --render png --out "$out/wobble-$spp"
  echo "== Cycles at $spp spp" >&2
  profile "cycles-$spp" "$blender" -b --factory-startup --python-exit-code 1 --python "$script_dir/cycles_scene.py" \
    -- "$out/export/frame" "$out/cycles-$spp.exr" "$spp"
done

rows=""
for r in wobble cycles; do
  de=$((embree[$r-$high] - embree[$r-$low])) da=$((all[$r-$high] - all[$r-$low]))
  ((da > 0)) || die 1 "$r: no more samples at $high spp than at $low (too few samples: raise FREQ or the resolution)"
  rows+="$(awk -v r="$r" -v e="$de" -v a="$da" 'BEGIN { printf "| %s | %d | %d | %.1f%% |", r, e, a, 100 * e / a }')"$'\n'
done
{
  echo "| renderer | Embree's samples | all samples | Embree's share of path tracing |"
  echo "|---|---|---|---|"
  printf '%s' "$rows"
  echo
  echo "(perf cpu-clock at $freq Hz, $resolution, $high spp minus $low spp; $(basename "$scene") frame $frame)"
} | tee "$out/share.md"
