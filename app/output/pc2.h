// The PC2 point cache format, as Blender's Mesh Cache modifier and 3ds Max's Point Cache 2 read it: a 32-byte header,
// then for each sample every point's x, y, z; all little-endian.
//   char[12] "POINTCACHE2\0", int32 version (1), int32 point count, float32 start frame, float32 sample rate (frames
//   between samples), int32 sample count
// wobble writes one per body (pc2_writer.h): points in ObjVertexOrder, one sample per frame from the first frame
// written, Y up and metres like the OBJ files.
#pragma once
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace wobble {

struct Pc2Header {
  std::int32_t points = 0;
  float start_frame = 1;
  float sample_rate = 1;
  std::int32_t samples = 0;

  static constexpr std::size_t kSize = 32;
  static constexpr std::size_t kSamplesOffset = 28;  // where the sample count is, rewritten as samples are added
};

std::string encodePc2Header(const Pc2Header& header);
// x, y, z of each point, float32 little-endian: one sample's bytes.
std::string encodePc2Sample(const std::vector<Eigen::Vector3f>& points);

struct Pc2File {
  Pc2Header header;
  std::vector<Eigen::Vector3f> positions;  // sample-major: positions[sample * points + point]

  const Eigen::Vector3f& at(int sample, int point) const {
    return positions[std::size_t(sample) * std::size_t(header.points) + std::size_t(point)];
  }
};

// Throws std::runtime_error naming the file: unreadable, not PC2 version 1, or shorter than its header says.
Pc2File readPc2(const std::filesystem::path& file);

}  // namespace wobble
