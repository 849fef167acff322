// idiff-style comparison of two images or image files (see image_diff.h).
#include "image_diff.h"

#include <cmath>
#include <sstream>

#include "png_io.h"

namespace wobble::render {

namespace {

std::string shape(const ImageF& i) {
  return std::to_string(i.width) + "x" + std::to_string(i.height) + "x" + std::to_string(i.channels);
}

}  // namespace

DiffResult diffImages(const ImageF& a, const ImageF& b, const DiffOptions& o, ImageF* difference) {
  DiffResult r;
  if (!a.sameShape(b)) {
    r.code = DiffCode::DifferentSize;
    r.message = "Images do not match in size: (" + shape(a) + ") versus (" + shape(b) + ")";
    return r;
  }
  r.pixels = long(a.width) * a.height;
  if (difference) *difference = ImageF(a.width, a.height, a.channels);
  double total = 0;
  for (int y = 0; y < a.height; ++y)
    for (int x = 0; x < a.width; ++x) {
      double pixel_error = 0;
      for (int c = 0; c < a.channels; ++c) {
        const double e = std::fabs(double(a.at(x, y, c)) - double(b.at(x, y, c)));
        total += e;
        if (e > r.max_error) {
          r.max_error = e;
          r.max_x = x, r.max_y = y, r.max_channel = c;
        }
        pixel_error = std::max(pixel_error, e);
        if (difference) {
          const bool alpha = (a.channels == 2 && c == 1) || (a.channels == 4 && c == 3);
          difference->at(x, y, c) = alpha ? 1.0f : std::min(1.0f, static_cast<float>(e) * o.diff_scale);
        }
      }
      if (pixel_error > o.warn) ++r.warn_pixels;
      if (pixel_error > o.fail) ++r.fail_pixels;
    }
  r.mean_error = r.pixels ? total / (double(r.pixels) * a.channels) : 0;

  if (r.fail_pixels > o.fail_percent / 100.0 * r.pixels || r.max_error > o.hard_fail)
    r.code = DiffCode::Fail;
  else if (r.warn_pixels > o.warn_percent / 100.0 * r.pixels || r.max_error > o.hard_warn)
    r.code = DiffCode::Warning;
  else
    r.code = DiffCode::Pass;

  std::ostringstream m;
  m << "  Mean error = " << r.mean_error << "\n  Max error  = " << r.max_error;
  if (r.max_error > 0) m << " @ (" << r.max_x << ", " << r.max_y << ", channel " << r.max_channel << ")";
  const auto percent = [&](long k) { return r.pixels ? 100.0 * double(k) / double(r.pixels) : 0.0; };
  m << "\n  " << r.warn_pixels << " pixels (" << percent(r.warn_pixels) << "%) over " << o.warn << "\n  "
    << r.fail_pixels << " pixels (" << percent(r.fail_pixels) << "%) over " << o.fail << "\n"
    << (r.code == DiffCode::Fail ? "FAILURE" : r.code == DiffCode::Warning ? "WARNING" : "PASS");
  r.message = m.str();
  return r;
}

DiffResult diffFiles(const std::filesystem::path& a, const std::filesystem::path& b, const DiffOptions& o,
                     const std::filesystem::path& difference_png) {
  ImageF ia, ib;
  try {
    ia = toFloat(readImage(a));
    ib = toFloat(readImage(b));
  } catch (const std::exception& e) {
    DiffResult r;
    r.code = DiffCode::FileError;
    r.message = e.what();
    return r;
  }
  ImageF difference;
  DiffResult r = diffImages(ia, ib, o, difference_png.empty() ? nullptr : &difference);
  if (!difference_png.empty() && r.code != DiffCode::DifferentSize) writePng(difference_png, toImage8(difference));
  return r;
}

}  // namespace wobble::render
