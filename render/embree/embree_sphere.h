// EmbreeSphere: one analytic sphere, Embree's RTC_GEOMETRY_TYPE_SPHERE_POINT primitive (ray-sphere intersection,
// exact silhouette). Embree API used here: rtcNewGeometry, rtcSetNewGeometryBuffer (one float4: x, y, z, radius),
// rtcUpdateGeometryBuffer, rtcCommitGeometry, rtcReleaseGeometry.
// Parameters: device; set(center, radius) moves it (the scene still needs rtcCommitScene afterwards).
#pragma once
#include <embree3/rtcore.h>
#include <Eigen/Core>

namespace wobble::render {

class EmbreeSphere {
 public:
  explicit EmbreeSphere(RTCDevice device);
  ~EmbreeSphere();
  EmbreeSphere(const EmbreeSphere&) = delete;
  EmbreeSphere& operator=(const EmbreeSphere&) = delete;

  void set(const Eigen::Vector3f& center, float radius);
  RTCGeometry get() const { return geometry_; }

 private:
  RTCGeometry geometry_ = nullptr;
  float* vertex_ = nullptr;  // Embree-owned (padded by Embree itself)
};

}  // namespace wobble::render
