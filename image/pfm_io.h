// Portable float map (PFM) files: linear RGB in 32-bit floats, the simplest lossless HDR format (OpenImageIO, GIMP
// and Photoshop read it). The render study caches its reference images in it. Rows are stored bottom to top, little
// endian (scale -1), as the format says; in memory row 0 is the top, as everywhere in the renderer.
// writePfm is atomic (atomic_file.h); both throw std::runtime_error naming the file.
#pragma once
#include <filesystem>
#include <span>
#include <vector>

#include "image/color.h"

namespace wobble::image {

struct FloatImage {
  int width = 0, height = 0;
  std::vector<Color> pixels;  // row-major, row 0 at the top
};

void writePfm(const std::filesystem::path& file, int width, int height, std::span<const Color> pixels);
FloatImage readPfm(const std::filesystem::path& file);

}  // namespace wobble::image
