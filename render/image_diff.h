// Image comparison with OpenImageIO idiff's semantics, for regression tests against golden images.
//
// Per pixel, the error is the largest absolute difference over its channels, on values in [0, 1] (8-bit codes / 255
// for PNG files, no colour decoding: the comparison is of the stored values, as idiff does).
//   A pixel "fails" when its error exceeds `fail`, and "warns" when it exceeds `warn`.
//   Result:  DifferentSize  when width, height or channel count differ
//            Fail     when more than fail_percent % of the pixels fail, or any error exceeds hard_fail
//            Warning  otherwise, when more than warn_percent % of the pixels warn, or any error exceeds hard_warn
//            Pass     otherwise (identical, or different only within tolerance; max_error tells which)
//   FileError when a file cannot be read.
// The integer value of DiffCode is idiff's exit code: 0 pass, 1 warning, 2 failure, 3 different size, 4 file error.
// Defaults are idiff's: fail = warn = 1e-6, both percentages 0, hard limits infinite (any difference fails).
//
// The difference image is |A - B| * diff_scale per channel, clamped to [0, 1] (alpha forced opaque so it shows);
// diffFiles writes it as PNG whenever a path is given and the sizes match, even when the images are equal.
#pragma once
#include <filesystem>
#include <limits>
#include <string>

#include "image.h"

namespace wobble::render {

struct DiffOptions {
  float fail = 1e-6f, fail_percent = 0, hard_fail = std::numeric_limits<float>::infinity();
  float warn = 1e-6f, warn_percent = 0, hard_warn = std::numeric_limits<float>::infinity();
  float diff_scale = 1;  // e.g. 10 or 20 to make small differences visible
};

enum class DiffCode : int { Pass = 0, Warning = 1, Fail = 2, DifferentSize = 3, FileError = 4 };

struct DiffResult {
  DiffCode code = DiffCode::Pass;
  long pixels = 0, warn_pixels = 0, fail_pixels = 0;
  double mean_error = 0;  // mean absolute difference over all channel values
  double max_error = 0;
  int max_x = 0, max_y = 0, max_channel = 0;  // where max_error occurs (first such)
  std::string message;  // idiff-style report, or why the files could not be compared

  int exitCode() const { return static_cast<int>(code); }
};

// difference (optional): receives the difference image when the shapes match.
DiffResult diffImages(const ImageF& a, const ImageF& b, const DiffOptions& options = {},
                      ImageF* difference = nullptr);

// Reads both files (readImage: PNG and other 8-bit formats). Never throws for unreadable inputs: that is
// DiffCode::FileError with the reason in message. Throws only if the difference image cannot be written.
DiffResult diffFiles(const std::filesystem::path& a, const std::filesystem::path& b, const DiffOptions& options = {},
                     const std::filesystem::path& difference_png = {});

}  // namespace wobble::render
