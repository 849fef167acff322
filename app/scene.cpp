#include "scene.h"

#include <cmath>

#include "overrides.h"
#include "scene_error.h"
#include "sim/bodies/cloth.h"
#include "sim/bodies/jelly.h"
#include "sim/colliders/elevator.h"
#include "sim/colliders/plane.h"
#include "sim/colliders/sphere.h"
#include "sim/simulation.h"
#include "table_reader.h"

namespace fs = std::filesystem;

namespace wobble {
namespace {

std::vector<std::string> names(std::span<const std::string_view> list) { return {list.begin(), list.end()}; }

void readSimulation(TableReader r, Scene& scene, Vec3& gravity) {
  scene.integrator = r.string("integrator", "rk4", names(integratorNames()));
  scene.dt = r.number("dt", 0.001, Range::positive());
  scene.duration = r.number("duration", 10, Range::positive());
  scene.fps = r.number("fps", 30, Range::positive());
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
  r.finish();
}

// A start faster than the blow-up rule allows would be reported as a blow-up at step 1, advising a smaller dt.
void checkSpeed(TableReader& r, const Vec3& velocity) {
  if (velocity.squaredNorm() > kBlowUpSpeedSquared)
    r.fail("velocity", "a speed of " + std::to_string(std::lround(velocity.norm())) +
                           " m/s is above the blow-up threshold of 1000 m/s (|v|^2 > 1e6, sim/simulation.h)");
}

Body readJelly(TableReader& r, const std::string& name) {
  JellyParams p;
  p.n = r.integer("n", p.n, Range::atLeast(2));
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

Body readCloth(TableReader& r, const std::string& name) {
  ClothParams p;
  p.nx = r.integer("nx", p.nx, Range::atLeast(2));
  p.ny = r.integer("ny", p.ny, Range::atLeast(2));
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
  Body body = type == "jelly" ? readJelly(r, name) : readCloth(r, name);
  if (const auto texture = r.optionalString("texture")) {
    const fs::path path = scene.file.parent_path() / *texture;
    if (!fs::is_regular_file(path)) r.fail("texture", "file not found: " + path.string());
    scene.textures[name] = path;
  }
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
    if (!node.is_table()) TableReader(*table, scene.file, std::string(group)).fail(name, "must be a table");
    readOne(TableReader(*node.as_table(), scene.file, std::string(group) + "." + name), name, scene);
  }
}

toml::table parseFile(const fs::path& file) {
  if (!fs::is_regular_file(file)) throw SceneError(file.string() + ": scene file not found");
  try {
    return toml::parse_file(file.string());
  } catch (const toml::parse_error& e) {
    const auto& at = e.source().begin;
    throw SceneError(file.string() + ":" + std::to_string(at.line) + ":" + std::to_string(at.column) +
                     ": TOML syntax error: " + std::string(e.description()));
  }
}

}  // namespace

int Scene::frameCount() const { return std::max(1, static_cast<int>(std::floor(duration * fps + 1e-9))); }

Scene loadScene(const fs::path& file, const std::vector<std::string>& overrides) {
  Scene scene;
  scene.file = file;
  scene.name = file.stem().string();
  scene.table = parseFile(file);
  for (const std::string& o : overrides) applyOverride(scene.table, o);

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
  if (scene.system->bodies().empty())
    root.fail("bodies", "a scene needs at least one body: [bodies.NAME] with type = \"jelly\" or \"cloth\"");
  root.finish();
  return scene;
}

}  // namespace wobble
