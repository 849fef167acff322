// BoxCollider: a solid static axis-aligned box (a step, a crate, a table top).
// Parameters: center, size (full extents along x, y, z; each > 0), restitution, friction, epsilon.
#pragma once
#include "sim/contact/colliders/collider.h"

namespace wobble {

class BoxCollider final : public Collider {
 public:
  BoxCollider(std::string name, ContactParams contact, const Vec3& center, const Vec3& size);
  std::optional<SurfacePoint> query(double t, const Vec3& x) const override;
  bool mayBeNear(double t, const Eigen::AlignedBox3d& box, double margin) const override;
  std::optional<Eigen::AlignedBox3d> bounds(double t) const override;
  bool isStatic() const override { return true; }
  const Vec3& center() const { return center_; }
  const Vec3& size() const { return size_; }

 private:
  Vec3 center_, size_;
};

}  // namespace wobble
