#include "sphere.h"

namespace wobble {

Sphere::Sphere(std::string name, ContactParams contact, const Vec3& center, double radius, const Vec3& velocity)
    : Collider(std::move(name), contact), center_(center), radius_(radius), velocity_(velocity) {}

std::optional<SurfacePoint> Sphere::query(double t, const Vec3& x) const {
  const Vec3 d = x - center(t);
  const double len = d.norm();
  const Vec3 normal = len > 0 ? Vec3(d / len) : Vec3::UnitY();
  return SurfacePoint{len - radius_, normal, velocity_, Vec3::Zero()};
}

}  // namespace wobble
