#include "plane.h"

namespace wobble {

Plane::Plane(std::string name, ContactParams contact, const Vec3& point, const Vec3& normal)
    : Collider(std::move(name), contact), point_(point), normal_(normal.normalized()) {}

std::optional<SurfacePoint> Plane::query(double, const Vec3& x) const {
  return SurfacePoint{normal_.dot(x - point_), normal_, Vec3::Zero(), Vec3::Zero()};
}

}  // namespace wobble
