// An image file's size from its header alone, before anything is decoded: a small PNG can declare 20000 x 20000
// pixels, and decoding it would allocate gigabytes. readImage (png_io.h) checks every image with it, and the scene
// reader checks textures and the environment map with it when the scene is read. OpenEXR files through OpenEXR's
// header, every other format through stb_image.
#pragma once
#include <filesystem>
#include <optional>
#include <string>

namespace wobble::image {

struct ImageHeader {
  int width = 0, height = 0, channels = 0;
  bool linear = false;  // scene-referred values: OpenEXR or Radiance HDR (not a PNG's display values)
  std::string format;   // "EXR", "HDR", "PNG" or "image" (another format stb_image reads)
};

// Nothing when neither OpenEXR nor stb_image can read the header; reason then says why.
std::optional<ImageHeader> readImageHeader(const std::filesystem::path& file, std::string& reason);

}  // namespace wobble::image
