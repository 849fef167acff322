#include "app/study/study_accuracy.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <functional>
#include <limits>
#include <sstream>

#include <nlohmann/json.hpp>

#include "app/output/progress.h"
#include "app/run/run_driver.h"
#include "app/scene/input_error.h"
#include "app/scene/scene_file.h"
#include "app/study/order_fit.h"
#include "app/study/study_report.h"
#include "io/content_hash.h"
#include "io/text_table.h"

namespace fs = std::filesystem;

namespace wobble {
namespace {

using Clock = std::chrono::steady_clock;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

struct RunSpec {
  std::string integrator;
  double dt = 0;
  IntegratorOptions options;
};

struct Trajectory {
  std::vector<VecX> x;  // positions at the sample times reached
  double seconds = 0;
  long steps = 0, evaluations = 0, accepted = 0;
  std::string failure;  // empty when every sample was reached
};

// One run of the system from its initial state through the sample times. The system is shared between runs: a
// RunDriver keeps the state; the system only takes the step size (for static friction), set anew per run.
Trajectory simulate(MassSpringSystem& system, const RunSpec& spec, const std::vector<double>& times) {
  Trajectory r;
  r.x.reserve(times.size());
  RunDriver run(system, spec.integrator, spec.options, spec.dt);
  const auto start = Clock::now();
  try {
    for (double t : times) {
      if (const auto blow_up = run.advanceTo(t)) {
        std::ostringstream m;
        m << "blew up at t = " << blow_up->time << " s (step " << blow_up->step << ")";
        r.failure = m.str();
        break;
      }
      r.x.push_back(run.x());
    }
  } catch (const std::exception& e) {
    r.failure = e.what();
  }
  r.seconds = std::chrono::duration<double>(Clock::now() - start).count();
  const IntegratorStats& s = run.simulation().integrator().stats();
  r.steps = run.simulation().steps();
  r.evaluations = s.evaluations;
  r.accepted = s.accepted;
  return r;
}

// Final error: max over moving particles of |x - ref| at the last sample; RMS over all samples and moving particles.
std::pair<double, double> errors(const Trajectory& run, const Trajectory& ref, const std::vector<int>& moving) {
  double final_error = 0, sum = 0;
  for (std::size_t s = 0; s < ref.x.size(); ++s)
    for (int i : moving) {
      const double d2 = (particle(run.x[s], i) - particle(ref.x[s], i)).squaredNorm();
      sum += d2;
      if (s + 1 == ref.x.size()) final_error = std::max(final_error, std::sqrt(d2));
    }
  const double count = double(ref.x.size()) * double(std::max<std::size_t>(1, moving.size()));
  return {final_error, std::sqrt(sum / count)};
}

void check(bool ok, const std::string& message) {
  if (!ok) throw InputError(message);
}

void validate(const AccuracyOptions& o) {
  check(o.duration > 0 && std::isfinite(o.duration), "--duration " + io::formatNumber(o.duration) + ": must be > 0");
  check(o.samples >= 1 && (o.samples & (o.samples - 1)) == 0 && o.samples <= 4096,
        "--samples " + std::to_string(o.samples) + ": must be a power of 2 in [1, 4096]");
  check(o.k_min >= 0 && o.k_max <= 24 && o.k_min <= o.k_max,
        "--kmin " + std::to_string(o.k_min) + " --kmax " + std::to_string(o.k_max) + ": need 0 <= kmin <= kmax <= 24");
  check((1L << o.k_min) >= o.samples, "--kmin " + std::to_string(o.k_min) +
                                          ": the largest step T/2^kmin must divide the "
                                          "sample interval T/" +
                                          std::to_string(o.samples) + " (use --kmin >= " +
                                          std::to_string(int(std::log2(o.samples))) + " or fewer --samples)");
  check(o.tol_min >= 1 && o.tol_max <= 13 && o.tol_min <= o.tol_max,
        "--tol-min " + std::to_string(o.tol_min) + " --tol-max " + std::to_string(o.tol_max) +
            ": need 1 <= tol-min <= tol-max <= 13 (rtol = 10^-j)");
  check(o.repeats >= 0 && o.repeats <= 100, "--repeats " + std::to_string(o.repeats) + ": must be in [0, 100]");
  check(o.reference == "auto" || o.reference == "rk45" || o.reference == "rk4",
        "--reference " + o.reference + ": must be auto, rk45 or rk4");
}

// A work item: the reference, its twin, or a point of the sweep (rtol: rk45's, else 0).
struct Item {
  RunSpec spec;
  double rtol = 0;
  bool point = false;
};

// An item's run: the trajectory of its first (warm-up) run, and its time: a point's the minimum of `repeats` timed
// runs after it (the warm-up's when none), the reference's and twin's their one run.
struct Ran {
  Trajectory run;
  double seconds = 0;
};

// tick(n): n runs done.
Ran runItem(MassSpringSystem& system, const Item& item, const std::vector<double>& times, int repeats,
            const std::function<void(int)>& tick) {
  Ran r{simulate(system, item.spec, times), 0};
  tick(1);
  r.seconds = r.run.seconds;
  if (!r.run.failure.empty()) {
    tick(repeats);
    return r;
  }
  for (int k = 0; k < repeats; ++k) {
    const double seconds = simulate(system, item.spec, times).seconds;
    r.seconds = k == 0 ? seconds : std::min(r.seconds, seconds);
    tick(1);
  }
  return r;
}

// What a farm piece keeps of an item (farm_pieces.h): the counts and times in its .json, the trajectory's positions
// at the sample times reached, exact doubles, as its data.
nlohmann::json ranJson(const Ran& r) {
  return {{"seconds", r.seconds},       {"run_seconds", r.run.seconds},
          {"steps", r.run.steps},       {"evaluations", r.run.evaluations},
          {"accepted", r.run.accepted}, {"failure", r.run.failure},
          {"samples", r.run.x.size()}};
}

std::string ranData(const Ran& r) {
  std::string bytes;
  for (const VecX& x : r.run.x) bytes.append(reinterpret_cast<const char*>(x.data()), sizeof(double) * x.size());
  return bytes;
}

Ran ranOf(const nlohmann::json& j, const std::string& data, std::size_t state_size) {
  Ran r;
  r.seconds = j.at("seconds").get<double>();
  r.run.seconds = j.at("run_seconds").get<double>();
  r.run.steps = j.at("steps").get<long>();
  r.run.evaluations = j.at("evaluations").get<long>();
  r.run.accepted = j.at("accepted").get<long>();
  r.run.failure = j.at("failure").get<std::string>();
  const std::size_t samples = j.at("samples").get<std::size_t>(), bytes = sizeof(double) * state_size;
  if (data.size() != samples * bytes)
    throw InputError("accuracy study pieces: a kept trajectory holds " + std::to_string(data.size()) +
                     " bytes, not the " + std::to_string(samples * bytes) + " of " + std::to_string(samples) +
                     " samples of this scene; run its piece again");
  for (std::size_t s = 0; s < samples; ++s) {
    VecX x(static_cast<Eigen::Index>(state_size));
    std::memcpy(x.data(), data.data() + s * bytes, bytes);
    r.run.x.push_back(std::move(x));
  }
  return r;
}

// Everything the items' results depend on, hashed: the pieces of one study share it.
std::string studyKey(const AccuracyOptions& o, const std::string& scene_text, const std::vector<Item>& items) {
  io::ContentHash h;
  h.add(std::string_view("wobble study accuracy 1"));
  h.add(std::string_view(scene_text));
  h.add(o.duration), h.add(o.samples), h.add(o.repeats);
  for (const Item& item : items) {
    h.add(std::string_view(item.spec.integrator));
    h.add(item.spec.dt), h.add(item.rtol), h.add(item.spec.options.rtol), h.add(item.spec.options.atol);
    h.add(item.spec.options.max_substeps);
  }
  return h.hex();
}

}  // namespace

std::string accuracyStepLabel(double duration, double dt) {
  const double k = std::log2(duration / dt);
  if (std::abs(k - std::round(k)) < 1e-9) return "T/" + std::to_string(1L << long(std::round(k)));
  return io::formatNumber(dt, 4);
}

std::vector<AccuracyFit> fitAccuracy(const std::vector<AccuracyPoint>& points) {
  std::vector<AccuracyFit> fits;
  for (const AccuracyPoint& p : points) {
    auto it =
        std::find_if(fits.begin(), fits.end(), [&](const AccuracyFit& f) { return f.integrator == p.integrator; });
    if (it == fits.end()) {
      fits.push_back({p.integrator, convergenceOrder(p.integrator)});
      it = fits.end() - 1;
    }
  }
  for (AccuracyFit& f : fits) {
    std::vector<double> h, final_error, rms_error;
    for (const AccuracyPoint& p : points)
      if (p.integrator == f.integrator && p.in_fit) {
        h.push_back(p.mean_step);
        final_error.push_back(p.final_error);
        rms_error.push_back(p.rms_error);
      }
    f.points = int(h.size());
    f.order_final = fitOrder(h, final_error);
    f.order_rms = fitOrder(h, rms_error);
  }
  return fits;
}

AccuracyResult runAccuracyStudy(const AccuracyOptions& o) {
  validate(o);
  const std::vector<std::string> integrators = selectIntegrators(o.integrators);
  SceneFile scene = loadScene(o.scene, o.sets);
  MassSpringSystem& system = *scene.system;

  AccuracyResult result;
  result.scene_name = scene.name;
  result.scene_file = o.scene;
  result.has_colliders = !system.colliders().empty();
  result.duration = o.duration;
  result.particles = system.particleCount();
  std::vector<int> moving;
  for (int i = 0; i < system.particleCount(); ++i)
    if (system.inverseMass()[i] != 0) moving.push_back(i);
  result.moving_particles = int(moving.size());

  std::vector<double> times;
  for (int j = 1; j <= o.samples; ++j) times.push_back(o.duration * j / o.samples);
  const double finest = o.duration / double(1L << o.k_max);

  // The work items: the reference and a looser twin whose difference from it bounds the reference's own error, then
  // every point. rk45's largest step: a sample interval on a smooth scene; with colliders the scene's dt, since
  // collisions are resolved only between steps.
  const double rk45_largest =
      result.has_colliders ? std::min(scene.dt, o.duration / o.samples) : o.duration / o.samples;
  const bool use_rk45 = o.reference == "rk45" || (o.reference == "auto" && !result.has_colliders);
  RunSpec ref{use_rk45 ? "rk45" : "rk4", use_rk45 ? rk45_largest : finest / 16, scene.integrator_options};
  RunSpec twin = ref;
  if (use_rk45) {
    ref.options.rtol = ref.options.atol = 1e-12;
    twin.options.rtol = twin.options.atol = 1e-11;
    ref.options.max_substeps = twin.options.max_substeps = 100000000;
    result.reference = "rk45 (DOPRI5) at rtol = atol = 1e-12, largest step " + io::formatNumber(ref.dt, 4) +
                       " s; its error estimated against rtol = atol = 1e-11";
  } else {
    twin.dt = 2 * ref.dt;
    result.reference = "rk4 at dt = " + accuracyStepLabel(o.duration, ref.dt) +
                       " (finest swept dt / 16); its error estimated "
                       "against rk4 at twice that step";
  }
  std::vector<Item> items = {{ref, 0, false}, {twin, 0, false}};
  for (const std::string& name : integrators) {
    const bool adaptive = integratorTraits(name).adaptive;
    const int first = adaptive ? o.tol_min : o.k_min, last = adaptive ? o.tol_max : o.k_max;
    for (int k = first; k <= last; ++k) {
      Item item{{name, adaptive ? rk45_largest : o.duration / double(1L << k), scene.integrator_options}, 0, true};
      if (adaptive) item.rtol = item.spec.options.rtol = item.spec.options.atol = std::pow(10.0, -k);
      // With contacts, tight tolerances make DOPRI5 crawl through every contact switch (substeps of nanoseconds):
      // a run needing more than kAccuracyContactSubsteps substeps in one scene step gives up, and is listed as left
      // out.
      if (adaptive && result.has_colliders) item.spec.options.max_substeps = kAccuracyContactSubsteps;
      items.push_back(item);
    }
  }
  std::optional<FarmPieces> pieces;
  if (o.piece || o.gather) {
    if (o.out.empty()) throw InputError("--piece, --gather: need the study's folder (--out)");
    pieces.emplace(o.out, "accuracy", studyKey(o, scene.text, items), items.size(), o.gather ? std::nullopt : o.piece);
  }
  std::tie(result.piece.first, result.piece.last) =
      pieces ? pieces->range() : std::pair<std::size_t, std::size_t>{0, items.size()};
  result.piece.items = items.size();
  std::vector<nlohmann::json> gathered;
  if (o.gather) gathered = pieces->gather();

  int total_runs = 0;
  for (std::size_t i = result.piece.first; i < result.piece.last && !o.gather; ++i)
    total_runs += items[i].point ? 1 + o.repeats : 1;
  Progress progress("accuracy " + scene.name, total_runs, "run");
  int done = 0;
  const auto tick = [&](int runs) {
    done += runs;
    if (o.progress && runs) progress.update(done);
  };
  const std::size_t state_size = std::size_t(system.particleCount()) * 3;
  // Item i's run: made here (one machine, or this piece's), kept by a piece, or gathered.
  const auto ran = [&](std::size_t i) -> Ran {
    if (o.gather) return ranOf(gathered[i], pieces->data(i), state_size);
    if (pieces && pieces->load(i)) {  // a piece's own item, done by an earlier run of it
      ++result.piece.kept;
      tick(items[i].point ? 1 + o.repeats : 1);
      return {};
    }
    Ran r = runItem(system, items[i], times, items[i].point ? o.repeats : 0, tick);
    if (pieces) pieces->store(i, ranJson(r), ranData(r));
    return r;
  };
  if (o.piece) {  // its own items, kept for the gathering; no errors without the reference
    for (std::size_t i = result.piece.first; i < result.piece.last; ++i) ran(i);
    progress.finish();
    return result;
  }

  const Ran reference = ran(0);
  if (!reference.run.failure.empty())
    throw std::runtime_error("the reference solution (" + result.reference + ") failed: " + reference.run.failure);
  result.reference_seconds = reference.seconds;
  {
    const Ran loose = ran(1);
    result.reference_error = loose.run.failure.empty() ? errors(loose.run, reference.run, moving).first : kNaN;
  }
  const double floor = 10 * result.reference_error;
  for (std::size_t i = 2; i < items.size(); ++i) {
    const Item& item = items[i];
    const Ran r = ran(i);
    AccuracyPoint p;
    p.integrator = item.spec.integrator;
    p.dt = item.spec.dt;
    p.rtol = item.rtol;
    p.steps = r.run.steps;
    p.evaluations = r.run.evaluations;
    p.mean_step = o.duration / double(std::max(1L, item.rtol > 0 ? r.run.accepted : r.run.steps));
    if (!r.run.failure.empty()) {
      p.diverged = true;
      p.failure = r.run.failure;
      p.final_error = p.rms_error = p.seconds = kNaN;
      result.points.push_back(p);
      continue;
    }
    std::tie(p.final_error, p.rms_error) = errors(r.run, reference.run, moving);
    if (!std::isfinite(p.final_error) || !std::isfinite(p.rms_error)) {
      p.diverged = true;
      p.failure = "non-finite error";
    }
    p.seconds = r.seconds;
    p.in_fit = !p.diverged && !(p.final_error <= floor);  // a NaN floor (twin failed) excludes nothing
    result.points.push_back(p);
  }
  progress.finish();
  result.fits = fitAccuracy(result.points);
  return result;
}

}  // namespace wobble
