// cie76: the CIE76 colour difference (image/color_difference.h) of two display images, e.g. wobble's converged
// frame and Cycles' render of the same frame from `wobble blend`'s .blend (bench/blend_compare.sh).
//
//   cie76 A.png B.png
//
// Prints key=value lines: mean, p95 and max Delta E*ab over the pixels.
// Exit status: 0 done; 2 bad input (unreadable file, different sizes, not RGB).
#include <cstdio>
#include <exception>

#include "image/color_difference.h"
#include "image/png_io.h"

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: cie76 A.png B.png\n");
    return 2;
  }
  try {
    const auto d = wobble::image::cie76(wobble::image::readImage(argv[1]), wobble::image::readImage(argv[2]));
    std::printf("mean=%.3f\np95=%.3f\nmax=%.3f\n", d.mean, d.p95, d.max);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "cie76: %s\n", e.what());
    return 2;
  }
  return 0;
}
