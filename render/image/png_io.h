// PNG files: readImage through stb (PNG and anything else stb_image reads) and writePng through libpng (atomic:
// written to a temporary name in the same directory, then renamed into place, so no reader ever sees half a file).
// Frames are written with zlib level 1 and the Sub filter: 4x faster than stb's encoder at 720p (35 ms against 125)
// and 20% smaller.
// Errors throw std::runtime_error naming the file and stb's reason.
#pragma once
#include <filesystem>

#include "render/image/image.h"

namespace wobble::render {

inline constexpr int kPngCompressionLevel = 1;
// The largest width or height readImage decodes: its header is read first, so a small file that declares a huge
// image cannot make it allocate gigabytes (scene textures and `wobble diff` inputs alike).
inline constexpr int kMaxImageSide = 16384;

// Keeps the file's own channel count (1 to 4).
Image8 readImage(const std::filesystem::path& file);

void writePng(const std::filesystem::path& file, const Image8& image);

}  // namespace wobble::render
