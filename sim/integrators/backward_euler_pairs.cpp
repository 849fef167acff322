#include "sim/integrators/backward_euler_pairs.h"

#include <algorithm>
#include <cmath>

#include "sim/solver/parallel.h"
#include "sim/solver/sym3.h"

namespace wobble {

PairJoin PenaltyPairs::begin() {
  pairs_.clear();
  terms_.clear();
  rhs_pairs_.resize(0);
  carried_elements_.clear();
  for (const Carried& c : carried_) carried_elements_.push_back(c.element);
  return PairJoin{.only = &carried_elements_};
}

template <class Fn>
std::size_t PenaltyPairs::countOverPairs(std::size_t n, bool parallel, Fn&& fn) {
  return sumOverChunks(int(n), parallel, pair_counts_, [&](int begin, int end) {
    std::size_t count = 0;
    for (int k = begin; k < end; ++k) count += fn(std::size_t(k)) ? 1 : 0;
    return count;
  });
}

std::size_t PenaltyPairs::update(const VecX& inverse_mass, double h, const VecX& x0, const VecX& x1, bool first,
                                 bool parallel) {
  // On threads in fixed chunks of pairs (each pair's term its own; the counts summed per chunk, in order).
  const std::size_t known = terms_.size();
  terms_.resize(pairs_.size());
  std::size_t changed = countOverPairs(pairs_.size() - known, parallel, [&](std::size_t j) {
    const std::size_t k = known + j;
    const ContactPair& c = pairs_[k];
    const double weight = c.stencil.inverseMass(inverse_mass);
    const double stiffness = weight > 0 ? kPenalty / (weight * h * h) : 0;
    Term term{stiffness, 0, penaltyRestGap(c.gap(x0), kRecovery), activeSlack(kActiveSlack, c.gap(x0), c.thickness),
              false};
    if (c.collider) term.rest = std::max(term.rest, c.gap(x0) + c.rise);
    if (first) {  // the last step's active set, and its friction, start this step's
      const auto it = std::lower_bound(carried_.begin(), carried_.end(), Carried{c.element, 0});
      if (it != carried_.end() && it->element == c.element && stiffness > 0) {
        term.active = true;
        term.damping = it->damping;
      }
    }
    terms_[k] = term;
    return term.active;
  });
  if (first) return changed;
  changed += countOverPairs(pairs_.size(), parallel, [&](std::size_t k) {
    const double past = pairs_[k].gap(x1) - terms_[k].rest;  // < 0: pressed
    const bool active = terms_[k].stiffness > 0 && past < 0;
    if (active == terms_[k].active || std::abs(past) < terms_[k].slack) return false;
    terms_[k].active = active;
    return true;
  });
  return changed;
}

long PenaltyPairs::apply(double h, const VecX& x, const VecX& v, PairBlockMatrix& matrix, VecX& rhs) {
  if (rhs_pairs_.size() == rhs.size()) rhs -= rhs_pairs_;
  rhs_pairs_.setZero(rhs.size());
  matrix.stencils().clear();
  long active = 0;
  for (std::size_t k = 0; k < pairs_.size(); ++k) {
    const ContactPair& c = pairs_[k];
    const Term& term = terms_[k];
    if (!term.active) continue;
    ++active;
    Sym3 block = (h * h * term.stiffness) * Sym3::outer(c.normal);
    Vec3 force = -h * term.stiffness * (c.gap(x) - term.rest + h * c.normal.dot(c.relative(v))) * c.normal;
    if (term.damping > 0) {
      const Eigen::Matrix3d tangential = Eigen::Matrix3d::Identity() - c.normal * c.normal.transpose();
      block += Sym3::fromDense((h * term.damping) * tangential);
      force -= h * term.damping * (tangential * c.relative(v));
    }
    force += h * term.coulomb;
    matrix.stencils().push_back({c.stencil, block});
    c.stencil.spread(force, rhs_pairs_);
  }
  rhs += rhs_pairs_;
  return active;
}

// A pair pressed at the step's end (normal force k (g_rest - g(x1))) gets for the next step a tangential damper F_i =
// -c w_i P sum w_j v_j (P = I - n n^T) of coefficient c = mu |normal force| / max(|P sum w_j v1_j|, kStickSpeed):
// Coulomb's force on the sliding speed just found, and below kStickSpeed a damper strong enough to hold the pair
// (static friction as a creep slower than kStickSpeed). Linear in v, so exact in the step and dissipative. Lagged by a
// step, as IPC lags its friction (Li et al. 2020): a solve of its own, with every pair's stencil in it, would cost a
// step as much again.
void PenaltyPairs::carry(double h, const VecX& x, const VecX& v, const VecX& dv) {
  carried_.clear();
  for (std::size_t k = 0; k < pairs_.size(); ++k) {
    const ContactPair& c = pairs_[k];
    const Term& term = terms_[k];
    if (!term.active) continue;
    double damping = 0;
    if (c.friction > 0) {
      Vec3 x1 = Vec3::Zero(), v1 = Vec3::Zero();
      const WeightedStencil& s = c.stencil;
      for (int i = 0; i < s.size; ++i) {
        const Vec3 vi = particle(v, s.particle[i]) + particle(dv, s.particle[i]);
        v1 += s.w[i] * vi;
        x1 += s.w[i] * (particle(x, s.particle[i]) + h * vi);
      }
      const double pressed = term.stiffness * std::max(0.0, term.rest + c.surface + c.thickness - c.normal.dot(x1));
      const double slide = (v1 - c.normal.dot(v1) * c.normal).norm();
      damping = c.friction * pressed / std::max(slide, kStickSpeed);
    }
    carried_.push_back({c.element, damping});
  }
  std::sort(carried_.begin(), carried_.end());
}

void PenaltyPairs::addForces(const VecX& x1, const VecX& v1, VecX& f) const {
  for (std::size_t k = 0; k < pairs_.size(); ++k) {
    const ContactPair& c = pairs_[k];
    const Vec3 n = c.normal;
    if (!terms_[k].active) continue;
    Vec3 force = -terms_[k].stiffness * (c.gap(x1) - terms_[k].rest) * n;
    const Vec3 u = c.relative(v1);
    force -= terms_[k].damping * (u - n.dot(u) * n);
    force += terms_[k].coulomb;
    c.stencil.spread(force, f);
  }
}

double PenaltyPairs::potential(double h, const VecX& x1, const VecX& v1) const {
  double e = 0;
  for (std::size_t k = 0; k < pairs_.size(); ++k) {
    if (!terms_[k].active) continue;
    const ContactPair& c = pairs_[k];
    const double past = c.gap(x1) - terms_[k].rest;
    const Vec3 u = c.relative(v1);
    e += 0.5 * terms_[k].stiffness * past * past +
         0.5 * h * terms_[k].damping * (u - c.normal.dot(u) * c.normal).squaredNorm();
    if (terms_[k].coulomb != Vec3::Zero()) e -= h * terms_[k].coulomb.dot(u);  // a constant force's
  }
  return e;
}

bool PenaltyPairs::hasFriction() const {
  return std::any_of(terms_.begin(), terms_.end(),
                     [](const Term& t) { return t.active && (t.damping > 0 || t.coulomb != Vec3::Zero()); });
}

// As BackwardEuler::boundFriction turns a collider's (ContactConstraint::turnedDamping).
bool PenaltyPairs::dampTurned(const VecX& v1) {
  bool turned = false;
  for (std::size_t k = 0; k < terms_.size(); ++k) {
    Term& term = terms_[k];
    if (!term.active || term.coulomb == Vec3::Zero()) continue;
    const ContactPair& c = pairs_[k];
    const Vec3 u = c.relative(v1);
    const Vec3 slide = u - c.normal.dot(u) * c.normal;
    const double damping = ContactConstraint::turnedDamping(term.coulomb, slide);
    if (damping == 0) continue;
    term.damping = damping;
    term.coulomb = Vec3::Zero();
    term.turned = turned = true;
  }
  return turned;
}

double PenaltyPairs::work(const VecX& x0, const VecX& x1) const {
  double w = 0;
  for (std::size_t k = 0; k < terms_.size(); ++k) {
    if (!terms_[k].active || pairs_[k].collider) continue;
    const double end = pairs_[k].gap(x1);
    w -= terms_[k].stiffness * (end - terms_[k].rest) * (end - pairs_[k].gap(x0));
  }
  return w;
}

}  // namespace wobble
