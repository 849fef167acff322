#include "sim/contact/candidates/clearance.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>

#include "sim/contact/distance/separation.h"
#include "sim/solver/parallel.h"

namespace wobble::collision {
namespace {
std::atomic<bool> skip_while_apart{true};
// The clearance is measured with each element's box padded by half the thickness and half this many thicknesses
// more: G is at most (1 + kMarginThicknesses) thicknesses, and the steps it serves may close up to kMarginThicknesses
// of them. More serves longer and lists more pairs (a cloth's elements a spacing apart).
constexpr double kMarginThicknesses = 4;
// A measure that served fewer steps than this did not pay: the next one waits (twice as long each time).
constexpr long kPayoff = 8;
constexpr int kMostWait = 256;

// Over count particles: the largest of |a_k - r_k - sa|^2 and |b_k - r_k - sb|^2 into largest, and their sum into sum
// (not finite where a coordinate is not), 3 coordinates a particle. Run on every step that may skip: its cost is what
// a skipped step costs, so it has AVX-512 and AVX2 clones.
__attribute__((target_clones("avx512f", "avx2", "default"))) void driftSquared(const double* a, const double* b,
                                                                               const double* r, int count,
                                                                               const double* sa, const double* sb,
                                                                               double& largest, double& sum) {
  double most = largest, total = sum;
  for (int i = 0; i < count; ++i) {
    const double ax = a[3 * i] - r[3 * i] - sa[0], ay = a[3 * i + 1] - r[3 * i + 1] - sa[1],
                 az = a[3 * i + 2] - r[3 * i + 2] - sa[2];
    const double bx = b[3 * i] - r[3 * i] - sb[0], by = b[3 * i + 1] - r[3 * i + 1] - sb[1],
                 bz = b[3 * i + 2] - r[3 * i + 2] - sb[2];
    const double qa = ax * ax + ay * ay + az * az, qb = bx * bx + by * by + bz * bz;
    const double q = qa > qb ? qa : qb;
    most = q > most ? q : most;
    total += qa + qb;
  }
  largest = most, sum = total;
}
}  // namespace

void setSkipWhileApart(bool on) { skip_while_apart = on; }
bool skipWhileApart() { return skip_while_apart; }

Clearance::Clearance(const SurfaceNodes& nodes, CandidateSearch& search, bool parallel, Stats& counters)
    : nodes_(nodes), search_(search), parallel_(parallel), counters_(counters) {
  const int bodies = int(nodes.params.size());
  std::vector<std::vector<int>> particles(bodies);
  std::vector<double> weight(bodies, 0.0);
  for (int k = 0; k < nodes.nodeCount(); ++k) {
    const int b = nodes.vertex_body[k];
    double sum = 0;
    for (int j = nodes.node_start[k]; j < nodes.node_start[k + 1]; ++j) {
      particles[b].push_back(nodes.node_particle[j]);
      sum += std::abs(nodes.node_weight[j]);
    }
    weight[b] = std::max(weight[b], sum);
  }
  for (int b = 0; b < bodies; ++b) {
    std::vector<int>& p = particles[b];
    std::sort(p.begin(), p.end());
    p.erase(std::unique(p.begin(), p.end()), p.end());
    Body body{{}, p.empty() ? 0 : p[p.size() / 2], weight[b]};
    for (std::size_t i = 0; i < p.size(); ++i)
      if (i > 0 && p[i] == p[i - 1] + 1) body.ranges.back().second = p[i] + 1;
      else body.ranges.emplace_back(p[i], p[i] + 1);
    bodies_.push_back(std::move(body));
    for (int a = 0; a < b; ++a)
      if (nodes.bodiesMeet(a, b)) meeting_.emplace_back(a, b);
  }
}

double Clearance::closing(const VecX& x0, const VecX& x1, double limit) {
  const int bodies = int(bodies_.size());
  drift_.assign(bodies, 0.0);
  shift_.resize(2 * bodies);
  double most = 0;
  for (int b = 0; b < bodies; ++b) {
    const Body& body = bodies_[b];
    const int r = body.reference_particle;
    const Vec3 s0 = particle(x0, r) - particle(reference_, r), s1 = particle(x1, r) - particle(reference_, r);
    shift_[2 * b] = s0, shift_[2 * b + 1] = s1;
    double largest = 0, sum = 0;  // squared
    for (const auto& [begin, stop] : body.ranges)
      driftSquared(x0.data() + 3 * begin, x1.data() + 3 * begin, reference_.data() + 3 * begin, stop - begin, s0.data(),
                   s1.data(), largest, sum);
    if (!std::isfinite(sum)) return std::numeric_limits<double>::infinity();  // a coordinate that is not finite
    drift_[b] = std::sqrt(largest);
    if (nodes_.params[b].self_contact) {
      most = std::max(most, 2 * body.weight * drift_[b]);
      if (most >= limit) return most;
    }
  }
  for (const auto& [a, b] : meeting_) {
    const double apart =
        std::max((shift_[2 * a] - shift_[2 * b]).norm(), (shift_[2 * a + 1] - shift_[2 * b + 1]).norm());
    most = std::max(most, bodies_[a].weight * drift_[a] + bodies_[b].weight * drift_[b] + apart);
  }
  return most;
}

bool Clearance::covers(const VecX& x0, const VecX& x1) {
  if (!skipWhileApart() || x0.size() != x1.size()) return false;
  const bool stale = valid_ && !(x0.size() == reference_.size() && closing(x0, x1, allowance_) < allowance_);
  if (stale) {  // the end of what the measure served: measure again at this step's start if it paid
    valid_ = false;
    backoff_ = served_ >= kPayoff ? 0 : std::min(std::max(1, 2 * backoff_), kMostWait);
    wait_ = backoff_;
  }
  if (!valid_) {
    if (near_) return false;  // the last pass found contact: no measure until one finds none
    if (wait_ > 0) return --wait_, false;
    measure(x0);
    if (!valid_ || !(closing(x0, x1, allowance_) < allowance_)) return false;
  }
  ++served_;
  return true;
}

// Each body's shift follows the particle whose displacement since the last reference lay nearest the middle of the
// body's displacements (per axis, halfway between the least and the greatest): if the body keeps moving so, its
// other particles stay nearer it than a particle at one end of the range, and the measure serves longer. (Any
// particle keeps the bound: this only picks one.)
void Clearance::chooseShifts(const VecX& x) {
  for (Body& body : bodies_) {
    Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
    for (const auto& [begin, stop] : body.ranges)
      for (int k = begin; k < stop; ++k) {
        const Vec3 u = particle(x, k) - particle(reference_, k);
        lo = lo.cwiseMin(u), hi = hi.cwiseMax(u);
      }
    const Vec3 middle = 0.5 * (lo + hi);
    double nearest = std::numeric_limits<double>::infinity();
    for (const auto& [begin, stop] : body.ranges)
      for (int k = begin; k < stop; ++k) {
        const double d = (particle(x, k) - particle(reference_, k) - middle).squaredNorm();
        if (d < nearest) nearest = d, body.reference_particle = k;
      }
  }
}

void Clearance::passed(bool near) { near_ = near; }

void Clearance::measure(const VecX& x) {
  ++counters_.clearance_measures;
  served_ = 0;
  valid_ = false;
  const double thickness = nodes_.max_thickness;
  const double pad = 0.5 * (1 + kMarginThicknesses) * thickness;
  nodes_.blendNodes(x, blended_, parallel_);
  const Vec3 none = Vec3::Zero();
  fillBoxes(nodes_, search_.marks, boxes_, false, parallel_,
            [&](const auto& element, int, Box& box_out, Diagonals& diagonals_out) {
              box_out = sweptBox(element, pad, blended_, blended_, none);
              diagonals_out = sweptDiagonals(element, pad, blended_, blended_, none);
            });
  if (!search_.findPairs(
          boxes_, true, [&](int a, int b) { return nodes_.bodiesMeet(a, b); }, false, false, vf_, ee_, 0)) {
    backoff_ = std::min(std::max(1, 2 * backoff_), kMostWait), wait_ = backoff_;
    return;
  }
  // Per pair, the gap between its elements' projections on the direction of their nearest points: a lower bound of
  // their distance whatever the rounding of the nearest points.
  const int vf = int(vf_.size()), n = vf + int(ee_.size()), chunk = particleChunk(n);
  partials_.assign((n + chunk - 1) / chunk, 2 * pad);
  forEachChunk(n, parallel_, [&](int begin, int end) {
    double least = 2 * pad;
    for (int k = begin; k < end; ++k) {
      const bool point = k < vf;
      const auto& [first, second] = point ? vf_[k] : ee_[k - vf];
      const Primitive kind = point ? Primitive::PointTriangle : Primitive::EdgeEdge;
      const auto q = nodes_.nodes(kind, first, second);
      std::array<Vec3, 4> at;
      for (int i = 0; i < 4; ++i) at[i] = particle(blended_, q[i]);
      const Closest c = nearest(kind, at);
      const double bound = c.distance > 0 ? gapAlong(c.delta / c.distance, blended_, q, point ? 1 : 2) : 0.0;
      least = std::min(least, bound);
    }
    partials_[begin / chunk] = least;
  });
  clearance_ = 2 * pad;
  for (const double p : partials_) clearance_ = std::min(clearance_, p);
  // The rounding of the coordinates' sums and products (a few ulps of the largest), and a hair of the thickness for
  // the pass's own distances.
  const double slack = 1e-6 * thickness + 1e-12 * (1 + blended_.lpNorm<Eigen::Infinity>());
  allowance_ = clearance_ - thickness - slack;
  if (allowance_ > 0) {
    if (reference_.size() == x.size()) chooseShifts(x);
    reference_ = x;
    valid_ = true;
  } else {  // (a measure that serves no step)
    backoff_ = std::min(std::max(1, 2 * backoff_), kMostWait), wait_ = backoff_;
  }
}

}  // namespace wobble::collision
