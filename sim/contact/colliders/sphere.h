// SphereCollider: a solid ball, static or moving at constant velocity (the cloth scene's obstacle).
// Parameters: center (at t = 0), radius (> 0), velocity (default 0), restitution, friction, epsilon.
#pragma once
#include "sim/contact/colliders/collider.h"

namespace wobble {

class SphereCollider final : public Collider {
 public:
  SphereCollider(std::string name, ContactParams contact, const Vec3& center, double radius, const Vec3& velocity);
  std::optional<SurfacePoint> query(double t, const Vec3& x) const override;
  void near(double t, const StateRef& x, double margin, std::vector<int>& out) const override;
  bool mayBeNear(double t, const Eigen::AlignedBox3d& box, double margin) const override;
  std::optional<Eigen::AlignedBox3d> bounds(double t) const override;
  bool isStatic() const override { return velocity_.isZero(0); }
  Vec3 center(double t) const { return center_ + t * velocity_; }
  double radius() const { return radius_; }

 private:
  Vec3 center_;
  double radius_;
  Vec3 velocity_;
};

}  // namespace wobble
