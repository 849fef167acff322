#include "sim/contact/colliders/box.h"

#include <cmath>

namespace wobble {

BoxCollider::BoxCollider(std::string name, ContactParams contact, const Vec3& center, const Vec3& size)
    : Collider(std::move(name), contact), center_(center), size_(size) {}

// Signed distance to the box surface: outside, the distance to the nearest point of the box, with the normal
// towards x; inside, minus the distance to the nearest face, with that face's normal.
std::optional<SurfacePoint> BoxCollider::query(double, const Vec3& x) const {
  const Vec3 d = x - center_;
  const Vec3 q = d.cwiseAbs() - size_ / 2;
  const Vec3 outside = q.cwiseMax(0.0);
  if (outside.squaredNorm() > 0) {
    const Vec3 normal = (outside.array() * d.array().sign()).matrix().normalized();
    return SurfacePoint{outside.norm(), normal, Vec3::Zero(), Vec3::Zero()};
  }
  Eigen::Index axis;
  const double distance = q.maxCoeff(&axis);
  Vec3 normal = Vec3::Zero();
  normal[axis] = d[axis] < 0 ? -1 : 1;
  return SurfacePoint{distance, normal, Vec3::Zero(), Vec3::Zero()};
}

bool BoxCollider::mayBeNear(double, const Eigen::AlignedBox3d& box, double margin) const {
  // query()'s distance is at least the Euclidean distance to the solid (negative only inside it).
  const Eigen::AlignedBox3d solid(center_ - size_ / 2, center_ + size_ / 2);
  const double slack = roundOffSlack(magnitude(box) + magnitude(solid));
  return std::sqrt(box.squaredExteriorDistance(solid)) < std::max(margin, 0.0) + slack;
}

std::optional<Eigen::AlignedBox3d> BoxCollider::bounds(double) const {
  return Eigen::AlignedBox3d(center_ - size_ / 2, center_ + size_ / 2);
}

}  // namespace wobble
