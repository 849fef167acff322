#include "sim/system.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>
#include <tuple>

#include "sim/contact/colliders/response.h"
#include "sim/contact/constraints/constraints.h"
#include "sim/contact/pair_set.h"
#include "sim/force_jacobian.h"
#include "sim/solver/pair_block_matrix.h"
#include "sim/spring_runs.h"

namespace wobble {
namespace {

void appendTo(VecX& v, const VecX& tail) {
  const Eigen::Index n = v.size();
  v.conservativeResize(n + tail.size());
  v.tail(tail.size()) = tail;
}

}  // namespace

void MassSpringSystem::addBody(Body body) {
  const int first = particleCount(), count = body.particleCount();
  appendTo(x0_, body.x);
  appendTo(v0_, body.v);
  appendTo(mass_, body.mass);
  VecX inv_mass = body.mass.cwiseInverse(), drag = VecX::Constant(count, body.drag);
  for (int i = 0; i < count; ++i)
    if (body.pinned[i]) {
      inv_mass[i] = 0;
      particle(v0_, first + i).setZero();
    }
  appendTo(inv_mass_, inv_mass);
  const SurfaceMesh& surface = body.surface;
  if (!surface.embedded.empty()) {
    std::vector<char> used(surface.embedded.size(), 0);
    for (const auto& t : surface.triangles)
      for (const int vertex : t) used[surface.particle[vertex]] = 1;
    for (std::size_t e = 0; e < used.size(); ++e)
      if (used[e]) points_.add(surface.embedded[e].particle, surface.embedded[e].weight, first, inv_mass_);
    inv_mass.setZero();
  }
  appendTo(collider_inv_mass_, inv_mass);
  particles_meet_colliders_ = (collider_inv_mass_.array() != 0).any();
  appendTo(drag_, drag);
  springs_.append(body.springs, first);
  // The springs go into the schedule's order once, here, so every force and Jacobian loop runs over them in turn.
  schedule_ = PairSchedule(springs_.a, springs_.b, particleCount());
  springs_ = springs_.permuted(schedule_.order());
  ++schedule_builds_;
  bodies_.push_back({std::move(body), first});
  body_firsts_.push_back(first);
}

void MassSpringSystem::smoothForce(double, const VecX& x, const VecX& v, VecX& f) const {
  const int n = particleCount();
  const bool threads = parallel();
  f.resize(3 * n);
  forEachChunk(n, threads, [&](int begin, int end) {
    for (int i = begin; i < end; ++i) particle(f, i) = mass_[i] * gravity_ - drag_[i] * particle(v, i);
  });
  schedule_.runByRuns(threads, [&](std::span<const PairRun> runs) { addSpringForces(springs_, runs, x, v, f); });
}

void MassSpringSystem::force(double t, const VecX& x, const VecX& v, VecX& f) const {
  smoothForce(t, x, v, f);
  // Contact support cancels the net push of the other forces, so it is added last.
  addContactForces(particleColliders(), t, x, v, mass_, collider_inv_mass_, stick_time_, f);
  addContactForces(colliders_, points_, t, x, v, inv_mass_, stick_time_, f);
}

void MassSpringSystem::addForceJacobians(double, const VecX& x, const VecX&, Triplets& dfdx, Triplets& dfdv) const {
  addSpringJacobians(springs_, x, dfdx, dfdv);
  addDragJacobian(drag_, dfdv);
}

void MassSpringSystem::fillJacobian(double, const VecX& x, const VecX&, double cx, double cv, PairBlockMatrix& a,
                                    const VecX* w, VecX* kw) const {
  if (!a.fits(schedule_)) throw std::invalid_argument("fillJacobian: the matrix is not sized for this system");
  const int n = particleCount();
  const bool threads = parallel();
  if (kw) kw->setZero(3 * n);
  forEachChunk(n, threads, [&](int begin, int end) {
    for (int i = begin; i < end; ++i) a.self()[i] = cv * drag_[i];
  });
  schedule_.runByRuns(threads, [&](std::span<const PairRun> runs) {
    fillSpringBlocks(springs_, runs, x, cx, cv, a.pair(), w, kw);
  });
}

void MassSpringSystem::contactConstraints(double t, const VecX& x, const VecX& v, std::vector<ContactConstraint>& out,
                                          std::vector<ReleasedSupport>* released) const {
  out.clear();
  if (released) released->clear();
  if (colliders_.empty()) return;
  thread_local VecX f;  // kept between calls: no allocation per step
  smoothForce(t, x, v, f);
  findContactConstraints(colliders_, t, stick_time_ / 2, x, v, f, mass_, collider_inv_mass_, out,  // h: setStepSize
                         released);
  // The embedded points' supports, as the accelerations add them (after the particles'), all released: the implicit
  // step holds the points by colliderPairs' penalty instead.
  if (points_.empty() || !released) return;
  addContactForces(particleColliders(), t, x, v, mass_, collider_inv_mass_, stick_time_, f);
  addContactForces(colliders_, points_, t, x, v, inv_mass_, stick_time_, f, released);
}

bool MassSpringSystem::impactConstraints(double t, double h, const VecX& x0, const VecX& v0, const VecX& x1,
                                         const VecX& v1, std::vector<ContactConstraint>& out) const {
  return addImpactConstraints(colliders_, t, h, x0, v0, x1, v1, collider_inv_mass_, out);
}

bool MassSpringSystem::colliderPairs(double t, double h, const VecX& x0, const VecX& v0, const VecX& x1,
                                     std::vector<ContactPair>& out) const {
  if (points_.empty()) return false;
  thread_local std::vector<int> near;  // kept between calls: no allocation per step
  thread_local VecX at;
  thread_local CellBoxes cells;
  thread_local ContactPairSet known;  // the points' pairs already in out
  known.assign(out, [](const ContactPair& c) { return c.element[0] < 0; });
  const std::size_t before = out.size();
  for (std::size_t k = 0; k < colliders_.size(); ++k) {
    const Collider& collider = *colliders_[k];
    // Within the band, as the particles' resting constraints: a pair not pressed stays out of the solve, and a
    // resting point whose pair the last step left active is found again even when the step's first guess lifts it.
    const double band = collider.contact().epsilon;
    cells.clear();
    nearPoints(collider, t + h, points_, x1, cells, band, near, at);
    for (std::size_t j = 0; j < near.size(); ++j) {
      const int p = near[j];
      if (points_[p].inverse_mass == 0) continue;
      const Vec3 end = particle(at, Eigen::Index(j));
      const auto s = collider.query(t + h, end);
      if (!s || !(s->distance < band)) continue;
      // Negative first entry: apart from the pairs between bodies, whose elements are surface vertices.
      const std::array<int, 4> element{-1 - int(k), p, 0, 0};
      if (known.contains(element)) continue;
      ContactPair pair{element, {}, s->normal, 0, collider.contact().friction};
      for (int i = 0; i < 8; ++i) pair.stencil.add(points_[p].particle[i], points_[p].weight[i]);
      pair.collider = true;
      pair.surface = s->normal.dot(end) - s->distance;  // the tangent plane at the nearest surface point at t + h
      // Restitution's bounce on the approach at the step's start, as addImpactConstraints gives a particle.
      const auto start = collider.query(t, points_.blend(x0, p));
      const double approach = s->normal.dot(points_.blend(v0, p) - (start ? start->velocity : s->velocity));
      pair.rise = h * (s->normal.dot(s->velocity) + collider.contact().restitution * std::max(0.0, -approach));
      out.push_back(pair);
    }
  }
  return out.size() > before;
}

void MassSpringSystem::acceleration(double t, const VecX& x, const VecX& v, VecX& a) const {
  force(t, x, v, a);
  forEachChunk(particleCount(), parallel(), [&](int begin, int end) {
    for (int i = begin; i < end; ++i) particle(a, i) *= inv_mass_[i];
  });
}

void MassSpringSystem::resolveCollisions(double t, VecX& x, VecX& v, const VecX* v_start) const {
  wobble::resolveCollisions(particleColliders(), t, x, v, collider_inv_mass_, v_start);
  wobble::resolveCollisions(colliders_, points_, t, x, v, inv_mass_, v_start);
}

double MassSpringSystem::colliderWork(double t, double h, const VecX& x0, const VecX& v0, const VecX& x1,
                                      const VecX& v1) const {
  // Static colliders do no work: nothing to look up (the points' blends below cost as much as a force evaluation).
  if (std::all_of(colliders_.begin(), colliders_.end(), [](const auto& c) { return c->isStatic(); })) return 0;
  // Every particle that may have touched a collider during the step (at either end within epsilon plus the distance
  // it moves relative to the surface in a step: an implicit step's impact leaves it bouncing above the surface at
  // both ends) is given the velocity of the nearest surface it touched (a static one's is 0); an embedded point's
  // particles, the velocity of the surface their point touched.
  const int n = particleCount();
  thread_local std::vector<int> near;  // kept between calls: no allocation per step
  thread_local std::vector<double> nearest;
  thread_local std::vector<const Collider*> surface;
  thread_local std::vector<int> touched;
  nearest.assign(std::size_t(n), std::numeric_limits<double>::infinity());
  surface.resize(std::size_t(n));
  touched.clear();
  double reach = 0;  // the farthest a particle moves in the step
  for (int i = 0; i < n; ++i) reach = std::max(reach, h * std::max(particle(v0, i).norm(), particle(v1, i).norm()));
  const auto claim = [&](int i, double distance, const Collider* c) {
    if (inv_mass_[i] == 0 || !(distance < nearest[i])) return;
    if (std::isinf(nearest[i])) touched.push_back(i);
    nearest[i] = distance;
    surface[i] = c;
  };
  // The particles colliders meet, then the embedded points (those of the cells near the collider,
  // contact/colliders/response.h's nearPoints), each claiming its particles.
  thread_local VecX point_x, point_v;  // the near points' positions and velocities
  thread_local CellBoxes cells0, cells1;
  cells0.clear();
  cells1.clear();
  using End = std::tuple<double, const VecX*, const VecX*, CellBoxes*>;
  for (const auto& collider : colliders_)
    for (const auto& [time, x, v, cells] : {End{t, &x0, &v0, &cells0}, End{t + h, &x1, &v1, &cells1}}) {
      const double epsilon = collider->contact().epsilon, margin = epsilon + 2 * reach;  // the surface moves too
      const auto touch = [&](const Vec3& xi, const Vec3& vi) -> std::optional<SurfacePoint> {
        auto s = collider->query(time, xi);
        if (!s || std::abs(s->distance) >= epsilon + h * (vi - s->velocity).norm()) return std::nullopt;
        return s;
      };
      collider->near(time, *x, margin, near);
      for (const int i : near)
        if (collider_inv_mass_[i] != 0)
          if (const auto s = touch(particle(*x, i), particle(*v, i))) claim(i, std::abs(s->distance), collider.get());
      if (points_.empty()) continue;
      nearPoints(*collider, time, points_, *x, *cells, margin, near, point_x);
      points_.blendSome(*v, near, point_v);
      for (std::size_t j = 0; j < near.size(); ++j)
        if (points_[near[j]].inverse_mass > 0)
          if (const auto s = touch(particle(point_x, Eigen::Index(j)), particle(point_v, Eigen::Index(j)))) {
            const WeightedPoint& point = points_[near[j]];
            for (int k = 0; k < 8; ++k)
              if (point.weight[k] > 0) claim(point.particle[k], std::abs(s->distance), collider.get());
          }
    }
  if (touched.empty()) return 0;
  // Each touched particle's contact impulse: its momentum change less the step's impulse of the other forces (gravity,
  // drag, its springs and dampers) at the step's midpoint, a second-order estimate for every integrator; its work,
  // that impulse times the velocity of the surface it touched. Per particle, so that a body pressed between a moving
  // and a static surface counts the moving one's push alone (the two impulses cancel in the bodies' sum).
  thread_local std::vector<char> marked;
  thread_local VecX mid_x, mid_v, spring_force;
  marked.assign(std::size_t(n), 0);
  for (const int i : touched) marked[std::size_t(i)] = 1;
  mid_x = 0.5 * (x0 + x1);
  mid_v = 0.5 * (v0 + v1);
  spring_force.setZero(3 * n);
  for (int k = 0; k < int(springs_.size()); ++k)
    if (marked[std::size_t(springs_.a[k])] || marked[std::size_t(springs_.b[k])])
      addSpringForces(springs_, k, k + 1, mid_x, mid_v, spring_force);
  double work = 0;
  for (const int i : touched) {
    if (surface[i]->isStatic()) continue;
    const Vec3 other = mass_[i] * gravity_ - drag_[i] * particle(mid_v, i) + particle(spring_force, i);
    const Vec3 impulse = mass_[i] * (particle(v1, i) - particle(v0, i)) - h * other;
    // The surface's velocity at the step's midpoint (an accelerating platform's changes within the step).
    auto s = surface[i]->query(t + h / 2, particle(mid_x, i));
    if (!s) s = surface[i]->query(t, particle(x0, i));
    if (s) work += impulse.dot(s->velocity);
  }
  return work;
}

double MassSpringSystem::energyMadeUp(double t, double h, const VecX& x0, const VecX& v0, const VecX& x1,
                                      const VecX& v1) const {
  const double start = energy(x0, v0);
  return energy(x1, v1) - start - colliderWork(t, h, x0, v0, x1, v1) -
         kStepEnergyMargin * std::max(std::abs(start), liftEnergy());
}

double MassSpringSystem::stepPotential(double, const VecX& x1, const VecX&) const {
  // One thread, in a fixed order: the line search compares these sums, which must not depend on the thread count.
  double e = springEnergy(springs_, x1);
  for (int i = 0; i < particleCount(); ++i) e -= mass_[i] * gravity_.dot(particle(x1, i));
  return e;
}

double MassSpringSystem::liftEnergy() const {
  double free_mass = 0;
  for (int i = 0; i < particleCount(); ++i) free_mass += inv_mass_[i] > 0 ? mass_[i] : 0;
  return free_mass * std::max(gravity_.norm(), 1.0) * kEnergyGainLift;
}

double MassSpringSystem::energy(const VecX& x, const VecX& v) const {
  double e = springEnergy(springs_, x);
  for (int i = 0; i < particleCount(); ++i)
    e += mass_[i] * (0.5 * particle(v, i).squaredNorm() - gravity_.dot(particle(x, i)));
  return e;
}

}  // namespace wobble
