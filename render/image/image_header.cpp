#include "render/image/image_header.h"

#include <stb/stb_image.h>

namespace wobble::render {

std::optional<ImageHeader> readImageHeader(const std::filesystem::path& file, std::string& reason) {
  ImageHeader h;
  if (stbi_info(file.c_str(), &h.width, &h.height, &h.channels)) return h;
  const char* why = stbi_failure_reason();
  reason = why ? why : "unknown error";
  return std::nullopt;
}

}  // namespace wobble::render
