#!/usr/bin/env bash
# One setup step for a Debian 12 machine: installs the Debian packages wobble needs that are missing,
# then configures and builds the release tree in build/. Idempotent: quick when everything is there.
# `./setup.sh tests` (the README's test command, and CI's) adds Blender, which only the Blender tests need (about
# 115 MB to fetch with its libraries, 450 MB installed); without it they skip, saying so (tests/app/blender_test.cpp).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")"

packages=(
  cmake ninja-build g++ pkg-config                      # build tools
  libeigen3-dev libtbb-dev                              # simulator numerics, threads
  libassimp-dev                                         # OBJ export/import
  libembree-dev libstb-dev libopenexr-dev libpng-dev   # renderer, images
  libfontconfig-dev fonts-dejavu-core                   # labels of `wobble compare` (stb_truetype draws them)
  libtomlplusplus-dev libcli11-dev nlohmann-json3-dev   # scene files, command line, run.json
  libxxhash-dev                                         # content hashes (frames' settings, study caches)
  libdeflate-dev                                        # PNG frames' image data (twice zlib's speed)
  libgtest-dev libgmock-dev libbenchmark-dev            # tests, benchmarks
  ffmpeg gnuplot-nox                                    # video and plots (external programs)
  openimageio-tools                                     # idiff: wobble diff's conformance test (~60 MB to fetch)
  parallel                                              # GNU parallel: the split-render test (docs/farm-rendering.md)
)
case "${1:-}" in
  "") ;;
  tests) packages+=(blender) ;;                         # wobble blend's tests (tests/app/blender_test.cpp)
  *) echo "setup: unknown argument '$1' (allowed: none, or 'tests' to add Blender for the whole test suite)" >&2; exit 2 ;;
esac

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed' || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "setup: installing ${missing[*]}" >&2
  sudo=""; [ "$(id -u)" -eq 0 ] || sudo="sudo"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

[ -f build/CMakeCache.txt ] || cmake --preset release >/dev/null
cmake --build --preset release
