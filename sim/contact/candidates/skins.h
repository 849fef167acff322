// Candidate lists kept across steps (candidates.h), as a Verlet list keeps its neighbours within a skin: the pass's
// (Skin, kept whole or not at all) and backward Euler's searches' (StepSkin, kept up to date in part).
#pragma once
#include <initializer_list>
#include <vector>

#include "sim/contact/broad_phase/element_bounds.h"
#include "sim/contact/candidates/candidates.h"
#include "sim/contact/candidates/search.h"
#include "sim/contact/node_motion.h"
#include "sim/contact/stats.h"

namespace wobble::collision {

// Candidates kept across steps, as a Verlet list keeps its neighbours within a skin: found for boxes padded by a
// margin (kSkinFraction of the largest thickness) more than a broad phase needs, they hold every pair of that broad
// phase for any step whose nodes all lie, at its start and its end, within half that margin of the box each swept
// when they were found (the other half covers the rounding of the boxes): each padded box the step needs then lies
// inside the skin's. The surplus pairs, in the same ascending order, fail the geometric tests that follow (start
// boxes within the thickness, an axis apart all along, a hit, a gap): the same contacts in the same order. Serves
// steps that move a node by a small part of the thickness (an explicit integrator's; a body resting under backward
// Euler), where the broad phase is much of the work; a skin is built only after such a step. This one is the pass's
// (the exact broad phase's pairs; backward Euler's step lists keep theirs up to date in part, StepSkin).
// The pass's also keeps a lower bound of each candidate's distance at the start of the step that found the list
// (its nearest points' distance where repulsion found them, else its start boxes' gap along an axis). Moving each
// node by at most D from there changes the distance between two elements by at most 2 D (each element's hull moves
// by at most D), and along a linear step each node stays within the larger of its two ends' displacements. So a
// later step skips, in repulsion, the candidates whose bound less 2 D stays above the thickness and the smallest
// distance seen (they neither touch nor lower it), and in continuous detection those whose bound less 2 D stays
// above twice eta: the same contacts, hits and statistics.
struct Skin {
  bool valid = false;
  VecX lo, hi;  // per node coordinate: where the node may lie at a step's start and end
  PairList vf, ee;
  VecX reference;             // the nodes' start when the list was found
  std::vector<double> lower;  // the pass's, per candidate: a lower bound of its distance there
  bool lower_valid = false;   // filled by the repulsion of the step that found the list
  int served = 1;             // steps the last list found served (before any: taken as served)
};

// Backward Euler's step lists kept across steps, as a Verlet list kept up to date in part (the pass's Skin is kept
// whole or not at all): each node has an interval per coordinate, its start and end when it was set widened by
// kNodeSlackFraction of the largest thickness each way; each element a box (and diagonals) over its nodes'
// intervals, padded as the step's boxes are; and the list holds every pair whose boxes overlap (found as a broad
// phase finds them). At a step whose nodes all lie, at its start and its end, within their intervals, each element's
// box for the step (in the world's frame) lies inside its kept one (rounding is monotone: the same sums of smaller
// numbers are no larger), so every pair of that step's broad phase is in the list, and testing each listed pair's
// boxes and diagonals for the step cuts the list down to exactly that broad phase's pairs, in the same order, with no
// lookup. A node outside its interval gets a new one, and only the elements holding such a node are looked up again
// (their kept pairs dropped, their new ones merged in order): on a cloth lying collapsed on itself 4 to 8% of the
// nodes a step, where a whole broad phase was the largest part of detection (docs/body-contact.md).
struct StepSkin {
  bool valid = false;
  VecX lo, hi;  // per node coordinate
  ElementBoxes boxes;
  PairList vf, ee;
  std::vector<char> outside;  // per node: outside its interval at this step
  PairList fresh_vf, fresh_ee, merged;
};

class Skins {
 public:
  Skins(const SurfaceNodes& nodes, const NodeMotion& motion, CandidateSearch& search, bool parallel, Stats& counters)
      : nodes_(nodes), motion_(motion), search_(search), parallel_(parallel), counters_(counters) {}

  // The candidates for the pass over (nxs, nxe) into round: the pass's skin's when it serves, else a broad phase's.
  // False: over the budget.
  bool passCandidates(Candidates& round);
  // Into round, the pairs of a broad phase over (nxs, nxe) in the world's frame with boxes padded by pad, from the
  // step skin: 1 when it served (brought up to date or not), 2 when it was found anew; 0 when it cannot serve this
  // step (the caller then runs the broad phase): more than a quarter of the nodes left their intervals, or it is not
  // found anew after a step that moved more than an eighth of the nodes by more than their slack (most of a falling
  // body's: they would leave at the next step), or it would exceed the candidate budget.
  int stepCandidates(Candidates& round, double pad);
  // The largest distance of a node from the pass's skin's reference, over the given per-node vectors.
  double skinDrift(std::initializer_list<const VecX*> xs) const;

  Skin skin;  // the pass's: repulsion and detection read and fill its bounds

 private:
  int keptCandidates(Candidates& round, Skin& k, double margin);
  bool updateStepSkin(double pad, double slack, bool cull);
  auto stepSkinBox(double pad) const;
  template <class Keep>
  void keepPairs(const PairList& in, PairList& out, Keep&& keep);

  const SurfaceNodes& nodes_;
  const NodeMotion& motion_;
  CandidateSearch& search_;
  bool parallel_;
  Stats& counters_;
  StepSkin step_skin_;
  std::vector<char> keep_scratch_;  // keepPairs', kept from step to step
};

}  // namespace wobble::collision
