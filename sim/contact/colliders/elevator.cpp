#include "sim/contact/colliders/elevator.h"

#include <cmath>

namespace wobble {
namespace {

enum class Phase { Rise, HoldTop, Fall, HoldBottom };

// Phase at time t and the time since that phase began.
std::pair<Phase, double> phaseAt(const ElevatorSchedule& s, double t) {
  double tau = t <= 0 ? 0 : std::fmod(t, s.period());
  if (tau < s.travel) return {Phase::Rise, tau};
  tau -= s.travel;
  if (tau < s.pause) return {Phase::HoldTop, tau};
  tau -= s.pause;
  if (tau < s.travel) return {Phase::Fall, tau};
  return {Phase::HoldBottom, tau - s.travel};
}

}  // namespace

double ElevatorSchedule::height(double t) const {
  const auto [phase, tau] = phaseAt(*this, t);
  const double top = 0.5 * accel * travel * travel;
  switch (phase) {
    case Phase::Rise:
      return 0.5 * accel * tau * tau;
    case Phase::HoldTop:
      return top;
    case Phase::Fall:
      return top - 0.5 * accel * tau * tau;
    case Phase::HoldBottom:
      return 0;
  }
  return 0;
}

double ElevatorSchedule::velocity(double t) const {
  const auto [phase, tau] = phaseAt(*this, t);
  if (phase == Phase::Rise) return accel * tau;
  if (phase == Phase::Fall) return -accel * tau;
  return 0;
}

double ElevatorSchedule::acceleration(double t) const {
  const auto [phase, tau] = phaseAt(*this, t);
  if (phase == Phase::Rise) return accel;
  if (phase == Phase::Fall) return -accel;
  return 0;
}

ElevatorCollider::ElevatorCollider(std::string name, ContactParams contact, ElevatorSchedule schedule, double size,
                                   double thickness)
    : Collider(std::move(name), contact), schedule_(schedule), size_(size), thickness_(thickness) {}

std::optional<SurfacePoint> ElevatorCollider::query(double t, const Vec3& x) const {
  const Vec3 top = topCenter(t);
  const double half = size_ / 2, distance = x.y() - top.y();
  if (std::abs(x.x() - top.x()) > half || std::abs(x.z() - top.z()) > half || distance < -thickness_)
    return std::nullopt;
  return SurfacePoint{distance, Vec3::UnitY(), Vec3(0, schedule_.velocity(t), 0),
                      Vec3(0, schedule_.acceleration(t), 0)};
}

void ElevatorCollider::near(double t, const StateRef& x, double margin, std::vector<int>& out) const {
  out.clear();
  const Vec3 top = topCenter(t);  // query's tests, once per call instead of once per particle
  const double half = size_ / 2;
  const int n = static_cast<int>(x.size() / 3);
  out.reserve(n);  // once: the list never reallocates while a body settles onto the collider
  for (int i = 0; i < n; ++i) {
    const Vec3 p = particle(x, i);
    const double distance = p.y() - top.y();
    if (std::abs(p.x() - top.x()) <= half && std::abs(p.z() - top.z()) <= half && distance >= -thickness_ &&
        distance < margin)
      out.push_back(i);
  }
}

bool ElevatorCollider::mayBeNear(double t, const Eigen::AlignedBox3d& box, double margin) const {
  // near()'s slab, widened by the slack: does the box reach into it?
  const Vec3 top = topCenter(t);
  const double half = size_ / 2, slack = roundOffSlack(magnitude(box) + top.cwiseAbs().maxCoeff() + half + thickness_);
  const Vec3 &lo = box.min(), &hi = box.max();
  return hi.x() >= top.x() - half - slack && lo.x() <= top.x() + half + slack && hi.z() >= top.z() - half - slack &&
         lo.z() <= top.z() + half + slack && hi.y() - top.y() >= -thickness_ - slack &&
         lo.y() - top.y() < margin + slack;
}

std::optional<Eigen::AlignedBox3d> ElevatorCollider::bounds(double) const {
  const Vec3 half(size_ / 2, 0, size_ / 2);
  const Vec3 bottom = topCenter(0) - half - Vec3(0, thickness_, 0);
  const Vec3 top = topCenter(0) + half + Vec3(0, schedule_.accel * schedule_.travel * schedule_.travel / 2, 0);
  return Eigen::AlignedBox3d(bottom, top);
}

}  // namespace wobble
