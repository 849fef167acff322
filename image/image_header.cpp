#include "image/image_header.h"

#include <algorithm>
#include <fstream>

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <stb/stb_image.h>

namespace wobble::image {

namespace {

bool startsWith(const std::filesystem::path& file, const unsigned char* magic, std::size_t size) {
  std::ifstream in(file, std::ios::binary);
  unsigned char head[8] = {};
  in.read(reinterpret_cast<char*>(head), std::streamsize(size));
  return std::size_t(in.gcount()) == size && std::equal(magic, magic + size, head);
}

}  // namespace

std::optional<ImageHeader> readImageHeader(const std::filesystem::path& file, std::string& reason) {
  ImageHeader h;
  static constexpr unsigned char kExr[] = {0x76, 0x2f, 0x31, 0x01};
  if (startsWith(file, kExr, sizeof kExr)) {
    try {
      Imf::InputFile in(file.c_str());
      const Imath::Box2i window = in.header().dataWindow();
      const long width = long(window.max.x) - window.min.x + 1, height = long(window.max.y) - window.min.y + 1;
      h.width = int(std::clamp(width, 0L, long(1) << 30));
      h.height = int(std::clamp(height, 0L, long(1) << 30));
      for (auto c = in.header().channels().begin(); c != in.header().channels().end(); ++c) ++h.channels;
      h.linear = true;
      h.format = "EXR";
      return h;
    } catch (const std::exception& e) {
      reason = std::string("a damaged OpenEXR header: ") + e.what();
      return std::nullopt;
    }
  }
  if (stbi_info(file.c_str(), &h.width, &h.height, &h.channels)) {
    static constexpr unsigned char kPng[] = {0x89, 'P', 'N', 'G'};
    h.linear = stbi_is_hdr(file.c_str());
    h.format = h.linear ? "HDR" : startsWith(file, kPng, sizeof kPng) ? "PNG" : "image";
    return h;
  }
  const char* why = stbi_failure_reason();
  reason = why ? why : "unknown error";
  return std::nullopt;
}

}  // namespace wobble::image
