// When a step needs no detection at all: the pass between bodies (and backward Euler's searches) skipped while no two
// surface elements can come within the thickness, a conservative version of the time-coherence schemes that
// schedule detection by how far things can move (Mirtich 1996, "Impulse-based dynamic simulation of rigid body
// systems", safe time steps; the Verlet skin of skins.h, taken to a whole pass).
// The clearance is measured at a reference state: every node's position blended from x_ref, each element's box
// there padded by pad (and its diagonals, element_bounds.h), the pairs whose padded bounds meet found as a broad
// phase finds them (the same pairs the pass tests: not adjacent, not of pinned nodes only, of bodies that meet; listed
// through the pairs of triangles whose boxes meet, each vertex and edge owned by one triangle: listPairs), and
// per pair a lower bound of its distance (the gap between its two elements' projections on the direction of their
// nearest points, which no direction exceeds). Every other pair is further apart than 2 pad. So the smallest distance
// between any two elements the pass tests is at least G, the least of 2 pad and the pairs' bounds.
// A later step moves the particles linearly from x0 to x1. Per body b and end, the displacements u_k = x_k - x_ref,k of
// the body's particles lie in their box (per axis, from the least to the greatest; at a step's start, the box the last
// covered step found at its end where the pass says the step continues from there), within its half-diagonal h_b of its
// centre c_b (a common translation moves the box, not h_b); in between, each u_k(t) lies within the larger h_b of the
// two ends of the centre's own straight path (the norm is convex). A node blends particles with weights that sum to
// 1, so it moves from its reference by c_b plus at most W_b D_b, D_b the larger h_b of the two ends and W_b the largest
// sum of |weights| of a node (1 for a node that is a particle). Two elements of body b come closer by at most
// 2 W_b D_b; of bodies a and b by at most W_a D_a + W_b D_b + |c_a - c_b| (the larger of the two ends). While the
// largest such closing over the pairs of bodies that meet stays below G less the largest thickness (less a slack for
// rounding), every pair stays further apart than the thickness all through the step: the pass would find no pair
// within it at the start, no collision along the step (those are within a thousandth of it) and change no byte of
// x1 or v1, and backward Euler's searches would hand over no pair (they hand over only pairs within the thickness at
// the end or colliding). Such a step skips them.
// The reference need not be a state the run passes through: the bound holds for any x_ref at which G was measured.
// The clearance is measured again at a step that the last measure no longer covers, unless the last pass that ran
// found something near (a pair within the thickness, a collision): a scene in contact never pays for it. After a
// measure that served to its end, at a reference ahead of the step's start x0 along the motion since that measure's
// own start (kAhead), so that the next steps move about it rather than away from it; where that does not cover the
// step, and otherwise, at x0 itself. A measure that served fewer than kPayoff steps makes the next wait for twice as
// many steps (up to kMostWait).
#pragma once
#include <vector>

#include "sim/contact/broad_phase/element_bounds.h"
#include "sim/contact/candidates/search.h"
#include "sim/contact/stats.h"
#include "sim/contact/surface_nodes.h"

namespace wobble::collision {

// Whether steps skip detection where they can (setSkipWhileApart, body_collisions.h).
bool skipWhileApart();

// What a call of Clearance::covers checks. final_pass: the pass after a step, whose x1 stays as it is where covers
// returns true (false: a trial end, as the solve's near-pair searches check); continues: the caller vouches that x0 is
// the same bytes as the x1 of its last call, so where that call was a final pass and covered its step, x0's spread (the
// first of the two passes over the particles a check makes) is that call's.
struct ClearanceQuery {
  bool final_pass = false;
  bool continues = false;
};

class Clearance {
 public:
  Clearance(const SurfaceNodes& nodes, CandidateSearch& search, bool parallel, Stats& counters);

  // Whether no two elements the pass tests can come within the thickness over a step from x0 to x1 (particles'
  // positions): detection would find nothing. Measures the clearance at x0 first where there is none that serves
  // (and a measure may pay).
  bool covers(const VecX& x0, const VecX& x1, ClearanceQuery query = {});
  // After a pass that ran: whether it found a pair within the thickness or a collision.
  void passed(bool near);

  double clearance() const { return clearance_; }  // G of the last measure (0: none yet)

 private:
  void measure(const VecX& x);
  // Into vf_ and ee_: the pairs the pass tests whose padded boxes and diagonals (boxes_) overlap, as
  // CandidateSearch::findPairs lists them; through the pairs of triangles whose boxes overlap where every vertex lies
  // on a triangle. False: over the search's budget.
  bool listPairs();
  // Per body, the centre and half-diagonal of its displacements' box at x, into end (0 or 1) of centre_ and half_;
  // false where a coordinate is not finite.
  bool spread(const VecX& x, int end);
  // The largest closing of two elements over a step whose ends are x0 and x1, by the bound above; stops early (and
  // returns at least limit) once it reaches limit.
  // start_known: x0's spread is at end 1 already (covers' continues).
  double closing(const VecX& x0, const VecX& x1, double limit, bool start_known = false);

  const SurfaceNodes& nodes_;
  CandidateSearch& search_;
  bool parallel_;
  Stats& counters_;
  struct Body {
    std::vector<std::pair<int, int>> ranges;  // its nodes' particles, as runs [begin, end)
    double weight;                            // W_b
  };
  std::vector<Body> bodies_;
  std::vector<std::pair<int, int>> meeting_;  // the pairs of bodies a < b that meet
  // Per triangle, the vertices and the edges it owns (runs [start[t], start[t + 1]) of owned): each vertex and edge is
  // owned by the first triangle that holds it. Empty where some vertex lies on no triangle.
  std::vector<int> vertex_start_, vertex_owned_, edge_start_, edge_owned_;
  bool valid_ = false, near_ = false;
  bool end_known_ =
      false;            // the last call was a final pass and covered: its x1's spread is at end 1 of centre_ and half_
  VecX reference_;      // x_ref, per particle
  VecX start_, ahead_;  // x0 of the step that took the last measure; the reference ahead of one
  double clearance_ = 0, allowance_ = 0;  // G, and the closing a step may have: G less the thickness and the slack
  long served_ = 0;                       // steps skipped since the last measure
  int wait_ = 0, backoff_ = 0;            // passes before the next measure; the wait after a measure that did not pay
  VecX blended_;
  ElementBoxes boxes_;
  PairList vf_, ee_, triangle_pairs_;
  std::vector<PairList> vf_parts_, ee_parts_;  // listPairs' per chunk
  std::vector<double> partials_;
  std::vector<Vec3> centre_;  // closing's, per body and end: c_b
  std::vector<double> half_;  // h_b
};

}  // namespace wobble::collision
