// PNG reading through stb, atomic writing and text chunks through libpng, image data through libdeflate (see
// png_io.h).
#include "image/png_io.h"

#include <map>
#include <memory>
#include <new>
#include <span>
#include <stdexcept>
#include <string>

#include <csetjmp>
#include <cstdio>
#include <vector>

#include <libdeflate.h>
#include <png.h>
#include <stb/stb_image.h>

#include "image/file_size_bound.h"
#include "image/image_header.h"
#include "io/atomic_file.h"

namespace wobble::image {

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

// The image data (IDAT) as PNG wants it: each row prefixed by its filter type, Sub (each byte minus the one a pixel
// to its left), then a zlib stream. libdeflate at level 1 compresses it twice as fast as zlib's level 1 (which libpng
// would use), a little smaller, and always to the same bytes.
std::vector<unsigned char> compressedImageData(const Image8& image) {
  const std::size_t bpp = std::size_t(image.channels), row = std::size_t(image.width) * bpp;
  std::vector<unsigned char> filtered(std::size_t(image.height) * (row + 1));
  for (int y = 0; y < image.height; ++y) {
    const unsigned char* in = image.pixels.data() + std::size_t(y) * row;
    unsigned char* out = filtered.data() + std::size_t(y) * (row + 1);
    out[0] = PNG_FILTER_VALUE_SUB;
    for (std::size_t i = 0; i < row; ++i) out[1 + i] = static_cast<unsigned char>(in[i] - (i >= bpp ? in[i - bpp] : 0));
  }
  thread_local const std::unique_ptr<libdeflate_compressor, void (*)(libdeflate_compressor*)>
      compressor(libdeflate_alloc_compressor(kPngCompressionLevel), libdeflate_free_compressor);
  if (!compressor) throw std::bad_alloc();
  std::vector<unsigned char> zlib(libdeflate_zlib_compress_bound(compressor.get(), filtered.size()));
  // 0 when it does not fit (it always fits its bound): an empty result, which writePng refuses.
  zlib.resize(libdeflate_zlib_compress(compressor.get(), filtered.data(), filtered.size(), zlib.data(), zlib.size()));
  return zlib;
}

// The whole PNG in memory: libpng writes the signature, header and text chunks, then the image data compressed above
// as one IDAT chunk, and the end. libpng reports errors by longjmp: nothing with a destructor lives between setjmp and
// the calls that may jump. Returns false on a libpng error.
bool encodePng(const Image8& image, std::span<const png_text> text, std::span<const unsigned char> idat,
               std::vector<unsigned char>& out) {
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  if (!png) return false;
  png_infop info = png_create_info_struct(png);
  if (!info || setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    return false;
  }
  png_set_write_fn(png, &out, appendBytes, nullptr);
  static constexpr int kColorTypes[] = {PNG_COLOR_TYPE_GRAY, PNG_COLOR_TYPE_GRAY_ALPHA, PNG_COLOR_TYPE_RGB,
                                        PNG_COLOR_TYPE_RGB_ALPHA};
  png_set_IHDR(png, info, png_uint_32(image.width), png_uint_32(image.height), 8, kColorTypes[image.channels - 1],
               PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  if (!text.empty()) png_set_text(png, info, text.data(), int(text.size()));  // before the image data
  png_write_info(png, info);
  png_write_chunk(png, reinterpret_cast<png_const_bytep>("IDAT"), idat.data(), idat.size());
  png_write_chunk(png, reinterpret_cast<png_const_bytep>("IEND"), nullptr, 0);
  png_destroy_write_struct(&png, &info);
  return true;
}

// The text chunks of an open PNG file into out; false on a libpng error (not a PNG, truncated). As encodePng, nothing
// with a destructor is made between setjmp and the calls that may jump.
bool readTextChunks(std::FILE* file, std::map<std::string, std::string>& out) {
  // Quiet: a file that is not a PNG (or an older frame's) only means "no text" to the caller.
  const auto jump = [](png_structp p, png_const_charp) { png_longjmp(p, 1); };
  const auto ignore = [](png_structp, png_const_charp) {};
  png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, nullptr, jump, ignore);
  if (!png) return false;
  png_infop info = png_create_info_struct(png);
  if (!info || setjmp(png_jmpbuf(png))) {
    png_destroy_read_struct(&png, &info, nullptr);
    return false;
  }
  png_init_io(png, file);
  png_read_info(png, info);  // every chunk up to the first IDAT
  png_textp text = nullptr;
  const int count = png_get_text(png, info, &text, nullptr);
  for (int i = 0; i < count; ++i) out[text[i].key] = std::string(text[i].text, text[i].text_length);
  png_destroy_read_struct(&png, &info, nullptr);
  return true;
}

}  // namespace

std::uint64_t pngSizeBound(int width, int height, int channels, const std::map<std::string, std::string>& text) {
  constexpr std::uint64_t kChunk = 12;  // length, type, CRC
  const std::uint64_t filtered = std::uint64_t(height) * (std::uint64_t(width) * std::uint64_t(channels) + 1);
  std::uint64_t bytes = 8 + (kChunk + 13) + kChunk + kChunk;   // signature, IHDR, IDAT's frame, IEND
  bytes += libdeflate_zlib_compress_bound(nullptr, filtered);  // any compressor: the stored worst case
  for (const auto& [keyword, value] : text) bytes += kChunk + keyword.size() + 1 + value.size();
  return bytes;
}

void writePng(const std::filesystem::path& file, const Image8& image, const std::map<std::string, std::string>& text) {
  if (image.width <= 0 || image.height <= 0 || image.channels < 1 || image.channels > 4 ||
      image.pixels.size() != std::size_t(image.width) * image.height * image.channels)
    throw std::invalid_argument(file.string() + ": cannot write PNG of an empty or inconsistent image");
  std::vector<png_text> chunks;
  for (const auto& [keyword, value] : text) {
    if (keyword.empty() || keyword.size() > 79)
      throw std::invalid_argument(file.string() + ": a PNG text keyword has 1 to 79 characters");
    png_text& chunk = chunks.emplace_back();
    chunk.compression = PNG_TEXT_COMPRESSION_NONE;
    chunk.key = const_cast<char*>(keyword.c_str());  // libpng only reads them
    chunk.text = const_cast<char*>(value.c_str());
    chunk.text_length = value.size();
  }
  const std::vector<unsigned char> idat = compressedImageData(image);
  if (idat.empty()) throw std::runtime_error(file.string() + ": cannot compress the PNG image data (libdeflate)");
  std::vector<unsigned char> bytes;
  bytes.reserve(idat.size() + 1024);
  if (!encodePng(image, chunks, idat, bytes))
    throw std::runtime_error(file.string() + ": cannot encode PNG (libpng error)");
  io::writeFileAtomically(file, std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()));
}

std::map<std::string, std::string> readPngText(const std::filesystem::path& file) {
  std::map<std::string, std::string> text;
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> in(std::fopen(file.c_str(), "rb"), std::fclose);
  if (!in || !readTextChunks(in.get(), text)) return {};
  return text;
}

}  // namespace wobble::image
