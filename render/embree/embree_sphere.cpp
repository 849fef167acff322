// One Embree SPHERE_POINT primitive (see embree_sphere.h).
#include "render/embree/embree_sphere.h"

#include <stdexcept>

namespace wobble::render {

EmbreeSphere::EmbreeSphere(RTCDevice device) {
  geometry_ = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_SPHERE_POINT);
  if (!geometry_) throw std::runtime_error("Embree: cannot create a sphere geometry");
  vertex_ = static_cast<float*>(
      rtcSetNewGeometryBuffer(geometry_, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4, 4 * sizeof(float), 1));
  if (!vertex_) throw std::runtime_error("Embree: cannot allocate a sphere vertex buffer");
}

EmbreeSphere::~EmbreeSphere() { rtcReleaseGeometry(geometry_); }

void EmbreeSphere::set(const Eigen::Vector3f& center, float radius) {
  vertex_[0] = center.x();
  vertex_[1] = center.y();
  vertex_[2] = center.z();
  vertex_[3] = radius;
  rtcUpdateGeometryBuffer(geometry_, RTC_BUFFER_TYPE_VERTEX, 0);
  rtcCommitGeometry(geometry_);
}

}  // namespace wobble::render
