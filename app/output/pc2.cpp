#include "app/output/pc2.h"

#include <cstring>
#include <fstream>
#include <limits>
#include <stdexcept>

namespace wobble {
namespace {

static_assert(sizeof(float) == 4 && std::numeric_limits<float>::is_iec559);

template <typename T>
void appendLittleEndian(std::string& out, T value) {
  static_assert(sizeof(T) == 4);
  std::uint32_t bits;
  std::memcpy(&bits, &value, 4);
  for (int k = 0; k < 4; ++k) out += char((bits >> (8 * k)) & 0xff);
}

template <typename T>
T readLittleEndian(const char* bytes) {
  std::uint32_t bits = 0;
  for (int k = 0; k < 4; ++k) bits |= std::uint32_t(static_cast<unsigned char>(bytes[k])) << (8 * k);
  T value;
  std::memcpy(&value, &bits, 4);
  return value;
}

constexpr char kMagic[12] = "POINTCACHE2";  // with its terminating NUL: 12 bytes

}  // namespace

std::string encodePc2Header(const Pc2Header& h) {
  std::string out(kMagic, sizeof kMagic);
  appendLittleEndian(out, std::int32_t{1});
  appendLittleEndian(out, h.points);
  appendLittleEndian(out, h.start_frame);
  appendLittleEndian(out, h.sample_rate);
  appendLittleEndian(out, h.samples);
  return out;
}

std::string encodePc2Sample(const std::vector<Eigen::Vector3f>& points) {
  std::string out;
  out.reserve(12 * points.size());
  for (const Eigen::Vector3f& p : points)
    for (int k = 0; k < 3; ++k) appendLittleEndian(out, p[k]);
  return out;
}

Pc2File readPc2(const std::filesystem::path& file) {
  const auto fail = [&](const std::string& why) { return std::runtime_error(file.string() + ": " + why); };
  std::ifstream in(file, std::ios::binary);
  if (!in) throw fail("cannot read");
  char header[Pc2Header::kSize];
  if (!in.read(header, sizeof header)) throw fail("shorter than a PC2 header (32 bytes)");
  if (std::memcmp(header, kMagic, sizeof kMagic) != 0) throw fail("not a PC2 file (no POINTCACHE2 signature)");
  if (const auto version = readLittleEndian<std::int32_t>(header + 12); version != 1)
    throw fail("PC2 version " + std::to_string(version) + ", expected 1");
  Pc2File pc2;
  pc2.header.points = readLittleEndian<std::int32_t>(header + 16);
  pc2.header.start_frame = readLittleEndian<float>(header + 20);
  pc2.header.sample_rate = readLittleEndian<float>(header + 24);
  pc2.header.samples = readLittleEndian<std::int32_t>(header + 28);
  if (pc2.header.points < 0 || pc2.header.samples < 0) throw fail("negative point or sample count in the header");
  const std::size_t values = std::size_t(pc2.header.points) * std::size_t(pc2.header.samples) * 3;
  std::error_code ec;
  const auto size = std::filesystem::file_size(file, ec);
  std::string bytes;
  if (!ec && size >= Pc2Header::kSize + values * 4) bytes.resize(values * 4);  // checked before allocating
  if (bytes.size() != values * 4 || !in.read(bytes.data(), std::streamsize(bytes.size())))
    throw fail("shorter than its header says (" + std::to_string(pc2.header.samples) + " samples of " +
               std::to_string(pc2.header.points) + " points)");
  pc2.positions.resize(values / 3);
  for (std::size_t i = 0; i < values; ++i) pc2.positions[i / 3][int(i % 3)] = readLittleEndian<float>(&bytes[4 * i]);
  return pc2;
}

}  // namespace wobble
