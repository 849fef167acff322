// MeshCollider: any triangle mesh (stairs, a ramp, a plate, a bowl), static or moving at constant velocity.
// Parameters: the mesh placed in the scene (points, triangles: counter-clockwise seen from the free side), velocity
// (default 0), restitution, friction, epsilon. Open meshes are allowed: a plate is a sheet whose front side faces up.
// query() finds the closest point on the mesh with Embree's BVH point query (rtcPointQuery, Embree 3; the closest
// point on each candidate triangle in double: Ericson, Real-Time Collision Detection, 5.1.5). The sign is the side of
// the closest triangle's plane (behind its front face: inside), and the normal is the direction from the closest point
// to the particle (the face normal at the surface itself), so edges and corners push out along their bisector.
// near() asks Embree only about particles within the margin of the mesh's bounding box (the contact code's cheap test).
#pragma once
#include <array>
#include <memory>
#include <vector>

#include "sim/contact/colliders/collider.h"

namespace wobble {

class MeshCollider final : public Collider {
 public:
  MeshCollider(std::string name, ContactParams contact, std::vector<Vec3> points,
               std::vector<std::array<int, 3>> triangles, const Vec3& velocity);
  ~MeshCollider() override;
  std::optional<SurfacePoint> query(double t, const Vec3& x) const override;
  std::optional<Eigen::AlignedBox3d> bounds(double t) const override;
  bool isStatic() const override { return velocity_.isZero(0); }
  // Skips the point query for a particle farther than margin from the mesh's box: for a closed mesh, such a particle
  // is outside at a distance of at least that, so the answer is the default's; an open mesh (a plate) touches only
  // what comes within margin of its box, never a particle far behind its sheet.
  void near(double t, const StateRef& x, double margin, std::vector<int>& out) const override;
  bool mayBeNear(double t, const Eigen::AlignedBox3d& box, double margin) const override;

  // The mesh at t = 0 in the scene's frame; at time t it is moved by offset(t).
  const std::vector<Vec3>& points() const { return points_; }
  const std::vector<std::array<int, 3>>& triangles() const { return triangles_; }
  Vec3 offset(double t) const { return t * velocity_; }

 private:
  struct Embree;
  std::vector<Vec3> points_;
  std::vector<std::array<int, 3>> triangles_;
  std::vector<Vec3> normals_;  // unit, per triangle
  Vec3 velocity_;
  Eigen::AlignedBox3d box_;
  std::unique_ptr<Embree> embree_;
};

}  // namespace wobble
