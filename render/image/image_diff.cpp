// idiff-style comparison of two images or image files (see image_diff.h).
#include "render/image/image_diff.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "render/image/png_io.h"

namespace wobble::render {

namespace {

std::string shape(const ImageF& i) {
  return std::to_string(i.width) + " x " + std::to_string(i.height) + ", " + std::to_string(i.channels) + " channels";
}

// idiff reads outside an image, or past its channels, as black.
float valueOrBlack(const ImageF& i, int x, int y, int c) {
  return x < i.width && y < i.height && c < i.channels ? i.at(x, y, c) : 0.0f;
}

// 8-bit codes as OpenImageIO converts them (times 1/255, not divided by 255: they differ in the last bit for some
// codes, which decides a difference right at a threshold).
ImageF unitFloat(const Image8& image) {
  ImageF out(image.width, image.height, image.channels);
  for (std::size_t i = 0; i < image.pixels.size(); ++i) out.pixels[i] = float(image.pixels[i]) * (1.0f / 255.0f);
  return out;
}

}  // namespace

DiffResult diffImages(const ImageF& a, const ImageF& b, const DiffOptions& o, ImageF* difference) {
  DiffResult r;
  const int width = std::max(a.width, b.width), height = std::max(a.height, b.height);
  const int channels = std::max(a.channels, b.channels);
  r.pixels = long(a.width) * a.height;
  if (difference) *difference = ImageF(width, height, channels);
  double total = 0;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      float pixel_error = 0;
      for (int c = 0; c < channels; ++c) {
        // In float, as idiff: a difference right at a threshold falls on the same side.
        const float e = std::fabs(valueOrBlack(a, x, y, c) - valueOrBlack(b, x, y, c));
        total += e;
        if (e > r.max_error) {
          r.max_error = e;
          r.max_x = x, r.max_y = y, r.max_channel = c;
        }
        pixel_error = std::max(pixel_error, e);
        if (difference) {
          const bool alpha = (channels == 2 && c == 1) || (channels == 4 && c == 3);
          difference->at(x, y, c) = alpha ? 1.0f : std::min(1.0f, e * o.diff_scale);
        }
      }
      if (pixel_error > o.warn) ++r.warn_pixels;
      if (pixel_error > o.fail) ++r.fail_pixels;
    }
  const double values = double(width) * height * channels;
  r.mean_error = values > 0 ? total / values : 0;

  if (r.fail_pixels <= o.allow_failures)  // first, as in idiff: no failing pixel passes, warnings or not
    r.code = DiffCode::Pass;
  else if (r.fail_pixels > o.fail_percent / 100.0 * r.pixels || r.max_error > o.hard_fail) r.code = DiffCode::Fail;
  else if (r.warn_pixels > o.warn_percent / 100.0 * r.pixels || r.max_error > o.hard_warn) r.code = DiffCode::Warning;
  else r.code = DiffCode::Pass;

  std::ostringstream m;
  if (!a.sameShape(b))
    m << "  Images differ in size: " << shape(a) << " versus " << shape(b)
      << "; compared over both, missing pixels and channels as 0\n";
  m << "  Mean error = " << r.mean_error << "\n  Max error  = " << r.max_error;
  if (r.max_error > 0) m << " @ (" << r.max_x << ", " << r.max_y << ", channel " << r.max_channel << ")";
  const auto percent = [&](long k) { return r.pixels ? 100.0 * double(k) / double(r.pixels) : 0.0; };
  m << "\n  " << r.warn_pixels << " pixels (" << percent(r.warn_pixels) << "%) over " << o.warn << "\n  "
    << r.fail_pixels << " pixels (" << percent(r.fail_pixels) << "%) over " << o.fail << "\n"
    << (r.code == DiffCode::Fail      ? "FAILURE"
        : r.code == DiffCode::Warning ? "WARNING"
                                      : "PASS");
  r.message = m.str();
  return r;
}

DiffResult diffFiles(const std::filesystem::path& a, const std::filesystem::path& b, const DiffOptions& o,
                     const std::filesystem::path& difference_png) {
  ImageF ia, ib;
  try {
    ia = unitFloat(readImage(a));
    ib = unitFloat(readImage(b));
  } catch (const std::exception& e) {
    DiffResult r;
    r.code = DiffCode::FileError;
    r.message = e.what();
    return r;
  }
  ImageF difference;
  DiffResult r = diffImages(ia, ib, o, difference_png.empty() ? nullptr : &difference);
  if (!difference_png.empty()) writePng(difference_png, toImage8(difference));
  return r;
}

}  // namespace wobble::render
