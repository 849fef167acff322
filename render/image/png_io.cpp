// PNG reading and atomic writing through stb (see png_io.h).
#include "render/image/png_io.h"

#include <memory>
#include <stdexcept>
#include <string>

#include <csetjmp>
#include <cstdio>
#include <vector>

#include <png.h>
#include <stb/stb_image.h>

#include "io/atomic_file.h"
#include "render/image/image_header.h"

namespace wobble::render {

Image8 readImage(const std::filesystem::path& file) {
  std::string unreadable;  // stb_load says why below
  if (const auto header = readImageHeader(file, unreadable);
      header && (header->width > kMaxImageSide || header->height > kMaxImageSide))
    throw std::runtime_error(file.string() + ": the image is " + std::to_string(header->width) + " x " +
                             std::to_string(header->height) + " pixels; at most " + std::to_string(kMaxImageSide) +
                             " on each side can be read");
  int w = 0, h = 0, channels = 0;
  std::unique_ptr<stbi_uc, void (*)(void*)> data(stbi_load(file.c_str(), &w, &h, &channels, 0), stbi_image_free);
  if (!data) {
    const char* reason = stbi_failure_reason();
    throw std::runtime_error(file.string() + ": cannot read image (" + (reason ? reason : "unknown error") + ")");
  }
  Image8 image(w, h, channels);
  std::copy(data.get(), data.get() + image.pixels.size(), image.pixels.begin());
  return image;
}

namespace {

void appendBytes(png_structp png, png_bytep data, png_size_t length) {
  auto* out = static_cast<std::vector<unsigned char>*>(png_get_io_ptr(png));
  out->insert(out->end(), data, data + length);
}

// The whole PNG in memory. libpng reports errors by longjmp: nothing with a destructor lives between setjmp and the
// calls that may jump. Returns false on a libpng error.
bool encodePng(const Image8& image, std::vector<unsigned char>& out) {
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  if (!png) return false;
  png_infop info = png_create_info_struct(png);
  if (!info || setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    return false;
  }
  png_set_write_fn(png, &out, appendBytes, nullptr);
  png_set_compression_level(png, kPngCompressionLevel);
  png_set_filter(png, 0, PNG_FILTER_SUB);
  static constexpr int kColorTypes[] = {PNG_COLOR_TYPE_GRAY, PNG_COLOR_TYPE_GRAY_ALPHA, PNG_COLOR_TYPE_RGB,
                                        PNG_COLOR_TYPE_RGB_ALPHA};
  png_set_IHDR(png, info, png_uint_32(image.width), png_uint_32(image.height), 8, kColorTypes[image.channels - 1],
               PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  for (int y = 0; y < image.height; ++y)
    png_write_row(png, image.pixels.data() + std::size_t(y) * image.width * image.channels);
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  return true;
}

}  // namespace

void writePng(const std::filesystem::path& file, const Image8& image) {
  if (image.width <= 0 || image.height <= 0 || image.channels < 1 || image.channels > 4 ||
      image.pixels.size() != std::size_t(image.width) * image.height * image.channels)
    throw std::invalid_argument(file.string() + ": cannot write PNG of an empty or inconsistent image");
  std::vector<unsigned char> bytes;
  bytes.reserve(image.pixels.size() / 2);
  if (!encodePng(image, bytes)) throw std::runtime_error(file.string() + ": cannot encode PNG (libpng error)");
  io::writeFileAtomically(file, std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()));
}

}  // namespace wobble::render
