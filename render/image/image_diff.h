// Image comparison with the semantics and exit codes of OpenImageIO's idiff 2.4 (Debian 12's openimageio-tools), for
// regression tests against golden images; tests/render/idiff_conformance_test.cpp runs the real idiff beside it.
//
// Per pixel, the error is the largest absolute difference over its channels, on values in [0, 1] (8-bit codes / 255
// for PNG files, no colour decoding: the comparison is of the stored values, as idiff does). Images of different
// size or channel count are compared as idiff does: over the union of their extents and channels, a pixel or channel
// one image lacks counting as 0 (black); percentages are of the first image's pixel count.
//   A pixel "fails" when its error exceeds `fail`, and "warns" when it exceeds `warn`.
//   Result:  Pass     when at most allow_failures pixels fail (0 by default: no pixel over `fail` passes, however
//                     many warn and whatever hard_fail and hard_warn say; idiff's rule)
//            Fail     otherwise, when more than fail_percent % of the pixels fail, or any error exceeds hard_fail
//            Warning  otherwise, when more than warn_percent % of the pixels warn, or any error exceeds hard_warn
//            Pass     otherwise (failing pixels within fail_percent and warnings within warn_percent)
//   FileError when a file cannot be read.
// The integer value of DiffCode is idiff's exit code: 0 pass, 1 warning, 2 failure, 4 file error. (idiff's 3,
// "different size", is left for MIP levels and deep data, which these images do not have: it never occurs here.)
// Defaults are idiff's: fail = warn = 1e-6, both percentages 0, hard limits infinite (any difference fails).
//
// The difference image is |A - B| * diff_scale per channel over the union, clamped to [0, 1] (alpha forced opaque so
// it shows); diffFiles writes it as PNG whenever a path is given, even when the images are equal.
#pragma once
#include <filesystem>
#include <limits>
#include <string>

#include "render/image/image.h"

namespace wobble::render {

struct DiffOptions {
  float fail = 1e-6f, fail_percent = 0, hard_fail = std::numeric_limits<float>::infinity();
  float warn = 1e-6f, warn_percent = 0, hard_warn = std::numeric_limits<float>::infinity();
  long allow_failures = 0;  // this many failing pixels pass, by any amount
  float diff_scale = 1;     // e.g. 10 or 20 to make small differences visible
};

enum class DiffCode : int { Pass = 0, Warning = 1, Fail = 2, FileError = 4 };

struct DiffResult {
  DiffCode code = DiffCode::Pass;
  long pixels = 0, warn_pixels = 0, fail_pixels = 0;  // pixels: the first image's, as idiff's percentages
  double mean_error = 0;                              // mean absolute difference over all channel values
  double max_error = 0;
  int max_x = 0, max_y = 0, max_channel = 0;  // where max_error occurs (first such)
  std::string message;                        // idiff-style report, or why the files could not be compared

  int exitCode() const { return static_cast<int>(code); }
};

// difference (optional): receives the difference image (the union's size and channels).
DiffResult diffImages(const ImageF& a, const ImageF& b, const DiffOptions& options = {}, ImageF* difference = nullptr);

// Reads both files (readImage: PNG and other 8-bit formats). Never throws for unreadable inputs: that is
// DiffCode::FileError with the reason in message. Throws only if the difference image cannot be written.
DiffResult diffFiles(const std::filesystem::path& a, const std::filesystem::path& b, const DiffOptions& options = {},
                     const std::filesystem::path& difference_png = {});

}  // namespace wobble::render
