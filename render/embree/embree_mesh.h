// EmbreeTriangleMesh: a triangle mesh geometry whose vertices change every frame. Embree API used here:
// rtcNewGeometry(RTC_GEOMETRY_TYPE_TRIANGLE), rtcSetNewGeometryBuffer (indices), rtcSetSharedGeometryBuffer
// (vertices), rtcSetGeometryBuildQuality, rtcSetGeometryTimeStepCount, rtcUpdateGeometryBuffer, rtcCommitGeometry,
// rtcReleaseGeometry.
//
// The vertex buffer is owned here and shared with Embree: 3 floats per vertex plus one float of padding, because
// Embree reads each vertex with a 16-byte SSE load and so reads 4 bytes past the last one.
// Motion blur: with several time steps (Embree's multi-segment motion blur) the buffer holds one such block per step,
// each shared as its own vertex slot; the steps are evenly spaced over the ray time range [0, 1], and Embree
// interpolates linearly between the two around a ray's time.
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

  // Copies the positions of each time step (exactly vertex_count each; one step: a still mesh) into the buffer, then
  // rtcUpdateGeometryBuffer and rtcCommitGeometry. The scene still needs rtcCommitScene afterwards.
  void setVertices(std::span<const std::span<const Eigen::Vector3f>> steps);
  void setVertices(std::span<const Eigen::Vector3f> positions) { setVertices({&positions, 1}); }

  RTCGeometry get() const { return geometry_; }
  std::size_t vertexCount() const { return vertex_count_; }

 private:
  RTCGeometry geometry_ = nullptr;
  std::size_t vertex_count_;
  unsigned time_steps_ = 0;
  std::vector<float> vertices_;  // per time step 3 * vertex_count + 1 (padding)
};

}  // namespace wobble::render
