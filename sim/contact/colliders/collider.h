// A collider is a surface particles cannot pass. It only answers geometry: the nearest surface point to a particle
// at a time, with the surface's velocity and acceleration there. The response (restitution, penetration
// correction, contact force, friction) is shared by every collider and lives in contact/colliders/response.h.
#pragma once
#include <algorithm>
#include <optional>
#include <string>
#include <vector>

#include "sim/types.h"

namespace wobble {

// Course-framework defaults: epsilon 0.01, restitution (coefResist) 0.8, friction (coefFriction) 0.5.
struct ContactParams {
  double restitution = 0.8;  // in [0, 1]: normal speed kept after a bounce, relative to the surface
  double friction = 0.5;     // Coulomb coefficient, >= 0
  double epsilon = 0.01;     // contact tolerance (m), > 0
};

struct SurfacePoint {
  double distance;    // signed: negative inside
  Vec3 normal;        // unit, outward
  Vec3 velocity;      // of the surface at that point
  Vec3 acceleration;  // of the surface at that point
};

// A half-space's boundary plane: what a plane collider's near() tests, normal.dot(x - point) < margin.
struct HalfSpace {
  Vec3 point, normal;
};

class Collider {
 public:
  Collider(std::string name, ContactParams contact) : name_(std::move(name)), contact_(contact) {}
  virtual ~Collider() = default;

  // Nearest surface point to x at time t, or nothing where the collider cannot touch x at all.
  virtual std::optional<SurfacePoint> query(double t, const Vec3& x) const = 0;
  // Replaces out by the particles of x (flat, 3 per particle) whose query() distance at t is below margin (inside
  // included), in index order: the cheap test contact code runs before it asks query() anything. The default asks
  // query() itself; colliders override it with a tight loop over the coordinates.
  virtual void near(double t, const StateRef& x, double margin, std::vector<int>& out) const;
  // Whether near(t, ., margin) could keep any point of box: false only where it keeps none (a conservative test,
  // with slack for round-off). Contact asks it for each cell of an embedded surface before it blends the cell's
  // points (contact/colliders/response.h, nearPoints). The default (true) is always safe; colliders override it with a
  // box test.
  virtual bool mayBeNear(double t, const Eigen::AlignedBox3d& box, double margin) const;
  // For a collider whose near(t, ., margin) keeps exactly the x with normal.dot(x - point) < margin (a plane): that
  // half-space. Contact then bounds an embedded surface's points by blending that one number per particle instead of
  // boxes (contact/colliders/response.h, nearPoints). Nothing, the default, for every other surface.
  virtual std::optional<HalfSpace> halfSpace(double) const { return std::nullopt; }

  // A box holding the solid at time t (one that moves on a repeating schedule: over its whole cycle), or nothing if it
  // is unbounded (a plane). Used to frame a camera around the action.
  virtual std::optional<Eigen::AlignedBox3d> bounds(double t) const = 0;
  // Whether the surface stands still at every time (its velocity and acceleration 0 everywhere): then it does no work
  // on the bodies, and MassSpringSystem::colliderWork skips it. The default (false) is always safe.
  virtual bool isStatic() const { return false; }

  const std::string& name() const { return name_; }
  const ContactParams& contact() const { return contact_; }

 private:
  std::string name_;
  ContactParams contact_;
};

// Slack for the round-off of a test at coordinates of this size: far above it, far below any distance that matters.
inline double roundOffSlack(double magnitude) { return 1e-9 * (1 + magnitude); }

// The largest absolute coordinate of a box.
inline double magnitude(const Eigen::AlignedBox3d& box) {
  return std::max(box.min().cwiseAbs().maxCoeff(), box.max().cwiseAbs().maxCoeff());
}

}  // namespace wobble
