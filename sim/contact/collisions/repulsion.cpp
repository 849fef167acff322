#include "sim/contact/collisions/repulsion.h"

#include <algorithm>
#include <iterator>
#include <limits>
#include <optional>

#include "sim/solver/parallel.h"

namespace wobble::collision {
namespace {

// Repulsion pushes apart at most this fraction of the thickness left per step (Bridson 2002, 7.2: 0.1 d / h).
constexpr double kRepulsionFraction = 0.1;
// settle's Gauss-Seidel stops when a sweep changes no pair's normal velocity by more than this (m/s), or than this
// fraction of the first sweep's largest change, and after this many sweeps at most.
constexpr double kSettleTolerance = 1e-5, kSettleRelative = 1e-3;
constexpr int kSettleSweeps = 500;

// The normal of a pair whose nearest points at x are c: along them, or where they touch (no direction between
// them) the triangle's or the edges'. Not finite for a degenerate touching pair.
Vec3 contactNormal(Primitive kind, const std::array<Vec3, 4>& x, const Closest& c) {
  if (c.distance > 0) return c.delta / c.distance;
  if (kind == Primitive::PointTriangle) return (x[2] - x[1]).cross(x[3] - x[1]).normalized();
  return (x[1] - x[0]).cross(x[3] - x[2]).normalized();
}

// The largest gap along an axis between the start's boxes of the pair's elements (the swept ones found it): at
// most the distance between the elements.
double startBoxGap(const PairInfo& p, const std::array<Vec3, 4>& x) {
  Vec3 lo0 = x[0].cwiseMin(x[1]), hi0 = x[0].cwiseMax(x[1]), lo1 = x[2].cwiseMin(x[3]), hi1 = x[2].cwiseMax(x[3]);
  if (p.kind == Primitive::PointTriangle) {
    lo0 = hi0 = x[0];
    lo1 = x[1].cwiseMin(lo1);
    hi1 = x[1].cwiseMax(hi1);
  }
  return std::max((lo0.array() - hi1.array()).maxCoeff(), (lo1.array() - hi0.array()).maxCoeff());
}

}  // namespace

void Repulsion::repel(Candidates& round, double h, Stats& stats, bool impulses, bool ahead) {
  // With the step's candidates: those within the thickness at the start, their smallest distance known (near_min).
  const std::vector<int>* only = round.step ? &round.step->near : nullptr;
  if (only) stats.min_distance = std::min(stats.min_distance, round.step->near_min);
  if (only && !impulses && !round.from_skin) {
    // Counting is all that is left (the pairs' distances are in near_min): the pairs the gather below would
    // return as contacts, counted per chunk, without gathering them.
    const std::vector<int>& near = *only;
    stats.contacts += sumOverChunks(int(near.size()), parallel_, contact_counts_, [&](int begin, int end) {
      long count = 0;
      for (int j = begin; j < end; ++j) {
        const int k = near[j];
        const PairInfo p = round.info(nodes_, k);
        const auto x = points(motion_.nxs, p.stencil);
        const Closest& c = round.step->closest[k];
        if (startBoxGap(p, x) > p.thickness || !(c.distance < p.thickness)) continue;
        count += contactNormal(p.kind, x, c).allFinite();
      }
      return count;
    });
    round.round_closest_valid = false;
    return;
  }
  if (only && impulses && ahead) {  // with the pairs apart at the start whose gap may close within the thickness
    const std::vector<int>& closing = *round.subsetOf(round.step->closing);
    listed_.clear();
    std::set_union(only->begin(), only->end(), closing.begin(), closing.end(), std::back_inserter(listed_));
    only = &listed_;
  }
  round.round_closest_valid = !round.step;
  if (round.round_closest_valid)
    round.round_closest.assign(round.count(), Closest{std::numeric_limits<double>::quiet_NaN(), {}, Vec3::Zero()});
  // The skin's candidates: those its bounds keep apart are skipped (Skin), or the bounds are filled.
  const bool skip = round.from_skin && skins_.skin.lower_valid, fill = round.from_skin && !skins_.skin.lower_valid;
  const double moved = skip ? 2 * skins_.skinDrift({&motion_.nxs}) : 0, seen = stats.min_distance;
  // With ahead, a pair apart at the start is stopped where it comes within the thickness: one whose distance may
  // close by up to twice the largest node displacement over the step (reach) may be such a pair.
  double reach = 0;
  if (impulses && ahead)
    for (int k = 0; k < nodes_.nodeCount(); ++k)
      reach = std::max(reach, (particle(motion_.nxe, k) - particle(motion_.nxs, k)).squaredNorm());
  reach = 2 * std::sqrt(reach);
  const std::vector<Contact> near = round.gather(
      nodes_, parallel_,
      [&](int k, const PairInfo& p) -> std::optional<Contact> {
        if (skip && skins_.skin.lower[k] - moved > std::max(p.thickness + reach, seen)) return std::nullopt;
        const auto x = points(motion_.nxs, p.stencil);
        // The start's boxes (the swept ones found the pair) further apart than the thickness: not near.
        const double box_gap = startBoxGap(p, x);
        if (box_gap > p.thickness + reach) {
          if (fill) skins_.skin.lower[k] = box_gap;  // each k on one thread
          return std::nullopt;
        }
        const Closest c = round.startClosest(k, p.kind, x);
        if (fill) skins_.skin.lower[k] = c.distance;
        if (round.round_closest_valid) round.round_closest[k] = c;  // each k on one thread
        if (c.distance >= p.thickness) {  // apart: a contact if it ends within the thickness, approaching
          if (!(reach > 0 && c.distance > 0)) return std::nullopt;
          const Vec3 d = c.delta / c.distance;
          if (!(c.distance + h * d.dot(motion_.relativeVelocity(p.stencil, c.w)) < p.thickness)) return std::nullopt;
          if (!(nearest(p.kind, points(motion_.nxe, p.stencil)).distance < p.thickness)) return std::nullopt;
          return Contact{k, c, d, 0};
        }
        const Vec3 normal = contactNormal(p.kind, x, c);
        if (!normal.allFinite()) return Contact{k, c, Vec3::Zero(), -1};
        return Contact{k, c, normal, 0};
      },
      only);
  skins_.skin.lower_valid = skins_.skin.lower_valid || fill;
  pressed_.clear();
  for (const Contact& c : near) {
    const PairInfo p = round.info(nodes_, c.pair);
    if (c.at.distance < p.thickness) stats.min_distance = std::min(stats.min_distance, c.at.distance);
    if (c.t < 0) continue;
    ++stats.contacts;
    if (!impulses) continue;
    const double denom = weightNorm(p.stencil, c.at.w);
    if (denom <= 0) continue;
    const Vec3 u = motion_.relativeVelocity(p.stencil, c.at.w);
    // A pair apart at the start may approach until it reaches the thickness.
    const double allowed = std::max(0.0, c.at.distance - p.thickness) / h;
    const double un = c.normal.dot(u), gap = std::max(0.0, p.thickness - c.at.distance);
    // Inelastic: stop the approach. Repulsion: a spring of stiffness k over the gap left for one step, at most
    // enough to close a tenth of it within the step (Bridson 2002, 7.2).
    const double stop = std::max(0.0, -(un + allowed)), after = un + allowed + stop;
    const double spring = h * p.stiffness * gap * denom;
    const double repel = std::max(0.0, std::min(spring, kRepulsionFraction * gap / h - after));
    const double dn = stop + repel;
    if (allowed == 0 || dn > 0) pressed_.push_back({nodes_.expand(p.stencil, c.at.w), c.normal, denom});
    if (dn <= 0) continue;
    Vec3 dv = dn * c.normal;
    const Vec3 ut = u - un * c.normal;
    const double speed = ut.norm();
    if (speed > 0) dv -= std::min(p.friction * dn / speed, 1.0) * ut;  // Coulomb: at most mu times the normal change
    motion_.applyImpulse(nodes_, inv_mass_, p.stencil, c.at.w, dv, h);
  }
}

void Repulsion::settle(VecX& v) const {
  const auto approach = [&](const Pressed& c) {
    double un = 0;
    for (int j = 0; j < c.stencil.size; ++j) un += c.stencil.w[j] * c.normal.dot(particle(v, c.stencil.particle[j]));
    return un;
  };
  // Projected Gauss-Seidel on the pairs' accumulated normal impulses (each at least 0, its pair not approaching
  // unless the impulse is 0), until a sweep changes no pair's velocity by more than the tolerance.
  std::vector<double> impulse(pressed_.size(), 0.0);
  double tolerance = kSettleTolerance;
  for (int sweep = 0; sweep < kSettleSweeps; ++sweep) {
    double largest = 0;
    for (std::size_t k = 0; k < pressed_.size(); ++k) {
      const Pressed& c = pressed_[k];
      const double change = std::max(-impulse[k], -approach(c));
      if (change == 0) continue;
      impulse[k] += change;
      largest = std::max(largest, std::abs(change));
      for (int j = 0; j < c.stencil.size; ++j) {
        const int q = c.stencil.particle[j];
        particle(v, q) += (change * c.stencil.w[j] * inv_mass_[q] / c.denom) * c.normal;
      }
    }
    if (sweep == 0) tolerance = std::max(tolerance, kSettleRelative * largest);
    if (largest <= tolerance) break;
  }
}

double Repulsion::weightNorm(const Stencil& s, const std::array<double, 4>& w) const {
  return nodes_.expand(s, w).inverseMass(inv_mass_);
}

}  // namespace wobble::collision
