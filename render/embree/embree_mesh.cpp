// Triangle geometry with a shared, padded vertex buffer updated every frame (see embree_mesh.h).
#include "render/embree/embree_mesh.h"

#include <stdexcept>
#include <string>

namespace wobble::render {

EmbreeTriangleMesh::EmbreeTriangleMesh(RTCDevice device, std::span<const std::array<int, 3>> triangles,
                                       std::size_t vertex_count, RTCBuildQuality quality)
    : vertex_count_(vertex_count), vertices_(3 * vertex_count + 1, 0.0f) {
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
  rtcSetSharedGeometryBuffer(geometry_, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, vertices_.data(), 0,
                             3 * sizeof(float), vertex_count);
}

EmbreeTriangleMesh::~EmbreeTriangleMesh() { rtcReleaseGeometry(geometry_); }

void EmbreeTriangleMesh::setVertices(std::span<const Eigen::Vector3f> positions) {
  if (positions.size() != vertex_count_)
    throw std::invalid_argument("Embree mesh: " + std::to_string(positions.size()) + " positions for a mesh of " +
                                std::to_string(vertex_count_) + " vertices");
  for (std::size_t i = 0; i < vertex_count_; ++i)
    for (int k = 0; k < 3; ++k) vertices_[3 * i + k] = positions[i][k];
  rtcUpdateGeometryBuffer(geometry_, RTC_BUFFER_TYPE_VERTEX, 0);
  rtcCommitGeometry(geometry_);
}

}  // namespace wobble::render
