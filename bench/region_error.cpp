// region_error: RMSE of a display image against a reference inside and outside a region given by a mask image
// (bench/region_noise.sh: wobble's and Cycles' default pictures against their own converged ones, in the jelly and
// in the cloth's shadow).
//
//   region_error IMAGE.png REFERENCE.png MASK.png [--region body|shadow] [--dark L]
//
// MASK.png is the same frame with the region's body drawn in pure green (a diffuse material with a green texture):
//   body    the pixels where that body shows: green clearly dominates (G >= 24 and R, B at most G / 3)
//   shadow  the pixels where it does not and the reference's luminance is below L (default 0.35 of full scale): the
//           shade the body casts on what lies under it (the sky and sunlit surfaces are brighter)
// RMSE over R, G and B of the 8-bit codes / 255, as docs/rendering.md measures frames. Prints key=value lines:
// pixels_in, rmse_in, rmse_out, share_over_0.05 (the region's pixels with a channel off by more than 0.05).
// Exit status: 0 done; 2 bad input (unreadable file, different sizes, not RGB, empty region, bad option).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <string>

#include "image/png_io.h"

namespace {

int fail(const std::string& message) {
  std::fprintf(stderr, "region_error: %s\n", message.c_str());
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 4) return fail("usage: region_error IMAGE.png REFERENCE.png MASK.png [--region body|shadow] [--dark L]");
  std::string region = "body";
  double dark = 0.35;
  for (int i = 4; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--region" && i + 1 < argc &&
        (std::strcmp(argv[i + 1], "body") == 0 || std::strcmp(argv[i + 1], "shadow") == 0))
      region = argv[++i];
    else if (a == "--dark" && i + 1 < argc && (dark = std::atof(argv[i + 1])) > 0 && dark <= 1) ++i;
    else return fail(a + ": unknown or bad option (--region body|shadow, --dark L in (0, 1])");
  }
  try {
    using wobble::image::readImage;
    const auto image = readImage(argv[1]), reference = readImage(argv[2]), mask = readImage(argv[3]);
    if (!image.sameShape(reference) || image.width != mask.width || image.height != mask.height)
      return fail("the three images differ in size");
    if (image.channels < 3 || mask.channels < 3) return fail("need RGB images");
    double in_sq = 0, out_sq = 0;
    std::size_t in = 0, out = 0, over = 0;
    for (int y = 0; y < image.height; ++y)
      for (int x = 0; x < image.width; ++x) {
        const int r = mask.at(x, y, 0), g = mask.at(x, y, 1), b = mask.at(x, y, 2);
        const bool body = g >= 24 && 3 * r <= g && 3 * b <= g;
        bool inside = body;
        if (region == "shadow") {
          const double l =
              (0.2126 * reference.at(x, y, 0) + 0.7152 * reference.at(x, y, 1) + 0.0722 * reference.at(x, y, 2)) /
              255.0;
          inside = !body && l < dark;
        }
        double sq = 0, worst = 0;
        for (int c = 0; c < 3; ++c) {
          const double d = (double(image.at(x, y, c)) - double(reference.at(x, y, c))) / 255.0;
          sq += d * d, worst = std::max(worst, std::abs(d));
        }
        if (inside) in_sq += sq, ++in, over += worst > 0.05;
        else out_sq += sq, ++out;
      }
    if (in == 0) return fail("the region is empty (no green in the mask?)");
    std::printf("pixels_in=%zu\nrmse_in=%.4f\nrmse_out=%.4f\nshare_over_0.05=%.4f\n", in, std::sqrt(in_sq / (3.0 * in)),
                out ? std::sqrt(out_sq / (3.0 * out)) : 0.0, double(over) / double(in));
  } catch (const std::exception& e) {
    return fail(e.what());
  }
  return 0;
}
