#!/usr/bin/env bash
# The README's picture: five frames of the default scene (scenes/jelly_slope.toml) side by side, written to
# docs/jelly_slope_strip.png. Run it again when the default scene's look changes, and commit the picture.
#   scripts/readme_strip.sh [OUT]      OUT: the run's folder (default out/jelly_slope, where `build/wobble run` writes)
# It runs the README's first command, `wobble run` on the default scene, with --skip-existing: frames already in OUT
# from the same build and settings are kept, so after a plain `build/wobble run` it only simulates again (a few
# seconds). Environment: WOBBLE (default build/wobble), FRAMES (the frame numbers, default "1 60 120 180 240"),
# TILE (each frame's size in the strip, default 320x180). Needs ffmpeg.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
out=${1:-out/jelly_slope}
wobble=${WOBBLE:-build/wobble}
read -r -a frames <<<"${FRAMES:-1 60 120 180 240}"
tile=${TILE:-320x180}
picture=docs/jelly_slope_strip.png

"$wobble" run scenes/jelly_slope.toml --out "$out" --skip-existing

# ffmpeg numbers the PNG sequence from 0 (frame 1 is n = 0); select those frames, shrink, tile them in one row, and
# store the strip with a 256-colour palette to keep the file small.
select=""
for f in "${frames[@]}"; do
  [ -f "$out/frames/jelly_slope_$(printf %04d "$f").png" ] || { echo "readme_strip: frame $f missing in $out/frames" >&2; exit 1; }
  select+="${select:++}eq(n\,$((f - 1)))"
done
ffmpeg -v error -y -start_number 1 -i "$out/frames/jelly_slope_%04d.png" -filter_complex \
  "select='$select',scale=${tile/x/:}:flags=lanczos,tile=${#frames[@]}x1:padding=4:color=white,split[a][b];[a]palettegen=max_colors=256[p];[b][p]paletteuse=dither=sierra2_4a" \
  -frames:v 1 -update 1 "$picture"
echo "readme_strip: $picture ($(stat -c %s "$picture") bytes)"
