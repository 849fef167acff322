// PNG reading and atomic writing through stb (see png_io.h).
#include "png_io.h"

#include <memory>
#include <stdexcept>
#include <string>

#include <stb/stb_image.h>
#include <stb/stb_image_write.h>

#include "atomic_file.h"

namespace wobble::render {

Image8 readImage(const std::filesystem::path& file) {
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

void writePng(const std::filesystem::path& file, const Image8& image) {
  if (image.width <= 0 || image.height <= 0 || image.channels < 1 || image.channels > 4 ||
      image.pixels.size() != std::size_t(image.width) * image.height * image.channels)
    throw std::invalid_argument(file.string() + ": cannot write PNG of an empty or inconsistent image");
  writeAtomically(file, [&](const std::filesystem::path& temp) {
    if (!stbi_write_png(temp.c_str(), image.width, image.height, image.channels, image.pixels.data(),
                        image.width * image.channels))
      throw std::runtime_error(file.string() + ": cannot write PNG");
  });
}

}  // namespace wobble::render
