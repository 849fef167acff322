#include "app/study/study_stability.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <map>
#include <mutex>
#include <optional>
#include <sstream>
#include <thread>

#include "app/output/progress.h"
#include "app/scene/input_error.h"
#include "app/scene/scene_file.h"
#include "app/study/stability_theory.h"
#include "app/study/study_report.h"
#include "io/text_file.h"
#include "io/text_table.h"
#include "sim/simulation.h"

namespace fs = std::filesystem;

namespace wobble {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

std::vector<double> logSpaced(double lo, double hi, int count) {
  std::vector<double> values;
  for (int i = 0; i < count; ++i) values.push_back(count == 1 ? lo : lo * std::pow(hi / lo, double(i) / (count - 1)));
  return values;
}

void check(bool ok, const std::string& message) {
  if (!ok) throw InputError(message);
}

void validate(const StabilityOptions& o) {
  check(o.duration > 0 && std::isfinite(o.duration), "--duration " + io::formatNumber(o.duration) + ": must be > 0");
  check(o.strain_bound > 0, "--strain-bound " + io::formatNumber(o.strain_bound) + ": must be > 0");
  check(o.ks_min > 0 && o.ks_min <= o.ks_max, "--ks-min/--ks-max: need 0 < min <= max");
  check(o.dt_min > 0 && o.dt_min <= o.dt_max, "--dt-min/--dt-max: need 0 < min <= max");
  check(o.ks_points >= 1 && o.ks_points <= 200 && o.dt_points >= 1 && o.dt_points <= 200,
        "--ks-points/--dt-points: must be in [1, 200]");
  check(o.jobs >= 0, "--jobs " + std::to_string(o.jobs) + ": must be >= 0");
  for (const auto& c : o.cases)
    check(c[0] >= 0 && c[1] > 0,
          "--case " + io::formatNumber(c[0]) + "," + io::formatNumber(c[1]) + ": need ks >= 0, dt > 0");
}

// The scene with every spring's ks set: one override per body.
std::unique_ptr<MassSpringSystem> systemAt(const StabilityOptions& o, const std::vector<std::string>& bodies,
                                           double ks) {
  std::vector<std::string> sets = o.sets;
  for (const std::string& b : bodies) sets.push_back("bodies." + b + ".ks=" + io::formatNumber(ks, 17));
  return std::move(loadScene(o.scene, sets).system);
}

std::string cellSymbol(const StabilityCell& c) {
  switch (c.outcome) {
    case Outcome::Stable:
      return c.inferred ? "ok*" : "ok";
    case Outcome::LostShape:
      return c.inferred ? "SHAPE*" : "SHAPE";
    case Outcome::BlewUp:
      return "BLOW";
    case Outcome::Failed:
      return "FAIL";
    case Outcome::GainedEnergy:
      return "GAIN";
  }
  return "?";
}

}  // namespace

const char* toString(Outcome outcome) {
  switch (outcome) {
    case Outcome::Stable:
      return "stable";
    case Outcome::LostShape:
      return "lost-shape";
    case Outcome::BlewUp:
      return "blew-up";
    case Outcome::Failed:
      return "failed";
    case Outcome::GainedEnergy:
      return "gained-energy";
  }
  return "?";
}

StabilityCell classifyCell(MassSpringSystem& system, const std::string& integrator, double dt, double duration,
                           double strain_bound) {
  StabilityCell c;
  c.integrator = integrator;
  c.dt = dt;
  Simulation sim(system, makeIntegrator(integrator), dt);
  const long per_check = std::max(1L, std::lround(0.01 / dt));  // strain every ~0.01 s: it costs a force evaluation
  try {
    for (long k = 1;; ++k) {
      const double t = std::min(duration, double(k * per_check) * dt);
      if (const auto blow_up = sim.advanceTo(t)) {
        c.outcome = Outcome::BlewUp;
        std::ostringstream m;
        m << "blew up at t = " << blow_up->time << " s, step " << blow_up->step;
        c.note = m.str();
        break;
      }

      c.final_strain = maxStrain(system.springs(), sim.x());
      c.max_strain = std::max(c.max_strain, c.final_strain);
      if (t >= duration) break;
    }
  } catch (const std::exception& e) {
    c.outcome = Outcome::Failed;
    c.note = e.what();
  }
  if (const auto& gain = sim.energyGain(); gain && c.outcome == Outcome::Stable) {  // a blow-up or failure says more
    c.outcome = Outcome::GainedEnergy;
    std::ostringstream m;
    m << "gained energy at t = " << gain->time << " s, step " << gain->step << ": " << gain->energy << " J from "
      << gain->start << " J";
    c.note = m.str();
  }
  if (c.outcome == Outcome::Stable && c.max_strain > strain_bound) c.outcome = Outcome::LostShape;
  if (c.outcome == Outcome::BlewUp) c.final_strain = kNaN;
  c.end_time = sim.time();
  c.steps = sim.steps();
  c.max_speed = sim.maxSpeed();
  return c;
}

StabilityResult runStabilityStudy(const StabilityOptions& o) {
  validate(o);
  StabilityResult result;
  std::vector<std::string> adaptive;  // no fixed-step limit to map (IntegratorTraits)
  for (std::string_view name : integratorNames())
    if (integratorTraits(name).adaptive) adaptive.emplace_back(name);
  result.integrators = selectIntegrators(o.integrators, adaptive);
  if (o.integrators.empty())
    result.notes.push_back(
        "rk45 is left out by default: it chooses its own substeps (dt is only its largest step), "
        "so it does not blow up at any dt, it only slows down; name it with --integrators to map it.");
  const SceneFile base = loadScene(o.scene, o.sets);
  result.scene_name = base.name;
  result.scene_file = o.scene;
  result.duration = o.duration;
  result.strain_bound = o.strain_bound;
  result.ks = logSpaced(o.ks_min, o.ks_max, o.ks_points);
  result.dt = logSpaced(o.dt_min, o.dt_max, o.dt_points);
  std::vector<std::string> bodies;
  for (const BodySlot& slot : base.system->bodies()) bodies.push_back(slot.body.name);

  // Theory at every ks the study touches.
  std::vector<double> theory_ks = result.ks;
  for (const auto& c : o.cases) theory_ks.push_back(c[0]);
  for (double ks : theory_ks) {
    const auto system = systemAt(o, bodies, ks);
    StabilityTheory t;
    t.ks = ks;
    t.omega_gershgorin = gershgorinOmegaMax(*system);
    t.omega_power = powerIterationOmegaMax(*system);
    t.damper_ratio = damperRatio(*system);
    for (const std::string& name : result.integrators) {
      t.dt_gershgorin.push_back(stableStep(name, t.omega_gershgorin, t.damper_ratio));
      t.dt_power.push_back(stableStep(name, t.omega_power, t.damper_ratio));
    }
    result.theory.push_back(t);
  }

  // Work items: one grid row (integrator, ks) each, plus one item per user case; each with its own system (a
  // Simulation sets the system's step size, so systems are not shared between threads).
  struct Item {
    std::string integrator;
    double ks;
    std::vector<double> dts;  // descending for grid rows
    bool user_case;
    std::unique_ptr<MassSpringSystem> system;
    std::vector<StabilityCell> cells;
  };
  std::vector<Item> items;
  std::vector<double> descending(result.dt.rbegin(), result.dt.rend());
  for (const std::string& name : result.integrators) {
    for (double ks : result.ks) items.push_back({name, ks, descending, false, systemAt(o, bodies, ks), {}});
    for (const auto& c : o.cases) items.push_back({name, c[0], {c[1]}, true, systemAt(o, bodies, c[0]), {}});
  }
  int total = 0;
  for (const Item& item : items) total += int(item.dts.size());
  Progress progress("stability " + result.scene_name, total, "cell");
  std::mutex mutex;
  int done = 0;
  std::atomic<std::size_t> next{0};
  const auto work = [&] {
    for (std::size_t i; (i = next++) < items.size();) {
      Item& item = items[i];
      std::optional<Outcome> survived_above;  // the outcome of the first cell from the top that did not blow up
      for (double dt : item.dts) {
        StabilityCell c;
        if (survived_above) {
          c.integrator = item.integrator;
          c.dt = dt;
          c.outcome = *survived_above;
          c.inferred = true;
          c.max_strain = c.final_strain = c.max_speed = kNaN;
        } else {
          c = classifyCell(*item.system, item.integrator, dt, o.duration, o.strain_bound);
          if (o.infer && !item.user_case && (c.outcome == Outcome::Stable || c.outcome == Outcome::LostShape))
            survived_above = c.outcome;
        }
        c.ks = item.ks;
        c.user_case = item.user_case;
        item.cells.push_back(c);
        std::lock_guard lock(mutex);
        if (o.progress) progress.update(++done);
      }
    }
  };
  const int jobs = o.jobs > 0 ? o.jobs : int(std::max(1u, std::thread::hardware_concurrency()));
  std::vector<std::thread> threads;
  for (int j = 1; j < jobs; ++j) threads.emplace_back(work);
  work();
  for (std::thread& t : threads) t.join();
  progress.finish();
  for (Item& item : items)  // in item order, whatever thread ran it: the output does not depend on jobs
    for (StabilityCell& c : item.cells) result.cells.push_back(std::move(c));
  std::stable_sort(result.cells.begin(), result.cells.end(), [](const StabilityCell& a, const StabilityCell& b) {
    return a.user_case != b.user_case ? !a.user_case : false;
  });
  return result;
}

std::string stabilityMarkdown(const StabilityResult& r) {
  std::ostringstream md;
  const auto theoryAt = [&](double ks) -> const StabilityTheory* {
    for (const StabilityTheory& t : r.theory)
      if (t.ks == ks) return &t;
    return nullptr;
  };
  const auto index = [&](const std::string& name) {
    return std::size_t(std::find(r.integrators.begin(), r.integrators.end(), name) - r.integrators.begin());
  };
  md << "# Stability study: " << r.scene_name << "\n\n"
     << "Scene `" << r.scene_file.string() << "` with every spring's ks set to the map's value (kd as in the scene), "
     << "each cell run for " << io::formatNumber(r.duration)
     << " simulated seconds from the initial state. Machine: " << machineDescription() << ".\n\n"
     << "- **ok**: ran to the end with the largest spring strain |l - rest|/rest <= "
     << io::formatNumber(r.strain_bound)
     << " at every check (every 0.01 s); **SHAPE**: survived but the strain exceeded "
     << io::formatNumber(r.strain_bound)
     << "; **ok\\*** / **SHAPE\\***: not run, inferred from the largest dt at this ks that did not blow up (stability "
        "regions contain the segment from 0 to their boundary, and a smaller step solves the same physics more "
        "accurately; --no-infer runs them); **BLOW**: blew up (a NaN or |v|^2 > 1e6, sim/simulation.h), the cell "
        "stopped there; **GAIN**: gained energy (the total passed the start's plus the moving colliders' work by the "
        "margin of docs/energy.md) and did not blow up, whatever its strain; **FAIL**: the integrator gave up (message "
        "in the CSV).\n"
     << "- Theory (numerics.md): omega_max by Gershgorin (omega_max^2 <= max_i 2 sum_j k_ij / m_i, a bound) and by "
        "power iteration on M^-1 K at the initial state (an estimate); a mode w has damping ratio zeta = (kd/ks) w / "
        "2; "
        "the largest stable dt is the least of limit(zeta)/w over the modes, with each method's limit of w h measured "
        "on its own one-step map (explicit Euler needs h <= kd/ks on underdamped modes). Gravity, drag and contact "
        "are left out of the theory.\n";
  for (const std::string& note : r.notes) md << "- " << note << "\n";
  md << "\n";

  // The users' cases first: the question they asked.
  bool any_case = false;
  for (const StabilityCell& c : r.cells) any_case |= c.user_case;
  if (any_case) {
    md << "## The users' cases (course framework reports)\n\n"
       << "Reported with the course framework: at ks 5e4, dt 1.2e-3 explicit Euler and pc-euler blow up, midpoint and "
          "RK4 survive; at ks 1e5, dt 1.4e-3 midpoint jitters and shrinks, RK4 stays stable.\n\n";
    io::TextTable t{{"ks", "dt (s)", "integrator", "outcome", "max strain", "final strain", "max speed (m/s)",
                     "theory dt_max (power it.)", "theory dt_max (Gershgorin)", "note"}};
    for (const StabilityCell& c : r.cells)
      if (c.user_case) {
        const StabilityTheory* th = theoryAt(c.ks);
        const std::size_t i = index(c.integrator);
        t.add({io::formatNumber(c.ks), io::formatNumber(c.dt), c.integrator, toString(c.outcome),
               io::formatNumber(c.max_strain, 3), io::formatNumber(c.final_strain, 3), io::formatNumber(c.max_speed, 3),
               th ? io::formatNumber(th->dt_power[i], 3) : "", th ? io::formatNumber(th->dt_gershgorin[i], 3) : "",
               c.note});
      }
    md << t.markdown() << "\n";
  }

  md << "## Theory: fastest mode and largest stable dt per ks\n\n";
  std::vector<std::string> header{"ks", "omega_max Gershgorin", "omega_max power it.", "zeta at omega_max (power)"};
  for (const std::string& n : r.integrators) header.push_back(n + " dt_max");
  io::TextTable theory{header};
  for (const StabilityTheory& t : r.theory) {
    std::vector<std::string> row{io::formatNumber(t.ks), io::formatNumber(t.omega_gershgorin, 4),
                                 io::formatNumber(t.omega_power, 4),
                                 io::formatNumber(t.damper_ratio * t.omega_power / 2, 3)};
    for (std::size_t i = 0; i < r.integrators.size(); ++i)
      row.push_back(std::isinf(t.dt_power[i])
                        ? "unbounded"
                        : io::formatNumber(t.dt_power[i], 3) + " (G " + io::formatNumber(t.dt_gershgorin[i], 3) + ")");
    theory.add(row);
  }
  md << "dt_max from the power-iteration omega_max, and in brackets from Gershgorin's bound (smaller, safe).\n\n"
     << theory.markdown() << "\n";

  md << "## Measured boundary against theory\n\n";
  io::TextTable boundary{{"integrator", "ks", "largest dt that did not blow up", "smallest dt that blew up or failed",
                          "theory dt_max (power it.)", "theory dt_max (Gershgorin)"}};
  for (const std::string& name : r.integrators)
    for (double ks : r.ks) {
      double largest_ok = 0, smallest_bad = std::numeric_limits<double>::infinity();
      for (const StabilityCell& c : r.cells)
        if (!c.user_case && c.integrator == name && c.ks == ks) {
          const bool survived = c.outcome == Outcome::Stable || c.outcome == Outcome::LostShape;
          if (survived && !c.inferred) largest_ok = std::max(largest_ok, c.dt);
          if (c.outcome == Outcome::BlewUp || c.outcome == Outcome::Failed) smallest_bad = std::min(smallest_bad, c.dt);
        }
      const StabilityTheory* th = theoryAt(ks);
      const std::size_t i = index(name);
      boundary.add({name, io::formatNumber(ks), largest_ok > 0 ? io::formatNumber(largest_ok, 3) : "none",
                    std::isinf(smallest_bad) ? "none" : io::formatNumber(smallest_bad, 3),
                    std::isinf(th->dt_power[i]) ? "unbounded" : io::formatNumber(th->dt_power[i], 3),
                    std::isinf(th->dt_gershgorin[i]) ? "unbounded" : io::formatNumber(th->dt_gershgorin[i], 3)});
    }
  md << boundary.markdown() << "\n";

  md << "## Maps\n\nRows: ks; columns: dt (s). The last column is theory's dt_max (power iteration).\n\n";
  for (const std::string& name : r.integrators) {
    md << "### " << name << "\n\n";
    std::vector<std::string> head{"ks \\ dt"};
    for (double dt : r.dt) head.push_back(io::formatNumber(dt, 3));
    head.push_back("theory dt_max");
    io::TextTable map{head};
    for (double ks : r.ks) {
      std::vector<std::string> row{io::formatNumber(ks)};
      for (double dt : r.dt)
        for (const StabilityCell& c : r.cells)
          if (!c.user_case && c.integrator == name && c.ks == ks && c.dt == dt) row.push_back(cellSymbol(c));
      const double th = theoryAt(ks)->dt_power[index(name)];
      row.push_back(std::isinf(th) ? "unbounded" : io::formatNumber(th, 3));
      map.add(row);
    }
    md << map.markdown() << "\n";
  }
  return md.str();
}

std::vector<PlotResult> writeStabilityOutputs(const StabilityResult& r, const fs::path& out,
                                              const std::string& gnuplot) {
  fs::create_directories(out);
  io::TextTable csv{{"scene", "integrator", "ks", "dt", "outcome", "inferred", "user_case", "max_strain",
                     "final_strain", "max_speed", "end_time", "steps", "theory_dt_power", "theory_dt_gershgorin",
                     "note"}};
  for (const StabilityCell& c : r.cells) {
    const auto i =
        std::size_t(std::find(r.integrators.begin(), r.integrators.end(), c.integrator) - r.integrators.begin());
    const StabilityTheory* th = nullptr;
    for (const StabilityTheory& t : r.theory)
      if (t.ks == c.ks) th = &t;
    csv.add({r.scene_name, c.integrator, io::formatNumber(c.ks, 10), io::formatNumber(c.dt, 10), toString(c.outcome),
             c.inferred ? "1" : "0", c.user_case ? "1" : "0", io::formatNumber(c.max_strain, 6),
             io::formatNumber(c.final_strain, 6), io::formatNumber(c.max_speed, 6), io::formatNumber(c.end_time, 6),
             std::to_string(c.steps), th ? io::formatNumber(th->dt_power[i], 6) : "",
             th ? io::formatNumber(th->dt_gershgorin[i], 6) : "", c.note});
  }
  io::writeTextFile(out / "stability.csv", csv.csv());
  io::writeTextFile(out / "stability.md", stabilityMarkdown(r));

  std::vector<PlotResult> plots;
  for (std::size_t i = 0; i < r.integrators.size(); ++i) {
    const std::string& name = r.integrators[i];
    std::ostringstream gp;
    gp << "# Stability map of " << name << " on " << r.scene_name << ": gnuplot stability-" << name << ".gp\n"
       << "if (!exists(\"out\")) out = 'stability-" << name << ".png'\n"
       << "set terminal pngcairo size 900,700 noenhanced\nset output out\n"
       << "set logscale xy\nset grid\nset format x '%.0e'\nset format y '%.0e'\n"
       << "set xlabel 'dt (s)'\nset ylabel 'ks (N/m)'\nset key outside bottom center horizontal\n"
       << "set xrange [" << r.dt.front() / 1.6 << ":" << r.dt.back() * 1.6 << "]\n"
       << "set yrange [" << r.ks.front() / 2 << ":" << r.ks.back() * 2 << "]\n"
       << "set title "
       << gnuplotQuote("wobble study stability: " + name + " on " + r.scene_name + ", " + io::formatNumber(r.duration) +
                       " s per cell")
       << "\n";
    const char* kinds[] = {"ok", "ok*", "SHAPE", "BLOW", "FAIL", "SHAPE*", "GAIN"};
    for (int k = 0; k < 7; ++k) {
      gp << "$c" << k << " << EOD\n";
      for (const StabilityCell& c : r.cells)
        if (c.integrator == name && cellSymbol(c) == kinds[k])
          gp << io::formatNumber(c.dt, 10) << " " << io::formatNumber(c.ks, 10) << " " << (c.user_case ? 1 : 0) << "\n";
      gp << "EOD\n";
    }
    gp << "$theory << EOD\n";
    for (const StabilityTheory& t : r.theory)
      if (std::find(r.ks.begin(), r.ks.end(), t.ks) != r.ks.end() && std::isfinite(t.dt_power[i]))
        gp << io::formatNumber(t.dt_power[i], 10) << " " << io::formatNumber(t.ks, 10) << " "
           << io::formatNumber(t.dt_gershgorin[i], 10) << "\n";
    gp << "EOD\n"
       << "plot $c0 using 1:2 with points pt 5 ps 4 lc rgb '#2ca02c' title 'stable', "
       << "$c1 using 1:2 with points pt 4 ps 4 lc rgb '#2ca02c' title 'stable (inferred)', "
       << "$c2 using 1:2 with points pt 5 ps 4 lc rgb '#ff7f0e' title 'lost shape', "
       << "$c3 using 1:2 with points pt 5 ps 4 lc rgb '#d62728' title 'blew up', "
       << "$c4 using 1:2 with points pt 5 ps 4 lc rgb '#7f7f7f' title 'failed', "
       << "$c5 using 1:2 with points pt 4 ps 4 lc rgb '#ff7f0e' title 'lost shape (inferred)', "
       << "$c6 using 1:2 with points pt 5 ps 4 lc rgb '#9467bd' title 'gained energy', "
       << "$theory using 1:2 with lines lw 3 lc rgb 'black' title 'theory dt_max (power iteration)', "
       << "$theory using 3:2 with lines lw 2 dt 2 lc rgb 'black' title 'theory dt_max (Gershgorin)'\n";
    const fs::path script = out / ("stability-" + name + ".gp");
    io::writeTextFile(script, gp.str());
    plots.push_back(runGnuplot(script, out / ("stability-" + name + ".png"), gnuplot));
  }
  return plots;
}

}  // namespace wobble
