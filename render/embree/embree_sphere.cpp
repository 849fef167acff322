// One Embree SPHERE_POINT primitive (see embree_sphere.h).
#include "render/embree/embree_sphere.h"

#include <stdexcept>

namespace wobble::render {

EmbreeSphere::EmbreeSphere(RTCDevice device) {
  geometry_ = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_SPHERE_POINT);
  if (!geometry_) throw std::runtime_error("Embree: cannot create a sphere geometry");
}

EmbreeSphere::~EmbreeSphere() { rtcReleaseGeometry(geometry_); }

void EmbreeSphere::set(const Eigen::Vector3f& center, float radius) {
  const Pose pose{center, radius};
  set({&pose, 1});
}

void EmbreeSphere::set(std::span<const Pose> steps) {
  if (steps.empty()) throw std::invalid_argument("Embree sphere: no time step");
  if (steps.size() != vertex_.size()) {
    vertex_.clear();
    rtcSetGeometryTimeStepCount(geometry_, static_cast<unsigned>(steps.size()));
    for (unsigned k = 0; k < steps.size(); ++k) {
      vertex_.push_back(static_cast<float*>(
          rtcSetNewGeometryBuffer(geometry_, RTC_BUFFER_TYPE_VERTEX, k, RTC_FORMAT_FLOAT4, 4 * sizeof(float), 1)));
      if (!vertex_.back()) throw std::runtime_error("Embree: cannot allocate a sphere vertex buffer");
    }
  }
  for (unsigned k = 0; k < steps.size(); ++k) {
    float* v = vertex_[k];
    v[0] = steps[k].center.x();
    v[1] = steps[k].center.y();
    v[2] = steps[k].center.z();
    v[3] = steps[k].radius;
    rtcUpdateGeometryBuffer(geometry_, RTC_BUFFER_TYPE_VERTEX, k);
  }
  rtcCommitGeometry(geometry_);
}

}  // namespace wobble::render
