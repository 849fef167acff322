// PNG files: readImage through stb (PNG and anything else stb_image reads) and writePng through libpng (atomic:
// written to a temporary name in the same directory, then renamed into place, so no reader ever sees half a file).
// Frames are written with the Sub filter and libdeflate at level 1, several times faster and smaller than stb's
// encoder or zlib through libpng (docs/performance.md). A PNG may carry
// text chunks (keyword and text): wobble's frames record the settings they were rendered with there
// (app/output/picture_key.h), read back by readPngText without decoding the pixels. Errors throw std::runtime_error
// naming the file and stb's reason.
#pragma once
#include <filesystem>
#include <map>
#include <string>

#include "image/image.h"

namespace wobble::image {

inline constexpr int kPngCompressionLevel = 1;
// The largest width or height readImage decodes: its header is read first, so a small file that declares a huge
// image cannot make it allocate gigabytes (scene textures and `wobble diff` inputs alike).
inline constexpr int kMaxImageSide = 16384;

// Keeps the file's own channel count (1 to 4).
Image8 readImage(const std::filesystem::path& file);

// text: tEXt chunks, keyword (1 to 79 printable Latin-1 characters) -> text.
void writePng(const std::filesystem::path& file, const Image8& image,
              const std::map<std::string, std::string>& text = {});

// The text chunks before the image data (where writePng puts them), keyword -> text; empty when the file is missing,
// has none, or is not a readable PNG. Cheap: the pixels are not read.
std::map<std::string, std::string> readPngText(const std::filesystem::path& file);

}  // namespace wobble::image
