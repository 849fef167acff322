// The step's candidates (candidates.h, StepCandidates), kept through backward Euler's solves
// (BodyCollisions::nearPairs) and the pass after the step (resolve).
#pragma once
#include <cstddef>
#include <vector>

#include "sim/contact/candidates/candidates.h"
#include "sim/contact/candidates/search.h"
#include "sim/contact/candidates/skins.h"

namespace wobble::collision {

// The step's candidates are found once for the swept boxes from the start to the first solve's end, padded by
// kStepMarginFraction of the thickness more, with each pair's nearest points at the start. They stand while the start
// is the same bytes and every node's end lies within that margin of the end they were found for: each exact swept box
// then lies inside its padded one, so the list holds every pair of the exact broad phase, in the same ascending order,
// and the tests that follow (a distance within the thickness, a gap, a hit along the step) drop the others: the same
// contacts in the same order, without a broad phase and nearest points again at each solve. (Of those pairs the list
// keeps the ones a search may test, keepMeasured; an end with some nodes beyond the margin brings it up to date in
// part, update. The boxes of a body's pairs with itself are in its moving frame, search.h.) Most candidates lie far
// apart along their nearest points' direction d at the start, and stay so at the end (neighbours within one flat layer
// of a cloth). Along a fixed unit d the gap between the two elements' projections is concave over the step
// (distance/separation.h). An end whose nodes moved by at most `drift` (Euclidean) from the one the candidates were
// found for changes that gap by at most 2 drift. So each candidate keeps its gap there, less what a search looks for
// (its slack), and a later search tests only the candidates whose slack is at most 2 drift: every other one would fail
// its tests anyway.
class StepList {
 public:
  StepList(const SurfaceNodes& nodes, const NodeMotion& motion, CandidateSearch& search, Skins& skins, bool parallel,
           Stats& counters)
      : nodes_(nodes), motion_(motion), search_(search), skins_(skins), parallel_(parallel), counters_(counters) {}

  // Takes the step's candidates if they stand for (nxs, nxe), or can be brought to it (may_update:
  // update); returns whether it did.
  bool reuse(Candidates& round, bool may_update = true);
  // The candidates of a later round of the pass, after impulses changed some trajectories (dirty nodes): the step's
  // list where it stands for the new ends as it is (each within the margin of the end it was found for: detect then
  // tests its candidates with a dirty node), else a broad phase of the elements holding a dirty node. Never the step's
  // list brought up to date: impulses may move many nodes a little beyond the margin, and an update sorts the whole
  // list again, where the marked lookup touches only what moved. False: over the budget.
  bool laterRound(Candidates& round);
  // The step's candidates for (nxs, nxe), found anew, with their nearest points at the start and gaps
  // at the end. Returns false (no candidates: the step stays invalid) when the broad phase exceeds its budget.
  bool find(Candidates& round);

  StepCandidates step;  // the near pairs' search notes where it put each candidate's pair (joined)

 private:
  // Candidate k of the step's lists: its nearest points at the start, and the values the searches' lists are sorted by,
  // at the nodes' ends step.end.
  struct Measure {
    Closest closest;
    double closing, hitting;
    char near;
  };
  Measure measured(const Candidates& round, int k) const;
  // Whether a candidate so measured stays in the step's lists, and the slack beyond which none is tested.
  bool kept(const Measure& m) const;
  double most() const;
  // Candidate j of the lists (its measures in place) into the lists each search takes, and near_min.
  void list(int j);
  // A candidate kept, with its measures and where the near pairs' search put its pair (StepCandidates::joined).
  struct Kept {
    int k;
    Measure m;
    std::size_t joined;
  };
  // The step's lists (StepCandidates) from the candidates of its lists as they stand (round reads them) that
  // measure(k, Kept&) keeps, in order, with the measures it gives; near_min lowered by theirs. Only the candidates
  // in a list stay: any other can pass no test at an end the list serves, and is measured again only if update finds
  // it again. Measured on threads, chunk by chunk, and only the kept ones held: arrays of every candidate's measures
  // would take most of a large cloth's memory at a landing.
  template <class Fn>
  void keepMeasured(const Candidates& round, Fn&& measure);
  // Brings the step's own list (found by a broad phase for this start) to the end nxe when some nodes' ends lie
  // beyond the margin of those it was found for (a later solve of backward Euler's that moved part of the body far: an
  // impact): each such node's reference end becomes its new end; the candidates with no such node keep their place,
  // nearest points and measures (their boxes did not change); those with one are listed again, for their new
  // boxes in the list's frames, measured and kept or dropped (keepMeasured). The list then holds, in the same order,
  // what find would keep of a broad phase of the same frames and padding for the new reference ends; and every node's
  // end lies within the margin of its reference, as reuse asks. Returns false (the list is left as it was) when it
  // would exceed the candidate budget.
  bool update(Candidates& round);

  const SurfaceNodes& nodes_;
  const NodeMotion& motion_;
  CandidateSearch& search_;
  Skins& skins_;
  bool parallel_;
  Stats& counters_;
  // The step's per-candidate values (beside StepCandidates'), kept: fresh pages each step cost more than the work.
  struct {
    std::vector<double> closing, hitting;
    std::vector<char> near;
  } scratch_;
  struct {
    std::vector<char> beyond;
    PairList fresh_vf, fresh_ee, merged_vf, merged_ee;
    std::vector<int> from;
  } update_scratch_;                             // update's
  std::vector<std::vector<Kept>> kept_scratch_;  // keepMeasured's kept candidates, per chunk
};

}  // namespace wobble::collision
