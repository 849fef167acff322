// `wobble study accuracy`: error against run time for each integrator on one scene (a work-precision study).
// Each integrator runs a sweep of fixed steps dt = T / 2^k (k = k_min..k_max) over the simulated time T; rk45 runs
// a sweep of tolerances rtol = atol = 10^-j (j = tol_min..tol_max) with a sample interval as its largest step (the
// scene's dt if smaller and the scene has colliders: collisions are resolved only between steps). Every
// run is compared with a reference solution at `samples` equally spaced times (multiples of every swept dt, so no
// step is shortened): the final error is max over moving particles of |x - x_ref| at T, the RMS error is over all
// samples and moving particles (metres, positions only). Run time is the minimum of `repeats` runs after a warm-up
// run (the warm-up gives the errors). Runs that blow up (sim/simulation.h) or fail are left out and listed.
// Reference: "rk45" (DOPRI5 at rtol = atol = 1e-12, largest step as for the sweep) or "rk4" (RK4 at the
// finest swept dt / 16); "auto" picks rk45 for a scene without colliders, else rk4 (contact makes the right-hand
// side discontinuous and a tolerance-driven DOPRI5 crawl). The reference's own error is estimated by comparing it
// with a second reference 10x looser (rk45) or at twice its step (rk4); errors below 10x that floor are shown but
// left out of the order fit. Fitted order: least-squares slope of log error against log dt (rk45: against the mean
// accepted substep T / accepted). With colliders, rk45 may take at most 64 substeps per scene step (else left out).
// On a farm (farm_pieces.h): the work items are the reference, its looser twin, then every point in the order above;
// `piece` runs only its own, keeping each run's trajectory at the sample times (exact doubles) and times in
// OUT/pieces/accuracy/, so no piece needs the reference; `gather` runs none and takes the errors from the kept
// trajectories: the errors, steps and fits of a one-machine run (run times are each run's where its piece ran).
#pragma once
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "app/study/farm_pieces.h"

namespace wobble {

// With colliders, rk45 may take at most this many substeps per scene step (it crawls through contact switches).
inline constexpr long kAccuracyContactSubsteps = 64;

struct AccuracyOptions {
  std::filesystem::path scene = "scenes/cloth_swing.toml";
  std::vector<std::string> sets;         // KEY=VALUE scene overrides, as for `wobble run`
  std::vector<std::string> integrators;  // empty: all
  std::filesystem::path out;             // empty: out/study-accuracy-<scene name>
  double duration = 1;                   // T, simulated seconds
  int k_min = 6, k_max = 12;             // dt = T / 2^k
  int tol_min = 3, tol_max = 9;          // rk45: rtol = atol = 10^-j
  int samples = 16;                      // comparison times T j / samples, j = 1..samples (a power of 2)
  int repeats = 3;                       // timed runs after the warm-up
  std::string reference = "auto";        // auto, rk45, rk4
  std::string gnuplot = "gnuplot";
  bool progress = true;        // on a terminal only (app/progress.h)
  std::optional<Piece> piece;  // run only this piece's work items, kept in out/pieces (out must be set)
  bool gather = false;         // run nothing: the result from every piece's items in out/pieces
};

struct AccuracyPoint {
  std::string integrator;
  double dt = 0;         // fixed step; rk45: its largest step
  double rtol = 0;       // rk45 only
  double mean_step = 0;  // T / steps; rk45: T / accepted substeps (what the order is fitted against)
  double final_error = 0, rms_error = 0, seconds = 0;
  long steps = 0, evaluations = 0;
  bool diverged = false;
  std::string failure;  // why it was left out
  bool in_fit = false;  // finite and above the reference's error floor
};

struct AccuracyFit {
  std::string integrator;
  int expected = 0;                       // theoretical order
  double order_final = 0, order_rms = 0;  // NaN when fewer than two points
  int points = 0;                         // used in the fit
};

struct AccuracyResult {
  std::string scene_name;
  std::filesystem::path scene_file;
  bool has_colliders = false;
  int particles = 0, moving_particles = 0;
  double duration = 0;
  std::string reference;         // description
  double reference_seconds = 0;  // wall time of the reference run
  double reference_error = 0;    // its estimated final error (floor of meaningful errors)
  std::vector<AccuracyPoint> points;
  std::vector<AccuracyFit> fits;
  PieceRun piece;  // with --piece: what it ran (points and fits are then empty)
};

// Throws InputError for bad options or scene input.
AccuracyResult runAccuracyStudy(const AccuracyOptions& options);

// Per-integrator fits of a result's points (also used by the tests on synthetic tables).
std::vector<AccuracyFit> fitAccuracy(const std::vector<AccuracyPoint>& points);

// "T/64" for a step that is T / 2^k, else the step in seconds (4 digits): how reports name a step.
std::string accuracyStepLabel(double duration, double dt);

}  // namespace wobble
