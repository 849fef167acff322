#!/usr/bin/env bash
# cycles_compare.sh: wobble's path tracer against Blender Cycles on the same frame, each image measured against its
# own renderer's converged picture (the GitHub issue's yardstick: "a picture with no more error than Cycles' 16-spp
# one in at most half of Cycles' time on the same machine").
#
#   bench/cycles_compare.sh SCENE FRAME RESOLUTION [SPP_LIST] [--out DIR]
#   bench/cycles_compare.sh scenes/jelly_slope.toml 150 640x360            # Cycles at 4, 16 and 64 spp
#   REF_SPP=64 bench/cycles_compare.sh scenes/jelly_slope.toml 30 160x90 "4 16"   # a quick check
#
# Steps:
#   1. `wobble study render SCENE --frame FRAME --resolution RESOLUTION --reference-spp REF_SPP --out OUT/wobble`:
#      wobble's reference (two halves, cached by the study), its sweep (OUT/wobble/render.csv) and the frame exported
#      for other renderers (OUT/wobble/frame: scene.obj, scene.json, textures).
#   2. Cycles' reference: bench/cycles_scene.py at REF_SPP/2 spp twice, with two seeds (as wobble's two halves), kept
#      in OUT/cycles and reused while the exported frame, REF_SPP, the bounces and cycles_scene.py are unchanged.
#   3. Cycles at every spp of SPP_LIST (16 is always included), seed SEED; time = Cycles' path tracing as Blender
#      reports it (from its first sample to the end; scene synchronisation, BVH build and the world's importance map
#      excluded, as the study times render() on a built scene), the minimum of REPEATS renders.
#   4. exr_error (bench/exr_error.cpp): each Cycles image against the mean of Cycles' reference halves, with the
#      scene's exposure, exactly as the study measures wobble's images against wobble's reference.
#   5. A Markdown table (stdout and OUT/compare.md): Cycles per spp; the cheapest wobble point (any variant of the
#      study, by time) whose RMSE is at most Cycles' 16-spp RMSE; and the time ratio wobble / Cycles-16.
#      OUT/cycles.csv holds the Cycles figures; OUT/cycles/*.png the Cycles images through wobble's tone map.
#
# Environment (all optional):
#   OUT          output folder (default out/cycles-compare-<scene>-<frame>; --out DIR too)
#   REF_SPP      reference samples per pixel, both renderers (default 1024; even)
#   MAX_SPP      the study's largest spp (default 64)       VARIANTS  the study's variants, comma-separated (default all)
#   REPEATS      timed renders per point, both renderers (default 1)
#   SEED         Cycles' seed for the measured images (default 1; the reference halves use 1000001 and 2000001)
#   THREADS      Cycles' threads (default 0: all cores, as wobble)
#   BUILD_DIR    where wobble and exr_error are (default <repo>/build); WOBBLE, EXR_ERROR override each
#   BLENDER      the Blender program (default blender; Cycles 3.4 checked)
#
# Matching (bench/cycles_scene.py has the details): Y-up converted to Blender's Z-up as its OBJ importer does; the
# camera's vertical fov; Lambertian Diffuse BSDF for plain surfaces; the coat as Diffuse x (1 - coat F) + GGX Glossy
# x coat F (Schlick, roughness sqrt(alpha)); gelatine as a Glass BSDF mixed with its Diffuse print over Volume
# Absorption and Scatter with wobble's coefficients (app/blender/cycles_nodes.py, which `wobble blend` uses too); sun
# strength = irradiance, angle = 2 x radius, unseen by the camera; the sky as a world shader, or a scene's environment
# map (render.environment) as an Environment Texture of the same file (cycles_nodes.py: Closest, its rotation and
# strength); wobble's light paths (sky light at vertices 0..B-1, sun at 0..B, refractions not counted); box pixel
# filter, no clamping, no light threshold, no glossy filter, caustics on, no denoising, no adaptive sampling.
# Known mismatches:
#   - textures: Cycles reads the baked 1024 x 1024 8-bit PNG (bilinear, no mip-maps), wobble evaluates the
#     procedural texture filtered over the pixel's footprint: the converged floors differ by about 1% (wood) and
#     Cycles gets texture aliasing noise that wobble filters away (a wobble feature, measured as such);
#   - analytic spheres become 128 x 64 UV spheres, smooth shaded; area lights (none in the shipped scenes) become
#     emitting meshes that stop BSDF rays;
#   - each renderer keeps its own sampling: Cycles picks one light (sun or sky) per vertex, uses Russian roulette,
#     progressive multi-jitter samples and importance-samples the sky; wobble samples every sun at every vertex
#     (the sky only in its +sky variants), Sobol samples, no roulette.
#
# Exit status: 0 done; 1 a step failed (its log is named); 2 bad arguments or a missing wobble/exr_error build;
# 3 Blender is missing.
set -euo pipefail

script_dir="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
repo="$(cd "$script_dir/.." && pwd)"

usage() {
  sed -n '2,/^set -euo/p' "${BASH_SOURCE[0]}" | sed -e '/^set -euo/d' -e 's/^# \{0,1\}//' >&2
}
die() {  # die CODE MESSAGE
  echo "cycles_compare.sh: $2" >&2
  exit "$1"
}
is_uint() { [[ "$1" =~ ^[0-9]+$ ]]; }

# ------------------------------------------------------------------------------------------------ arguments
out="${OUT:-}"
positional=()
while (($#)); do
  case "$1" in
    -h | --help) usage; exit 0 ;;
    --out) (($# >= 2)) || die 2 "--out needs a folder"; out="$2"; shift 2 ;;
    --out=*) out="${1#--out=}"; shift ;;
    -*) die 2 "$1: unknown option (see --help)" ;;
    *) positional+=("$1"); shift ;;
  esac
done
((${#positional[@]} >= 3 && ${#positional[@]} <= 4)) || { usage; die 2 "expected SCENE FRAME RESOLUTION [SPP_LIST]"; }
scene="${positional[0]}"
frame="${positional[1]}"
resolution="${positional[2]}"
spp_list="${positional[3]:-4 16 64}"

[[ -f "$scene" ]] || die 2 "$scene: no such scene file"
is_uint "$frame" && ((frame >= 1)) || die 2 "FRAME $frame: must be a whole number >= 1"
[[ "$resolution" =~ ^[1-9][0-9]*x[1-9][0-9]*$ ]] || die 2 "RESOLUTION $resolution: must be WxH, e.g. 640x360"
ref_spp="${REF_SPP:-1024}"
is_uint "$ref_spp" && ((ref_spp >= 2 && ref_spp % 2 == 0)) || die 2 "REF_SPP $ref_spp: must be even, >= 2"
max_spp="${MAX_SPP:-64}"
is_uint "$max_spp" && ((max_spp >= 1)) || die 2 "MAX_SPP $max_spp: must be a whole number >= 1"
repeats="${REPEATS:-1}"
is_uint "$repeats" && ((repeats >= 1)) || die 2 "REPEATS $repeats: must be a whole number >= 1"
seed="${SEED:-1}"
is_uint "$seed" || die 2 "SEED $seed: must be a whole number"
threads="${THREADS:-0}"
is_uint "$threads" || die 2 "THREADS $threads: must be a whole number (0: all cores)"
spps=()
for s in $spp_list; do
  is_uint "$s" && ((s >= 1)) || die 2 "SPP_LIST: $s is not a whole number >= 1"
  spps+=("$s")
done
((${#spps[@]})) || die 2 "SPP_LIST is empty"
[[ " ${spps[*]} " == *" 16 "* ]] || { spps+=(16); echo "cycles_compare.sh: 16 spp added to SPP_LIST (the goal's yardstick)" >&2; }
mapfile -t spps < <(printf '%s\n' "${spps[@]}" | sort -n -u)

scene_name="$(basename "$scene" .toml)"
out="${out:-out/cycles-compare-$scene_name-$frame}"
build_dir="${BUILD_DIR:-$repo/build}"
wobble="${WOBBLE:-$build_dir/wobble}"
exr_error="${EXR_ERROR:-$build_dir/exr_error}"
blender="${BLENDER:-blender}"

# ------------------------------------------------------------------------------------------------ tools
command -v "$blender" >/dev/null 2>&1 ||
  die 3 "Blender is missing: '$blender' is not on PATH (install it, e.g. 'apt-get install blender' on Debian 12, which gives Cycles 3.4, or set BLENDER=/path/to/blender)"
[[ -x "$wobble" ]] || die 2 "$wobble: not built (cmake --build $build_dir --target wobble; or set BUILD_DIR / WOBBLE)"
[[ -x "$exr_error" ]] || die 2 "$exr_error: not built (cmake --build $build_dir --target exr_error; or set BUILD_DIR / EXR_ERROR)"
command -v python3 >/dev/null 2>&1 || die 2 "python3 is needed (scene settings and the table)"
blender_version="$("$blender" --version 2>/dev/null | sed -n '1p' || true)"
[[ "$blender_version" == Blender* ]] || die 3 "'$blender --version' does not answer as Blender: is it installed correctly?"

mkdir -p "$out/cycles/logs" || die 1 "$out: cannot create the output folder"
out="$(cd "$out" && pwd)"
step() { echo "== $*" >&2; }

# The scene's render settings that matter here: bounces (default 2) and exposure (default -0.5).
read -r bounces exposure < <(python3 - "$scene" <<'EOF'
import sys, tomllib
try:
    with open(sys.argv[1], "rb") as f:
        r = tomllib.load(f).get("render", {})
except Exception as e:  # wobble itself reports bad scenes; fall back to the defaults here
    r = {}
print(int(r.get("bounces", 2)), float(r.get("exposure", -0.5)))
EOF
) || die 1 "cannot read $scene's [render] settings"

# ------------------------------------------------------------------------------------------------ 1. wobble
study="$out/wobble"
study_log="$out/wobble-study.log"
study_args=(study render "$scene" --frame "$frame" --resolution "$resolution" --reference-spp "$ref_spp"
            --max-spp "$max_spp" --repeats "$repeats" --out "$study")
[[ -n "${VARIANTS:-}" ]] && study_args+=(--variants "$VARIANTS")
step "wobble ${study_args[*]} (log: $study_log)"
if ! "$wobble" "${study_args[@]}" >"$study_log" 2>&1; then
  tail -n 20 "$study_log" >&2
  die 1 "wobble study render failed (log: $study_log)"
fi
frame_dir="$study/frame"
[[ -f "$frame_dir/scene.json" && -f "$frame_dir/scene.obj" ]] || die 1 "$frame_dir: the study exported no frame"
[[ -f "$study/render.csv" ]] || die 1 "$study/render.csv: missing after the study"

# ------------------------------------------------------------------------------------------------ 2-3. Cycles
# cycles_render NAME SPP SEED: renders OUT/cycles/NAME.exr (REPEATS times when timing), prints the fastest
# "render_seconds sync_seconds total_seconds".
cycles_render() {
  local name="$1" spp="$2" seed="$3" times="$4" best="" k log line
  for ((k = 1; k <= times; k++)); do
    log="$out/cycles/logs/$name.log"
    if ! "$blender" -b --factory-startup --python-exit-code 1 --python "$script_dir/cycles_scene.py" -- "$frame_dir" \
        "$out/cycles/$name.exr" "$spp" --seed "$seed" --threads "$threads" --bounces "$bounces" >"$log" 2>&1; then
      grep -v '^Fra:' "$log" | tail -n 15 >&2
      die 1 "Cycles failed on $name (log: $log)"
    fi
    line="$(python3 - "$log" <<'EOF'
import re, sys
text = open(sys.argv[1], errors="replace").read()
v = {k: re.findall(r"^%s=([0-9.eE+-]+)$" % k, text, re.M) for k in ("render_seconds", "sync_seconds", "total_render_seconds")}
if not all(v.values()):
    sys.exit(1)
print(v["render_seconds"][-1], v["sync_seconds"][-1], v["total_render_seconds"][-1])
EOF
)" || { grep -v '^Fra:' "$log" | tail -n 15 >&2; die 1 "no render_seconds in $log"; }
    if [[ -z "$best" ]] || python3 -c "import sys; sys.exit(not float('${line%% *}') < float('${best%% *}'))"; then
      best="$line"
    fi
  done
  echo "$best"
}

# The reference cache key: the exported frame, the reference settings and the script that builds the scene.
key="$( {
  cat "$frame_dir/scene.json" "$frame_dir/scene.obj"
  find "$frame_dir" -maxdepth 1 -name '*.png' -print0 | sort -z | xargs -0 -r cat
  cat "$script_dir/cycles_scene.py" "$repo/app/blender/cycles_nodes.py"
  python3 -c 'import json, sys; e = json.load(open(sys.argv[1])).get("environment"); print(e["file"] if e else "")' \
    "$frame_dir/scene.json" | xargs -r cat  # an environment map: its pixels
  echo "ref_spp=$ref_spp bounces=$bounces blender=$blender_version"
} | sha256sum | cut -d' ' -f1)"
ref_a="$out/cycles/reference_a.exr"
ref_b="$out/cycles/reference_b.exr"
ref_times="$out/cycles/reference.times"
if [[ -f "$ref_a" && -f "$ref_b" && -f "$out/cycles/reference.key" && "$(cat "$out/cycles/reference.key")" == "$key" ]]; then
  step "Cycles reference: cached ($ref_a, $ref_b)"
  ref_cached=1
else
  rm -f "$out/cycles/reference.key"
  step "Cycles reference: 2 x $((ref_spp / 2)) spp (log: $out/cycles/logs/reference_*.log)"
  ta="$(cycles_render reference_a $((ref_spp / 2)) 1000001 1)" || exit $?
  tb="$(cycles_render reference_b $((ref_spp / 2)) 2000001 1)" || exit $?
  echo "$ta $tb" >"$ref_times"
  echo "$key" >"$out/cycles/reference.key"
  ref_cached=0
fi

cycles_csv="$out/cycles.csv"
echo "spp,rmse,relmse,worst_tile_rmse,worst_tile_relmse,render_seconds,sync_seconds,total_render_seconds" >"$cycles_csv.tmp"
ref_line=""
for spp in "${spps[@]}"; do
  step "Cycles: $spp spp (log: $out/cycles/logs/cycles_$spp.log)"
  times="$(cycles_render "cycles_$spp" "$spp" "$seed" "$repeats")" || exit $?
  read -r t_render t_sync t_total <<<"$times"
  errors="$("$exr_error" "$out/cycles/cycles_$spp.exr" "$ref_a" "$ref_b" --exposure "$exposure" \
            --png "$out/cycles/cycles_$spp.png" 2>"$out/cycles/logs/exr_error_$spp.log")" ||
    { cat "$out/cycles/logs/exr_error_$spp.log" >&2; die 1 "exr_error failed on cycles_$spp.exr"; }
  get() { sed -n "s/^$1=//p" <<<"$errors"; }
  echo "$spp,$(get rmse),$(get relmse),$(get worst_tile_rmse),$(get worst_tile_relmse),$t_render,$t_sync,$t_total" >>"$cycles_csv.tmp"
  ref_line="$(get half_rmse)"
done
mv "$cycles_csv.tmp" "$cycles_csv"
"$exr_error" "$ref_a" "$ref_b" --exposure "$exposure" --png "$out/cycles/reference.png" >/dev/null
# How far the two renderers' converged pictures are from each other (scene matching, not noise): Cycles' reference
# half a against wobble's reference (the mean of its halves). The study keeps one reference pair per settings in its
# folder and does not name the one it used: take the pair whose own RMSE is the study's reference_rmse.
study_floor="$(python3 -c 'import csv,sys; print(next(csv.DictReader(open(sys.argv[1])))["reference_rmse"])' "$study/render.csv" 2>/dev/null || echo nan)"
cross=""
best_gap=""
for wobble_ref in "$study"/reference-*.pfm; do
  [[ -f "$wobble_ref" && "$wobble_ref" != *-b.pfm && -f "${wobble_ref%.pfm}-b.pfm" ]] || continue
  pair="$("$exr_error" "$ref_a" "$wobble_ref" "${wobble_ref%.pfm}-b.pfm" --exposure "$exposure" 2>/dev/null)" || continue
  gap="$(python3 -c 'import sys; print(abs(float(sys.argv[1]) / 2 - float(sys.argv[2])))' \
           "$(sed -n 's/^half_rmse=//p' <<<"$pair")" "$study_floor" 2>/dev/null || echo inf)"
  if [[ -z "$best_gap" ]] || python3 -c "import sys; sys.exit(not float('$gap') < float('$best_gap'))"; then
    best_gap="$gap"
    cross="$pair"
  fi
done

# ------------------------------------------------------------------------------------------------ 5. table
python3 - "$study/render.csv" "$cycles_csv" "$out/compare.md" "$scene" "$frame" "$resolution" "$ref_spp" \
  "$bounces" "$exposure" "$blender_version" "$ref_line" "$cross" "$threads" "$repeats" "$ref_cached" <<'EOF'
import csv, math, sys
(study_csv, cycles_csv, md_path, scene, frame, resolution, ref_spp, bounces, exposure, blender_version,
 cycles_half_rmse, cross, threads, repeats, ref_cached) = sys.argv[1:]

def f(x, digits=4):
    return "%.*g" % (digits, x) if isinstance(x, float) and math.isfinite(x) else str(x)

wob = list(csv.DictReader(open(study_csv)))
cyc = list(csv.DictReader(open(cycles_csv)))
for r in wob + cyc:
    for k, v in list(r.items()):
        try:
            r[k] = float(v)
        except (TypeError, ValueError):
            pass
c16 = next(r for r in cyc if int(r["spp"]) == 16)
lines = []
out = lines.append
out("# wobble vs Blender Cycles: %s, frame %s, %s" % (scene, frame, resolution))
out("")
out("Each image against its own renderer's reference (%s spp, two halves with independent seeds), RMSE of display "
    "values through wobble's tone map (exposure %s) and its worst 32 x 32 tile (render/image_error.h). "
    "%s bounces. Cycles: %s, CPU (%s); time = path tracing as Blender reports it (10 ms resolution), "
    "scene synchronisation excluded; wobble: the study's render (+ denoise) time. Minimum of %s run(s)."
    % (ref_spp, exposure, bounces, blender_version, ("%s threads" % threads) if threads != "0" else "all cores", repeats))
out("")
out("Cycles settings: Diffuse + GGX Glossy weighted by Schlick's Fresnel for the coat, sun strength = irradiance, "
    "sky as a world shader, no sky light at the last vertex (as wobble), box pixel filter, no clamping, no denoising, "
    "no adaptive sampling (bench/cycles_scene.py).")
out("")
ref_floor_w = wob[0].get("reference_rmse", float("nan")) if wob else float("nan")
try:
    ref_floor_c = float(cycles_half_rmse) / 2
except ValueError:
    ref_floor_c = float("nan")
out("References' own RMSE (about half the RMSE between their halves): wobble %s, Cycles %s%s."
    % (f(ref_floor_w), f(ref_floor_c), " (Cycles' reference read from the cache)" if ref_cached == "1" else ""))
if cross:
    kv = dict(l.split("=", 1) for l in cross.split() if "=" in l)
    out("Scene match, Cycles' reference (half a) against wobble's: RMSE %s (worst tile %s); mean linear colour Cycles %s, "
        "wobble %s." % (kv.get("rmse"), kv.get("worst_tile_rmse"), kv.get("image_mean"), kv.get("reference_mean")))
out("")
out("| renderer | setting | spp | RMSE | worst-tile RMSE | time (s) | note |")
out("|---|---|---|---|---|---|---|")
for r in cyc:
    out("| Cycles | path tracing | %d | %s | %s | %s | + %s s sync (total %s s) |"
        % (int(r["spp"]), f(r["rmse"]), f(r["worst_tile_rmse"]), f(r["render_seconds"], 3),
           f(r["sync_seconds"], 3), f(r["total_render_seconds"], 3)))
target = c16["rmse"]
ok = [r for r in wob if isinstance(r["rmse"], float) and r["rmse"] <= target]
best = min(ok, key=lambda r: r["seconds"]) if ok else None
if best:
    spp = f(best["mean_spp"], 3) + ("" if best.get("threshold", 0) in (0, 0.0) else " (threshold %s)" % f(best["threshold"], 3))
    out("| wobble | %s | %s | %s | %s | %s | cheapest study point with RMSE <= Cycles-16's |"
        % (best["variant"], spp, f(best["rmse"]), f(best["worst_tile_rmse"]), f(best["seconds"], 3)))
    plain = [r for r in ok if "denoise" not in r["variant"]]
    if plain and min(plain, key=lambda r: r["seconds"]) is not best:
        p = min(plain, key=lambda r: r["seconds"])
        out("| wobble | %s | %s | %s | %s | %s | the same, without denoising (for reference) |"
            % (p["variant"], f(p["mean_spp"], 3), f(p["rmse"]), f(p["worst_tile_rmse"]), f(p["seconds"], 3)))
    ratio = best["seconds"] / c16["render_seconds"] if c16["render_seconds"] > 0 else float("inf")
    out("")
    out("Time ratio wobble / Cycles-16: **%s** (goal: at most 0.5; %s)." % (f(ratio, 3), "met" if ratio <= 0.5 else "not met"))
else:
    close = min(wob, key=lambda r: r["rmse"]) if wob else None
    out("")
    out("No wobble point of the study reaches Cycles' 16-spp RMSE %s%s: raise MAX_SPP." % (
        f(target), "" if not close else " (closest: %s at %s spp, RMSE %s, %s s)" % (
            close["variant"], f(close["mean_spp"], 3), f(close["rmse"]), f(close["seconds"], 3))))
text = "\n".join(lines) + "\n"
open(md_path, "w").write(text)
sys.stdout.write(text)
EOF
step "wrote $out/compare.md, $cycles_csv; images: $out/cycles/*.png, $study/images, $study/reference.png"
