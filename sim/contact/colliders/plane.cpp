#include "sim/contact/colliders/plane.h"

namespace wobble {

PlaneCollider::PlaneCollider(std::string name, ContactParams contact, const Vec3& point, const Vec3& normal)
    : Collider(std::move(name), contact), point_(point), normal_(normal.normalized()) {}

std::optional<SurfacePoint> PlaneCollider::query(double, const Vec3& x) const {
  return SurfacePoint{normal_.dot(x - point_), normal_, Vec3::Zero(), Vec3::Zero()};
}

void PlaneCollider::near(double, const StateRef& x, double margin, std::vector<int>& out) const {
  out.clear();
  const int n = static_cast<int>(x.size() / 3);
  out.reserve(n);  // once: the list never reallocates while a body settles onto the collider
  for (int i = 0; i < n; ++i)
    if (normal_.dot(particle(x, i) - point_) < margin) out.push_back(i);  // query's distance, exactly
}

bool PlaneCollider::mayBeNear(double, const Eigen::AlignedBox3d& box, double margin) const {
  // The box's lowest point above the plane: the corner the normal points away from.
  Vec3 low;
  for (int a = 0; a < 3; ++a) low[a] = normal_[a] >= 0 ? box.min()[a] : box.max()[a];
  return normal_.dot(low - point_) < margin + roundOffSlack(magnitude(box) + point_.cwiseAbs().maxCoeff());
}

}  // namespace wobble
