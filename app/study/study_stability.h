// `wobble study stability`: for each integrator, a map over spring stiffness ks (every spring of every body) and
// time step dt of what a short run does: stable, blew up (sim/simulation.h's rule: a NaN or |v|^2 > 1e6), or
// survived but lost its shape (largest spring strain |l - rest| / rest above strain_bound at any check, every
// 0.01 s), or gained energy (the run's energy check, docs/energy.md). Each cell runs the scene from its initial state
// for `duration` simulated seconds, or until it blows up. Beside the map, theory's boundary (stability_theory.h): the
// largest stable dt at each ks from omega_max by Gershgorin and by power iteration. rk45 picks its own steps (dt is
// only its largest), so it is skipped unless named in integrators. With `infer`, a row (integrator, ks) is scanned from
// the largest dt down and stops at the first cell that did not blow up; the smaller steps get its outcome (stable or
// lost shape) without running
// ("inferred": stability regions of these methods contain the whole segment from 0 to their boundary, and a
// smaller step solves the same physics more accurately). The extra `cases` (ks, dt) always run, and so do the
// `contact` cases, each on its own scene (contact between bodies at large steps: ContactCase). Where no collider, pin
// or drag acts, a cell also measures how far the run moved the total linear momentum from what gravity alone gives
// (sum m v: p0 + M g t), and with no gravity either, the angular momentum (sum x x m v): internal forces (springs,
// dampers, contact between bodies) move neither.
// Rows run on `jobs` threads; each cell is single-threaded and deterministic, so the results do not depend on jobs.
// On a farm (farm_pieces.h): `piece` runs only that piece's rows (work items: per integrator, each grid ks, then each
// user case, then each contact case's runs) into OUT/pieces/stability/, resuming; `gather` runs none and reads them
// all, giving the StabilityResult of a one-machine run. This file runs the study into a plain StabilityResult;
// study_stability_report.h writes it.
#pragma once
#include <array>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "app/study/farm_pieces.h"
#include "sim/integrators/integrator.h"
#include "sim/system.h"

namespace wobble {

// A body whose largest spring strain passes this has lost its shape (also `wobble compare`'s mark).
inline constexpr double kStrainBound = 0.5;

// A contact case beside the map: a scene of bodies meeting, run under every integrator at each (ks, dt) of `runs`
// (every spring's ks set) for `duration` simulated seconds. `key` names it on the command line (--contact,
// --contact-scene KEY=FILE), in the CSV and in a piece's key; `title` heads its section of stability.md.
struct ContactCase {
  std::string key, title;
  std::filesystem::path scene;
  std::vector<std::array<double, 2>> runs;  // (ks, dt)
  double duration = 1;
};

// The study's contact cases, in report order:
//   landing    scenes/jelly_stack.toml, every spring at ks 1e5, dt 1/60, 1/120, 1/240 s for 1 s: a stiff jelly
//              landing on a jelly (blow-up, crush, energy gained at the landing);
//   free-pair  scenes/jelly_shot.toml at its own ks 2000, dt 1/60, 1/240, 1e-3, 5e-4, 2.5e-4 s for 0.5 s: a small jelly
//              shot into a large one, no gravity, no colliders (the momentum each integrator keeps through an impact).
const std::vector<ContactCase>& contactCases();
// The case of that key. Throws InputError naming `flag`, the key and the allowed keys when there is none.
const ContactCase& contactCase(const std::string& key, const std::string& flag);

struct StabilityOptions {
  std::filesystem::path scene = "scenes/jelly_impact.toml";
  std::vector<std::string> sets;
  std::vector<std::string> integrators;  // empty: all but rk45
  std::filesystem::path out;             // empty: out/study-stability-<scene name>
  double duration = 0.5;                 // simulated seconds per cell
  double strain_bound = kStrainBound;
  double ks_min = 1e3, ks_max = 1e9, dt_min = 1e-5, dt_max = 1.0 / 30;
  int ks_points = 7, dt_points = 6;  // log spaced, ends included (--fine: 13 x 12)
  std::vector<std::array<double, 2>> cases = {{5e4, 1.2e-3}, {1e5, 1.4e-3}};  // (ks, dt): the users' reports
  std::vector<ContactCase> contact = contactCases();                          // none: no contact case
  bool infer = true;
  int jobs = 0;  // 0: hardware threads
  std::string gnuplot = "gnuplot";
  bool progress = true;
  std::optional<Piece> piece;  // run only this piece's work items, kept in out/pieces (out must be set)
  bool gather = false;         // run nothing: the result from every piece's items in out/pieces
};

// GainedEnergy: ran to the end without blowing up, but the run's energy check failed (sim/simulation.h,
// docs/energy.md); it takes precedence over lost shape.
enum class Outcome { Stable, LostShape, BlewUp, Failed, GainedEnergy };
const char* toString(Outcome outcome);

struct StabilityCell {
  std::string integrator;
  double ks = 0, dt = 0;
  Outcome outcome = Outcome::Stable;
  bool inferred = false, user_case = false;
  std::string contact_case;                 // the contact case's key; empty in the map and the users' cases
  double max_strain = 0, final_strain = 0;  // over the checks / at the end (NaN when it blew up)
  double end_time = 0;                      // simulated time reached
  double max_speed = 0;                     // largest particle speed seen (m/s)
  // At the end: |p - (p0 + M g t)| / sum m |v0| (sum m |v0|: the largest |p0| the start's velocities could give), NaN
  // where a collider, a pin or drag acts or the state is not finite; and |L - L0| / sum m |(x0 - c0) x v0| (about the
  // origin; c0 the centre of mass: the start's angular momentum about it, were every particle turning one way), NaN
  // also under gravity.
  double momentum_drift = 0, angular_momentum_drift = 0;
  long steps = 0;
  std::string note;  // the failure's message
};

struct StabilityTheory {
  double ks = 0;
  double omega_gershgorin = 0, omega_power = 0, damper_ratio = 0;
  std::vector<double> dt_gershgorin, dt_power;  // per integrator, in StabilityResult::integrators order
};

struct StabilityResult {
  std::string scene_name;
  std::filesystem::path scene_file;
  std::vector<ContactCase> contact;         // the contact cases run
  std::vector<std::string> contact_scenes;  // their scenes' names
  double duration = 0, strain_bound = 0;
  std::vector<std::string> integrators;
  std::vector<double> ks, dt;  // the grid
  std::vector<StabilityCell> cells;
  std::vector<StabilityTheory> theory;  // per grid ks, then per user-case ks
  std::vector<std::string> notes;
  PieceRun piece;  // with --piece: what it ran (cells then holds its own rows only)
};

// One cell on a system already built at that ks, the integrator with the scene's options (its [simulation] solver keys
// and [contact] in_solve).
StabilityCell classifyCell(MassSpringSystem& system, const std::string& integrator, double dt, double duration,
                           double strain_bound, const IntegratorOptions& options = {});

// Throws InputError for bad options or scene input.
StabilityResult runStabilityStudy(const StabilityOptions& options);

}  // namespace wobble
