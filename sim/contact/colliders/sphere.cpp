#include "sim/contact/colliders/sphere.h"

namespace wobble {

SphereCollider::SphereCollider(std::string name, ContactParams contact, const Vec3& center, double radius,
                               const Vec3& velocity)
    : Collider(std::move(name), contact), center_(center), radius_(radius), velocity_(velocity) {}

std::optional<SurfacePoint> SphereCollider::query(double t, const Vec3& x) const {
  const Vec3 d = x - center(t);
  const double len = d.norm();
  const Vec3 normal = len > 0 ? Vec3(d / len) : Vec3::UnitY();
  return SurfacePoint{len - radius_, normal, velocity_, Vec3::Zero()};
}

void SphereCollider::near(double t, const StateRef& x, double margin, std::vector<int>& out) const {
  out.clear();
  const Vec3 c = center(t);
  // |x - c| - r < margin without a square root; a hair wider than that, so round-off never drops a particle
  // query() would keep (the contact code then tests query()'s distance itself).
  const double reach = (radius_ + margin) * (1 + 1e-9), reach2 = reach * reach;
  const int n = static_cast<int>(x.size() / 3);
  out.reserve(n);  // once: the list never reallocates while a body settles onto the collider
  const double* p = x.data();
  for (int i = 0; i < n; ++i, p += 3) {
    const double dx = p[0] - c.x(), dy = p[1] - c.y(), dz = p[2] - c.z();
    if (dx * dx + dy * dy + dz * dz < reach2) out.push_back(i);
  }
}

bool SphereCollider::mayBeNear(double t, const Eigen::AlignedBox3d& box, double margin) const {
  const Vec3 c = center(t);  // near()'s reach, and slack for the box's round-off
  const double reach = (radius_ + margin) * (1 + 1e-9) + roundOffSlack(magnitude(box) + c.cwiseAbs().maxCoeff());
  return box.squaredExteriorDistance(c) < reach * reach;
}

std::optional<Eigen::AlignedBox3d> SphereCollider::bounds(double t) const {
  return Eigen::AlignedBox3d(center(t) - Vec3::Constant(radius_), center(t) + Vec3::Constant(radius_));
}

}  // namespace wobble
