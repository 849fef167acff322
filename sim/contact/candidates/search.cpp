#include "sim/contact/candidates/search.h"

#include <algorithm>
#include <atomic>
#include <iterator>
#include <sstream>

namespace wobble::collision {
namespace {
std::atomic<bool> motion_cull{true};
}  // namespace

void setBroadPhaseCulls(bool on) { motion_cull = on; }
bool broadPhaseCulls() { return motion_cull; }

std::size_t CandidateSearch::budget() const {
  return std::max(std::size_t(std::max(0L, settings_.min_candidates)),
                  std::size_t(std::max(0, settings_.candidates_per_vertex)) * std::size_t(nodes_.nodeCount()));
}

std::vector<Vec3> CandidateSearch::frameShifts() const {
  const auto& params = nodes_.params;
  const VecX &nxs = motion_.nxs, &nxe = motion_.nxe;
  std::vector<std::vector<double>> moves(3 * params.size());  // per body and axis, its nodes' displacements
  bool any = false;
  for (int k = 0; k < nodes_.nodeCount(); ++k) {
    const int b = nodes_.vertex_body[k];
    if (!params[b].self_contact) continue;
    for (int a = 0; a < 3; ++a) moves[3 * b + a].push_back(nxe[3 * k + a] - nxs[3 * k + a]);
    any = true;
  }
  if (!any) return {};
  std::vector<Vec3> shift(params.size(), Vec3::Zero());
  for (std::size_t b = 0; b < params.size(); ++b)
    for (int a = 0; a < 3; ++a) {
      std::vector<double>& m = moves[3 * b + a];
      if (m.empty()) continue;
      std::nth_element(m.begin(), m.begin() + m.size() / 2, m.end());
      shift[b][a] = m[m.size() / 2];
    }
  return shift;
}

bool CandidateSearch::broadPhase(Candidates& round, bool after_impulses, double margin, bool world_only) {
  round.renew(broadPhaseCulls());
  const bool cull = round.cull;
  const bool moved_only = after_impulses && cull;
  round.listed.pad = 0.5 * nodes_.max_thickness + margin;
  round.listed.shifts = cull && !world_only ? frameShifts() : std::vector<Vec3>();
  if (moved_only) marks.mark(nodes_, motion_.dirty);
  const bool found =
      listPairs(cull, motion_.nxe, round.listed.shifts, round.listed.pad, moved_only, moved_only, round.vf, round.ee);
  if (!found) round.vf.clear(), round.ee.clear();
  return found;
}

bool CandidateSearch::listPairs(bool cull, const VecX& end, const std::vector<Vec3>& shifts, double pad, bool marked,
                                bool apart, PairList& vf_out, PairList& ee_out) {
  const auto& params = nodes_.params;
  bool found;
  if (shifts.empty()) {
    fillSweptBoxes(cull, end, nullptr, pad);
    found = findPairs(
        boxes, cull, [&](int a, int b) { return nodes_.bodiesMeet(a, b); }, marked, apart, vf_out, ee_out, 0);
  } else {
    fillSweptBoxes(cull, end, &shifts, pad);  // each body's pairs with itself in its own frame
    found = findPairs(
        boxes, cull, [&](int a, int b) { return a == b && params[a].self_contact; }, marked, apart, vf_out, ee_out, 0);
    if (found && params.size() > 1) {
      thread_local PairList self_vf, self_ee, other_vf, other_ee;
      self_vf.swap(vf_out), self_ee.swap(ee_out);
      fillSweptBoxes(cull, end, nullptr, pad);  // pairs of two bodies in the world's
      found = findPairs(
          boxes, cull, [&](int a, int b) { return a != b; }, marked, apart, other_vf, other_ee,
          self_vf.size() + self_ee.size());
      vf_out.clear(), ee_out.clear();
      std::merge(self_vf.begin(), self_vf.end(), other_vf.begin(), other_vf.end(), std::back_inserter(vf_out));
      std::merge(self_ee.begin(), self_ee.end(), other_ee.begin(), other_ee.end(), std::back_inserter(ee_out));
    }
  }
  counted(vf_out.size() + ee_out.size());
  return found;
}

void CandidateSearch::fillSweptBoxes(bool cull, const VecX& end, const std::vector<Vec3>* shifts, double pad) {
  const VecX& nxs = motion_.nxs;
  fillBoxes(nodes_, marks, boxes, false, parallel_,
            [&](const auto& element, int body, Box& box_out, Diagonals& diagonals_out) {
              const Vec3 shift = shifts ? (*shifts)[body] : Vec3::Zero();
              box_out = sweptBox(element, pad, nxs, end, shift);
              if (cull) diagonals_out = sweptDiagonals(element, pad, nxs, end, shift);  // read under the culls only
            });
}

Failure CandidateSearch::overwhelmedFailure() const {
  int furthest = 0;
  double most = 0;
  for (int k = 0; k < nodes_.nodeCount(); ++k) {
    const double move = (particle(motion_.nxe, k) - particle(motion_.nxs, k)).norm();
    if (move > most || !(move == move)) furthest = k, most = move;
  }
  std::ostringstream why;
  why << "the broad phase would list more than " << budget() << " candidate pairs in this step (" << nodes_.nodeCount()
      << " surface vertices): the surfaces moved too far in it (a vertex by " << most
      << " m, against a contact thickness of " << nodes_.max_thickness << " m)";
  return Failure{nodes_.mainParticle(furthest), why.str(),
                 "or bodies that start nearer rest (one released under strain can move many particle spacings in "
                 "a step)"};
}

}  // namespace wobble::collision
