// Triangle geometry with a shared, padded vertex buffer updated every frame (see embree_mesh.h).
#include "render/embree/embree_mesh.h"

#include <stdexcept>
#include <string>

namespace wobble::render {

EmbreeTriangleMesh::EmbreeTriangleMesh(RTCDevice device, std::span<const std::array<int, 3>> triangles,
                                       std::size_t vertex_count, RTCBuildQuality quality)
    : vertex_count_(vertex_count) {
  geometry_ = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
  if (!geometry_) throw std::runtime_error("Embree: cannot create a triangle geometry");
  rtcSetGeometryBuildQuality(geometry_, quality);
  auto* index = static_cast<unsigned*>(rtcSetNewGeometryBuffer(geometry_, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                               3 * sizeof(unsigned), triangles.size()));
  if (!index)
    throw std::runtime_error("Embree: cannot allocate an index buffer of " + std::to_string(triangles.size()) +
                             " triangles");
  for (std::size_t t = 0; t < triangles.size(); ++t)
    for (int k = 0; k < 3; ++k) index[3 * t + k] = static_cast<unsigned>(triangles[t][k]);
}

EmbreeTriangleMesh::~EmbreeTriangleMesh() { rtcReleaseGeometry(geometry_); }

void EmbreeTriangleMesh::setVertices(std::span<const std::span<const Eigen::Vector3f>> steps) {
  const auto count = static_cast<unsigned>(steps.size());
  if (count == 0) throw std::invalid_argument("Embree mesh: no time step");
  for (const auto& positions : steps)
    if (positions.size() != vertex_count_)
      throw std::invalid_argument("Embree mesh: " + std::to_string(positions.size()) + " positions for a mesh of " +
                                  std::to_string(vertex_count_) + " vertices");
  const std::size_t block = 3 * vertex_count_ + 1;
  if (count != time_steps_) {  // a new step count: a new buffer, each step's block shared as its own slot
    time_steps_ = count;
    vertices_.assign(block * count, 0.0f);
    rtcSetGeometryTimeStepCount(geometry_, count);
    for (unsigned k = 0; k < count; ++k)
      rtcSetSharedGeometryBuffer(geometry_, RTC_BUFFER_TYPE_VERTEX, k, RTC_FORMAT_FLOAT3, vertices_.data() + k * block,
                                 0, 3 * sizeof(float), vertex_count_);
  }
  for (unsigned k = 0; k < count; ++k) {
    float* out = vertices_.data() + k * block;
    for (std::size_t i = 0; i < vertex_count_; ++i)
      for (int c = 0; c < 3; ++c) out[3 * i + c] = steps[k][i][c];
    rtcUpdateGeometryBuffer(geometry_, RTC_BUFFER_TYPE_VERTEX, k);
  }
  rtcCommitGeometry(geometry_);
}

}  // namespace wobble::render
