// Image files of every format wobble writes or reads, as floats (see image_file.h).
#include "image/image_file.h"

#include <algorithm>
#include <bit>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <limits>
#include <memory>
#include <sstream>

#include <Imath/half.h>
#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfMultiPartInputFile.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfStdIO.h>
#include <OpenEXR/ImfVersion.h>
#include <stb/stb_image.h>

#include "image/png_io.h"
#include "io/atomic_file.h"

namespace wobble::image {

namespace {

[[noreturn]] void fail(const std::filesystem::path& file, const std::string& reason) {
  throw ImageFileError(file.string() + ": " + reason);
}

void checkSize(const std::filesystem::path& file, long width, long height) {
  if (width <= 0 || height <= 0)
    fail(file, "the image is empty (" + std::to_string(width) + " x " + std::to_string(height) + " pixels)");
  if (width > kMaxImageSide || height > kMaxImageSide)
    fail(file, "the image is " + std::to_string(width) + " x " + std::to_string(height) + " pixels; at most " +
                   std::to_string(kMaxImageSide) + " on each side can be read");
}

std::string layerOf(const std::string& name) {
  const auto dot = name.rfind('.');
  return dot == std::string::npos ? std::string() : name.substr(0, dot);
}

std::string joined(const std::vector<std::string>& names) {
  std::string out;
  for (const auto& n : names) out += (out.empty() ? "" : ", ") + n;
  return out;
}

// A layer's channels as OpenImageIO orders them: R, G, B, A first, then the rest in the file's order.
std::vector<std::string> layerChannels(const std::vector<std::string>& names, const std::string& layer) {
  std::vector<std::string> in_layer, out;
  for (const auto& n : names)
    if (layerOf(n) == layer) in_layer.push_back(n);
  const std::string prefix = layer.empty() ? "" : layer + ".";
  for (const char* first : {"R", "G", "B", "A"})
    if (std::find(in_layer.begin(), in_layer.end(), prefix + first) != in_layer.end()) out.push_back(prefix + first);
  for (const auto& n : in_layer)
    if (std::find(out.begin(), out.end(), n) == out.end()) out.push_back(n);
  return out;
}

// The channel names the choice asks for, in order; throws naming what is missing and what there is.
std::vector<std::string> resolve(const std::filesystem::path& file, const std::vector<std::string>& names,
                                 const ChannelChoice& choice, bool has_layers) {
  if (!has_layers && !choice.layer.empty())
    fail(file, "has no layers (asked for layer '" + choice.layer + "'); its channels: " + joined(names));
  if (choice.channels.empty()) {
    std::vector<std::string> picked = layerChannels(names, choice.layer);
    if (picked.empty() && !choice.layer.empty()) {
      std::vector<std::string> layers;
      for (const auto& n : names)
        if (const std::string l = layerOf(n); !l.empty() && std::find(layers.begin(), layers.end(), l) == layers.end())
          layers.push_back(l);
      fail(file, "has no layer '" + choice.layer + "'; its layers: " + (layers.empty() ? "none" : joined(layers)));
    }
    return picked.empty() ? names : picked;
  }
  std::vector<std::string> picked;
  std::string layer = choice.layer;
  for (const auto& item : choice.channels) {
    std::string name = item;
    if (item.find('.') == std::string::npos) {
      if (!layer.empty()) name = layer + "." + item;
    } else if (choice.layer.empty()) {
      layer = layerOf(item);
    }
    if (std::find(names.begin(), names.end(), name) == names.end())
      fail(file, "has no channel '" + name + "'; its channels: " + joined(names));
    picked.push_back(name);
  }
  return picked;
}

ImageFile select(const std::filesystem::path& file, ImageFile all, const ChannelChoice& choice, bool has_layers) {
  const std::vector<std::string> names = resolve(file, all.channels, choice, has_layers);
  if (names == all.channels) return all;
  ImageFile out;
  out.linear = all.linear;
  out.format = all.format;
  out.channels = names;
  out.image = ImageF(all.image.width, all.image.height, int(names.size()));
  for (int c = 0; c < out.image.channels; ++c) {
    const int from = int(std::find(all.channels.begin(), all.channels.end(), names[c]) - all.channels.begin());
    for (int y = 0; y < out.image.height; ++y)
      for (int x = 0; x < out.image.width; ++x) out.image.at(x, y, c) = all.image.at(x, y, from);
  }
  return out;
}

std::vector<std::string> unnamedChannels(int channels) {
  switch (channels) {
    case 1:
      return {"Y"};
    case 2:
      return {"Y", "A"};
    case 3:
      return {"R", "G", "B"};
    default:
      return {"R", "G", "B", "A"};
  }
}

ImageFile readExr(const std::filesystem::path& file) {
  try {
    Imf::InputFile in(file.c_str());
    const Imath::Box2i window = in.header().dataWindow();
    const long width = long(window.max.x) - window.min.x + 1, height = long(window.max.y) - window.min.y + 1;
    checkSize(file, width, height);
    ImageFile out;
    out.format = "EXR";
    out.linear = true;
    for (auto c = in.header().channels().begin(); c != in.header().channels().end(); ++c)
      out.channels.push_back(c.name());
    if (out.channels.empty()) fail(file, "the EXR file has no channels");
    out.image = ImageF(int(width), int(height), int(out.channels.size()));
    // Every channel as float, interleaved; the slice's origin is shifted so the data window starts at pixel 0.
    Imf::FrameBuffer frame;
    const std::size_t xs = sizeof(float) * out.channels.size(), ys = xs * std::size_t(width);
    for (std::size_t c = 0; c < out.channels.size(); ++c) {
      char* base =
          reinterpret_cast<char*>(out.image.pixels.data() + c) - window.min.x * long(xs) - window.min.y * long(ys);
      frame.insert(out.channels[c], Imf::Slice(Imf::FLOAT, base, xs, ys));
    }
    in.setFrameBuffer(frame);
    in.readPixels(window.min.y, window.max.y);
    return out;
  } catch (const ImageFileError&) {
    throw;
  } catch (const std::exception& e) {
    fail(file, std::string("cannot read the EXR file (") + e.what() + ")");
  }
}

ImageFile readPfmFile(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::string magic;
  long width = 0, height = 0;
  double scale = 0;
  in >> magic >> width >> height >> scale;
  in.get();  // the single whitespace character before the data
  if (!in || (magic != "PF" && magic != "Pf") || scale == 0) fail(file, "not a PFM file (bad header)");
  checkSize(file, width, height);
  const int channels = magic == "PF" ? 3 : 1;
  ImageFile out;
  out.format = "PFM";
  out.linear = true;
  out.channels = channels == 3 ? std::vector<std::string>{"R", "G", "B"} : std::vector<std::string>{"Y"};
  out.image = ImageF(int(width), int(height), channels);
  const bool swap = (scale < 0) != (std::endian::native == std::endian::little);
  const std::size_t row = std::size_t(width) * channels;
  for (long y = height - 1; y >= 0; --y) {
    float* dst = out.image.pixels.data() + std::size_t(y) * row;
    if (!in.read(reinterpret_cast<char*>(dst), std::streamsize(row * sizeof(float))))
      fail(file, "truncated PFM file (" + std::to_string(height - 1 - y) + " of " + std::to_string(height) +
                     " rows present)");
    if (swap)
      for (std::size_t i = 0; i < row; ++i) {
        std::uint32_t bits;
        std::memcpy(&bits, dst + i, 4);
        bits = __builtin_bswap32(bits);
        std::memcpy(dst + i, &bits, 4);
      }
  }
  return out;
}

// A PNG's gAMA chunk (the file gamma, e.g. 0.45455), read from the chunks before the image data; 0 when absent.
double pngFileGamma(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  in.seekg(8);  // the signature
  unsigned char head[8];
  while (in.read(reinterpret_cast<char*>(head), 8)) {
    const std::uint32_t length = std::uint32_t(head[0]) << 24 | head[1] << 16 | head[2] << 8 | head[3];
    const std::string type(reinterpret_cast<char*>(head + 4), 4);
    if (type == "IDAT" || type == "IEND") break;
    if (type == "gAMA" && length == 4) {
      unsigned char g[4];
      if (!in.read(reinterpret_cast<char*>(g), 4)) break;
      return double(std::uint32_t(g[0]) << 24 | g[1] << 16 | g[2] << 8 | g[3]) / 100000.0;
    }
    in.seekg(length + 4, std::ios::cur);  // the data and the CRC
  }
  return 0;
}

// OpenImageIO hands out PNG colours with associated (premultiplied) alpha, computed on the stored codes: times
// alpha / max in integers, or, when the file states a gamma, times (alpha / max)^(1 / file gamma), truncated. idiff
// compares those values, and so do we.
template <class Code>
void associateAlpha(Code* codes, std::size_t pixels, int channels, double file_gamma) {
  constexpr unsigned max = std::numeric_limits<Code>::max();
  const float gamma = file_gamma > 0 ? float(1.0 / file_gamma) : 1.0f;
  for (std::size_t i = 0; i < pixels; ++i, codes += channels) {
    const Code alpha = codes[channels - 1];
    const float factor = std::pow(float(alpha) * float(1.0 / max), gamma);
    for (int c = 0; c < channels - 1; ++c)
      codes[c] = gamma == 1.0f ? Code(unsigned(codes[c]) * alpha / max) : Code(float(codes[c]) * factor);
  }
}

// PNG, Radiance HDR and the other formats stb_image reads.
ImageFile readStb(const std::filesystem::path& file, bool png) {
  int w = 0, h = 0, channels = 0;
  if (!stbi_info(file.c_str(), &w, &h, &channels)) {
    const char* reason = stbi_failure_reason();
    fail(file, std::string("not an image wobble reads (") + (reason ? reason : "unknown format") +
                   "; formats: EXR, HDR, PFM, PNG)");
  }
  checkSize(file, w, h);
  ImageFile out;
  out.format = png ? "PNG" : "image";
  const auto loaded = [&](void* data) {
    if (!data) {
      const char* reason = stbi_failure_reason();
      fail(file,
           std::string("cannot decode the image (") + (reason ? reason : "unknown error") + "): truncated or corrupt");
    }
    return std::unique_ptr<void, void (*)(void*)>(data, stbi_image_free);
  };
  if (stbi_is_hdr(file.c_str())) {
    out.format = "HDR";
    out.linear = true;
    const auto data = loaded(stbi_loadf(file.c_str(), &w, &h, &channels, 0));
    out.image = ImageF(w, h, channels);
    std::memcpy(out.image.pixels.data(), data.get(), out.image.pixels.size() * sizeof(float));
  } else if (stbi_is_16_bit(file.c_str())) {
    const auto data = loaded(stbi_load_16(file.c_str(), &w, &h, &channels, 0));
    out.image = ImageF(w, h, channels);
    auto* codes = static_cast<std::uint16_t*>(data.get());
    if (png && (channels == 2 || channels == 4))
      associateAlpha(codes, std::size_t(w) * h, channels, pngFileGamma(file));
    for (std::size_t i = 0; i < out.image.pixels.size(); ++i) out.image.pixels[i] = float(codes[i]) / 65535.0f;
  } else {
    const auto data = loaded(stbi_load(file.c_str(), &w, &h, &channels, 0));
    out.image = ImageF(w, h, channels);
    auto* codes = static_cast<std::uint8_t*>(data.get());
    if (png && (channels == 2 || channels == 4))
      associateAlpha(codes, std::size_t(w) * h, channels, pngFileGamma(file));
    // Times 1/255 as OpenImageIO converts (not divided by 255: they differ in the last bit for some codes).
    for (std::size_t i = 0; i < out.image.pixels.size(); ++i) out.image.pixels[i] = float(codes[i]) * (1.0f / 255.0f);
  }
  out.channels = unnamedChannels(channels);
  return out;
}

}  // namespace

std::vector<std::string> splitChannelList(const std::string& list) {
  std::vector<std::string> items;
  std::stringstream in(list);
  for (std::string item; std::getline(in, item, ',');)
    if (!item.empty()) items.push_back(item);
  return items;
}

ImageFile readImageFile(const std::filesystem::path& file, const ChannelChoice& choice) {
  std::error_code ec;
  if (std::filesystem::is_directory(file, ec)) fail(file, "is a folder, not an image");
  std::ifstream in(file, std::ios::binary);
  if (!in) fail(file, std::string("cannot open (") + std::strerror(errno) + ")");
  char magic[4] = {};
  in.read(magic, 4);
  if (in.gcount() == 0) fail(file, "the file is empty");
  in.close();
  const unsigned char* m = reinterpret_cast<const unsigned char*>(magic);
  if (m[0] == 0x76 && m[1] == 0x2f && m[2] == 0x31 && m[3] == 0x01) return select(file, readExr(file), choice, true);
  if (magic[0] == 'P' && (magic[1] == 'F' || magic[1] == 'f') && std::isspace(static_cast<unsigned char>(magic[2])))
    return select(file, readPfmFile(file), choice, false);
  const bool png = m[0] == 0x89 && magic[1] == 'P' && magic[2] == 'N' && magic[3] == 'G';
  return select(file, readStb(file, png), choice, false);
}

int subimageCount(const std::filesystem::path& file) {
  try {
    char magic[4] = {};
    std::ifstream(file, std::ios::binary).read(magic, 4);
    if (!Imf::isImfMagic(magic)) return 1;
    Imf::MultiPartInputFile in(file.c_str());
    int count = 0;
    for (int part = 0; part < in.parts(); ++part) {
      const Imf::Header& h = in.header(part);
      if (!h.hasTileDescription() || h.tileDescription().mode == Imf::ONE_LEVEL) {
        ++count;
        continue;
      }
      const Imath::Box2i w = h.dataWindow();  // MIP levels: halving the larger side down to 1 pixel
      for (int size = std::max(w.max.x - w.min.x, w.max.y - w.min.y) + 1; size >= 1; size /= 2) ++count;
    }
    return count;
  } catch (const std::exception&) {
    return 1;
  }
}

void writeExrImage(const std::filesystem::path& file, const ImageF& image, const std::vector<std::string>& channels,
                   bool half_float) {
  if (image.width <= 0 || image.height <= 0 || channels.size() != std::size_t(image.channels))
    throw std::invalid_argument(file.string() + ": cannot write EXR of an empty or inconsistent image");
  Imf::Header header(image.width, image.height);
  header.compression() = Imf::ZIP_COMPRESSION;
  Imf::FrameBuffer frame;
  const std::size_t n = std::size_t(image.width) * image.height;
  std::vector<std::vector<half>> halves;
  std::vector<std::vector<float>> floats;
  halves.reserve(channels.size());
  floats.reserve(channels.size());
  for (std::size_t c = 0; c < channels.size(); ++c) {
    char* data = nullptr;
    std::size_t size = 0;
    if (half_float) {
      auto& v = halves.emplace_back(n);
      for (std::size_t i = 0; i < n; ++i) v[i] = half(image.pixels[i * channels.size() + c]);
      data = reinterpret_cast<char*>(v.data()), size = sizeof(half);
    } else {
      auto& v = floats.emplace_back(n);
      for (std::size_t i = 0; i < n; ++i) v[i] = image.pixels[i * channels.size() + c];
      data = reinterpret_cast<char*>(v.data()), size = sizeof(float);
    }
    const Imf::PixelType type = half_float ? Imf::HALF : Imf::FLOAT;
    header.channels().insert(channels[c], Imf::Channel(type));
    frame.insert(channels[c], Imf::Slice(type, data, size, size * image.width));
  }
  Imf::StdOSStream bytes;
  try {
    Imf::OutputFile out(bytes, header);
    out.setFrameBuffer(frame);
    out.writePixels(image.height);
  } catch (const std::exception& e) {
    throw std::runtime_error(file.string() + ": cannot encode EXR: " + e.what());
  }
  io::writeFileAtomically(file, bytes.str());
}

}  // namespace wobble::image
