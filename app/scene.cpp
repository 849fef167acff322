#include "scene.h"

#include <cmath>
#include <fstream>
#include <sstream>

#include "identifier.h"
#include "overrides.h"
#include "render/image_header.h"
#include "scene_error.h"
#include "sim/bodies/cloth.h"
#include "sim/bodies/jelly.h"
#include "sim/colliders/elevator.h"
#include "sim/colliders/plane.h"
#include "sim/colliders/sphere.h"
#include "sim/simulation.h"
#include "table_reader.h"
#include "text_table.h"
#include "toml_depth.h"

namespace fs = std::filesystem;

namespace wobble {
namespace {

std::vector<std::string> names(std::span<const std::string_view> list) { return {list.begin(), list.end()}; }

void readSimulation(TableReader r, Scene& scene, Vec3& gravity) {
  scene.integrator = r.string("integrator", "rk4", names(integratorNames()));
  scene.dt = r.number("dt", 0.001, Range::positive());
  scene.duration = r.number("duration", 10, Range::positive());
  scene.fps = r.number("fps", 30, Range::positive());
  // Frames and steps are bounded so that no scene runs for ever or fills the disk (scene_limits.h).
  const double frames = std::floor(scene.duration * scene.fps + 1e-9);
  if (frames > double(kMaxFrames))
    r.fail(r.node("duration") || !r.node("fps") ? "duration" : "fps",
           "duration * fps = " + formatNumber(frames, 3) + " frames (duration " + formatNumber(scene.duration) +
               " s at " + formatNumber(scene.fps) + " fps), above the cap of " +
               std::to_string(kMaxFrames) + " frames per run");
  if (1 / (scene.fps * scene.dt) > kMaxStepsPerFrame)
    r.fail("dt", "1 / (fps dt) = " + formatNumber(1 / (scene.fps * scene.dt), 3) +
                     " steps per frame, above the cap of " + std::to_string(std::llround(kMaxStepsPerFrame)) +
                     ": dt must be >= " + formatNumber(1 / (scene.fps * kMaxStepsPerFrame), 3) + " s at " +
                     formatNumber(scene.fps) + " fps");
  gravity = r.vec3("gravity", Vec3(0, -9.8, 0));
  IntegratorOptions& o = scene.integrator_options;
  o.rtol = r.number("rtol", o.rtol, Range::positive());
  o.atol = r.number("atol", o.atol, Range::positive());
  o.newton = r.boolean("newton", o.newton);
  o.cg_tolerance = r.number("cg_tolerance", o.cg_tolerance, Range::positive());
  o.cg_max_iterations = r.integer("cg_max_iterations", o.cg_max_iterations, Range::atLeast(1));
  r.finish();
}

void readOutput(TableReader r, Scene& scene) {
  scene.write_obj = r.boolean("obj", true);
  scene.write_pc2 = r.boolean("pc2", false);
  r.finish();
}

// A start faster than the blow-up rule allows would be reported as a blow-up at step 1, advising a smaller dt.
void checkSpeed(TableReader& r, const Vec3& velocity) {
  if (velocity.squaredNorm() > kBlowUpSpeedSquared)
    r.fail("velocity", "a speed of " + std::to_string(std::lround(velocity.norm())) +
                           " m/s is above the blow-up threshold of 1000 m/s (|v|^2 > 1e6, sim/simulation.h)");
}

[[noreturn]] void failOverBudget(TableReader& r, const Scene& scene, std::string_view key, const SceneEstimate& e,
                                 const std::string& hint) {
  const bool implicit = scene.integrator == "backward-euler";
  r.fail(key, "the scene would need " + e.describe(implicit) + ", above the memory budget of " +
                  formatBytes(scene.memory_budget) + " (--max-memory; the default is half of physical memory)" + hint);
}

// Adds a body to the scene's estimate before it is built, or fails at key (value as read): over the particle count
// one body may have, or over the memory budget. sizeOf(v) is the body's size with key = v; the message names the
// largest v that would fit.
template <typename SizeOf>
void reserveBody(TableReader& r, Scene& scene, std::string_view key, int value, SizeOf sizeOf) {
  const bool implicit = scene.integrator == "backward-euler";
  const auto fits = [&](int v) {
    const BodySize b = sizeOf(v);
    SceneEstimate e = scene.estimate;
    e.add(b);
    return b.particles <= kMaxBodyParticles && e.bytes(implicit) <= scene.memory_budget;
  };
  if (fits(value)) {
    scene.estimate.add(sizeOf(value));
    return;
  }
  int lo = 1, hi = value;  // fits(lo) or lo == 1; !fits(hi)
  while (hi - lo > 1) (fits(lo + (hi - lo) / 2) ? lo : hi) = lo + (hi - lo) / 2;
  const std::string hint = lo >= 2 ? "; " + std::string(key) + " <= " + std::to_string(lo) + " would fit" : "";
  const BodySize b = sizeOf(value);
  if (b.particles > kMaxBodyParticles)
    r.fail(key, std::to_string(b.particles) + " particles, above the " + std::to_string(kMaxBodyParticles) +
                    " one body may have (32-bit particle indices)" + hint);
  SceneEstimate e = scene.estimate;
  e.add(b);
  failOverBudget(r, scene, key, e, hint);
}

Body readJelly(TableReader& r, const std::string& name, Scene& scene) {
  JellyParams p;
  // n^3 particles: the cube root of the most one body may have bounds n before anything is multiplied.
  p.n = r.integer("n", p.n, Range{2, std::floor(std::cbrt(double(kMaxBodyParticles)))});
  reserveBody(r, scene, "n", p.n, [](int n) { return jellySize(n); });
  p.size = r.number("size", p.size, Range::positive());
  p.mass = r.number("mass", p.mass, Range::positive());
  p.ks = r.number("ks", p.ks, Range::nonNegative());
  p.kd = r.number("kd", p.kd, Range::nonNegative());
  p.center = r.vec3("center", p.center);
  p.rotation_axis = r.vec3("rotation_axis", p.rotation_axis);
  p.rotation_deg = r.number("rotation_deg", p.rotation_deg);
  p.velocity = r.vec3("velocity", p.velocity);
  checkSpeed(r, p.velocity);
  if (p.rotation_deg != 0 && p.rotation_axis.norm() == 0) r.fail("rotation_axis", "must not be zero");
  return buildJelly(name, p);
}

void readPins(TableReader& r, ClothParams& p) {
  const toml::node* node = r.node("pinned");
  if (!node) return;
  const toml::array* list = node->as_array();
  if (!list) r.fail("pinned", "must be an array of particle indices and/or \"corners\", \"top-edge\"");
  for (const toml::node& item : *list) {
    if (const auto* index = item.as_integer()) {
      if (index->get() < 0 || index->get() >= p.nx * p.ny)
        r.fail("pinned", "index " + std::to_string(index->get()) + " must be in [0, " + std::to_string(p.nx * p.ny - 1) +
                             "] (i + nx * j)");
      p.pinned.push_back(static_cast<int>(index->get()));
    } else if (const auto* set = item.as_string()) {
      try {
        const auto ids = clothPinSet(set->get(), p.nx, p.ny);
        p.pinned.insert(p.pinned.end(), ids.begin(), ids.end());
      } catch (const std::invalid_argument& e) {
        r.fail("pinned", e.what());
      }
    } else {
      r.fail("pinned", "items must be particle indices or \"corners\", \"top-edge\"");
    }
  }
}

Body readCloth(TableReader& r, const std::string& name, Scene& scene) {
  ClothParams p;
  // nx ny particles; bounding each by the most one body may have over 2 keeps 64-bit counts from overflowing.
  const Range side{2, double(kMaxBodyParticles / 2)};
  p.nx = r.integer("nx", p.nx, side);
  p.ny = r.integer("ny", p.ny, side);
  reserveBody(r, scene, "ny", p.ny, [nx = p.nx](int ny) { return clothSize(nx, ny); });
  const auto size = r.pair("size", {p.size_x, p.size_y}, Range::positive());
  p.size_x = size[0];
  p.size_y = size[1];
  p.center = r.vec3("center", p.center);
  p.hanging = r.boolean("hanging", p.hanging);
  p.mass = r.number("mass", p.mass, Range::positive());
  p.ks = r.number("ks", p.ks, Range::nonNegative());
  p.kd = r.number("kd", p.kd, Range::nonNegative());
  p.drag = r.number("drag", p.drag, Range::nonNegative());
  p.velocity = r.vec3("velocity", p.velocity);
  checkSpeed(r, p.velocity);
  readPins(r, p);
  return buildCloth(name, p);
}

void readBody(TableReader r, const std::string& name, Scene& scene) {
  const std::string type = r.string("type", "", {"jelly", "cloth"});
  if (const auto texture = r.optionalString("texture")) {
    const fs::path path = scene.file.parent_path() / *texture;
    if (!fs::is_regular_file(path)) r.fail("texture", "file not found: " + path.string());
    std::string reason;
    const auto header = render::readImageHeader(path, reason);
    if (!header) r.fail("texture", "cannot read the image " + path.string() + " (" + reason + ")");
    if (header->width > kMaxTextureSide || header->height > kMaxTextureSide)
      r.fail("texture", path.string() + " is " + std::to_string(header->width) + " x " + std::to_string(header->height) +
                            " pixels; a texture may have at most " + std::to_string(kMaxTextureSide) + " on each side");
    SceneEstimate e = scene.estimate;
    e.texture_pixels += std::int64_t(header->width) * header->height;
    if (e.bytes(scene.integrator == "backward-euler") > scene.memory_budget) failOverBudget(r, scene, "texture", e, "");
    scene.estimate = e;
    scene.textures[name] = path;
  }
  // Built after every check of its table but the look (read below, cheap): nothing large is allocated for a body
  // the reader refuses.
  Body body = type == "jelly" ? readJelly(r, name, scene) : readCloth(r, name, scene);
  readBodyLook(r, type, name, scene);
  r.finish();
  scene.system->addBody(std::move(body));
}

ContactParams readContact(TableReader& r) {
  ContactParams c;
  c.restitution = r.number("restitution", c.restitution, Range::unit());
  c.friction = r.number("friction", c.friction, Range::nonNegative());
  c.epsilon = r.number("epsilon", c.epsilon, Range::positive());
  return c;
}

void readCollider(TableReader r, const std::string& name, Scene& scene) {
  const std::string type = r.string("type", "", {"plane", "sphere", "elevator"});
  const ContactParams contact = readContact(r);
  std::unique_ptr<Collider> collider;
  if (type == "plane") {
    const Vec3 normal = r.vec3("normal", Vec3::UnitY());
    if (normal.norm() == 0) r.fail("normal", "must not be zero");
    collider = std::make_unique<Plane>(name, contact, r.vec3("point", Vec3::Zero()), normal);
    r.number("size", 30, Range::positive());  // drawn extent: read by the renderer
  } else if (type == "sphere") {
    const Vec3 center = r.vec3("center", Vec3::Zero());
    const double radius = r.number("radius", 1, Range::positive());
    collider = std::make_unique<Sphere>(name, contact, center, radius, r.vec3("velocity", Vec3::Zero()));
  } else {
    ElevatorSchedule s;
    s.start = r.vec3("start", s.start);
    s.accel = r.number("accel", s.accel, Range::nonNegative());
    s.travel = r.number("travel", s.travel, Range::positive());
    s.pause = r.number("pause", s.pause, Range::nonNegative());
    const double size = r.number("size", 5, Range::positive());
    collider = std::make_unique<Elevator>(name, contact, s, size, r.number("thickness", 0.25, Range::positive()));
  }
  readColliderLook(r, type, name, scene);
  r.finish();
  scene.system->addCollider(std::move(collider));
}

// Reads each entry of a group table ("bodies", "colliders") with readOne(reader, name, scene).
template <typename ReadOne>
void readGroup(TableReader& root, std::string_view group, Scene& scene, ReadOne readOne) {
  const toml::table* table = root.table(group);
  if (!table) return;
  for (const auto& [key, node] : *table) {
    const std::string name(key.str());
    if (const std::string problem = identifierProblem(name); !problem.empty())
      TableReader(*table, scene.file, std::string(group)).failName(name, problem);
    if (!node.is_table()) TableReader(*table, scene.file, std::string(group)).fail(name, "must be a table");
    readOne(TableReader(*node.as_table(), scene.file, std::string(group) + "." + name), name, scene);
  }
}

// Refuses text nested deeper than kMaxNestingDepth before toml++ (recursive) sees it; where: "file:" or "--set X:".
void checkNesting(std::string_view text, const std::string& where) {
  if (const auto excess = findExcessNesting(text, kMaxNestingDepth))
    throw SceneError(where + std::to_string(excess->line) + ": nesting too deep: " + std::to_string(excess->depth) +
                     " levels of [, { and dotted keys, above the limit of " + std::to_string(kMaxNestingDepth));
}

toml::table parseFile(const fs::path& file) {
  if (!fs::is_regular_file(file)) throw SceneError(file.string() + ": scene file not found");
  if (const auto size = fs::file_size(file); size > kMaxSceneFileBytes)
    throw SceneError(file.string() + ": " + std::to_string(size) + " bytes, above the limit of " +
                     std::to_string(kMaxSceneFileBytes) + " bytes for a scene file");
  std::ostringstream text;
  text << std::ifstream(file, std::ios::binary).rdbuf();
  const std::string content = text.str();
  checkNesting(content, file.string() + ":");
  try {
    return toml::parse(content, file.string());
  } catch (const toml::parse_error& e) {
    const auto& at = e.source().begin;
    throw SceneError(file.string() + ":" + std::to_string(at.line) + ":" + std::to_string(at.column) +
                     ": TOML syntax error: " + std::string(e.description()));
  }
}

}  // namespace

// Frames are capped at kMaxFrames when the scene is read: the int cannot overflow.
int Scene::frameCount() const { return std::max(1, static_cast<int>(std::floor(duration * fps + 1e-9))); }

Scene loadScene(const fs::path& file, const std::vector<std::string>& overrides, std::uint64_t max_memory) {
  Scene scene;
  scene.file = file;
  scene.name = file.stem().string();
  if (const std::string problem = identifierProblem(scene.name); !problem.empty())
    throw SceneError(file.string() + ": the scene name " + quotedName(scene.name) + " (the file name without .toml) is " +
                     problem);
  scene.memory_budget = max_memory > 0 ? max_memory : memoryBudget();
  scene.table = parseFile(file);
  for (const std::string& o : overrides) {
    checkNesting(o, "--set " + o.substr(0, 40) + ": line ");
    applyOverride(scene.table, o);
  }

  TableReader root(scene.table, file, "");
  Vec3 gravity;
  static const toml::table kEmpty;
  const toml::table* simulation = root.table("simulation");
  readSimulation(TableReader(simulation ? *simulation : kEmpty, file, "simulation"), scene, gravity);
  scene.system = std::make_unique<MassSpringSystem>(gravity);
  if (const toml::table* output = root.table("output")) readOutput(TableReader(*output, file, "output"), scene);
  readGroup(root, "bodies", scene, readBody);
  readGroup(root, "colliders", scene, readCollider);
  readRenderTables(root, scene);
  if (scene.render.options.png || scene.render.options.exr) {  // the render buffers count once the scene renders
    SceneEstimate e = scene.estimate;
    e.render_pixels = std::int64_t(scene.render.camera.resolution[0]) * scene.render.camera.resolution[1];
    if (e.bytes(scene.integrator == "backward-euler") > scene.memory_budget) {
      const toml::table* camera = root.table("camera");
      TableReader c(camera ? *camera : kEmpty, file, "camera");
      failOverBudget(c, scene, "resolution", e, "; a smaller camera.resolution (or --resolution) would fit");
    }
    scene.estimate = e;
  }
  if (scene.system->bodies().empty())
    root.fail("bodies", "a scene needs at least one body: [bodies.NAME] with type = \"jelly\" or \"cloth\"");
  root.finish();
  return scene;
}

}  // namespace wobble
