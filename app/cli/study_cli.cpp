// `wobble study accuracy|stability` on the command line: options, the summary on screen, where the files went.
#include <cmath>
#include <cstdio>
#include <memory>

#include "app/cli/commands.h"
#include "app/cli/max_memory_option.h"
#include "app/scene/input_error.h"
#include "app/study/study_accuracy_report.h"
#include "app/study/study_render_report.h"
#include "app/study/study_stability_report.h"
#include "io/text_table.h"

namespace fs = std::filesystem;

namespace wobble {
namespace {

fs::path defaultOut(const std::string& study, const fs::path& scene) {
  return fs::path("out") / ("study-" + study + "-" + scene.stem().string());
}

// --piece I/N and --gather, which every study takes (app/study/farm_pieces.h). items: what a study's work items are.
struct PieceFlags {
  std::string piece;
  bool gather = false;
};

void addPieceOptions(CLI::App& cmd, PieceFlags& flags, const std::string& items) {
  cmd.add_option("--piece", flags.piece,
                 "I/N: run only piece I of N of the study's " + items +
                     " into OUT/pieces (a farm's task; resumes what it finished); then --gather");
  cmd.add_flag("--gather", flags.gather,
               "Run nothing: write the report from every --piece's " + items + " in OUT/pieces");
}

// The piece asked for (none with --gather or neither); both is exit 2.
std::optional<Piece> pieceOf(const PieceFlags& flags) {
  if (!flags.piece.empty() && flags.gather)
    throw InputError("--piece and --gather: one or the other (a piece, or the report)");
  if (flags.piece.empty()) return std::nullopt;
  return parsePiece(flags.piece);
}

// A piece's line on screen: what it ran, and what comes next.
void printPiece(const std::string& study, const std::string& scene, const PieceFlags& flags, const char* items,
                const PieceRun& run, const fs::path& out, const std::string& sweep) {
  std::printf(
      "%s study of %s, piece %s: %s %zu to %zu of %zu (%zu kept from an earlier run) in %s/pieces/%s; when "
      "every piece is done: --gather\n",
      study.c_str(), scene.c_str(), flags.piece.c_str(), items, run.first + 1, run.last, run.items, run.kept,
      out.c_str(), sweep.c_str());
}

void addAccuracy(CLI::App& study, int& status) {
  auto o = std::make_shared<AccuracyOptions>();
  CLI::App* cmd = study.add_subcommand("accuracy",
                                       "Error against run time per integrator: OUT/accuracy.csv, .md (fitted orders) "
                                       "and .png (work-precision diagram, via gnuplot)");
  cmd->add_option("scene", o->scene, "Scene file (TOML)")->capture_default_str();
  cmd->add_option("--integrators", o->integrators,
                  "Integrators to study (default: all), e.g. --integrators rk4 midpoint")
      ->delimiter(',');
  cmd->add_option("--out", o->out, "Output folder (default out/study-accuracy-<scene name>)");
  cmd->add_option("--duration", o->duration, "Simulated time T in seconds")->capture_default_str();
  cmd->add_option("--kmin", o->k_min, "Largest step dt = T/2^kmin")->capture_default_str();
  cmd->add_option("--kmax", o->k_max, "Smallest step dt = T/2^kmax")->capture_default_str();
  cmd->add_option("--tol-min", o->tol_min, "rk45: loosest rtol = atol = 10^-tol-min")->capture_default_str();
  cmd->add_option("--tol-max", o->tol_max, "rk45: tightest rtol = atol = 10^-tol-max")->capture_default_str();
  cmd->add_option("--samples", o->samples, "Comparison times per run (a power of 2)")->capture_default_str();
  cmd->add_option("--repeats", o->repeats, "Timed runs after the warm-up (run time = their minimum)")
      ->capture_default_str();
  cmd->add_option("--reference", o->reference,
                  "Reference solution: rk45 (rtol 1e-12), rk4 (finest dt / 16), or auto (rk45 unless the scene has "
                  "colliders)")
      ->capture_default_str();
  cmd->add_option("--set", o->sets, "Override a scene key, KEY=VALUE (repeatable), as for `wobble run`");
  auto pieces = std::make_shared<PieceFlags>();
  addPieceOptions(*cmd, *pieces, "runs (the reference, its twin, every point)");
  addMaxMemoryOption(*cmd);
  cmd->add_option("--gnuplot", o->gnuplot, "The gnuplot program (name on PATH or a path)")->capture_default_str();
  cmd->footer("Example:\n  wobble study accuracy scenes/cloth_swing.toml --integrators rk4,midpoint --duration 0.5");
  cmd->callback([o, pieces, &status] {
    o->piece = pieceOf(*pieces);
    o->gather = pieces->gather;
    if (o->out.empty()) o->out = defaultOut("accuracy", o->scene);
    const AccuracyResult r = runAccuracyStudy(*o);
    const fs::path out = o->out;
    if (o->piece) {
      printPiece("accuracy", r.scene_name, *pieces, "runs", r.piece, out, "accuracy");
      status = kExitOk;
      return;
    }
    const PlotResult plot = writeAccuracyOutputs(r, out, o->gnuplot);
    std::printf("accuracy study of %s over T = %g s (reference: %s)\n", r.scene_name.c_str(), r.duration,
                r.reference.c_str());
    if (r.has_colliders) std::printf("note: the scene has colliders, so the fitted orders are not meaningful\n");
    std::printf("%-17s %6s %14s %14s %6s\n", "integrator", "theory", "order (final)", "order (RMS)", "points");
    for (const AccuracyFit& f : r.fits)
      std::printf("%-17s %6d %14s %14s %6d\n", f.integrator.c_str(), f.expected,
                  io::formatNumber(f.order_final, 3).c_str(), io::formatNumber(f.order_rms, 3).c_str(), f.points);
    int left_out = 0;
    for (const AccuracyPoint& p : r.points) left_out += p.diverged;
    if (left_out) std::printf("%d point(s) diverged and were left out (listed in accuracy.md)\n", left_out);
    std::printf("wrote %s/accuracy.csv and accuracy.md\n", out.c_str());
    if (!plot.ok) std::fprintf(stderr, "wobble: %s\n", plot.message.c_str());
    else std::printf("%s\n", plot.message.c_str());
    status = kExitOk;
  });
}

void addStability(CLI::App& study, int& status) {
  auto o = std::make_shared<StabilityOptions>();
  auto fine = std::make_shared<bool>(false);
  auto no_infer = std::make_shared<bool>(false);
  CLI::App* cmd = study.add_subcommand("stability",
                                       "Stable / blew up / lost shape over ks x dt per integrator, with theory's "
                                       "boundary: OUT/stability.csv, .md and stability-<integrator>.png (gnuplot)");
  cmd->add_option("scene", o->scene, "Scene file (TOML)")->capture_default_str();
  cmd->add_option("--integrators", o->integrators, "Integrators to map (default: all but rk45)")->delimiter(',');
  cmd->add_option("--out", o->out, "Output folder (default out/study-stability-<scene name>)");
  cmd->add_option("--duration", o->duration, "Simulated seconds per cell")->capture_default_str();
  cmd->add_option("--strain-bound", o->strain_bound,
                  "Largest spring strain |l - rest|/rest of a body that kept "
                  "its shape")
      ->capture_default_str();
  cmd->add_option("--ks-min", o->ks_min, "Smallest ks")->capture_default_str();
  cmd->add_option("--ks-max", o->ks_max, "Largest ks")->capture_default_str();
  cmd->add_option("--dt-min", o->dt_min, "Smallest dt")->capture_default_str();
  cmd->add_option("--dt-max", o->dt_max, "Largest dt")->capture_default_str();
  cmd->add_option("--ks-points", o->ks_points, "ks values, log spaced")->capture_default_str();
  cmd->add_option("--dt-points", o->dt_points, "dt values, log spaced")->capture_default_str();
  cmd->add_flag("--fine", *fine, "A finer grid: 13 ks x 12 dt values");
  cmd->add_flag("--no-infer", *no_infer, "Run every cell (default: below a stable dt, a row is taken as stable)");
  auto no_contact = std::make_shared<bool>(false);
  auto contact = std::make_shared<std::vector<std::string>>();
  auto contact_scenes = std::make_shared<std::vector<std::string>>();
  std::string cases;  // each case's key, what it is and its steps, from the table
  for (const ContactCase& c : contactCases()) {
    cases +=
        (cases.empty() ? "" : "; ") + c.key + ": " + c.title + ", ks " + io::formatNumber(c.runs.front()[0]) + ", dt";
    for (const auto& run : c.runs) cases.append(" ").append(io::formatNumber(run[1], 3));
    cases += " s";
  }
  cmd->add_option("--contact", *contact, "Contact cases to run (default: all): " + cases)->delimiter(',');
  cmd->add_option("--contact-scene", *contact_scenes, "KEY=FILE: run contact case KEY on another scene (repeatable)");
  cmd->add_flag("--no-contact", *no_contact, "Leave the contact cases out");
  cmd->add_option("--jobs", o->jobs, "Threads (0: one per hardware thread; results do not depend on it)")
      ->capture_default_str();
  auto pieces = std::make_shared<PieceFlags>();
  addPieceOptions(*cmd, *pieces, "rows");
  cmd->add_option("--set", o->sets, "Override a scene key, KEY=VALUE (repeatable), as for `wobble run`");
  addMaxMemoryOption(*cmd);
  cmd->add_option("--gnuplot", o->gnuplot, "The gnuplot program (name on PATH or a path)")->capture_default_str();
  cmd->footer(
      "The users' cases (ks 5e4 at dt 1.2e-3, ks 1e5 at dt 1.4e-3) and the contact cases are always run in full.\n"
      "Examples:\n"
      "  wobble study stability --integrators explicit-euler,rk4 --duration 0.3\n"
      "  wobble study stability --fine --out out/map --piece 3/8    # one task of a farm (scripts/slurm/)\n"
      "  wobble study stability --fine --out out/map --gather       # when all 8 are done");
  cmd->callback([o, fine, no_infer, no_contact, contact, contact_scenes, pieces, &status] {
    if (!contact->empty()) {
      o->contact.clear();
      for (const std::string& key : *contact) o->contact.push_back(contactCase(key, "--contact"));
    }
    for (const std::string& given : *contact_scenes) {
      const std::size_t eq = given.find('=');
      if (eq == std::string::npos || eq + 1 == given.size())
        throw InputError("--contact-scene '" + given + "': expected KEY=FILE, e.g. landing=my_stack.toml");
      const std::string key = given.substr(0, eq);
      contactCase(key, "--contact-scene");  // a known key
      bool found = false;
      for (ContactCase& c : o->contact)
        if (c.key == key) c.scene = given.substr(eq + 1), found = true;
      if (!found) throw InputError("--contact-scene '" + given + "': case " + key + " is not run (--contact)");
    }
    if (*no_contact) o->contact.clear();
    if (*fine) {
      o->ks_points = 13;
      o->dt_points = 12;
    }
    o->infer = !*no_infer;
    o->piece = pieceOf(*pieces);
    o->gather = pieces->gather;
    if (o->out.empty()) o->out = defaultOut("stability", o->scene);
    const StabilityResult r = runStabilityStudy(*o);
    const fs::path out = o->out;
    if (o->piece) {
      printPiece("stability", r.scene_name, *pieces, "rows", r.piece, out, "stability");
      status = kExitOk;
      return;
    }
    const auto plots = writeStabilityOutputs(r, out, o->gnuplot);
    std::printf("stability study of %s: %zu cells, %g s each\n", r.scene_name.c_str(), r.cells.size(), r.duration);
    for (const StabilityCell& c : r.cells)
      if (c.user_case)
        std::printf("  ks %-6g dt %-7g %-17s %-10s max strain %s\n", c.ks, c.dt, c.integrator.c_str(),
                    toString(c.outcome), io::formatNumber(c.max_strain, 3).c_str());
    for (const StabilityCell& c : r.cells)
      if (!c.contact_case.empty()) {
        std::printf("  %s: ks %-6g dt %-7.3g %-17s %-13s max strain %s", c.contact_case.c_str(), c.ks, c.dt,
                    c.integrator.c_str(), toString(c.outcome), io::formatNumber(c.max_strain, 3).c_str());
        if (std::isfinite(c.momentum_drift))
          std::printf(", momentum drift %s", io::formatNumber(c.momentum_drift, 2).c_str());
        std::printf("\n");
      }
    std::printf("wrote %s/stability.csv and stability.md\n", out.c_str());
    for (const PlotResult& p : plots) {
      if (!p.ok) std::fprintf(stderr, "wobble: %s\n", p.message.c_str());
      else std::printf("%s\n", p.message.c_str());
    }
    status = kExitOk;
  });
}

void addRender(CLI::App& study, int& status) {
  auto o = std::make_shared<RenderStudyOptions>();
  CLI::App* cmd = study.add_subcommand("render",
                                       "Image error against render time per renderer setting on one frame: "
                                       "OUT/render.csv, .md and .png (gnuplot), and every image in OUT/images");
  cmd->add_option("scene", o->scene, "Scene file (TOML)")->capture_default_str();
  cmd->add_option("--frame", o->frame, "Frame to render (default: the scene's middle frame)")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--resolution", o->resolution, "Image size WxH")->capture_default_str();
  cmd->add_option("--reference-spp", o->reference_spp, "Samples per pixel of the reference (cached in OUT)")
      ->capture_default_str();
  cmd->add_option("--max-spp", o->max_spp,
                  "Largest sample count of the sweep (1, 2, 4, ... this); the adaptive "
                  "variants' cap")
      ->capture_default_str();
  cmd->add_option("--variants", o->variants, "Variants to sweep (default: all), e.g. --variants sobol,sobol+denoise")
      ->delimiter(',');
  cmd->add_option("--thresholds", o->thresholds, "Noise thresholds of the adaptive variants")->delimiter(',');
  cmd->add_option("--repeats", o->repeats, "Timed renders per point (time = their minimum)")->capture_default_str();
  cmd->add_option("--out", o->out, "Output folder (default out/study-render-<scene name>)");
  cmd->add_option("--set", o->sets, "Override a scene key, KEY=VALUE (repeatable), as for `wobble run`");
  addMaxMemoryOption(*cmd);
  cmd->add_option("--gnuplot", o->gnuplot, "The gnuplot program (name on PATH or a path)")->capture_default_str();
  auto pieces = std::make_shared<PieceFlags>();
  addPieceOptions(*cmd, *pieces, "renders (the reference's two halves, every point)");
  cmd->footer("Example:\n  wobble study render scenes/cloth_sphere.toml --frame 60 --variants sobol,sobol+denoise");
  cmd->callback([o, pieces, &status] {
    o->piece = pieceOf(*pieces);
    o->gather = pieces->gather;
    if (o->out.empty()) o->out = defaultOut("render", o->scene);
    const RenderStudyResult r = runRenderStudy(*o);
    const fs::path out = o->out;
    if (o->piece) {
      printPiece("render", r.scene_name, *pieces, "renders", r.piece, out, "render");
      status = kExitOk;
      return;
    }
    const PlotResult plot = writeRenderStudyOutputs(r, out, o->gnuplot);
    std::printf("render study of %s, frame %d at %dx%d; reference %d spp (%s), its own RMSE ~%s\n",
                r.scene_name.c_str(), r.frame, r.width, r.height, r.reference_spp,
                r.reference_cached ? "cached" : (io::formatNumber(r.reference_seconds, 3) + " s").c_str(),
                io::formatNumber(r.reference_rmse, 3).c_str());
    std::printf("%-20s %-16s %9s %9s %9s\n", "variant", "setting", "mean spp", "RMSE", "time (s)");
    for (const RenderPoint& p : r.points)
      std::printf("%-20s %-16s %9s %9s %9s\n", p.variant.c_str(),
                  p.threshold > 0 ? ("threshold " + io::formatNumber(p.threshold, 3)).c_str()
                                  : (std::to_string(p.spp) + " spp").c_str(),
                  io::formatNumber(p.mean_spp, 4).c_str(), io::formatNumber(p.rmse, 3).c_str(),
                  io::formatNumber(p.seconds, 3).c_str());
    for (const RenderVariantFit& f : r.fits)
      std::printf("slope of log RMSE against log spp, %-20s %s\n", f.variant.c_str(),
                  io::formatNumber(f.slope, 3).c_str());
    std::printf("wrote %s/render.csv and render.md\n", out.c_str());
    if (!plot.ok) std::fprintf(stderr, "wobble: %s\n", plot.message.c_str());
    else std::printf("%s\n", plot.message.c_str());
    status = kExitOk;
  });
}

}  // namespace

void addStudyCommand(CLI::App& app, int& status) {
  CLI::App* study = app.add_subcommand(
      "study", "Studies: accuracy (error against run time), stability, render (image error against render time)");
  study->require_subcommand(1);
  addAccuracy(*study, status);
  addStability(*study, status);
  addRender(*study, status);
}

}  // namespace wobble
