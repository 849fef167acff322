// exr_error: image::imageError's figures (image/image_error.h) for an EXR image against an EXR reference, with the
// same tone map as wobble's scenes (ToneMap: exposure stops, then the ACES fit, then sRGB), so that an image from
// another renderer (bench/cycles_compare.sh: Blender Cycles) is measured exactly as `wobble study render` measures
// its own images.
//
//   exr_error IMAGE.exr REFERENCE.exr [REFERENCE_B.exr] [--exposure STOPS] [--tile N] [--png OUT.png]
//   exr_error IMAGE.exr --png OUT.png [--exposure STOPS]
//
// With REFERENCE_B the reference is the mean of the two (two halves rendered with independent seeds, as the study's
// reference), and the figures of REFERENCE against REFERENCE_B are printed too (half_rmse: the reference's own RMSE is
// about half of it). Reads R, G, B of any pixel type (half, float, uint); A and other channels are ignored. A file
// named *.pfm is read as a PFM (wobble's cached study reference halves), so the two renderers' references can be
// compared with each other too.
// --png writes IMAGE as wobble develops its frames (the same tone map, 8-bit sRGB), for looking at it.
// Prints key=value lines: rmse, relmse, worst_tile_rmse, worst_tile_relmse (and half_* figures), and the mean linear
// colours image_mean and reference_mean (r,g,b).
// Exit status: 0 done; 2 bad input (unreadable file, missing channels, different sizes, bad option).
#include <cstdlib>
#include <cstring>
#include <exception>
#include <iostream>
#include <string>
#include <vector>

#include <Imath/ImathBox.h>
#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfRgbaFile.h>

#include "image/color.h"
#include "image/film.h"
#include "image/image_error.h"
#include "image/pfm_io.h"
#include "image/png_io.h"

namespace {

using wobble::image::Color;

struct BadInput {
  std::string message;
};

struct ExrImage {
  int width = 0, height = 0;
  std::vector<Color> pixels;
};

ExrImage readExr(const std::string& file) {
  if (file.size() > 4 && file.compare(file.size() - 4, 4, ".pfm") == 0) {  // wobble's cached study references
    try {
      wobble::image::FloatImage pfm = wobble::image::readPfm(file);
      return {pfm.width, pfm.height, std::move(pfm.pixels)};
    } catch (const std::exception& e) {
      throw BadInput{std::string(e.what())};
    }
  }
  try {
    Imf::RgbaInputFile in(file.c_str());
    const Imf::ChannelList& channels = in.header().channels();
    for (const char* name : {"R", "G", "B"})
      if (!channels.findChannel(name))
        throw BadInput{file + ": no " + name + " channel (an RGB EXR is needed; a multilayer file is not read)"};
    const Imath::Box2i window = in.dataWindow();
    ExrImage image;
    image.width = window.max.x - window.min.x + 1;
    image.height = window.max.y - window.min.y + 1;
    if (image.width <= 0 || image.height <= 0) throw BadInput{file + ": empty image"};
    std::vector<Imf::Rgba> rgba(std::size_t(image.width) * image.height);
    // Data window coordinates may start anywhere: offset the base pointer accordingly.
    in.setFrameBuffer(rgba.data() - window.min.x - std::ptrdiff_t(window.min.y) * image.width, 1, image.width);
    in.readPixels(window.min.y, window.max.y);
    image.pixels.reserve(rgba.size());
    for (const Imf::Rgba& p : rgba) image.pixels.emplace_back(float(p.r), float(p.g), float(p.b));
    return image;
  } catch (const BadInput&) {
    throw;
  } catch (const std::exception& e) {
    throw BadInput{file + ": cannot read as OpenEXR (" + e.what() + ")"};
  }
}

double parseNumber(const std::string& option, const char* text) {
  char* end = nullptr;
  const double value = std::strtod(text, &end);
  if (end == text || *end != '\0') throw BadInput{option + " " + text + ": not a number"};
  return value;
}

void printMean(const std::string& key, const std::vector<Color>& pixels) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (const Color& c : pixels) sum += c.cast<double>();
  sum /= double(pixels.size());
  std::cout << key << "=" << sum.x() << "," << sum.y() << "," << sum.z() << "\n";
}

void print(const std::string& prefix, const wobble::image::ImageError& e) {
  std::cout.precision(8);
  std::cout << prefix << "rmse=" << e.rmse << "\n"
            << prefix << "relmse=" << e.relmse << "\n"
            << prefix << "worst_tile_rmse=" << e.worst_tile_rmse << "\n"
            << prefix << "worst_tile_relmse=" << e.worst_tile_relmse << "\n";
}

const char* kUsage =
    "usage: exr_error IMAGE.exr REFERENCE.exr [REFERENCE_B.exr] [--exposure STOPS] [--tile N] [--png OUT.png]\n"
    "       exr_error IMAGE.exr --png OUT.png [--exposure STOPS]\n"
    "  prints rmse, relmse, worst_tile_rmse, worst_tile_relmse of IMAGE against REFERENCE (image/image_error.h),\n"
    "  display values through wobble's tone map at --exposure (default -0.5, the scenes' default);\n"
    "  with REFERENCE_B the reference is the mean of the two, and half_* are REFERENCE against REFERENCE_B;\n"
    "  --png writes IMAGE tone-mapped as wobble's PNG frames\n";

}  // namespace

int main(int argc, char** argv) {
  try {
    std::vector<std::string> files;
    wobble::image::ToneMap tone;
    tone.exposure = -0.5f;
    int tile = 32;
    std::string png;
    for (int i = 1; i < argc; ++i) {
      const std::string arg = argv[i];
      if (arg == "-h" || arg == "--help") {
        std::cout << kUsage;
        return 0;
      }
      if (arg == "--png") {
        if (i + 1 >= argc) throw BadInput{arg + ": needs a file name"};
        png = argv[++i];
      } else if (arg == "--exposure" || arg == "--tile") {
        if (i + 1 >= argc) throw BadInput{arg + ": needs a value"};
        const double v = parseNumber(arg, argv[++i]);
        if (arg == "--exposure") {
          if (!(v >= -20 && v <= 20)) throw BadInput{"--exposure " + std::string(argv[i]) + ": must be in [-20, 20]"};
          tone.exposure = float(v);
        } else {
          if (!(v >= 1 && v <= 4096) || v != int(v))
            throw BadInput{"--tile " + std::string(argv[i]) + ": must be a whole number in [1, 4096]"};
          tile = int(v);
        }
      } else if (arg.size() > 1 && arg[0] == '-') {
        throw BadInput{arg + ": unknown option"};
      } else {
        files.push_back(arg);
      }
    }
    if (files.empty() || files.size() > 3 || (files.size() == 1 && png.empty()))
      throw BadInput{"expected 2 or 3 EXR files (or one with --png)"};
    const ExrImage image = readExr(files[0]);
    if (!png.empty()) {
      try {
        wobble::image::writePng(png, wobble::image::develop(image.width, image.height, image.pixels, tone));
      } catch (const std::exception& e) {
        std::cerr << "exr_error: " << png << ": " << e.what() << "\n";
        return 1;
      }
      if (files.size() == 1) return 0;
    }
    ExrImage reference = readExr(files[1]);
    const auto sameSize = [&](const ExrImage& other, const std::string& file) {
      if (other.width != image.width || other.height != image.height)
        throw BadInput{file + ": " + std::to_string(other.width) + "x" + std::to_string(other.height) + ", but " +
                       files[0] + " is " + std::to_string(image.width) + "x" + std::to_string(image.height)};
    };
    sameSize(reference, files[1]);
    for (std::size_t k = 0; k < 2; ++k)
      for (const Color& c : (k == 0 ? image : reference).pixels)
        if (!c.allFinite()) {
          std::cerr << "exr_error: warning: " << files[k]
                    << " has non-finite pixels (they count as 0 in display values)\n";
          break;
        }
    if (files.size() == 3) {
      const ExrImage half_b = readExr(files[2]);
      sameSize(half_b, files[2]);
      print("half_", wobble::image::imageError(image.width, image.height, reference.pixels, half_b.pixels, tone, tile));
      for (std::size_t i = 0; i < reference.pixels.size(); ++i)
        reference.pixels[i] = 0.5f * (reference.pixels[i] + half_b.pixels[i]);
    }
    print("", wobble::image::imageError(image.width, image.height, image.pixels, reference.pixels, tone, tile));
    printMean("image_mean", image.pixels);
    printMean("reference_mean", reference.pixels);
    return 0;
  } catch (const BadInput& e) {
    std::cerr << "exr_error: " << e.message << "\n" << kUsage;
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "exr_error: " << e.what() << "\n";
    return 1;
  }
}
