#include "app/scene/scene_file.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "app/scene/body_kinds.h"
#include "app/scene/collider_kinds.h"
#include "app/scene/identifier.h"
#include "app/scene/input_error.h"
#include "app/scene/overrides.h"
#include "app/scene/scene_budget.h"
#include "app/scene/table_reader.h"
#include "app/scene/toml_depth.h"
#include "image/image_header.h"
#include "io/content_hash.h"
#include "io/number_text.h"
#include "io/text_file.h"

namespace fs = std::filesystem;

namespace wobble {
namespace {

std::vector<std::string> names(std::span<const std::string_view> list) { return {list.begin(), list.end()}; }

void readSimulation(TableReader r, SceneFile& scene, Vec3& gravity) {
  scene.integrator = r.string("integrator", "rk4", names(integratorNames()));
  scene.dt = r.number("dt", 0.001, Range::positive());
  scene.duration = r.number("duration", 10, Range::positive());
  scene.fps = r.number("fps", 30, Range::positive());
  // Frames and steps are bounded so that no scene runs for ever or fills the disk (scene_limits.h).
  const double frames = std::floor(scene.duration * scene.fps + 1e-9);
  if (frames > double(kMaxFrames))
    r.fail(r.node("duration") || !r.node("fps") ? "duration" : "fps",
           "duration * fps = " + io::formatNumber(frames, 3) + " frames (duration " + io::formatNumber(scene.duration) +
               " s at " + io::formatNumber(scene.fps) + " fps), above the cap of " + std::to_string(kMaxFrames) +
               " frames per run");
  if (1 / (scene.fps * scene.dt) > kMaxStepsPerFrame)
    r.fail("dt", "1 / (fps dt) = " + io::formatNumber(1 / (scene.fps * scene.dt), 3) +
                     " steps per frame, above the cap of " + std::to_string(std::llround(kMaxStepsPerFrame)) +
                     ": dt must be >= " + io::formatNumber(1 / (scene.fps * kMaxStepsPerFrame), 3) + " s at " +
                     io::formatNumber(scene.fps) + " fps");
  gravity = r.vec3("gravity", Vec3(0, -9.8, 0));
  IntegratorOptions& o = scene.integrator_options;
  o.rtol = r.number("rtol", o.rtol, Range::positive());
  o.atol = r.number("atol", o.atol, Range::positive());
  o.newton = r.boolean("newton", o.newton);
  o.newton_tolerance = r.number("newton_tolerance", o.newton_tolerance, Range::positive());
  o.newton_max_iterations = r.integer("newton_max_iterations", o.newton_max_iterations, Range{1, 1000});
  const std::vector<std::string> searches = {"potential", "residual"};
  o.line_search = LineSearch(
      std::find(searches.begin(), searches.end(), r.string("line_search", "potential", searches)) - searches.begin());
  o.line_search_halvings = r.integer("line_search_halvings", o.line_search_halvings, Range{0, 60});
  o.cg_tolerance = r.number("cg_tolerance", o.cg_tolerance, Range::positive());
  o.cg_error_fraction = r.number("cg_error_fraction", o.cg_error_fraction, Range::nonNegative());
  o.cg_max_iterations = r.integer("cg_max_iterations", o.cg_max_iterations, Range::atLeast(1));
  const std::vector<std::string> preconditioners = {"auto", "block-jacobi", "two-level"};
  const std::string preconditioner = r.string("cg_preconditioner", "auto", preconditioners);
  o.cg_preconditioner = CgPreconditioner(std::find(preconditioners.begin(), preconditioners.end(), preconditioner) -
                                         preconditioners.begin());
  r.finish();
}

void readOutput(TableReader r, SceneFile& scene) {
  scene.write_obj = r.boolean("obj", true);
  scene.write_pc2 = r.boolean("pc2", false);
  r.finish();
}

void readBody(TableReader r, const std::string& name, SceneFile& scene) {
  const BodyKind& kind = bodyKind(r.string("type", "", bodyTypes()));
  if (const auto texture = r.optionalString("texture")) {
    const fs::path path = r.filePath("texture", *texture);
    if (!fs::is_regular_file(path)) r.fail("texture", "file not found: " + path.string());
    std::string reason;
    const auto header = image::readImageHeader(path, reason);
    if (!header || header->format == "EXR")
      r.fail("texture", "cannot read the image " + path.string() + " (" + (header ? "OpenEXR" : reason) +
                            "; a texture is a PNG, JPEG, BMP or TGA image)");
    if (header->width > kMaxTextureSide || header->height > kMaxTextureSide)
      r.fail("texture", path.string() + " is " + std::to_string(header->width) + " x " +
                            std::to_string(header->height) + " pixels; a texture may have at most " +
                            std::to_string(kMaxTextureSide) + " on each side");
    SceneEstimate e = scene.estimate;
    e.texture_pixels += std::int64_t(header->width) * header->height;
    if (e.bytes(integratorTraits(scene.integrator).implicit) > scene.memory_budget)
      failOverBudget(r, scene, "texture", e, "");
    scene.estimate = e;
    scene.textures[name] = path;
  }
  // Built after every check of its table but the look (read below, cheap): nothing large is allocated for a body
  // the reader refuses.
  Body body = kind.read(r, name, scene);
  readBodyContact(r, kind, scene.body_count, body);
  readBodyLook(r, kind, name, scene);
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

// [contact]: the caps of contact between bodies (sim/contact/params.h), and whether backward Euler carries the
// contacts in its solve (IntegratorOptions::body_contact_in_solve; the other integrators have no solve to carry them
// in and ignore the key, as they ignore [simulation]'s cg_ keys).
collision::Settings readContactTable(TableReader r, IntegratorOptions& options) {
  collision::Settings s;
  s.ccd_iterations = r.integer("ccd_iterations", s.ccd_iterations, Range{0, 1000});
  s.zone_iterations = r.integer("zone_iterations", s.zone_iterations, Range{1, 10000});
  s.split_steps = r.integer("split_steps", s.split_steps, Range{0, 20});
  options.body_contact_in_solve = r.boolean("in_solve", options.body_contact_in_solve);
  r.finish();
  return s;
}

void readCollider(TableReader r, const std::string& name, SceneFile& scene) {
  const ColliderKind& kind = colliderKind(r.string("type", "", colliderTypes()));
  const ContactParams contact = readContact(r);
  ColliderLook look;
  std::unique_ptr<Collider> collider = kind.read(r, name, contact, look);
  readColliderLook(r, kind, name, look, scene);
  r.finish();
  scene.system->addCollider(std::move(collider));
}

// Reads each entry of a group table ("bodies", "colliders") with readOne(reader, name, scene).
template <typename ReadOne>
void readGroup(TableReader& root, std::string_view group, SceneFile& scene, ReadOne readOne) {
  const toml::table* table = root.table(group);
  if (!table) return;
  TableReader entries = root.child(group);
  for (const auto& [key, node] : *table) {
    const std::string name(key.str());
    if (const std::string problem = identifierProblem(name); !problem.empty()) entries.failName(name, problem);
    if (!node.is_table()) entries.fail(name, "must be a table");
    readOne(entries.child(name), name, scene);
  }
}

// Refuses text nested deeper than kMaxNestingDepth before toml++ (recursive) sees it; where: "file:" or "--set X:".
void checkNesting(std::string_view text, const std::string& where) {
  if (const auto excess = findExcessNesting(text, kMaxNestingDepth))
    throw InputError(where + std::to_string(excess->line) + ": nesting too deep: " + std::to_string(excess->depth) +
                     " levels of [, { and dotted keys, above the limit of " + std::to_string(kMaxNestingDepth));
}

toml::table parseFile(const fs::path& file) {
  if (!fs::is_regular_file(file)) throw InputError(file.string() + ": scene file not found");
  if (const auto size = fs::file_size(file); size > kMaxSceneFileBytes)
    throw InputError(file.string() + ": " + std::to_string(size) + " bytes, above the limit of " +
                     std::to_string(kMaxSceneFileBytes) + " bytes for a scene file");
  std::string content;
  try {
    content = io::readTextFile(file);
  } catch (const std::runtime_error& e) {
    throw InputError(e.what());
  }
  checkNesting(content, file.string() + ":");
  try {
    return toml::parse(content, file.string());
  } catch (const toml::parse_error& e) {
    const auto& at = e.source().begin;
    throw InputError(file.string() + ":" + std::to_string(at.line) + ":" + std::to_string(at.column) +
                     ": TOML syntax error: " + std::string(e.description()));
  }
}

// SceneFile::picture_text: the table without the keys that only choose outputs.
std::string pictureText(toml::table table) {
  if (toml::table* render = table["render"].as_table())
    for (const char* key : {"png", "exr", "video"}) render->erase(key);
  if (toml::table* simulation = table["simulation"].as_table()) simulation->erase("duration");
  table.erase("output");
  std::ostringstream text;
  text << table;
  return text.str();
}

}  // namespace

// Frames are capped at kMaxFrames when the scene is read: the int cannot overflow.
int SceneFile::frameCount() const { return std::max(1, static_cast<int>(std::floor(duration * fps + 1e-9))); }

SceneFile loadScene(const fs::path& file, const std::vector<std::string>& overrides, const SceneFlags& flags,
                    std::uint64_t max_memory) {
  SceneFile scene;
  scene.file = file;
  scene.name = file.stem().string();
  if (const std::string problem = identifierProblem(scene.name); !problem.empty())
    throw InputError(file.string() + ": the scene name " + quotedName(scene.name) +
                     " (the file name without .toml) is " + problem);
  scene.memory_budget = max_memory > 0 ? max_memory : memoryBudget();
  toml::table table = parseFile(file);
  for (const std::string& o : overrides) {
    checkNesting(o, "--set " + o.substr(0, 40) + ": line ");
    applyOverride(table, o);
  }
  const SceneFlags used = flags.yieldingTo(overrides);  // --set render.noise_threshold wins over --spp's
  applyFlags(table, used);
  std::ostringstream text;
  text << table;
  scene.text = text.str();

  TableReader root(table, file, "", &used, &scene.files);
  Vec3 gravity;
  readSimulation(root.child("simulation"), scene, gravity);
  scene.system = std::make_unique<MassSpringSystem>(gravity);
  readOutput(root.child("output"), scene);
  if (root.table("contact"))
    scene.system->setContactSettings(readContactTable(root.child("contact"), scene.integrator_options));
  if (const toml::table* bodies = root.table("bodies")) scene.body_count = int(bodies->size());
  readGroup(root, "bodies", scene, readBody);
  readGroup(root, "colliders", scene, readCollider);
  readRenderTables(root, scene);
  if (scene.render.options.png || scene.render.options.exr) {  // the render buffers count once the scene renders
    SceneEstimate e = scene.estimate;
    e.render_pixels = std::int64_t(scene.render.camera.resolution[0]) * scene.render.camera.resolution[1];
    if (e.bytes(integratorTraits(scene.integrator).implicit) > scene.memory_budget) {
      TableReader camera = root.child("camera");
      failOverBudget(camera, scene, "resolution", e, "; a smaller camera.resolution (or --resolution) would fit");
    }
    scene.estimate = e;
  }
  if (scene.system->bodies().empty())
    root.fail("bodies", "a scene needs at least one body: [bodies.NAME] with type = \"jelly\" or \"cloth\"");
  root.finish();
  // What a picture shows depends on the files' bytes, not on where they are: a run folder's carried copies
  // (carried_scene.h) render the frames of the original to the byte.
  scene.picture_text = pictureText(withFileValues(table, scene.files, [](const SceneFileUse& use) {
    io::ContentHash h;
    h.addFile(use.path);
    return "content " + h.hex();
  }));
  return scene;
}

}  // namespace wobble
