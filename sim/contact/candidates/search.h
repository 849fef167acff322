// The candidate search: the pairs of surface elements whose boxes, swept over the step and padded by half the largest
// thickness (so that every pair within the thickness at the start or meeting on the way is found), overlap, by the
// spatial hash (broad_phase/broad_phase.h) over the elements' bounds (broad_phase/element_bounds.h), less the pairs of
// adjacent elements, of pinned nodes only, of bodies that do not meet, and (with the culls) those the diagonals part.
// Moving frames (with the culls on): a body's pairs with itself are found in a frame that moves with the body's
// typical motion over the step (the median of its nodes' displacements, axis by axis), its pairs with other bodies in
// the world's. Every test that follows a broad phase (a distance within the thickness at the start, a gap along a
// direction at an end, a hit along the step) is of the two elements' relative positions at one instant, which a common
// translation of both leaves alone: in the world frame a falling cloth's swept boxes reach many spacings along its
// fall, and each overlaps the boxes of its neighbours within one flat layer, which never collide; in the body's frame
// they are as short as the cloth's deformation in the step. The same contacts in the same order, fewer candidates.
#pragma once
#include <atomic>
#include <cstddef>
#include <functional>
#include <vector>

#include "sim/contact/broad_phase/element_bounds.h"
#include "sim/contact/candidates/candidates.h"
#include "sim/contact/distance/separation.h"
#include "sim/contact/node_motion.h"
#include "sim/contact/params.h"
#include "sim/contact/stats.h"

namespace wobble::collision {

// Whether the searches take their shortcuts (setBroadPhaseCulls, body_collisions.h).
bool broadPhaseCulls();

// What counts as a candidate pair, given elements whose boxes in b overlap and whose bodies the search accepts: not of
// adjacent elements (sharing a node), not of pinned nodes only (they never move: no impulse could act on such a pair;
// counted in *pinned where given), and (with the culls) not parted by their diagonals. Every search that lists pairs
// (findPairs, Clearance::listPairs) keeps a pair by these. cull by reference: read only for the pairs the cheap checks
// pass (by value, GCC loads it first on every call, which findPairs' broad phase feels).
inline bool candidateVertexTriangle(const SurfaceNodes& n, const ElementBoxes& b, const bool& cull, int v, int t,
                                    std::atomic<long>* pinned = nullptr) {
  const auto& tri = n.triangles[t];
  if (v == tri[0] || v == tri[1] || v == tri[2]) return false;
  const auto& m = n.node_inv_mass;
  if (!(m[v] + m[tri[0]] + m[tri[1]] + m[tri[2]] > 0)) {
    if (pinned) pinned->fetch_add(1, std::memory_order_relaxed);
    return false;
  }
  return !(cull && diagonallyApart(b.vertex_diagonals[v], b.triangle_diagonals[t]));
}
inline bool candidateEdgeEdge(const SurfaceNodes& n, const ElementBoxes& b, const bool& cull, int e, int f,
                              std::atomic<long>* pinned = nullptr) {
  const auto &p = n.edges[e], &q = n.edges[f];
  if (p[0] == q[0] || p[0] == q[1] || p[1] == q[0] || p[1] == q[1]) return false;
  const auto& m = n.node_inv_mass;
  if (!(m[p[0]] + m[p[1]] + m[q[0]] + m[q[1]] > 0)) {
    if (pinned) pinned->fetch_add(1, std::memory_order_relaxed);
    return false;
  }
  return !(cull && diagonallyApart(b.edge_diagonals[e], b.edge_diagonals[f]));
}

class CandidateSearch {
 public:
  CandidateSearch(const SurfaceNodes& nodes, const NodeMotion& motion, const Settings& settings, bool parallel,
                  Stats& counters)
      : nodes_(nodes), motion_(motion), settings_(settings), parallel_(parallel), counters_(counters) {}

  // The most candidate pairs a broad phase may list (Settings::candidates_per_vertex, min_candidates).
  std::size_t budget() const;
  // The round's candidates from the swept boxes (nxs to nxe) padded by half the largest thickness and margin more.
  // Directly before a detection (after_impulses: a later round, impulses applied since the last broad phase), less the
  // pairs a fixed axis keeps further apart than the thickness all through the step (apartAllStep), which continuous
  // detection would not find (never within eta, a thousandth of it), and only the pairs with a node moved since the
  // last detection (dirty), the only ones it tests then: the same pairs that detection finds, in the same order. The
  // step's first broad phase keeps them all: repulsion changes the trajectories before that round's detection, which
  // tests apartAllStep per pair. In the world's frame alone when world_only (a list kept across steps must serve steps
  // with other shifts). Returns false when the lists would exceed the budget (they are then left empty).
  bool broadPhase(Candidates& round, bool after_impulses = false, double margin = 0, bool world_only = false);
  // Into vf_out and ee_out, ascending: the pairs whose boxes swept from nxs to `end` (each in its body's frame when
  // shifts is not empty, the world's for pairs of two bodies; padded by pad) overlap. marked: only the pairs with an
  // element marked in marks; apart: less those apartAllStep keeps apart all through (nxs to nxe). Counts the broad
  // phase; false when it would exceed the budget (the lists are then incomplete).
  bool listPairs(bool cull, const VecX& end, const std::vector<Vec3>& shifts, double pad, bool marked, bool apart,
                 PairList& vf_out, PairList& ee_out);
  // Every element's box (in boxes) swept from nxs to end, each in its body's frame (moving by shifts[body] over the
  // step) or, without shifts, the world's, padded by pad; with the culls, its diagonals too.
  void fillSweptBoxes(bool cull, const VecX& end, const std::vector<Vec3>* shifts, double pad);
  // Into vf_found and ee_found, ascending: the pairs whose boxes in b overlap and whose bodies `bodies` accepts, less
  // those of adjacent elements, of pinned nodes only, and (with the culls) those the diagonals part; marked and apart
  // as for listPairs. used: candidates found already (of the budget). False: over the budget.
  template <class Bodies>
  bool findPairs(const ElementBoxes& b, bool cull, const Bodies& bodies, bool marked, bool apart, PairList& vf_found,
                 PairList& ee_found, std::size_t used);
  // Counts a broad phase that listed `listed` candidates.
  void counted(std::size_t listed) {
    ++counters_.broad_phases;
    counters_.candidates += long(listed);
  }
  // Why the pass stops when the broad phase exceeds its budget: the vertex that moved furthest in the step.
  Failure overwhelmedFailure() const;

  ElementBoxes boxes;  // the last broad phase's
  ElementMarks marks;  // the elements a partial search looks up (ElementMarks::mark)

 private:
  // Per body, the shift of the frame its own pairs are found in (the header): the median of its nodes'
  // displacements over the step, axis by axis (the motion most of the body shares: when part of a falling cloth has
  // landed, a mean would leave both parts' boxes long). Empty when no body has self-contact.
  std::vector<Vec3> frameShifts() const;

  const SurfaceNodes& nodes_;
  const NodeMotion& motion_;
  Settings settings_;
  bool parallel_;
  Stats& counters_;
};

template <class Bodies>
bool CandidateSearch::findPairs(const ElementBoxes& b, bool cull, const Bodies& bodies, bool marked, bool apart,
                                PairList& vf_found, PairList& ee_found, std::size_t used) {
  const SurfaceNodes& n = nodes_;
  const VecX &nxs = motion_.nxs, &nxe = motion_.nxe;
  const std::size_t limit = budget();
  const auto pairs = [&](const std::vector<Box>& queries, const std::vector<Box>& targets, bool same,
                         const std::vector<char>& query_moved, const std::vector<char>& target_moved,
                         const std::function<bool(int, int)>& keep, PairList& out, std::size_t most) {
    return marked
               ? overlappingMarkedPairs(queries, targets, same, parallel_, query_moved, target_moved, keep, out, most)
               : overlappingPairs(queries, targets, same, parallel_, keep, out, most);
  };
  std::atomic<long> pinned{0};  // pairs of pinned nodes only, dropped (Stats::pinned_pairs)
  const bool found =
      pairs(
          b.vertex, b.triangle, false, marks.vertex, marks.triangle,
          [&](int v, int t) {
            if (!bodies(n.vertex_body[v], n.triangle_body[t]) || !candidateVertexTriangle(n, b, cull, v, t, &pinned))
              return false;
            return !apart || !(cull && apartAllStep(nxs, nxe, &v, 1, n.triangles[t].data(), 3,
                                                    n.pairThickness(n.vertex_body[v], n.triangle_body[t])));
          },
          vf_found, limit - std::min(limit, used)) &&
      pairs(
          b.edge, b.edge, true, marks.edge, marks.edge,
          [&](int e, int f) {
            if (!bodies(n.edge_body[e], n.edge_body[f]) || !candidateEdgeEdge(n, b, cull, e, f, &pinned)) return false;
            return !apart || !(cull && apartAllStep(nxs, nxe, n.edges[e].data(), 2, n.edges[f].data(), 2,
                                                    n.pairThickness(n.edge_body[e], n.edge_body[f])));
          },
          ee_found, limit - std::min(limit, used + vf_found.size()));
  counters_.pinned_pairs += pinned.load(std::memory_order_relaxed);
  return found;
}

}  // namespace wobble::collision
