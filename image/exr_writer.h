// writeExr: a Film as an OpenEXR file (scanline, ZIP compression), written atomically (atomic_file.h).
//
// Channels (OpenEXR "layer.channel" naming, as Nuke and Blender read them):
//   R, G, B                       colour, linear, half float: the denoised colour when one is given
//   noisy.R, noisy.G, noisy.B     only with a denoised colour: the film's own (noisy) colour
//   albedo.R, albedo.G, albedo.B  half float
//   normal.X, normal.Y, normal.Z  half float, world space
//   depth.Z                       32-bit float: half float has only 11 bits of mantissa, too coarse for distances
// Text attributes (name -> string) go into the header: wobble's frames record the settings they were rendered with
// there (app/output/picture_key.h), read back by readExrText without reading the pixels.
// Errors throw std::runtime_error naming the file.
#pragma once
#include <array>
#include <filesystem>
#include <map>
#include <span>
#include <string>
#include <string_view>

#include "image/film.h"

namespace wobble::image {

inline constexpr std::array<std::string_view, 10> kExrChannels = {"R",        "G",        "B",        "albedo.R",
                                                                  "albedo.G", "albedo.B", "normal.X", "normal.Y",
                                                                  "normal.Z", "depth.Z"};

void writeExr(const std::filesystem::path& file, const Film& film, std::span<const Color> denoised = {},
              const std::map<std::string, std::string>& text = {});

// The header's string attributes, name -> value; empty when the file is missing or not a readable EXR.
std::map<std::string, std::string> readExrText(const std::filesystem::path& file);

}  // namespace wobble::image
