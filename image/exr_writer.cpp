// Film -> multi-layer OpenEXR file (see exr_writer.h).
#include "image/exr_writer.h"

#include <stdexcept>
#include <string>

#include <vector>

#include <Imath/half.h>
#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfStdIO.h>
#include <OpenEXR/ImfStringAttribute.h>

#include "image/file_size_bound.h"
#include "io/atomic_file.h"

namespace wobble::image {

std::uint64_t exrSizeBound(int width, int height, bool denoised, const std::map<std::string, std::string>& text) {
  constexpr std::uint64_t kLinesPerBlock = 16;                 // ZIP_COMPRESSION's block
  constexpr std::uint64_t kStandardAttributes = 512;           // magic, version, windows, ... (under 300 bytes)
  const std::uint64_t halves = denoised ? 12 : 9, floats = 1;  // the channels writeExr writes
  std::uint64_t bytes = kStandardAttributes;
  for (std::string_view name : kExrChannels) bytes += name.size() + 1 + 16;  // the channel list
  if (denoised) bytes += 3 * (std::string_view("noisy.R").size() + 1 + 16);
  for (const auto& [name, value] : text) bytes += name.size() + 1 + 7 + 4 + value.size();  // "string" attributes
  const std::uint64_t blocks = (std::uint64_t(height) + kLinesPerBlock - 1) / kLinesPerBlock;
  bytes += blocks * (8 + 4 + 4);  // offset table entry, block's first line and size
  bytes += std::uint64_t(width) * std::uint64_t(height) * (2 * halves + 4 * floats);
  return bytes;
}

void writeExr(const std::filesystem::path& file, const Film& film, std::span<const Color> denoised,
              const std::map<std::string, std::string>& text) {
  const std::size_t n = std::size_t(film.width) * film.height;
  if (film.width <= 0 || film.height <= 0 || film.color.size() != n || film.albedo.size() != n ||
      film.normal.size() != n || film.depth.size() != n || (!denoised.empty() && denoised.size() != n))
    throw std::invalid_argument(file.string() + ": cannot write EXR of an empty or inconsistent film");

  Imf::Header header(film.width, film.height);
  header.compression() = Imf::ZIP_COMPRESSION;
  for (const auto& [name, value] : text) header.insert(name, Imf::StringAttribute(value));
  Imf::FrameBuffer frame;
  // OpenEXR converts pixel types when reading but not when writing: half channels need half buffers.
  std::vector<std::vector<half>> halves;
  halves.reserve(12);
  const auto addVector = [&](const std::string& layer, const char* names, std::span<const Eigen::Vector3f> values) {
    for (int k = 0; k < 3; ++k) {
      const std::string name = layer.empty() ? std::string(1, names[k]) : layer + "." + names[k];
      std::vector<half>& channel = halves.emplace_back(n);
      for (std::size_t i = 0; i < n; ++i) channel[i] = half(values[i][k]);
      header.channels().insert(name, Imf::Channel(Imf::HALF));
      frame.insert(name, Imf::Slice(Imf::HALF, reinterpret_cast<char*>(channel.data()), sizeof(half),
                                    sizeof(half) * film.width));
    }
  };
  if (denoised.empty()) {
    addVector("", "RGB", film.color);
  } else {
    addVector("", "RGB", denoised);
    addVector("noisy", "RGB", film.color);
  }
  addVector("albedo", "RGB", film.albedo);
  addVector("normal", "XYZ", film.normal);
  // OpenEXR takes non-const pointers even for writing; it only reads through them here.
  header.channels().insert("depth.Z", Imf::Channel(Imf::FLOAT));
  frame.insert("depth.Z", Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(const_cast<float*>(film.depth.data())),
                                     sizeof(float), sizeof(float) * film.width));

  // Encoded in memory, then written by the one checked writer: a full disk is reported with the OS reason.
  Imf::StdOSStream bytes;
  try {
    Imf::OutputFile out(bytes, header);
    out.setFrameBuffer(frame);
    out.writePixels(film.height);
  } catch (const std::exception& e) {
    throw std::runtime_error(file.string() + ": cannot encode EXR: " + e.what());
  }
  io::writeFileAtomically(file, bytes.str());
}

std::map<std::string, std::string> readExrText(const std::filesystem::path& file) {
  std::map<std::string, std::string> text;
  try {
    const Imf::InputFile in(file.c_str());  // reads the header only
    for (auto a = in.header().begin(); a != in.header().end(); ++a)
      if (const auto* s = dynamic_cast<const Imf::StringAttribute*>(&a.attribute())) text[a.name()] = s->value();
  } catch (const std::exception&) {
    return {};  // missing, or not an EXR: no text
  }
  return text;
}

}  // namespace wobble::image
