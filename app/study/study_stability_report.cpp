#include "app/study/study_stability_report.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "app/study/study_report.h"
#include "io/text_file.h"
#include "io/text_table.h"

namespace fs = std::filesystem;

namespace wobble {
namespace {

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

bool gridCell(const StabilityCell& c) { return !c.user_case && c.contact_case.empty(); }

// A relative momentum drift for the report: NaN (does not apply) as "-".
std::string drift(double d) { return std::isfinite(d) ? io::formatNumber(d, 2) : "-"; }

}  // namespace

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

  for (std::size_t k = 0; k < r.contact.size(); ++k) {
    const ContactCase& contact = r.contact[k];
    bool any = false, momentum = false, angular = false;
    for (const StabilityCell& c : r.cells)
      if (c.contact_case == contact.key) {
        any = true;
        momentum |= std::isfinite(c.momentum_drift);
        angular |= std::isfinite(c.angular_momentum_drift);
      }
    if (!any) continue;
    md << "## Contact: " << contact.title << "\n\n"
       << "Contact case `" << contact.key << "`: scene `" << contact.scene.string()
       << "` (contact between bodies, docs/body-contact.md) with every spring's ks set to the case's value, run for "
       << io::formatNumber(contact.duration)
       << " simulated seconds at each step: the contact is where a step too large for the bodies blows up (BLOW), "
          "crushes them (SHAPE), or gives energy back (GAIN); a contact the fail-safe cannot resolve stops the run "
          "like a blow-up (BLOW, the note says so).";
    if (momentum)
      md << " No collider, pin or drag acts, so only internal forces move the bodies: **momentum drift** is |p - (p0 + "
            "M g t)| at the run's end over sum m |v0| (the bodies' momentum scale), which they keep to round-off under "
            "an exact integrator";
    if (angular)
      md << ", and with no gravity **angular drift** is |L - L0| (about the origin) over sum m |(x0 - c0) x v0| (c0: "
            "the centre of mass)";
    if (momentum) md << "; '-': not finite.";
    md << "\n\n";
    std::vector<std::string> head{"ks",         "dt (s)",       "integrator",      "outcome",
                                  "max strain", "final strain", "max speed (m/s)", "end time (s)"};
    if (momentum) head.push_back("momentum drift");
    if (angular) head.push_back("angular drift");
    head.push_back("note");
    io::TextTable t{head};
    for (const StabilityCell& c : r.cells)
      if (c.contact_case == contact.key) {
        std::vector<std::string> row{io::formatNumber(c.ks),
                                     io::formatNumber(c.dt, 3),
                                     c.integrator,
                                     cellSymbol(c),
                                     io::formatNumber(c.max_strain, 3),
                                     io::formatNumber(c.final_strain, 3),
                                     io::formatNumber(c.max_speed, 3),
                                     io::formatNumber(c.end_time, 3)};
        if (momentum) row.push_back(drift(c.momentum_drift));
        if (angular) row.push_back(drift(c.angular_momentum_drift));
        row.push_back(c.note);
        t.add(row);
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
        if (gridCell(c) && c.integrator == name && c.ks == ks) {
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
          if (gridCell(c) && c.integrator == name && c.ks == ks && c.dt == dt) row.push_back(cellSymbol(c));
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
  io::TextTable csv{{"scene", "integrator", "ks", "dt", "outcome", "inferred", "user_case", "contact_case",
                     "max_strain", "final_strain", "max_speed", "end_time", "steps", "momentum_drift",
                     "angular_momentum_drift", "theory_dt_power", "theory_dt_gershgorin", "note"}};
  for (const StabilityCell& c : r.cells) {
    const auto i =
        std::size_t(std::find(r.integrators.begin(), r.integrators.end(), c.integrator) - r.integrators.begin());
    const StabilityTheory* th = nullptr;  // the theory is the main scene's
    for (const StabilityTheory& t : r.theory)
      if (t.ks == c.ks && c.contact_case.empty()) th = &t;
    std::string scene = r.scene_name;  // a contact case's own
    for (std::size_t k = 0; k < r.contact.size(); ++k)
      if (r.contact[k].key == c.contact_case) scene = r.contact_scenes[k];
    const auto optional = [](double v) { return std::isfinite(v) ? io::formatNumber(v, 6) : std::string(); };
    csv.add({scene, c.integrator, io::formatNumber(c.ks, 10), io::formatNumber(c.dt, 10), toString(c.outcome),
             c.inferred ? "1" : "0", c.user_case ? "1" : "0", c.contact_case, io::formatNumber(c.max_strain, 6),
             io::formatNumber(c.final_strain, 6), io::formatNumber(c.max_speed, 6), io::formatNumber(c.end_time, 6),
             std::to_string(c.steps), optional(c.momentum_drift), optional(c.angular_momentum_drift),
             th ? io::formatNumber(th->dt_power[i], 6) : "", th ? io::formatNumber(th->dt_gershgorin[i], 6) : "",
             c.note});
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
        if (c.contact_case.empty() && c.integrator == name && cellSymbol(c) == kinds[k])
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
