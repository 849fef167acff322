// idiff-style comparison of two images or image files (see image_diff.h).
#include "image/image_diff.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>

#include "image/png_io.h"
#include "image/yee.h"

namespace wobble::image {

namespace {

std::string shape(const ImageF& i) {
  return std::to_string(i.width) + " x " + std::to_string(i.height) + ", " + std::to_string(i.channels) + " channels";
}

// idiff reads outside an image, or past its channels, as black.
float valueOrBlack(const ImageF& i, int x, int y, int c) {
  return x < i.width && y < i.height && c < i.channels ? i.at(x, y, c) : 0.0f;
}

std::string printf1(const char* format, double value) {
  char text[64];
  std::snprintf(text, sizeof text, format, value);
  return text;
}

// As idiff prints doubles: "nan", "inf", or %g.
std::string safeDouble(double v) { return std::isnan(v) ? "nan" : std::isinf(v) ? "inf" : printf1("%g", v); }

// As idiff prints pixel values ({fmt}'s shortest representation that reads back as the same float).
std::string shortest(float v) {
  if (std::isnan(v)) return "nan";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  char text[32];
  const auto end = std::to_chars(text, text + sizeof text, v).ptr;
  return std::string(text, end);
}

std::string channelName(int c, const std::vector<std::string>& a, const std::vector<std::string>& b) {
  if (c < int(a.size())) return a[std::size_t(c)];
  if (c < int(b.size())) return b[std::size_t(c)];
  return "channel " + std::to_string(c);
}

}  // namespace

const char* verdict(DiffCode code) {
  switch (code) {
    case DiffCode::Pass:
      return "PASS";
    case DiffCode::Warning:
      return "WARNING";
    case DiffCode::Fail:
      return "FAILURE";
    default:
      return "FILE ERROR";
  }
}

DiffResult diffImages(const ImageF& a, const ImageF& b, const DiffOptions& o, ImageF* difference,
                      const std::vector<std::string>& names_a, const std::vector<std::string>& names_b,
                      ImageF* error_map) {
  DiffResult r;
  const int width = std::max(a.width, b.width), height = std::max(a.height, b.height);
  const int channels = std::max(a.channels, b.channels);
  r.pixels = std::max(1L, long(a.width) * a.height);  // idiff: 1 for an empty image (no division by 0)
  if (difference) *difference = ImageF(width, height, channels);
  if (error_map) *error_map = ImageF(width, height, 1);
  double total = 0, total_squared = 0;
  float max_value = 1;  // the peak of the PSNR: 1, or the largest magnitude in either image
  float max_error = 0;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      bool warned = false, failed = false;
      float pixel_error = 0;
      for (int c = 0; c < channels; ++c) {
        const float va = valueOrBlack(a, x, y, c), vb = valueOrBlack(b, x, y, c);
        if (difference) {
          const bool alpha = (channels == 2 && c == 1) || (channels == 4 && c == 3);
          const float e = std::fabs(va - vb);
          difference->at(x, y, c) = alpha ? 1.0f : std::isfinite(e) ? std::min(1.0f, e * o.diff_scale) : 1.0f;
        }
        if (!std::isfinite(va) || !std::isfinite(vb)) {
          if (std::isnan(va) == std::isnan(vb) && std::isinf(va) == std::isinf(vb)) continue;  // NaN = NaN, inf = inf
          pixel_error = 1;                 // shown at full scale in the error map
          if (std::isfinite(max_error)) {  // non-finite errors trump finite ones, and this one is not counted
            max_error = std::numeric_limits<float>::infinity();
            r.max_x = x, r.max_y = y, r.max_channel = c;
            continue;
          }
        }
        max_value = std::max(max_value, std::max(std::fabs(va), std::fabs(vb)));
        // In float, as idiff: a difference right at a threshold falls on the same side.
        const double e = std::fabs(va - vb);
        const double mean_abs = 0.5 * (std::fabs(va) + std::fabs(vb));
        const double relative = mean_abs > 0 ? e / mean_abs : 0.0;  // idiff's relative test
        total += e;
        total_squared += e * e;
        if (!(e <= max_error)) {
          max_error = float(e);
          r.max_x = x, r.max_y = y, r.max_channel = c;
        }
        if (std::isfinite(e)) pixel_error = std::max(pixel_error, float(e));
        if (!warned && !(e <= o.warn) && !(relative <= o.warn_relative)) ++r.warn_pixels, warned = true;
        if (!failed && !(e <= o.fail) && !(relative <= o.fail_relative)) ++r.fail_pixels, failed = true;
      }
      if (error_map) error_map->at(x, y) = pixel_error;
    }
  const double values = double(width) * height * channels;
  r.max_error = max_error;
  r.mean_error = total / values;
  r.rms_error = std::sqrt(total_squared / values);
  r.psnr = 20.0 * std::log10(max_value / r.rms_error);
  if (o.perceptual) r.perceptual_failures = yeeFailures(a, b);

  const double allowed_failures = o.fail_percent / 100.0 * double(r.pixels);
  if (r.fail_pixels <= o.allow_failures)  // first, as in idiff: no failing pixel passes, warnings or not
    r.code = DiffCode::Pass;
  else if (double(r.fail_pixels) > allowed_failures || max_error > o.hard_fail ||
           double(r.perceptual_failures) > allowed_failures)
    r.code = DiffCode::Fail;
  else if (double(r.warn_pixels) > o.warn_percent / 100.0 * double(r.pixels) || max_error > o.hard_warn)
    r.code = DiffCode::Warning;
  else r.code = DiffCode::Pass;

  std::string m;
  if (!a.sameShape(b))
    m += "  Images differ in size: " + shape(a) + " versus " + shape(b) +
         "; compared over both, missing pixels and channels as 0\n";
  m += "  Mean error = " + safeDouble(r.mean_error) + "\n  RMS error = " + safeDouble(r.rms_error) +
       "\n  Peak SNR = " + safeDouble(r.psnr) + "\n  Max error  = " + printf1("%g", max_error);
  if (max_error != 0) {
    m += " @ (" + std::to_string(r.max_x) + ", " + std::to_string(r.max_y) + ", " +
         channelName(r.max_channel, names_a, names_b) + ")  values are ";
    for (int c = 0; c < a.channels; ++c) m += (c ? ", " : "") + shortest(valueOrBlack(a, r.max_x, r.max_y, c));
    m += " vs ";
    for (int c = 0; c < b.channels; ++c) m += (c ? ", " : "") + shortest(valueOrBlack(b, r.max_x, r.max_y, c));
  }
  const auto percent = [&](long k) { return 100.0 * double(k) / double(r.pixels); };
  m += "\n  " + std::to_string(r.warn_pixels) + " pixels (" + printf1("%1.3g", percent(r.warn_pixels)) + "%) over " +
       shortest(o.warn) + "\n  " + std::to_string(r.fail_pixels) + " pixels (" +
       printf1("%1.3g", percent(r.fail_pixels)) + "%) over " + shortest(o.fail) + "\n";
  if (o.perceptual)
    m += "  " + std::to_string(r.perceptual_failures) + " pixels (" + printf1("%3g", percent(r.perceptual_failures)) +
         "%) failed the perceptual test\n";
  r.stats = m;
  r.message = m + verdict(r.code);
  return r;
}

DiffResult diffFiles(const std::filesystem::path& a, const std::filesystem::path& b, const DiffOptions& o,
                     const std::filesystem::path& difference_png, ImageF* error_map) {
  ImageFile fa, fb;
  try {
    fa = readImageFile(a, o.channels);
    fb = readImageFile(b, o.channels);
  } catch (const std::exception& e) {
    DiffResult r;
    r.code = DiffCode::FileError;
    r.message = e.what();
    return r;
  }
  ImageF difference;
  DiffResult r = diffImages(fa.image, fb.image, o, difference_png.empty() ? nullptr : &difference, fa.channels,
                            fb.channels, error_map);
  if (!difference_png.empty() && !(o.difference_only_if_different && r.max_error == 0)) {
    if (difference.channels > 4) {  // a PNG holds at most 4: the first three (colour) show
      ImageF rgb(difference.width, difference.height, 3);
      for (int y = 0; y < rgb.height; ++y)
        for (int x = 0; x < rgb.width; ++x)
          for (int c = 0; c < 3; ++c) rgb.at(x, y, c) = difference.at(x, y, c);
      difference = std::move(rgb);
    }
    writePng(difference_png, toImage8(difference));
  }
  return r;
}

}  // namespace wobble::image
