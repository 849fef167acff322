// PlaneCollider: an infinite static plane (the half-space below it is solid).
// Parameters: point (on the plane), normal (any length; normalized), size (drawn extent, renderer only),
// restitution, friction, epsilon. The slope of the course framework is the plane through the origin with normal
// (sin 20deg, cos 20deg, 0).
#pragma once
#include "sim/contact/colliders/collider.h"

namespace wobble {

class PlaneCollider final : public Collider {
 public:
  PlaneCollider(std::string name, ContactParams contact, const Vec3& point, const Vec3& normal);
  std::optional<SurfacePoint> query(double t, const Vec3& x) const override;
  void near(double t, const StateRef& x, double margin, std::vector<int>& out) const override;
  bool mayBeNear(double t, const Eigen::AlignedBox3d& box, double margin) const override;
  std::optional<HalfSpace> halfSpace(double) const override { return HalfSpace{point_, normal_}; }
  std::optional<Eigen::AlignedBox3d> bounds(double) const override { return std::nullopt; }  // infinite
  bool isStatic() const override { return true; }
  const Vec3& point() const { return point_; }
  const Vec3& normal() const { return normal_; }

 private:
  Vec3 point_, normal_;
};

}  // namespace wobble
