#include "app/study/study_stability.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <mutex>
#include <optional>
#include <span>
#include <sstream>
#include <thread>

#include <nlohmann/json.hpp>

#include "app/output/progress.h"
#include "app/run/run_driver.h"
#include "app/scene/input_error.h"
#include "app/scene/scene_file.h"
#include "app/study/stability_theory.h"
#include "app/study/study_report.h"
#include "io/content_hash.h"
#include "io/text_table.h"

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
  for (const ContactCase& contact : o.contact) {
    int same = 0;
    for (const ContactCase& other : o.contact) same += other.key == contact.key;
    check(same == 1, "contact case " + contact.key + ": named " + std::to_string(same) + " times; once at most");
    for (const auto& c : contact.runs)
      check(c[0] >= 0 && c[1] > 0, "contact case " + contact.key + " " + io::formatNumber(c[0]) + "," +
                                       io::formatNumber(c[1]) + ": need ks >= 0, dt > 0");
    check(contact.duration > 0 && std::isfinite(contact.duration),
          "contact case " + contact.key + " duration " + io::formatNumber(contact.duration) + ": must be > 0");
  }
}

// The bodies' total linear and angular momentum (about the origin), and their scales: sum m |v|, and
// sum m |(x - c) x v| about the centre of mass c.
struct Momenta {
  Vec3 linear = Vec3::Zero(), angular = Vec3::Zero();
  double linear_scale = 0, angular_scale = 0;
};

Momenta momenta(const MassSpringSystem& system, const VecX& x, const VecX& v) {
  Momenta m;
  const VecX& mass = system.mass();
  Vec3 c = Vec3::Zero();
  for (int i = 0; i < system.particleCount(); ++i) {
    m.linear += mass[i] * particle(v, i);
    m.angular += mass[i] * particle(x, i).cross(particle(v, i));
    m.linear_scale += mass[i] * particle(v, i).norm();
    c += mass[i] * particle(x, i);
  }
  c /= mass.sum();
  for (int i = 0; i < system.particleCount(); ++i)
    m.angular_scale += mass[i] * (particle(x, i) - c).cross(particle(v, i)).norm();
  return m;
}

// Which momenta only internal forces change (StabilityCell::momentum_drift): no collider, pin or drag for the linear
// one (gravity's share is known), and no gravity either for the angular one.
struct Conserved {
  bool linear = false, angular = false;
};

Conserved conserved(const MassSpringSystem& system) {
  bool external = !system.colliders().empty();
  for (const BodySlot& slot : system.bodies()) {
    external |= slot.body.drag != 0;
    for (const bool pinned : slot.body.pinned) external |= pinned;
  }
  return {!external, !external && system.gravity().isZero()};
}

// The scene with every spring's ks set: one override per body.
std::unique_ptr<MassSpringSystem> systemAt(const std::filesystem::path& scene, std::vector<std::string> sets,
                                           const std::vector<std::string>& bodies, double ks) {
  for (const std::string& b : bodies) sets.push_back("bodies." + b + ".ks=" + io::formatNumber(ks, 17));
  return std::move(loadScene(scene, sets).system);
}

std::vector<std::string> bodyNames(const SceneFile& scene) {
  std::vector<std::string> names;
  for (const BodySlot& slot : scene.system->bodies()) names.push_back(slot.body.name);
  return names;
}

nlohmann::json number(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }
double number(const nlohmann::json& j) { return j.is_null() ? kNaN : j.get<double>(); }

// A relative drift, NaN where it does not apply or cannot be measured.
double relative(bool applies, double drift, double scale) {
  return applies && scale > 0 && std::isfinite(drift) ? drift / scale : kNaN;
}

// A work item's cells as a piece keeps them (farm_pieces.h): every field, doubles exact (NaN as null).
nlohmann::json cellsJson(const std::vector<StabilityCell>& cells) {
  nlohmann::json list = nlohmann::json::array();
  for (const StabilityCell& c : cells)
    list.push_back({{"integrator", c.integrator},
                    {"ks", c.ks},
                    {"dt", c.dt},
                    {"outcome", int(c.outcome)},
                    {"inferred", c.inferred},
                    {"user_case", c.user_case},
                    {"contact_case", c.contact_case},
                    {"max_strain", number(c.max_strain)},
                    {"final_strain", number(c.final_strain)},
                    {"end_time", number(c.end_time)},
                    {"max_speed", number(c.max_speed)},
                    {"momentum_drift", number(c.momentum_drift)},
                    {"angular_momentum_drift", number(c.angular_momentum_drift)},
                    {"steps", c.steps},
                    {"note", c.note}});
  return list;
}

std::vector<StabilityCell> cellsOf(const nlohmann::json& list) {
  std::vector<StabilityCell> cells;
  for (const nlohmann::json& j : list) {
    StabilityCell c;
    c.integrator = j.at("integrator").get<std::string>();
    c.ks = j.at("ks").get<double>();
    c.dt = j.at("dt").get<double>();
    c.outcome = Outcome(j.at("outcome").get<int>());
    c.inferred = j.at("inferred").get<bool>();
    c.user_case = j.at("user_case").get<bool>();
    c.contact_case = j.at("contact_case").get<std::string>();
    c.max_strain = number(j.at("max_strain"));
    c.final_strain = number(j.at("final_strain"));
    c.end_time = number(j.at("end_time"));
    c.max_speed = number(j.at("max_speed"));
    c.momentum_drift = number(j.at("momentum_drift"));
    c.angular_momentum_drift = number(j.at("angular_momentum_drift"));
    c.steps = j.at("steps").get<long>();
    c.note = j.at("note").get<std::string>();
    cells.push_back(std::move(c));
  }
  return cells;
}

// Everything a cell's result depends on, hashed: pieces of one study share it (farm_pieces.h).
std::string studyKey(const StabilityOptions& o, const StabilityResult& r, const std::string& scene_text,
                     const std::vector<std::string>& contact_texts) {
  io::ContentHash h;
  h.add(std::string_view("wobble study stability 2"));
  h.add(std::string_view(scene_text));
  for (std::size_t i = 0; i < o.contact.size(); ++i) {
    const ContactCase& c = o.contact[i];
    h.add(std::string_view(c.key)), h.add(std::string_view(contact_texts[i])), h.add(c.duration);
    for (const auto& run : c.runs) h.add(run[0]), h.add(run[1]);
  }
  for (const std::string& name : r.integrators) h.add(std::string_view(name));
  h.addArray(std::span<const double>(r.ks));
  h.addArray(std::span<const double>(r.dt));
  for (const auto& c : o.cases) h.add(c[0]), h.add(c[1]);
  h.add(o.duration), h.add(o.strain_bound), h.add(o.infer);
  return h.hex();
}

}  // namespace

const std::vector<ContactCase>& contactCases() {
  static const std::vector<ContactCase> cases = {
      {"landing",
       "a stiff jelly landing on a jelly",
       "scenes/jelly_stack.toml",
       {{1e5, 1.0 / 60}, {1e5, 1.0 / 120}, {1e5, 1.0 / 240}},
       1.0},
      {"free-pair",
       "a free pair, a small jelly shot into a large one",
       "scenes/jelly_shot.toml",
       {{2000, 1.0 / 60}, {2000, 1.0 / 240}, {2000, 1e-3}, {2000, 5e-4}, {2000, 2.5e-4}},
       0.5},
  };
  return cases;
}

const ContactCase& contactCase(const std::string& key, const std::string& flag) {
  std::string allowed;
  for (const ContactCase& c : contactCases()) {
    if (c.key == key) return c;
    allowed += (allowed.empty() ? "" : ", ") + c.key;
  }
  throw InputError(flag + " '" + key + "': no such contact case; allowed: " + allowed);
}

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
                           double strain_bound, const IntegratorOptions& options) {
  StabilityCell c;
  c.integrator = integrator;
  c.dt = dt;
  RunDriver run(system, integrator, options, dt);
  const Simulation& sim = run.simulation();
  const Conserved kept = conserved(system);
  const Momenta start = momenta(system, sim.x(), sim.v());
  const long per_check = std::max(1L, std::lround(0.01 / dt));  // strain every ~0.01 s: it costs a force evaluation
  try {
    for (long k = 1;; ++k) {
      const double t = std::min(duration, double(k * per_check) * dt);
      if (const auto blow_up = run.advanceTo(t)) {
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
  const Momenta end = momenta(system, sim.x(), sim.v());
  const double mass = system.mass().sum();
  c.momentum_drift = relative(kept.linear, (end.linear - start.linear - mass * system.gravity() * c.end_time).norm(),
                              start.linear_scale);
  c.angular_momentum_drift = relative(kept.angular, (end.angular - start.angular).norm(), start.angular_scale);
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
  const std::vector<std::string> bodies = bodyNames(base);
  // Per contact case: its scene's bodies, text and options (its [simulation] solver keys and [contact] in_solve).
  std::vector<std::vector<std::string>> contact_bodies;
  std::vector<std::string> contact_texts;
  std::vector<IntegratorOptions> contact_options;
  result.contact = o.contact;
  for (const ContactCase& c : o.contact) {
    const SceneFile contact = loadScene(c.scene, {});
    contact_texts.push_back(contact.text);
    result.contact_scenes.push_back(contact.name);
    contact_bodies.push_back(bodyNames(contact));
    contact_options.push_back(contact.integrator_options);
  }

  // Theory at every ks the study touches (for the report: not in a piece).
  std::vector<double> theory_ks = result.ks;
  for (const auto& c : o.cases) theory_ks.push_back(c[0]);
  if (o.piece) theory_ks.clear();
  for (double ks : theory_ks) {
    const auto system = systemAt(o.scene, o.sets, bodies, ks);
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

  // Work items: one grid row (integrator, ks) each, plus one item per user case and contact case; each with its own
  // system (a run sets the system's step size, so systems are not shared between threads), built only for the
  // items this command runs.
  struct Item {
    std::string integrator;
    double ks;
    std::vector<double> dts;  // descending for grid rows
    bool user_case;
    int contact;  // the contact case's index in o.contact; -1: none
    double duration;
    IntegratorOptions options;
    std::unique_ptr<MassSpringSystem> system;
    std::vector<StabilityCell> cells;
  };
  std::vector<Item> items;
  std::vector<double> descending(result.dt.rbegin(), result.dt.rend());
  for (const std::string& name : result.integrators) {
    for (double ks : result.ks)
      items.push_back({name, ks, descending, false, -1, o.duration, base.integrator_options, nullptr, {}});
    for (const auto& c : o.cases)
      items.push_back({name, c[0], {c[1]}, true, -1, o.duration, base.integrator_options, nullptr, {}});
    for (std::size_t k = 0; k < o.contact.size(); ++k)
      for (const auto& c : o.contact[k].runs)
        items.push_back({name, c[0], {c[1]}, false, int(k), o.contact[k].duration, contact_options[k], nullptr, {}});
  }
  std::optional<FarmPieces> pieces;
  if (o.piece || o.gather) {
    if (o.out.empty()) throw InputError("--piece, --gather: need the study's folder (--out)");
    pieces.emplace(o.out, "stability", studyKey(o, result, base.text, contact_texts), items.size(),
                   o.gather ? std::nullopt : o.piece);
  }
  const auto [first, last] = pieces ? pieces->range() : std::pair<std::size_t, std::size_t>{0, items.size()};
  result.piece = {first, last, items.size(), 0};
  if (o.gather) {
    const std::vector<nlohmann::json> gathered = pieces->gather();
    for (std::size_t i = 0; i < items.size(); ++i) items[i].cells = cellsOf(gathered[i]);
  }
  for (std::size_t i = first; i < last && !o.gather; ++i) {
    Item& item = items[i];
    if (pieces)
      if (const auto kept = pieces->load(i)) {
        item.cells = cellsOf(*kept);
        ++result.piece.kept;
        continue;
      }
    item.system = item.contact >= 0 ? systemAt(o.contact[item.contact].scene, {}, contact_bodies[item.contact], item.ks)
                                    : systemAt(o.scene, o.sets, bodies, item.ks);
  }
  int total = 0;
  for (const Item& item : items) total += item.system ? int(item.dts.size()) : 0;
  Progress progress("stability " + result.scene_name, total, "cell");
  std::mutex mutex;
  int done = 0;
  std::atomic<std::size_t> next{0};
  const auto work = [&] {
    for (std::size_t i; (i = next++) < items.size();) {
      Item& item = items[i];
      if (!item.system) continue;             // another piece's, or kept from an earlier run of this piece
      std::optional<Outcome> survived_above;  // the outcome of the first cell from the top that did not blow up
      for (double dt : item.dts) {
        StabilityCell c;
        if (survived_above) {
          c.integrator = item.integrator;
          c.dt = dt;
          c.outcome = *survived_above;
          c.inferred = true;
          c.max_strain = c.final_strain = c.max_speed = c.momentum_drift = c.angular_momentum_drift = kNaN;
        } else {
          c = classifyCell(*item.system, item.integrator, dt, item.duration, o.strain_bound, item.options);
          if (o.infer && !item.user_case && item.contact < 0 &&
              (c.outcome == Outcome::Stable || c.outcome == Outcome::LostShape))
            survived_above = c.outcome;
        }
        c.ks = item.ks;
        c.user_case = item.user_case;
        if (item.contact >= 0) c.contact_case = o.contact[item.contact].key;
        item.cells.push_back(c);
        std::lock_guard lock(mutex);
        if (o.progress) progress.update(++done);
      }
      if (pieces) pieces->store(i, cellsJson(item.cells));  // done: a piece run again keeps it
    }
  };
  const int jobs = o.jobs > 0 ? o.jobs : int(std::max(1u, std::thread::hardware_concurrency()));
  std::vector<std::thread> threads;
  for (int j = 1; j < jobs; ++j) threads.emplace_back(work);
  work();
  for (std::thread& t : threads) t.join();
  progress.finish();
  for (Item& item : items)  // in item order, whatever thread ran it: the output does not depend on jobs
    for (StabilityCell& c : item.cells) result.cells.push_back(std::move(c));  // a piece: its own items only
  // The grid first, then the users' cases, then the contact cases in their order.
  const auto group = [&](const StabilityCell& c) {
    if (c.contact_case.empty()) return c.user_case ? 1 : 0;
    std::size_t k = 0;
    while (k < o.contact.size() && o.contact[k].key != c.contact_case) ++k;
    return int(2 + k);
  };
  std::stable_sort(result.cells.begin(), result.cells.end(),
                   [&](const StabilityCell& a, const StabilityCell& b) { return group(a) < group(b); });
  return result;
}

}  // namespace wobble
