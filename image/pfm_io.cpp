// PFM writing and reading (see pfm_io.h).
#include "image/pfm_io.h"

#include <bit>
#include <cstring>
#include <fstream>
#include <stdexcept>
#include <string>

#include "io/atomic_file.h"

namespace wobble::image {

static_assert(std::endian::native == std::endian::little, "PFM with scale -1 is little endian, as this machine");

void writePfm(const std::filesystem::path& file, int width, int height, std::span<const Color> pixels) {
  if (width <= 0 || height <= 0 || pixels.size() != std::size_t(width) * height)
    throw std::invalid_argument(file.string() + ": cannot write PFM of an empty or inconsistent image");
  std::string bytes = "PF\n" + std::to_string(width) + " " + std::to_string(height) + "\n-1.0\n";
  bytes.reserve(bytes.size() + pixels.size() * 3 * sizeof(float));
  std::vector<float> row(3 * std::size_t(width));
  for (int y = height - 1; y >= 0; --y) {
    for (int x = 0; x < width; ++x)
      for (int c = 0; c < 3; ++c) row[3 * std::size_t(x) + c] = pixels[std::size_t(y) * width + x][c];
    bytes.append(reinterpret_cast<const char*>(row.data()), row.size() * sizeof(float));
  }
  io::writeFileAtomically(file, bytes);
}

FloatImage readPfm(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw std::runtime_error(file.string() + ": cannot open");
  std::string magic;
  FloatImage image;
  double scale = 0;
  in >> magic >> image.width >> image.height >> scale;
  in.get();  // the single whitespace character before the data
  if (!in || magic != "PF" || image.width <= 0 || image.height <= 0 || image.width > 65536 || image.height > 65536 ||
      scale >= 0)
    throw std::runtime_error(file.string() + ": not a little-endian RGB PFM file");
  image.pixels.resize(std::size_t(image.width) * image.height);
  std::vector<float> row(3 * std::size_t(image.width));
  for (int y = image.height - 1; y >= 0; --y) {
    if (!in.read(reinterpret_cast<char*>(row.data()), std::streamsize(row.size() * sizeof(float))))
      throw std::runtime_error(file.string() + ": truncated PFM file");
    for (int x = 0; x < image.width; ++x)
      image.pixels[std::size_t(y) * image.width + x] = Color(row[3 * x], row[3 * x + 1], row[3 * x + 2]);
  }
  return image;
}

}  // namespace wobble::image
