// Image comparison with the semantics, exit codes and report of OpenImageIO's idiff 2.4 (Debian 12's
// openimageio-tools), for regression tests against golden images; tests/app/idiff_conformance_test.cpp runs the real
// idiff beside it on PNG, EXR, HDR and PFM pairs, with and without -p.
//
// Values are compared as stored and read as floats (image_file.h): PNG codes / 255 or / 65535 with no colour decoding,
// EXR, HDR and PFM in their linear values. Per pixel, the error is the largest absolute difference over its channels.
// Images of different size or channel count are compared as idiff does: over the union of their extents and
// channels, a pixel or channel one image lacks counting as 0 (black); percentages are of the first image's pixels.
// Non-finite values as idiff: NaN against NaN and infinity against infinity (of either sign) are equal; the first
// pixel where only one is non-finite sets the max error to infinity (and is not counted); any later one counts as a
// failing and warning pixel.
//   A pixel "fails" when its error exceeds `fail`, and "warns" when it exceeds `warn`.
//   Result:  Pass     when at most allow_failures pixels fail (0 by default: no pixel over `fail` passes, however
//                     many warn and whatever hard_fail and hard_warn say; idiff's rule)
//            Fail     otherwise, when more than fail_percent % of the pixels fail, or any error exceeds hard_fail,
//                     or (perceptual) more than fail_percent % of the pixels fail the perceptual test
//            Warning  otherwise, when more than warn_percent % of the pixels warn, or any error exceeds hard_warn
//            Pass     otherwise
//   FileError when a file cannot be read (image_file.h says why).
// perceptual: idiff -p, Yee's perceptual metric as OpenImageIO 2.4 computes it (yee.h); it adds a failure condition
// and never passes a pair the numbers fail.
// The integer value of DiffCode is idiff's exit code: 0 pass, 1 warning, 2 failure, 4 file error. (idiff's 3,
// "different size", is left for MIP levels and deep data, which these images do not have: it never occurs here.)
// Defaults are idiff's: fail = warn = 1e-6, both percentages 0, hard limits infinite (any difference fails).
//
// The report (DiffResult::stats) is idiff's: mean, RMS, peak SNR, max error with its pixel, channel and values, the
// warning and failing pixel counts, the perceptual failures; then PASS, WARNING or FAILURE.
// The difference image is |A - B| * diff_scale per channel over the union, clamped to [0, 1] (alpha forced opaque so
// it shows); diffFiles writes it as PNG whenever a path is given, also when the images are equal unless
// difference_only_if_different (idiff -od) says otherwise.
#pragma once
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include "image/image.h"
#include "image/image_file.h"

namespace wobble::image {

struct DiffOptions {
  float fail = 1e-6f, fail_percent = 0, hard_fail = std::numeric_limits<float>::infinity();
  float warn = 1e-6f, warn_percent = 0, hard_warn = std::numeric_limits<float>::infinity();
  // idiff -failrelative, -warnrelative: a value also needs |a - b| > relative * (|a| + |b|) / 2 to fail or warn.
  float fail_relative = 0, warn_relative = 0;
  long allow_failures = 0;                    // this many failing pixels pass, by any amount
  bool perceptual = false;                    // idiff -p
  float diff_scale = 1;                       // e.g. 10 or 20 to make small differences visible
  bool difference_only_if_different = false;  // idiff -od: no difference image when the images are the same
  ChannelChoice channels;                     // which channels of EXR files (image_file.h)
};

enum class DiffCode : int { Pass = 0, Warning = 1, Fail = 2, FileError = 4 };

const char* verdict(DiffCode code);  // "PASS", "WARNING", "FAILURE", "FILE ERROR"

struct DiffResult {
  DiffCode code = DiffCode::Pass;
  long pixels = 0, warn_pixels = 0, fail_pixels = 0;  // pixels: the first image's, as idiff's percentages
  long perceptual_failures = 0;                       // with DiffOptions::perceptual
  double mean_error = 0, rms_error = 0, psnr = 0;     // over all channel values of the union
  double max_error = 0;
  int max_x = 0, max_y = 0, max_channel = 0;  // where max_error occurs (first such)
  std::string stats;                          // idiff's report lines (empty for a file error)
  std::string message;                        // stats and the verdict, or why the files could not be compared

  int exitCode() const { return static_cast<int>(code); }
};

// Channel names (optional) label the report's max error as idiff does; difference (optional) receives the
// difference image (the union's size and channels); error_map (optional) the per-pixel error (max over channels,
// 1 where non-finite), one channel.
DiffResult diffImages(const ImageF& a, const ImageF& b, const DiffOptions& options = {}, ImageF* difference = nullptr,
                      const std::vector<std::string>& names_a = {}, const std::vector<std::string>& names_b = {},
                      ImageF* error_map = nullptr);

// Reads both files (readImageFile). Never throws for unreadable inputs: that is DiffCode::FileError with the reason in
// message. Throws only if the difference image cannot be written.
DiffResult diffFiles(const std::filesystem::path& a, const std::filesystem::path& b, const DiffOptions& options = {},
                     const std::filesystem::path& difference_png = {}, ImageF* error_map = nullptr);

}  // namespace wobble::image
