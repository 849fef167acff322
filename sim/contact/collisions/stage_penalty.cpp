#include "sim/contact/collisions/stage_penalty.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace wobble::collision {

StagePenalty::StagePenalty(std::vector<double> stiffness)
    : stiffness_(std::move(stiffness)), share_(stiffness_.size(), 0.0) {}

void StagePenalty::begin(std::vector<ContactPair>& pairs, const VecX& x0, const VecX& inverse_mass, double h) {
  pairs_.swap(pairs);
  terms_.resize(pairs_.size());
  for (const ContactPair& p : pairs_)
    for (int i = 0; i < p.stencil.size; ++i) share_[p.stencil.particle[i]] += p.stencil.w[i] * p.stencil.w[i];
  for (std::size_t k = 0; k < pairs_.size(); ++k) {
    const ContactPair& p = pairs_[k];
    const WeightedStencil& s = p.stencil;
    // The two bodies' layers in series (the stencil's first particle is the first element's, its last the second's),
    // and each free particle's budget over its share.
    const double a = stiffness_[s.particle[0]], b = stiffness_[s.particle[s.size - 1]];
    const double material = a + b > 0 ? a * b / (a + b) / p.thickness : 0;
    double stiffness = std::numeric_limits<double>::infinity(), damping_cap = stiffness;
    for (int i = 0; i < s.size; ++i) {
      const int q = s.particle[i];
      if (inverse_mass[q] == 0 || s.w[i] == 0) continue;
      const double m = 1 / inverse_mass[q];
      stiffness = std::min(stiffness, std::min(material, kMaxStiffness * m / (h * h)) / share_[q]);
      damping_cap = std::min(damping_cap, kMaxDamping * m / h / share_[q]);
    }
    const double inverse_mass_sum = s.inverseMass(inverse_mass);
    if (!std::isfinite(stiffness) || !(inverse_mass_sum > 0)) stiffness = damping_cap = 0;  // every particle pinned
    const double damping = std::min(damping_cap, 2 * std::sqrt(stiffness / inverse_mass_sum));
    // Friction's stretch as the last step left it, in this step's tangent plane.
    const auto at = std::lower_bound(stuck_.begin(), stuck_.end(), Stuck{p.element, Vec3::Zero()});
    Vec3 stretch = at != stuck_.end() && at->element == p.element ? at->stretch : Vec3::Zero();
    stretch -= p.normal.dot(stretch) * p.normal;
    terms_[k] = Term{stiffness, damping, p.relative(x0), stretch};
  }
  for (const ContactPair& p : pairs_)
    for (int i = 0; i < p.stencil.size; ++i) share_[p.stencil.particle[i]] = 0;
}

double StagePenalty::gap(std::size_t k, const VecX& x, Vec3& stretch) const {
  const ContactPair& p = pairs_[k];
  const Vec3 r = p.relative(x), d = r - terms_[k].r0;
  stretch = terms_[k].stretch + d - p.normal.dot(d) * p.normal;
  return p.normal.dot(r) - p.thickness;
}

Vec3 StagePenalty::force(std::size_t k, const VecX& x, const VecX& v, Vec3* stretch_out) const {
  const ContactPair& p = pairs_[k];
  const Term& t = terms_[k];
  Vec3 stretch;
  const double g = gap(k, x, stretch);
  if (!(g < 0)) return Vec3::Zero();
  const Vec3 u = p.relative(v);
  const double un = p.normal.dot(u);
  const double fn = std::max(0.0, -t.stiffness * g - t.damping * un);
  Vec3 ft = -t.stiffness * stretch - t.damping * (u - un * p.normal);
  const double limit = p.friction * fn, size = ft.norm();
  if (size > limit) {  // sliding: Coulomb's force, the anchor following
    ft *= limit / size;
    stretch = t.stiffness > 0 ? Vec3(-ft / t.stiffness) : Vec3::Zero();
  }
  if (stretch_out) *stretch_out = stretch;
  return fn * p.normal + ft;
}

void StagePenalty::addAccelerations(const VecX& x, const VecX& v, const VecX& inverse_mass, VecX& a) const {
  for (std::size_t k = 0; k < pairs_.size(); ++k) {
    const Vec3 f = force(k, x, v);
    if (f.isZero(0)) continue;
    const WeightedStencil& s = pairs_[k].stencil;
    for (int i = 0; i < s.size; ++i) particle(a, s.particle[i]) += (s.w[i] * inverse_mass[s.particle[i]]) * f;
  }
}

void StagePenalty::end(const VecX& x1, const VecX& v1) {
  stuck_.clear();
  for (std::size_t k = 0; k < pairs_.size(); ++k) {
    Vec3 stretch;
    if (force(k, x1, v1, &stretch).isZero(0)) continue;  // not pressed
    stuck_.push_back({pairs_[k].element, stretch});
  }
  std::sort(stuck_.begin(), stuck_.end());
}

double StagePenalty::energy(const VecX& x) const {
  double e = 0;
  for (std::size_t k = 0; k < pairs_.size(); ++k) {
    Vec3 stretch;
    const double g = gap(k, x, stretch);
    if (g < 0) e += 0.5 * terms_[k].stiffness * (g * g + stretch.squaredNorm());
  }
  return e;
}

}  // namespace wobble::collision
