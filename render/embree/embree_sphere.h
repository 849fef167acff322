// EmbreeSphere: one analytic sphere, Embree's RTC_GEOMETRY_TYPE_SPHERE_POINT primitive (ray-sphere intersection,
// exact silhouette). Embree API used here: rtcNewGeometry, rtcSetNewGeometryBuffer (one float4: x, y, z, radius),
// rtcSetGeometryTimeStepCount, rtcUpdateGeometryBuffer, rtcCommitGeometry, rtcReleaseGeometry.
// Parameters: device; set(center, radius) moves it (the scene still needs rtcCommitScene afterwards); set(steps)
// gives it a pose per time step, evenly spaced over the ray time range [0, 1] (motion blur, as embree_mesh.h).
#pragma once
#include <span>
#include <vector>

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
  struct Pose {
    Eigen::Vector3f center;
    float radius;
  };
  void set(std::span<const Pose> steps);
  RTCGeometry get() const { return geometry_; }

 private:
  RTCGeometry geometry_ = nullptr;
  std::vector<float*> vertex_;  // one per time step, Embree-owned (padded by Embree itself)
};

}  // namespace wobble::render
