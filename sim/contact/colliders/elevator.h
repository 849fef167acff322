// ElevatorCollider: a horizontal square platform (normal +y) driven by a time schedule, as in the course framework:
// from rest, accelerate upward for `travel` seconds, stop dead and hold for `pause`, accelerate downward from rest
// for `travel`, stop dead and hold for `pause`; repeat. The schedule is a function of time, not of steps, so the
// motion does not depend on dt. Infinite mass: particles bounce relative to its velocity, v_n' = u_n - e (v_n - u_n).
//
// Parameters (course-framework defaults): start = [0, 1, 0] (platform top centre at t = 0), size = 5 (square side),
// thickness = 0.25 (slab depth; particles further below are not pushed up), accel = 3 (m/s^2), travel = 2 (s),
// pause = 0.001 (s) — period 4.002 s, rising 6 m and reaching 6 m/s — restitution, friction, epsilon.
#pragma once
#include "sim/contact/colliders/collider.h"

namespace wobble {

struct ElevatorSchedule {
  Vec3 start{0, 1, 0};
  double accel = 3, travel = 2, pause = 0.001;

  double period() const { return 2 * (travel + pause); }
  // Height offset above start, vertical velocity and acceleration at time t.
  double height(double t) const;
  double velocity(double t) const;
  double acceleration(double t) const;
};

class ElevatorCollider final : public Collider {
 public:
  ElevatorCollider(std::string name, ContactParams contact, ElevatorSchedule schedule, double size, double thickness);
  std::optional<SurfacePoint> query(double t, const Vec3& x) const override;
  void near(double t, const StateRef& x, double margin, std::vector<int>& out) const override;
  bool mayBeNear(double t, const Eigen::AlignedBox3d& box, double margin) const override;
  // The slab over its whole travel, from its lowest bottom to its highest top (the same at every t).
  std::optional<Eigen::AlignedBox3d> bounds(double t) const override;
  Vec3 topCenter(double t) const { return schedule_.start + Vec3(0, schedule_.height(t), 0); }
  double size() const { return size_; }
  double thickness() const { return thickness_; }
  const ElevatorSchedule& schedule() const { return schedule_; }

 private:
  ElevatorSchedule schedule_;
  double size_, thickness_;
};

}  // namespace wobble
