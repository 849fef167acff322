// EmbreeTriangleMesh: a triangle mesh geometry whose vertices change every frame. Embree API used here:
// rtcNewGeometry(RTC_GEOMETRY_TYPE_TRIANGLE), rtcSetNewGeometryBuffer (indices), rtcSetSharedGeometryBuffer
// (vertices), rtcSetGeometryBuildQuality, rtcUpdateGeometryBuffer, rtcCommitGeometry, rtcReleaseGeometry.
//
// The vertex buffer is owned here and shared with Embree: 3 floats per vertex plus one float of padding, because
// Embree reads each vertex with a 16-byte SSE load and so reads 4 bytes past the last one.
// Parameters: device, triangles (vertex indices, counter-clockwise from outside), vertex count, build quality
// (RTC_BUILD_QUALITY_LOW or MEDIUM rebuild the BVH of this mesh on every commit, REFIT only refits it).
// The caller validates the values (mesh.h): this class only moves them into Embree.
#pragma once
#include <array>
#include <span>
#include <vector>

#include <embree3/rtcore.h>
#include <Eigen/Core>

namespace wobble::render {

class EmbreeTriangleMesh {
 public:
  EmbreeTriangleMesh(RTCDevice device, std::span<const std::array<int, 3>> triangles, std::size_t vertex_count,
                     RTCBuildQuality quality);
  ~EmbreeTriangleMesh();
  EmbreeTriangleMesh(const EmbreeTriangleMesh&) = delete;
  EmbreeTriangleMesh& operator=(const EmbreeTriangleMesh&) = delete;

  // Copies positions (exactly vertex_count of them) into the buffer, then rtcUpdateGeometryBuffer and
  // rtcCommitGeometry. The scene still needs rtcCommitScene afterwards.
  void setVertices(std::span<const Eigen::Vector3f> positions);

  RTCGeometry get() const { return geometry_; }
  std::size_t vertexCount() const { return vertex_count_; }

 private:
  RTCGeometry geometry_ = nullptr;
  std::size_t vertex_count_;
  std::vector<float> vertices_;  // 3 * vertex_count + 1 (padding)
};

}  // namespace wobble::render
