// PNG files through stb: readImage (PNG and anything else stb_image reads) and writePng (atomic: written to a
// temporary name in the same directory, then renamed into place, so no reader ever sees half a file).
// Errors throw std::runtime_error naming the file and stb's reason.
#pragma once
#include <filesystem>

#include "image.h"

namespace wobble::render {

// Keeps the file's own channel count (1 to 4).
Image8 readImage(const std::filesystem::path& file);

void writePng(const std::filesystem::path& file, const Image8& image);

}  // namespace wobble::render
