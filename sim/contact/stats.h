// What the pass between bodies counts, and how it fails (collisions/body_collisions.h).
#pragma once
#include <limits>
#include <string>

namespace wobble::collision {

struct Stats {
  long passes = 0;              // steps checked
  long passes_skipped = 0;      // of them, those the clearance showed free of contact without detection (clearance.h)
  long searches_skipped = 0;    // backward Euler's near-pair searches skipped so
  long clearance_measures = 0;  // clearances measured
  long skin_passes = 0;         // of them, those whose candidates came from an earlier step's broad phase (its skin)
  long skin_searches = 0;       // backward Euler's steps whose near-pair candidates came from an earlier step's
  long contacts = 0;            // pairs within the thickness at a step's start (repulsion impulses)
  long ccd_hits = 0;            // collisions found by continuous detection and stopped by impulses
  long zone_activations = 0;    // steps that needed rigid impact zones
  long zone_rounds = 0;         // impact-zone rounds over all steps
  int largest_zone = 0;         // particles in the largest impact zone
  long broad_phases = 0;        // broad phases run (a step's first, and those of its later rounds and solves)
  long candidates = 0;          // candidate pairs they listed (point-triangle and edge-edge)
  long pinned_pairs = 0;        // pairs of overlapping boxes they dropped for joining pinned nodes only (search.h)
  long step_updates = 0;        // backward Euler's searches that brought the step's candidates to a far end in part
  long skin_lists = 0;          // lists found padded for later steps (skins: the pass's and backward Euler's)
  long skin_updates = 0;        // backward Euler's kept lists brought up to date in part (vertices that left theirs)
  long step_rounds = 0;         // the pass's later rounds that took backward Euler's step list, not a broad phase
  // Smallest distance between non-adjacent surface elements seen at any step's start, over the pairs within the
  // thickness there (infinity when no pair ever was).
  double min_distance = std::numeric_limits<double>::infinity();
};

struct Failure {
  int particle;  // one particle of a collision left (or of the vertex that moved furthest)
  std::string reason;
  std::string fix;  // what to change, when not the contact settings (empty: Simulation suggests those)
};

}  // namespace wobble::collision
