// The facade's state (body_collisions.h): the stages of the pass and what they hand each other. Defined for
// body_collisions.cpp (the pass) and near_pairs.cpp (backward Euler's searches).
#pragma once
#include <algorithm>
#include <sstream>

#include "sim/contact/candidates/candidates.h"
#include "sim/contact/candidates/clearance.h"
#include "sim/contact/candidates/search.h"
#include "sim/contact/candidates/skins.h"
#include "sim/contact/candidates/step_list.h"
#include "sim/contact/ccd/detection.h"
#include "sim/contact/ccd/impact_zones.h"
#include "sim/contact/collisions/repulsion.h"
#include "sim/contact/node_motion.h"
#include "sim/contact/pair_set.h"

#include "sim/contact/collisions/body_collisions.h"

namespace wobble::collision {

struct BodyCollisions::Impl {
  Impl(const std::vector<Surface>& surfaces, const VecX& inverse_mass, Settings s, bool threads, Stats& counters)
      : nodes(surfaces, inverse_mass),
        inv_mass(inverse_mass),
        settings(s),
        parallel(threads),
        search(nodes, motion, settings, parallel, counters),
        skins(nodes, motion, search, parallel, counters),
        steps(nodes, motion, search, skins, parallel, counters),
        repulsion(nodes, motion, inv_mass, skins, parallel),
        detection(nodes, motion, inv_mass, skins, parallel),
        zones(nodes, motion, inv_mass),
        clearance(nodes, search, parallel, counters) {
    motion.node_mark.assign(nodes.nodeCount(), 0);
  }

  SurfaceNodes nodes;
  const VecX& inv_mass;
  Settings settings;
  bool parallel;
  NodeMotion motion;       // the step's trajectories, which the stages change
  CandidateSearch search;  // the broad phase
  Skins skins;             // lists kept across steps
  StepList steps;          // the step's list, kept through backward Euler's solves and the pass
  Candidates round;        // what the search hands the stages
  Repulsion repulsion;     // stage 1
  Detection detection;     // stage 2
  ImpactZones zones;       // stage 3
  ContactPairSet known;    // nearPairs: the pairs already in its list
  Clearance clearance;     // whether a step may skip all of it
};

}  // namespace wobble::collision
