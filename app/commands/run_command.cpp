#include "app/commands/run_command.h"

#include <array>
#include <cmath>
#include <cstdio>
#include <memory>

#include <nlohmann/json.hpp>

#include "app/commands/frame_range.h"
#include "app/commands/wall_clock.h"
#include "app/output/carried_scene.h"
#include "app/output/disk_budget.h"
#include "app/output/interrupt.h"
#include "app/output/obj_sequence.h"
#include "app/output/output_folder.h"
#include "app/output/pc2_writer.h"
#include "app/output/progress.h"
#include "app/pictures/frame_output.h"
#include "app/run/run_driver.h"
#include "app/scene/input_error.h"
#include "app/scene/scene_file.h"
#include "io/text_file.h"
#include "io/writable_place.h"

namespace fs = std::filesystem;

namespace wobble {
namespace {

void writeRunJson(const SceneFile& scene, const std::vector<std::string>& overrides,
                  const std::vector<CarriedFile>& carried, const Simulation& sim, const RunReport& r) {
  nlohmann::ordered_json j;
  j["scene"] = carried.front().path;  // relative to this folder: the scene as run, carried (carried_scene.h)
  j["overrides"] = overrides;         // --set and the flags that set keys (already applied in the carried scene)
  j["carried"] = nlohmann::ordered_json::array();
  for (const CarriedFile& c : carried)
    j["carried"].push_back({{"path", c.path}, {"hash", c.hash}, {"source", c.source}});
  j["integrator"] = scene.integrator;
  j["dt"] = scene.dt;
  j["fps"] = scene.fps;
  j["frames"] = {{"first", r.first_frame}, {"last", r.last_frame}, {"written", r.frames_written}};
  j["steps"] = r.steps;
  j["simulated_time"] = r.simulated_time;
  j["wall_time_seconds"] = {{"simulate", r.seconds_simulate},
                            {"export", r.seconds_export},
                            {"render", r.seconds_render}};
  j["frames_rendered"] = r.frames_rendered;
  j["frames_skipped"] = r.frames_skipped;  // --skip-existing: already rendered with the same settings
  // retakes: the steps (or parts of one) that made up energy and were taken again in halves (an implicit integrator's;
  // docs/energy.md).
  j["energy"] = {{"start", r.energy_start},
                 {"end", r.energy_end},
                 {"collider_work", r.collider_work},
                 {"penalty_work", sim.penaltyWork()},
                 {"retakes", sim.energyRetakes()}};
  j["max_speed"] = r.max_speed;
  // The end state: over the steps of the last frame simulated (whether the scene has come to rest).
  j["end_state"] = {{"max_speed", sim.lastIntervalMaxSpeed()}, {"max_kinetic_energy", sim.lastIntervalMaxKinetic()}};
  j["particles"] = sim.system().particleCount();
  j["springs"] = sim.system().springs().size();
  if (const IntegratorStats& s = sim.integrator().stats(); s.jacobians > 0)  // backward-euler's linear solves
    j["linear_solver"] =
        {{"method",
          "filtered PCG (Baraff-Witkin), 3x3 block-Jacobi plus an aggregation coarse level (two-level; auto: from " +
              std::to_string(kTwoLevelParticles) + " particles after a block-Jacobi solve of more than " +
              std::to_string(kTwoLevelIterations) +
              " iterations); stops at |S(b - A dv)| <= cg_tolerance |S(b - A z)|, or "
              "earlier once its error bound |S(b - A dv)| / m_min is at most cg_error_fraction times the step's "
              "error estimate |dv_n-1 - dv_n-2| / 2"},
         {"cg_preconditioner",
          std::array{"auto", "block-jacobi", "two-level"}[int(scene.integrator_options.cg_preconditioner)]},
         {"cg_tolerance", scene.integrator_options.cg_tolerance},
         {"cg_error_fraction", scene.integrator_options.cg_error_fraction},
         {"cg_max_iterations", scene.integrator_options.cg_max_iterations},
         {"error_rule_stops", s.error_rule_stops},
         // Why each linear solve stopped, and the worst relative residual of each kind (docs/integrators.md).
         {"stops",
          {{"cg_tolerance", s.tolerance_stops},
           {"error_rule", {{"solves", s.error_rule_stops}, {"max_relative_residual", s.max_cg_residual_error_rule}}},
           {"cg_max_iterations",
            {{"solves", s.iteration_cap_stops}, {"max_relative_residual", s.max_cg_residual_cap}}}}},
         {"impact_solves", s.impact_solves},      // solves again with impact constraints (docs/energy.md)
         {"friction_solves", s.friction_solves},  // solves again with friction within Coulomb's cone (docs/contact.md)
         {"exact_steps", s.exact_steps},  // linearized steps that made up energy, solved exactly (docs/energy.md)
         // Newton iterations ended because no step along their direction lowered the incremental potential
         {"line_search_stops", s.line_search_stops},
         {"cg_iterations", s.cg_iterations},
         {"cg_iterations_per_step", s.steps ? double(s.cg_iterations) / double(s.steps) : 0.0},
         {"max_relative_residual", s.max_cg_residual}};
  if (const collision::Stats* c =
          sim.bodyContact()) {  // contact between bodies (sim/contact/collisions/body_collisions.h)
    auto& b = j["body_contact"];
    b = {{"steps_checked", c->passes},
         // of them, those whose motion could not bring two surfaces within the thickness: no detection ran
         {"passes_skipped", c->passes_skipped},
         {"contacts", c->contacts},
         {"ccd_hits", c->ccd_hits},
         {"failsafe_activations", c->zone_activations},
         {"impact_zone_rounds", c->zone_rounds},
         {"largest_impact_zone", c->largest_zone},
         {"split_steps", sim.splitSteps()},
         {"min_distance_m",
          std::isfinite(c->min_distance) ? nlohmann::ordered_json(c->min_distance) : nlohmann::ordered_json(nullptr)},
         {"in_solve", sim.integrator().solvesBodyContact()},  // [contact] in_solve, as the integrator took it
         // What the thickness means for this run (docs/body-contact.md, "What the thickness guarantees").
         {"thickness_guarantee",
          sim.integrator().solvesBodyContact()
              ? "no surfaces cross; the solve's penalty pushes from the thickness, and pressed surfaces come closer "
                "than it (min_distance_m)"
          : integratorTraits(scene.integrator).contact_in_stages
              ? "no surfaces cross; a penalty layer inside the integrator's stages pushes from the thickness, and "
                "pressed surfaces come closer than it (min_distance_m)"
              : "no surfaces cross; the pass's repulsion pushes surfaces within the thickness apart after each step, "
                "so they may come closer than it within a step (min_distance_m)"}};
    if (integratorTraits(scene.integrator).body_contact_in_solve) {  // its solve's share (docs/body-contact.md)
      const IntegratorStats& s = sim.integrator().stats();
      b["pairs_in_solve"] = s.body_contact_pairs_carried;
      b["steps_with_pairs_in_solve"] = s.body_contact_steps;
      b["active_set_solves"] = s.body_contact_active_set_solves;
      b["solves_per_step"] = s.steps ? double(s.linear_solves) / double(s.steps) : 0.0;
    }
  }
  j["interrupted"] = r.interrupted;
  j["blew_up"] = r.blow_up.has_value();
  if (r.blow_up)
    j["blow_up"] = {{"step", r.blow_up->step},
                    {"time", r.blow_up->time},
                    {"particle", r.blow_up->particle},
                    {"message", r.blow_up_message}};
  j["gained_energy"] = r.energy_gain.has_value();
  if (const auto& g = r.energy_gain)
    j["energy_gain"] = {{"step", g->step},
                        {"time", g->time},
                        {"start", g->start},
                        {"energy", g->energy},
                        {"collider_work", g->collider_work},
                        {"penalty_work", g->penalty_work},
                        {"gained", g->gained()},
                        {"margin", g->margin},
                        {"message", r.energy_gain_message}};
  if (const auto& e = r.error_estimate) {
    j["error_estimate"] = {{"method",
                            "step halving: the same run at dt/2 (rk45: rtol, atol / 32), position "
                            "difference at each frame times 2^p/(2^p - 1) (Richardson)"},
                           {"order", e->order},
                           {"max_m", e->max_error},
                           {"rms_m", e->rms_error},
                           {"final_max_m", e->final_max_error},
                           {"frames_compared", e->frames},
                           {"seconds", e->seconds}};
    if (!e->failure.empty()) j["error_estimate"]["failure"] = e->failure;
  }
  io::writeTextFile(r.out / "run.json", j.dump(2) + "\n");
}

// The progress line's note: the steps taken again so far, in halves for their energy (docs/energy.md) or for contact
// between bodies (docs/body-contact.md); empty while there are none.
std::string retakeNote(const Simulation& sim) {
  std::string note;
  const auto count = [&](long n, const char* why) {
    if (n == 0) return;
    note +=
        (note.empty() ? "" : ", ") + std::to_string(n) + (n == 1 ? " step" : " steps") + " retaken in halves " + why;
  };
  count(sim.energyRetakes(), "(energy)");
  count(sim.splitSteps(), "(contact)");
  return note;
}

}  // namespace

RunReport runScene(const RunOptions& options) {
  std::vector<std::string> overrides;
  SceneFile scene = loadRunScene(options, &overrides);

  RunReport report;
  std::tie(report.first_frame, report.last_frame) =
      options.frames ? parseFrameRange(*options.frames, scene.frameCount()) : std::pair{1, scene.frameCount()};
  report.out = options.out.value_or(fs::path("out") / scene.name);
  io::checkWritable(report.out);  // the OS's reason first: the budget speaks only for a writable place
  checkDiskBudget(estimateRunOutput(scene, report.first_frame, report.last_frame), report.out);

  // Watched when it renders while simulating (no second simulation): the camera sees every frame, the shutter's
  // poses come from the steps.
  RunDriver run(scene, FrameOutput::wanted(scene));
  const Simulation& sim = run.simulation();
  const MassSpringSystem& system = run.system();
  report.energy_start = system.energy(sim.x(), sim.v());
  // Allowed (a body pushed out of a slope is a scene some want), but the push-out's energy is the collider's: say so
  // before step 1, so that an energy check it trips later is no surprise (docs/energy.md).
  if (const auto& inside = sim.startsInside())
    std::fprintf(stderr, "wobble: warning: %s: the collider pushes them out in the first steps, with energy it gives\n",
                 inside->describe().c_str());

  const OutputFolder folder(report.out);
  // With --skip-existing the pictures of this run's frames stay until the frame loop decides (frame_output.h).
  report.files_cleared =
      folder.clearEarlierRun(scene.name, options.skip_existing ? std::pair{report.first_frame, report.last_frame}
                                                               : std::pair{1, 0});
  const std::vector<CarriedFile> carried = carryScene(scene, report.out);  // the folder stands alone
  std::vector<ObjSequenceWriter> writers;  // the sequence, and the point cache's base mesh
  std::vector<std::unique_ptr<Pc2Writer>> caches;
  writers.reserve(system.bodies().size());  // the caches keep references to the writers' vertex orders
  if (scene.write_obj || scene.write_pc2)
    for (const BodySlot& slot : system.bodies()) {
      const auto texture = scene.textures.find(slot.body.name);
      writers.emplace_back(report.out / "mesh", slot.body,
                           texture == scene.textures.end() ? std::nullopt : std::optional(texture->second),
                           scene.render.bodies.at(slot.body.name));
      if (scene.write_pc2)
        caches.push_back(std::make_unique<Pc2Writer>(Pc2Writer::path(report.out / "mesh", slot.body.name),
                                                     writers.back().order(), report.first_frame));
    }

  std::optional<FrameOutput> pictures;
  if (FrameOutput::wanted(scene)) pictures.emplace(scene, report.out, options.skip_existing);

  std::optional<ErrorEstimator> estimator;
  if (options.estimate_error)
    estimator.emplace(loadRunScene(options), scene.integrator, scene.integrator_options, scene.dt);

  std::optional<Progress> progress;
  if (options.progress) progress.emplace(scene.name, report.last_frame);
  while (run.frame() < report.last_frame && !interrupted()) {
    auto start = Clock::now();
    report.blow_up = run.next();
    report.seconds_simulate += secondsSince(start);
    if (report.blow_up) break;
    const int frame = run.frame();
    if (!report.energy_gain && (report.energy_gain = sim.energyGain())) {
      report.energy_gain_message = report.energy_gain->message(scene.dt);
      if (options.stop_on_energy_gain) {
        if (progress) progress->finish();
        std::fprintf(stderr, "wobble: %s\n", report.energy_gain_message.c_str());  // at once, not after the video
        break;
      }
    }
    if (options.on_frame) options.on_frame(frame, sim.x());
    if (estimator) estimator->compare(scene.frameTime(frame), sim.x());
    if (frame >= report.first_frame) {  // before the range: simulated only (the camera has seen it)
      start = Clock::now();
      const std::vector<SurfaceFrame>& surfaces = run.surfaces();  // every body's, for the OBJ files and the picture
      for (std::size_t b = 0; b < writers.size(); ++b) {
        if (scene.write_obj) writers[b].write(frame, surfaces[b]);
        if (caches.empty()) continue;
        if (frame == report.first_frame) writers[b].writeBase(surfaces[b]);
        caches[b]->append(surfaces[b]);
      }
      ++report.frames_written;
      report.seconds_export += secondsSince(start);
      if (pictures) {
        start = Clock::now();
        pictures->frame(run.posed());
        report.seconds_render += secondsSince(start);
      }
    }
    if (progress) progress->update(frame, retakeNote(sim));
  }
  if (progress) progress->finish();
  for (const auto& cache : caches) cache->finish();  // the frames written, also after a blow-up or an interrupt
  if (pictures) {
    report.frames_rendered = pictures->framesRendered();
    report.frames_skipped = pictures->framesSkipped();
    const auto start = Clock::now();
    report.video = pictures->finish();
    report.seconds_render += secondsSince(start);
  }

  report.steps = sim.steps();
  report.simulated_time = sim.time();
  report.energy_end = system.energy(sim.x(), sim.v());
  report.collider_work = sim.colliderWork();
  report.max_speed = sim.maxSpeed();
  if (report.blow_up) report.blow_up_message = report.blow_up->message(scene.dt);
  if (estimator) report.error_estimate = estimator->result();
  report.interrupted = interrupted();  // between frames or during the video
  writeRunJson(scene, overrides, carried, sim, report);
  return report;
}

}  // namespace wobble
