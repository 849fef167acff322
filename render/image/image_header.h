// An image file's size from its header alone, before anything is decoded: a small PNG can declare 20000 x 20000
// pixels, and decoding it would allocate gigabytes. readImage (png_io.h) checks every image with it, and the scene
// reader checks textures with it when the scene is read.
#pragma once
#include <filesystem>
#include <optional>
#include <string>

namespace wobble::render {

struct ImageHeader {
  int width = 0, height = 0, channels = 0;
};

// Nothing when stb_image cannot read the header; reason then says why.
std::optional<ImageHeader> readImageHeader(const std::filesystem::path& file, std::string& reason);

}  // namespace wobble::render
