#include "app/commands/compare_command.h"

#include <algorithm>
#include <atomic>
#include <cctype>
#include <deque>
#include <exception>
#include <functional>
#include <future>
#include <mutex>
#include <thread>

#include <nlohmann/json.hpp>

#include "app/commands/frame_range.h"
#include "app/commands/wall_clock.h"
#include "app/compare/compare_report.h"
#include "app/compare/tile_label.h"
#include "app/compare/vary.h"
#include "app/output/frame_name.h"
#include "app/output/interrupt.h"
#include "app/output/obj_sequence_reader.h"
#include "app/output/output_folder.h"
#include "app/output/progress.h"
#include "app/output/video.h"
#include "app/pictures/frame_picture.h"
#include "app/pictures/render_scene.h"
#include "app/run/camera_rig.h"
#include "app/run/shutter.h"
#include "app/scene/input_error.h"
#include "image/compose.h"
#include "image/font.h"
#include "image/font_file.h"
#include "image/png_io.h"
#include "io/content_hash.h"
#include "io/number_text.h"
#include "io/text_file.h"
#include "sim/springs.h"

namespace fs = std::filesystem;

namespace wobble {
namespace {

constexpr int kMaxVariants = 36;
constexpr image::Rgb8 kEmptyCell{40, 40, 40};

// Single quotes around a word the shell would split or expand.
std::string shellWord(const std::string& word) {
  const bool plain = !word.empty() && word.find_first_not_of(
                                          "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz"
                                          "0123456789._-+=/:,@%") == std::string::npos;
  if (plain) return word;
  std::string quoted = "'";
  for (const char c : word) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}

// The flags of a run as `wobble run` takes them (the scene first; the output folder last).
std::string runFlags(const RunOptions& o, bool with_scene_and_out) {
  std::string s;
  const auto add = [&](const std::string& word) { s += (s.empty() ? "" : " ") + shellWord(word); };
  if (with_scene_and_out) add(o.scene.string());
  if (o.integrator) add("--integrator"), add(*o.integrator);
  if (o.dt) add("--dt"), add(io::shortestNumber(*o.dt));
  for (const std::string& set : o.sets) add("--set"), add(set);
  if (o.frames) add("--frames"), add(*o.frames);
  if (o.pc2) add("--pc2");
  if (o.estimate_error) add("--estimate-error");
  const RenderFlags& r = o.render;
  if (r.render) add("--render"), add(*r.render);
  if (r.quality) add("--quality"), add(*r.quality);
  if (r.samples_per_pixel) add("--spp"), add(std::to_string(*r.samples_per_pixel));
  if (r.denoise) add("--denoise"), add(*r.denoise);
  if (r.resolution) add("--resolution"), add(*r.resolution);
  if (with_scene_and_out && o.out) add("--out"), add(o.out->string());
  return s;
}

// "jelly.ks=5e4" -> "jelly.ks"
std::string keyOf(const std::string& assignment) { return assignment.substr(0, assignment.find('=')); }
std::string lastComponent(const std::string& key) { return key.substr(key.rfind('.') + 1); }

// A value as part of a folder name: letters, digits, '.', '+', '-'; the rest becomes '-'.
std::string folderWord(const std::string& value) {
  std::string word;
  for (const char c : value)
    word += std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '+' || c == '-' ? c : '-';
  return word;
}

// What a variant's state looks like frame by frame while it runs (RunOptions::on_frame, on the run's thread):
// the largest spring strain, and its camera (the scene's rig fed with its frames, as a run's would be).
struct Tracker {
  const SceneFile* scene = nullptr;
  std::optional<CameraRig> rig;
  std::vector<render::CameraParams> cameras;  // per frame from 1
  double max_strain = 0, lost_strain = 0;
  std::optional<int> lost_frame;
  double strain_bound = 0;

  void observe(int frame, const VecX& x) {
    const double strain = maxStrain(scene->system->springs(), x);
    max_strain = std::max(max_strain, strain);
    if (!lost_frame && strain > strain_bound) {
      lost_frame = frame;
      lost_strain = strain;
    }
    rig->observe(frame, *scene->system, x);
    cameras.push_back(rig->params());
  }
};

struct Planned {
  CompareVariant variant;
  std::vector<std::pair<std::string, std::string>> values;  // (key, value) per --vary
  SceneFile picture;  // the variant's scene with the comparison's render flags: camera, looks, springs
};

// The label's title: integrator and dt, then each varied scene key and each --set of a body or collider, by its
// last key component ("ks = 5e4") unless two share one.
std::string variantTitle(const SceneFile& scene, const std::vector<std::string>& sets,
                         const std::vector<std::pair<std::string, std::string>>& values) {
  std::vector<std::pair<std::string, std::string>> shown;
  const auto isSetting = [](const std::string& key) {
    for (const char* table : {"simulation.", "render.", "camera.", "output."})
      if (key.rfind(table, 0) == 0) return true;
    return false;
  };
  for (const std::string& set : sets)
    if (!isSetting(keyOf(set))) shown.emplace_back(keyOf(set), set.substr(set.find('=') + 1));
  for (const auto& [key, value] : values)
    if (key != "integrator" && key != "dt" && key != "simulation.integrator" && key != "simulation.dt")
      shown.emplace_back(key, value);
  std::string title = scene.integrator + ", dt = " + shortNumber(scene.dt);
  for (const auto& [key, value] : shown) {
    const std::string last = lastComponent(key);
    const bool unique =
        std::count_if(shown.begin(), shown.end(), [&](const auto& s) { return lastComponent(s.first) == last; }) == 1;
    title += ", " + (unique ? last : key) + " = " + value;
  }
  return title;
}

// Every variant checked as its run will be, before anything is written.
std::vector<Planned> planVariants(const CompareOptions& o, const std::vector<VaryAxis>& axes, const fs::path& out) {
  std::size_t count = 1;
  for (const VaryAxis& a : axes) count *= a.values.size();
  if (count > kMaxVariants)
    throw InputError("--vary: " + std::to_string(count) + " variants; at most " + std::to_string(kMaxVariants) +
                     " fit one video");
  const int digits = int(std::to_string(count).size());
  std::vector<Planned> plans;
  for (std::size_t index = 0; index < count; ++index) {
    Planned p;
    RunOptions& run = p.variant.run;
    run = o.run;
    run.render = RenderFlags{.render = "none"};  // the variant's pictures are its tiles
    run.progress = false;                        // several run at once: the comparison shows one line
    run.stop_on_energy_gain = false;  // a variant runs on to show what becomes of it; its run.json records the gain
    std::string folder = std::to_string(index + 1);
    folder.insert(0, std::size_t(digits) - folder.size(), '0');
    std::size_t rest = index;
    std::vector<std::size_t> picks(axes.size());
    for (std::size_t a = axes.size(); a-- > 0;) {
      picks[a] = rest % axes[a].values.size();
      rest /= axes[a].values.size();
    }
    std::string flags;  // this variant's --vary values, for messages
    for (std::size_t a = 0; a < axes.size(); ++a) {
      const std::string& value = axes[a].values[picks[a]];
      p.values.emplace_back(axes[a].key, value);
      folder += "_" + folderWord(value);
      flags += (flags.empty() ? "" : " ") + axes[a].key + "=" + value;
      const VariedSetting s = variedSetting(axes[a], value);
      if (s.integrator) run.integrator = s.integrator;
      if (s.dt) run.dt = s.dt;
      if (s.set) run.sets.push_back(*s.set);
    }
    run.out = out / folder;
    p.variant.folder = folder;
    try {
      const SceneFile scene = loadRunScene(run);
      if (run.frames) parseFrameRange(*run.frames, scene.frameCount());
      RunOptions look = run;
      look.render = o.run.render;
      p.picture = loadRunScene(look);
    } catch (const InputError& e) {
      throw InputError("--vary " + flags + " (variant " + std::to_string(index + 1) + " of " + std::to_string(count) +
                       "): " + e.what());
    }
    p.variant.label = variantTitle(p.picture, o.run.sets, p.values);
    p.variant.command = "wobble run " + runFlags(run, true);
    plans.push_back(std::move(p));
  }
  return plans;
}

std::vector<VaryAxis> parseAxes(const CompareOptions& o) {
  if (o.vary.empty())
    throw InputError("wobble compare needs --vary KEY=V1,V2,... (e.g. --vary integrator=midpoint,rk4)");
  if (o.vary.size() > 2)
    throw InputError("--vary given " + std::to_string(o.vary.size()) + " times: at most two (rows x columns)");
  std::vector<VaryAxis> axes;
  for (const std::string& v : o.vary) axes.push_back(parseVary(v));
  const auto clash = [&](const VaryAxis& a, const std::string& with) {
    return InputError(varyFlag(a) + ": " + a.key + " is also set by " + with + "; give it in one place");
  };
  if (axes.size() == 2 && axes[0].key == axes[1].key) throw clash(axes[1], varyFlag(axes[0]));
  for (const VaryAxis& a : axes) {
    if ((a.key == "integrator" || a.key == "simulation.integrator") && o.run.integrator) throw clash(a, "--integrator");
    if ((a.key == "dt" || a.key == "simulation.dt") && o.run.dt) throw clash(a, "--dt");
    for (const std::string& set : o.run.sets)
      if (keyOf(set) == a.key) throw clash(a, "--set " + set);
  }
  return axes;
}

// Runs every variant, `jobs` at a time; each run is single-threaded or deterministic on its own threads, so the
// results do not depend on jobs. The first error (in variant order) is rethrown after every run has ended.
// `which`: the variants to run (a piece's); `finished` is called on the run's thread when one ran to its end.
void runVariants(std::vector<Planned>& plans, std::vector<Tracker>& trackers, int jobs,
                 const std::vector<std::size_t>& which, const std::function<void(std::size_t)>& finished) {
  std::atomic<std::size_t> next{0};
  std::atomic<int> done{0};
  std::mutex progress_lock;
  Progress progress("compare", int(which.size()), "run");
  std::vector<std::exception_ptr> errors(plans.size());
  const auto work = [&] {
    for (std::size_t n; (n = next++) < which.size() && !interrupted();) {
      const std::size_t i = which[n];
      CompareVariant& v = plans[i].variant;
      RunOptions run = v.run;
      run.on_frame = [&tracker = trackers[i]](int frame, const VecX& x) { tracker.observe(frame, x); };
      const auto start = Clock::now();
      try {
        v.report = runScene(run);
      } catch (...) {
        errors[i] = std::current_exception();
      }
      v.wall_seconds = secondsSince(start);
      if (!errors[i] && !v.report.interrupted && finished) finished(i);
      const std::lock_guard lock(progress_lock);
      progress.update(++done);
    }
  };
  std::vector<std::thread> threads;
  for (int j = 1; j < jobs; ++j) threads.emplace_back(work);
  work();
  for (std::thread& t : threads) t.join();
  progress.finish();
  for (const std::exception_ptr& e : errors)
    if (e) std::rethrow_exception(e);
}

image::Font loadLabelFont() {
  const auto file = image::findFontFile();
  if (!file)
    throw std::runtime_error(std::string("no font for the tile labels: ") + image::kLabelFontFamily +
                             " is neither known to fontconfig nor at " + image::kLabelFontPath +
                             "; install it (Debian: apt-get install fonts-dejavu-core; setup.sh does) or use "
                             "--render none");
  return image::Font::load(*file);
}

// The checks only rendering needs, before anything is written.
void checkRenderable(const std::vector<Planned>& plans) {
  const SceneFile& first = plans.front().picture;
  for (const Planned& p : plans) {
    const SceneFile& s = p.picture;
    const std::string who = "variant " + p.variant.folder + ": ";
    if (s.fps != first.fps || s.frameCount() != first.frameCount())
      throw InputError(who + "the variants of one video need the same frame rate and length (fps " +
                       io::shortestNumber(s.fps) + ", " + std::to_string(s.frameCount()) + " frames against fps " +
                       io::shortestNumber(first.fps) + ", " + std::to_string(first.frameCount()) +
                       "); compare them with --render none");
    if (!s.write_obj)
      throw InputError(who +
                       "output.obj is false, but the tiles are rendered from the variants' OBJ files; set "
                       "output.obj = true or use --render none");
  }
}

// Whether every body's OBJ of frame k is in mesh_dir.
bool hasObjFrame(const fs::path& mesh_dir, const SceneFile& scene, int k) {
  if (k < 1) return false;
  for (const BodySlot& slot : scene.system->bodies())
    if (!fs::exists(objFramePath(mesh_dir, slot.body.name, k))) return false;
  return true;
}

// Renders the tiles of every frame into OUT/frames/compare_NNNN.png and OUT/compare.mp4.
void renderGrid(std::vector<Planned>& plans, const std::vector<Tracker>& trackers, const std::vector<VaryAxis>& axes,
                const image::Font& font, double strain_bound, CompareReport& report) {
  const SceneFile& lead_scene = plans.front().picture;
  const auto& box = lead_scene.render.camera.resolution;
  const GridLayout grid = axes.size() == 2
                              ? gridLayout(int(axes[0].values.size()), int(axes[1].values.size()), box[0], box[1])
                              : gridLayout(int(plans.size()), box[0], box[1]);
  report.grid = grid;
  // The camera: that of the first variant that ran to the end (else the first), so motion is comparable.
  std::size_t lead = 0;
  while (lead < plans.size() && plans[lead].variant.report.blow_up) ++lead;
  if (lead == plans.size()) lead = 0;
  const std::vector<render::CameraParams>& cameras = trackers[lead].cameras;

  std::deque<RenderScene> scenes;  // not movable: built in place
  std::vector<VariantTrack> tracks;
  for (std::size_t i = 0; i < plans.size(); ++i) {
    scenes.emplace_back(plans[i].picture);
    const RunReport& r = plans[i].variant.report;
    VariantTrack t;
    t.first_frame = report.first_frame;
    t.last_frame = r.first_frame + r.frames_written - 1;
    if (r.blow_up) t.blow_up_time = r.blow_up->time, t.blow_up_step = r.blow_up->step;
    t.lost_shape_frame = trackers[i].lost_frame;
    if (t.lost_shape_frame) t.lost_shape_time = plans[i].picture.frameTime(*t.lost_shape_frame);
    t.lost_shape_strain = trackers[i].lost_strain;
    t.strain_bound = strain_bound;
    tracks.push_back(t);
  }
  std::vector<image::Image8> tiles(plans.size());                 // each variant's last picture
  std::vector<std::vector<SurfaceFrame>> previous(plans.size());  // each variant's last frame read, for motion blur
  std::vector<int> previous_frame(plans.size(), -1);
  image::Image8 blank(grid.tile_width, grid.tile_height, 3);
  image::fill(blank, {0, 0, blank.width, blank.height}, kEmptyCell);

  fs::create_directories(report.out / "frames");
  std::unique_ptr<VideoStream> video =
      VideoStream::open(report.out / "compare.mp4", grid.width(), grid.height(), lead_scene.fps);
  std::future<void> writing;  // a frame's PNG and video frame are written while the next one renders
  Progress progress("compare", report.last_frame - report.first_frame + 1);
  for (int k = report.first_frame; k <= report.last_frame && !interrupted(); ++k) {
    render::CameraParams camera =
        cameras.empty() ? CameraRig(lead_scene).params() : cameras[std::min<std::size_t>(k, cameras.size()) - 1];
    camera.width = grid.tile_width;
    camera.height = grid.tile_height;
    auto canvas = std::make_shared<image::Image8>(grid.width(), grid.height(), 3);
    image::fill(*canvas, {0, 0, canvas->width, canvas->height}, kEmptyCell);
    for (std::size_t i = 0; i < plans.size(); ++i) {
      const SceneFile& scene = plans[i].picture;
      const TileView view = tileView(tracks[i], k, scene.frameTime(k));
      if (view.picture == k) {
        const fs::path mesh = plans[i].variant.run.out.value() / "mesh";
        std::vector<SurfaceFrame> surfaces = readObjFrame(mesh, scene, k);
        // Motion blur as `wobble render` does it: poses blended from the frame before (shutter.h); still when there
        // is none (frame 1, or the first frame of a range whose predecessor was not written).
        const std::vector<double> times = shutterTimes(scene, k);
        const bool blur = times.size() > 1 && (previous_frame[i] == k - 1 || hasObjFrame(mesh, scene, k - 1));
        if (blur) {
          if (previous_frame[i] != k - 1) previous[i] = readObjFrame(mesh, scene, k - 1);
          scenes[i].update(times, blendSurfaces(scene, k, previous[i], surfaces));
        } else {
          scenes[i].update(scene.frameTime(k), surfaces);
        }
        render::CameraParams tile_camera = camera;
        if (blur && k >= 2 && std::size_t(k) <= cameras.size())  // the eye's motion over the shutter
          tile_camera.shutter_motion = shutterMotion(scene, cameras[k - 2].position, camera.position);
        tiles[i] = developPicture(renderPicture(scenes[i].scene(), tile_camera, scene.render.options, k, blur),
                                  scene.render.options);
        previous[i] = std::move(surfaces);
        previous_frame[i] = k;
      }
      image::Image8 tile = view.picture ? tiles[i] : blank;
      drawLabel(tile, font, plans[i].variant.label, view);
      image::paste(*canvas, tile, grid.tileX(int(i)), grid.tileY(int(i)));
    }
    if (writing.valid()) writing.get();
    writing = std::async(std::launch::async, [&report, &video, canvas, k] {
      image::writePng(report.out / "frames" / frameFileName("compare", k, "png"), *canvas);
      if (video) video->write(*canvas);
    });
    ++report.frames_rendered;
    progress.update(k - report.first_frame + 1);
  }
  if (writing.valid()) writing.get();
  progress.finish();
  if (video && !interrupted()) report.video = video->finish();
}

int hardwareThreads() { return int(std::max(1u, std::thread::hardware_concurrency())); }

// What the pictures and compare.md need of a variant that ran, as a farm piece keeps it (farm_pieces.h): doubles
// exact, the camera of every frame.
// jobs: the runs at once in the piece that ran it (with its machine's hardware threads, for compare.md's times).
nlohmann::json variantJson(const CompareVariant& v, const Tracker& t, int jobs) {
  const RunReport& r = v.report;
  nlohmann::json j = {{"jobs", jobs},
                      {"threads", hardwareThreads()},
                      {"first_frame", r.first_frame},
                      {"frames_written", r.frames_written},
                      {"steps", r.steps},
                      {"simulated_time", r.simulated_time},
                      {"seconds_simulate", r.seconds_simulate},
                      {"wall_seconds", v.wall_seconds},
                      {"max_strain", t.max_strain},
                      {"lost_strain", t.lost_strain},
                      {"lost_frame", t.lost_frame ? nlohmann::json(*t.lost_frame) : nlohmann::json(nullptr)}};
  if (r.blow_up) j["blow_up"] = {{"time", r.blow_up->time}, {"step", r.blow_up->step}};
  if (r.error_estimate)
    j["error_estimate"] = {{"max_error", r.error_estimate->max_error}, {"failure", r.error_estimate->failure}};
  nlohmann::json cameras = nlohmann::json::array();
  for (const render::CameraParams& c : t.cameras) {
    nlohmann::json values = nlohmann::json::array();
    for (const Eigen::Vector3f* v3 : {&c.position, &c.look_at, &c.up, &c.shutter_motion})
      for (int k = 0; k < 3; ++k) values.push_back((*v3)[k]);
    for (const float f : {c.vfov_deg, c.aperture, c.focus}) values.push_back(f);
    values.push_back(c.width), values.push_back(c.height);
    cameras.push_back(values);
  }
  j["cameras"] = cameras;
  return j;
}

// Returns the runs at once and hardware threads of the piece that ran it.
std::pair<int, int> readVariantJson(const nlohmann::json& j, CompareVariant& v, Tracker& t) {
  RunReport& r = v.report;
  r.first_frame = j.at("first_frame").get<int>();
  r.frames_written = j.at("frames_written").get<int>();
  r.steps = j.at("steps").get<long>();
  r.simulated_time = j.at("simulated_time").get<double>();
  r.seconds_simulate = j.at("seconds_simulate").get<double>();
  v.wall_seconds = j.at("wall_seconds").get<double>();
  t.max_strain = j.at("max_strain").get<double>();
  t.lost_strain = j.at("lost_strain").get<double>();
  if (!j.at("lost_frame").is_null()) t.lost_frame = j.at("lost_frame").get<int>();
  if (j.contains("blow_up")) {
    r.blow_up = BlowUp{};
    r.blow_up->time = j.at("blow_up").at("time").get<double>();
    r.blow_up->step = j.at("blow_up").at("step").get<long>();
  }
  if (j.contains("error_estimate")) {
    r.error_estimate = ErrorEstimate{};
    r.error_estimate->max_error = j.at("error_estimate").at("max_error").get<double>();
    r.error_estimate->failure = j.at("error_estimate").at("failure").get<std::string>();
  }
  t.cameras.clear();
  for (const nlohmann::json& values : j.at("cameras")) {
    render::CameraParams c;
    int k = 0;
    for (Eigen::Vector3f* v3 : {&c.position, &c.look_at, &c.up, &c.shutter_motion})
      for (int i = 0; i < 3; ++i) (*v3)[i] = values.at(k++).get<float>();
    for (float* f : {&c.vfov_deg, &c.aperture, &c.focus}) *f = values.at(k++).get<float>();
    c.width = values.at(k++).get<int>();
    c.height = values.at(k++).get<int>();
    t.cameras.push_back(c);
  }
  return {j.value("jobs", 1), j.value("threads", 1)};
}

// Everything the variants' results depend on, hashed: the pieces of one comparison share it.
std::string compareKey(const CompareOptions& o, const std::vector<Planned>& plans) {
  io::ContentHash h;
  h.add(std::string_view("wobble compare 1"));
  for (const Planned& p : plans) {
    RunOptions run = p.variant.run;
    run.out.reset();
    h.add(std::string_view(runFlags(run, false)));
    h.add(std::string_view(p.picture.text));
  }
  h.add(o.strain_bound);
  h.add(std::string_view(o.run.frames.value_or("")));
  return h.hex();
}

CompareSummary summarize(const CompareOptions& o, const std::vector<Planned>& plans, const CompareReport& report) {
  CompareSummary s;
  s.scene = o.run.scene.string();
  s.vary = o.vary;
  RunOptions common = o.run;
  common.out.reset();
  s.common = runFlags(common, false);
  s.strain_bound = o.strain_bound;
  s.estimate_error = o.run.estimate_error;
  s.jobs = report.jobs;
  s.threads = report.threads;
  s.pieces = report.pieces;
  if (report.grid) {
    const GridLayout& g = *report.grid;
    s.video = report.video ? "`compare.mp4`" : "no video (ffmpeg missing)";
    s.video += " and `frames/compare_NNNN.png`, " + std::to_string(g.width()) + " x " + std::to_string(g.height()) +
               ", frames " + std::to_string(report.first_frame) + " to " + std::to_string(report.last_frame) + " at " +
               io::shortestNumber(plans.front().picture.fps) + " fps";
    s.layout = std::to_string(g.rows) + " x " + std::to_string(g.cols) + " tiles of " + std::to_string(g.tile_width) +
               " x " + std::to_string(g.tile_height);
  }
  for (const Planned& p : plans) {
    const CompareVariant& v = p.variant;
    const RunReport& r = v.report;
    CompareRow row;
    row.folder = v.folder;
    row.label = v.label;
    row.integrator = p.picture.integrator;
    row.dt = p.picture.dt;
    row.steps = r.steps;
    row.simulated_time = r.simulated_time;
    row.simulate_seconds = r.seconds_simulate;
    row.wall_seconds = v.wall_seconds;
    if (r.blow_up) row.blow_up_time = r.blow_up->time, row.blow_up_step = r.blow_up->step;
    row.max_strain = v.max_strain;
    if (v.lost_shape_frame) row.lost_shape_time = p.picture.frameTime(*v.lost_shape_frame);
    if (r.error_estimate)
      row.estimated_error = r.error_estimate->max_error, row.estimate_note = r.error_estimate->failure;
    row.command = v.command;
    s.rows.push_back(row);
  }
  return s;
}

}  // namespace

CompareReport runCompare(const CompareOptions& o) {
  // Everything is checked first: the flags, every variant's scene, the font. Nothing is written before.
  const std::vector<VaryAxis> axes = parseAxes(o);
  if (o.jobs < 0) throw InputError("--jobs " + std::to_string(o.jobs) + ": must be >= 0 (0: one per hardware thread)");
  if (!(o.strain_bound > 0)) throw InputError("--strain-bound " + io::shortestNumber(o.strain_bound) + ": must be > 0");
  if (o.run.render.render && o.run.render.render->find("exr") != std::string::npos)
    throw InputError("--render " + *o.run.render.render +
                     ": wobble compare writes PNG frames and a video: png or none");
  CompareReport report;
  {
    const SceneFile common = loadRunScene(o.run);  // the shared flags' own errors, without a variant named
    report.out = o.out.value_or(fs::path("out") / ("compare-" + common.name));
  }
  std::vector<Planned> plans = planVariants(o, axes, report.out);
  const bool rendering = plans.front().picture.render.options.png;
  std::optional<image::Font> font;
  if (rendering) {
    checkRenderable(plans);
    font = loadLabelFont();
  }
  const SceneFile& first = plans.front().picture;
  std::tie(report.first_frame, report.last_frame) =
      o.run.frames ? parseFrameRange(*o.run.frames, first.frameCount()) : std::pair{1, first.frameCount()};

  std::optional<FarmPieces> pieces;
  if (o.piece || o.gather)
    pieces.emplace(report.out, "compare", compareKey(o, plans), plans.size(), o.gather ? std::nullopt : o.piece);
  report.variant_count = plans.size();
  std::tie(report.piece_first, report.piece_last) =
      pieces ? pieces->range() : std::pair<std::size_t, std::size_t>{0, plans.size()};
  // A piece shares OUT with the others (each variant holds its own folder); the pictures and compare.md are the
  // gathering's, which holds OUT alone.
  const OutputFolder folder(report.out, o.piece ? OutputFolder::Access::shared : OutputFolder::Access::exclusive);
  if (!o.piece) {
    folder.clearEarlierRun("compare");  // frames/compare_NNNN.png, compare.mp4
    std::error_code ignored;
    fs::remove(report.out / "compare.md", ignored);
  }

  std::vector<Tracker> trackers(plans.size());
  for (std::size_t i = 0; i < plans.size(); ++i) {
    trackers[i].scene = &plans[i].picture;
    trackers[i].rig.emplace(plans[i].picture);
    trackers[i].strain_bound = o.strain_bound;
  }
  std::vector<std::size_t> which;  // the variants this command runs
  if (o.gather) {
    const std::vector<nlohmann::json> gathered = pieces->gather();
    report.pieces = pieces->count();
    report.jobs = report.threads = 1;  // the most in any piece
    for (std::size_t i = 0; i < plans.size(); ++i) {
      const auto [jobs, threads] = readVariantJson(gathered[i], plans[i].variant, trackers[i]);
      report.jobs = std::max(report.jobs, jobs), report.threads = std::max(report.threads, threads);
    }
  }
  for (std::size_t i = report.piece_first; i < report.piece_last && !o.gather; ++i) {
    if (pieces)
      if (const auto kept = pieces->load(i)) {
        readVariantJson(*kept, plans[i].variant, trackers[i]);
        ++report.variants_resumed;
        continue;
      }
    which.push_back(i);
  }
  if (!o.gather) {
    report.jobs = std::clamp(o.jobs > 0 ? o.jobs : hardwareThreads(), 1, int(std::max<std::size_t>(1, which.size())));
    report.threads = hardwareThreads();
  }
  auto start = Clock::now();
  runVariants(plans, trackers, report.jobs, which, [&](std::size_t i) {
    if (pieces) pieces->store(i, variantJson(plans[i].variant, trackers[i], report.jobs));
  });
  report.seconds_runs = secondsSince(start);
  for (std::size_t i = 0; i < plans.size(); ++i) {
    CompareVariant& v = plans[i].variant;
    v.max_strain = trackers[i].max_strain;
    v.lost_shape_frame = trackers[i].lost_frame;
    v.lost_shape_strain = trackers[i].lost_strain;
  }
  if (o.piece) {  // its own variants only; the pictures and numbers are the gathering's
    report.interrupted = interrupted();
    for (std::size_t i = report.piece_first; i < report.piece_last; ++i)
      report.variants.push_back(std::move(plans[i].variant));
    return report;
  }
  report.interrupted = interrupted();
  if (!report.interrupted && rendering) {
    start = Clock::now();
    renderGrid(plans, trackers, axes, *font, o.strain_bound, report);
    report.seconds_render = secondsSince(start);
    report.interrupted = interrupted();
  }
  if (!report.interrupted) io::writeTextFile(report.out / "compare.md", compareMarkdown(summarize(o, plans, report)));
  for (Planned& p : plans) report.variants.push_back(std::move(p.variant));
  return report;
}

}  // namespace wobble
