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
// of them. More serves longer where the elements are further apart and lists more pairs: 6 thicknesses is about the
// nearest non-adjacent elements of cloth_sphere's cloth (0.7 of its spacing), which bound its G below that.
constexpr double kMarginThicknesses = 5;
// A measure that served to its end measures again ahead of the step's start x0 by this much of the motion since the
// start of the last: x_ref = x0 + kAhead (x0 - that start). The motion going on so, the next steps' states lie on both
// sides of x_ref, nearer it than to x0, and the measure serves longer than one taken at x0.
constexpr double kAhead = 0.5;
// A measure that served fewer steps than this did not pay: the next one waits (twice as long each time).
constexpr long kPayoff = 8;
constexpr int kMostWait = 256;

// Over count particles, 3 coordinates each: per axis the least and the greatest of x - r folded into lo and hi, and
// their sum added to sum (not finite where a coordinate is not: the minimum and maximum pass a NaN by). Run on every
// step that may skip, so its cost is what a skipped step costs: its lanes are 8 particles' coordinates, each with its
// own least, greatest and sum (elementwise: they vectorize with no reordering of floating-point operations), folded
// per axis at the end; AVX-512 and AVX2 clones.
__attribute__((target_clones("avx512f", "avx2", "default"))) void displacementBox(const double* x, const double* r,
                                                                                  int count, double* lo, double* hi,
                                                                                  double& sum) {
  constexpr int kLanes = 24;  // 8 particles: whole AVX-512 and AVX2 vectors, and whole particles
  double l[kLanes], h[kLanes], s[kLanes];
  for (int j = 0; j < kLanes; ++j) l[j] = lo[j % 3], h[j] = hi[j % 3], s[j] = 0;
  const int blocks = count / 8;
  for (int k = 0; k < blocks; ++k)
    for (int j = 0; j < kLanes; ++j) {
      const double d = x[kLanes * k + j] - r[kLanes * k + j];
      l[j] = d < l[j] ? d : l[j];
      h[j] = d > h[j] ? d : h[j];
      s[j] += d;
    }
  for (int j = kLanes * blocks; j < 3 * count; ++j) {  // the last particles, fewer than 8
    const double d = x[j] - r[j];
    l[j % 3] = d < l[j % 3] ? d : l[j % 3];
    h[j % 3] = d > h[j % 3] ? d : h[j % 3];
    s[j % 3] += d;
  }
  double total = sum;
  for (int j = 0; j < kLanes; ++j) {
    lo[j % 3] = std::min(lo[j % 3], l[j]);
    hi[j % 3] = std::max(hi[j % 3], h[j]);
    total += s[j];
  }
  sum = total;
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
    Body body{{}, weight[b]};
    for (std::size_t i = 0; i < p.size(); ++i)
      if (i > 0 && p[i] == p[i - 1] + 1) body.ranges.back().second = p[i] + 1;
      else body.ranges.emplace_back(p[i], p[i] + 1);
    bodies_.push_back(std::move(body));
    for (int a = 0; a < b; ++a)
      if (nodes.bodiesMeet(a, b)) meeting_.emplace_back(a, b);
  }
  // Each vertex and edge to the first triangle that holds it (listPairs), found through each node's triangles.
  const int triangles = int(nodes.triangles.size());
  std::vector<std::vector<int>> around(nodes.nodeCount());
  for (int t = 0; t < triangles; ++t)
    for (const int k : nodes.triangles[t]) around[k].push_back(t);
  std::vector<std::vector<int>> vertices(triangles), edges(triangles);
  for (int k = 0; k < nodes.nodeCount(); ++k) {
    if (around[k].empty()) return;  // a vertex on no triangle: element pairs listed directly
    vertices[around[k][0]].push_back(k);
  }
  for (int e = 0; e < int(nodes.edges.size()); ++e) {
    const auto& [a, b] = nodes.edges[e];
    const auto& t = nodes.triangles;
    const auto holds = std::find_if(around[a].begin(), around[a].end(), [&](int s) {
      return (t[s][0] == b || t[s][1] == b || t[s][2] == b) && nodes.triangle_body[s] == nodes.edge_body[e];
    });
    if (holds == around[a].end()) return;
    edges[*holds].push_back(e);
  }
  const auto runs = [&](const std::vector<std::vector<int>>& owned, std::vector<int>& start, std::vector<int>& all) {
    start.assign(1, 0);
    for (const auto& items : owned) {
      all.insert(all.end(), items.begin(), items.end());
      start.push_back(int(all.size()));
    }
  };
  runs(vertices, vertex_start_, vertex_owned_);
  runs(edges, edge_start_, edge_owned_);
}

// Per body and end: the box of its particles' displacements from the reference, its centre c and half-diagonal h.
bool Clearance::spread(const VecX& x, int end) {
  for (std::size_t b = 0; b < bodies_.size(); ++b) {
    Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
    double sum = 0;
    for (const auto& [begin, stop] : bodies_[b].ranges)
      displacementBox(x.data() + 3 * begin, reference_.data() + 3 * begin, stop - begin, lo.data(), hi.data(), sum);
    if (!std::isfinite(sum)) return false;  // a coordinate that is not finite
    const bool none = bodies_[b].ranges.empty();
    centre_[2 * b + end] = none ? Vec3::Zero() : Vec3(0.5 * (lo + hi));
    half_[2 * b + end] = none ? 0.0 : 0.5 * (hi - lo).norm();
  }
  return true;
}

double Clearance::closing(const VecX& x0, const VecX& x1, double limit, bool start_known) {
  const std::size_t bodies = bodies_.size();
  centre_.resize(2 * bodies), half_.resize(2 * bodies);
  if (start_known)  // x0 is the end of the last call's step, whose spread is at end 1
    for (std::size_t b = 0; b < bodies; ++b) centre_[2 * b] = centre_[2 * b + 1], half_[2 * b] = half_[2 * b + 1];
  if (!(start_known || spread(x0, 0)) || !spread(x1, 1)) return std::numeric_limits<double>::infinity();
  double most = 0;
  for (std::size_t b = 0; b < bodies; ++b)
    if (nodes_.params[b].self_contact) {
      most = std::max(most, 2 * bodies_[b].weight * std::max(half_[2 * b], half_[2 * b + 1]));
      if (most >= limit) return most;
    }
  for (const auto& [a, b] : meeting_) {
    const double apart =
        std::max((centre_[2 * a] - centre_[2 * b]).norm(), (centre_[2 * a + 1] - centre_[2 * b + 1]).norm());
    most = std::max(most, bodies_[a].weight * std::max(half_[2 * a], half_[2 * a + 1]) +
                              bodies_[b].weight * std::max(half_[2 * b], half_[2 * b + 1]) + apart);
  }
  return most;
}

bool Clearance::covers(const VecX& x0, const VecX& x1, ClearanceQuery query) {
  const bool start_known = query.continues && end_known_;
  end_known_ = false;
  if (!skipWhileApart() || x0.size() != x1.size()) return false;
  const bool stale =
      valid_ && !(x0.size() == reference_.size() && closing(x0, x1, allowance_, start_known) < allowance_);
  bool paid = false;
  if (stale) {  // the end of what the measure served: measure again at once if it paid
    valid_ = false;
    paid = served_ >= kPayoff;
    backoff_ = paid ? 0 : std::min(std::max(1, 2 * backoff_), kMostWait);
    wait_ = backoff_;
  }
  if (!valid_) {
    if (near_) return false;  // the last pass found contact: no measure until one finds none
    if (wait_ > 0) return --wait_, false;
    // Ahead first, after a measure that served to its end; at the step's start where that does not cover the step.
    bool measured = false;
    if (paid && start_.size() == x0.size()) {
      ahead_ = x0 + kAhead * (x0 - start_);
      measure(ahead_);
      measured = valid_ && closing(x0, x1, allowance_) < allowance_;
    }
    if (!measured) {
      measure(x0);
      if (!valid_ || !(closing(x0, x1, allowance_) < allowance_)) return false;
    }
    start_ = x0;
  }
  ++served_;
  end_known_ = query.final_pass;  // the spread at x1 (end 1) against this reference, and x1 stays as it is
  return true;
}

void Clearance::passed(bool near) { near_ = near; }

// The pairs of triangles whose boxes and diagonals overlap, then of each such pair (s, t) the pairs of elements owned
// by one and the other: every vertex of s against t and of t against s, every edge of s against every edge of t. A
// triangle's box and diagonals hold those of its vertices and edges (the same pad), so every pair of elements whose
// bounds overlap is one of these, from the pair of its owners, and once: a vertex has one owner, an edge one, and a
// pair of elements with one owner shares a node (not a pair the pass tests). Each is kept by findPairs' own filters
// (candidateVertexTriangle, candidateEdgeEdge: search.h). The triangles are a third of the elements and the hash's
// lookups are most of a broad phase's work.
bool Clearance::listPairs() {
  const SurfaceNodes& n = nodes_;
  const ElementBoxes& b = boxes_;
  vf_.clear(), ee_.clear();
  if (vertex_start_.empty())
    return search_.findPairs(
        b, true, [&](int p, int q) { return n.bodiesMeet(p, q); }, false, false, vf_, ee_, 0);
  if (!overlappingPairs(
          b.triangle, b.triangle, true, parallel_,
          [&](int s, int t) { return n.bodiesMeet(n.triangle_body[s], n.triangle_body[t]); }, triangle_pairs_,
          search_.budget()))
    return false;
  // (The boxes first: most pairs of owned elements lie apart.)
  const auto vertexTriangle = [&](int v, int t, PairList& out) {
    if (b.vertex[v].overlaps(b.triangle[t]) && candidateVertexTriangle(n, b, true, v, t)) out.emplace_back(v, t);
  };
  const auto edgeEdge = [&](int e, int f, PairList& out) {
    if (b.edge[e].overlaps(b.edge[f]) && candidateEdgeEdge(n, b, true, e, f))
      out.emplace_back(std::min(e, f), std::max(e, f));
  };
  const int count = int(triangle_pairs_.size()), chunk = particleChunk(count), chunks = (count + chunk - 1) / chunk;
  std::vector<PairList>&vf = vf_parts_, &ee = ee_parts_;
  vf.resize(chunks), ee.resize(chunks);
  forEachChunk(count, parallel_, [&](int begin, int end) {
    PairList &vf_part = vf[begin / chunk], &ee_part = ee[begin / chunk];
    vf_part.clear(), ee_part.clear();
    for (int k = begin; k < end; ++k) {
      const auto [s, t] = triangle_pairs_[k];
      for (int i = vertex_start_[s]; i < vertex_start_[s + 1]; ++i) vertexTriangle(vertex_owned_[i], t, vf_part);
      for (int i = vertex_start_[t]; i < vertex_start_[t + 1]; ++i) vertexTriangle(vertex_owned_[i], s, vf_part);
      for (int i = edge_start_[s]; i < edge_start_[s + 1]; ++i)
        for (int j = edge_start_[t]; j < edge_start_[t + 1]; ++j) edgeEdge(edge_owned_[i], edge_owned_[j], ee_part);
    }
  });
  for (int c = 0; c < chunks; ++c) {
    vf_.insert(vf_.end(), vf[c].begin(), vf[c].end());
    ee_.insert(ee_.end(), ee[c].begin(), ee[c].end());
  }
  return true;
}

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
  if (!listPairs()) {
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
    reference_ = x;
    valid_ = true;
  } else {  // (a measure that serves no step)
    backoff_ = std::min(std::max(1, 2 * backoff_), kMostWait), wait_ = backoff_;
  }
}

}  // namespace wobble::collision
