#include "app/commands/blend_command.h"

#include <fstream>
#include <type_traits>
#include <variant>

#include <nlohmann/json.hpp>

#include "app/commands/blend_script.h"
#include "app/output/external_program.h"
#include "app/output/interrupt.h"
#include "app/output/obj_sequence.h"
#include "app/output/obj_vertex_order.h"
#include "app/output/output_folder.h"
#include "app/output/pc2.h"
#include "app/output/pc2_writer.h"
#include "app/output/run_record.h"
#include "app/scene/collider_kinds.h"
#include "app/scene/input_error.h"
#include "app/scene/scene_file.h"
#include "app/view/camera_rig.h"
#include "io/atomic_file.h"
#include "io/text_file.h"

namespace fs = std::filesystem;
using nlohmann::json;

namespace wobble {
namespace {

json vec(const Vec3& v) { return {v.x(), v.y(), v.z()}; }
json vec(const Eigen::Vector3f& v) { return {v.x(), v.y(), v.z()}; }

// A body's surface at one sample of its point cache (positions only: what the follow camera needs).
SurfaceFrame surfaceAt(const Pc2File& pc2, int sample, const ObjVertexOrder& order) {
  SurfaceFrame frame;
  frame.positions.reserve(order.line_of.size());
  for (const int line : order.line_of) frame.positions.push_back(pc2.at(sample, line));
  return frame;
}

json cameraViews(const SceneFile& scene, const RunRecord& run, const std::vector<Pc2File>& caches,
                 const std::vector<ObjVertexOrder>& orders) {
  CameraRig rig(scene);
  const auto view = [&] {
    const render::CameraParams p = rig.params();
    // The lens (render/camera.h): a thin lens's radius and the plane in focus (with focus = the followed body, per
    // view); make_blend.py turns them into Blender's f-stop and focus distance.
    const float focus = p.focus > 0 ? p.focus : (p.look_at - p.position).norm();
    return json{{"position", vec(p.position)},
                {"look_at", vec(p.look_at)},
                {"up", vec(p.up)},
                {"aperture", p.aperture},
                {"focus", focus}};
  };
  json views = json::array();
  const int followed = rig.followedBody();
  if (followed < 0) return json::array({view()});
  // The run's smoothing starts at frame 1; a cache that starts later starts it at its first frame (camera_rig.h).
  for (int k = run.first_frame; k <= run.last_frame; ++k) {
    rig.observe(k, surfaceAt(caches[followed], k - run.first_frame, orders[followed]));
    views.push_back(view());
  }
  return views;
}

json colliders(const SceneFile& scene, const RunRecord& run) {
  json list = json::array();
  for (const auto& c : scene.system->colliders()) {
    const ColliderLook& look = scene.render.colliders.at(c->name());
    json entry = {{"name", c->name()}, {"color", vec(look.color)}, {"texture", look.texture}};
    // The shape the renderer draws (collider_kinds.h), in the scene's doubles; a moving one's centre at every frame.
    const ColliderKind& kind = colliderKind(look.type);
    std::visit(
        [&](const auto& drawn) {
          using Drawn = std::decay_t<decltype(drawn)>;
          if constexpr (std::is_same_v<Drawn, DrawnQuad>)
            entry.update({{"type", "plane"},
                          {"point", vec(drawn.center)},
                          {"normal", vec(drawn.normal)},
                          {"size", drawn.size},
                          {"texture_scale", drawn.tile}});
          if constexpr (std::is_same_v<Drawn, DrawnSphere>)
            entry.update({{"type", "sphere"}, {"radius", drawn.radius}});
          if constexpr (std::is_same_v<Drawn, DrawnBox>)
            entry.update({{"type", "box"}, {"size", {drawn.size.x(), drawn.size.y(), drawn.size.z()}}});
          if constexpr (std::is_same_v<Drawn, DrawnMesh>) {  // points at t = 0; `centers` are the offsets
            json points = json::array();
            for (const Vec3& p : *drawn.points) points.push_back(vec(p));
            entry.update({{"type", "mesh"}, {"points", points}, {"triangles", *drawn.triangles}});
          }
        },
        kind.drawn(*c, look, 0));
    if (kind.moves) {
      json centers = json::array();
      for (int k = run.first_frame; k <= run.last_frame; ++k)
        centers.push_back(
            vec(std::visit([](const auto& d) { return d.center; }, kind.drawn(*c, look, scene.frameTime(k)))));
      if (!centers.empty()) entry["centers"] = centers;
    }
    list.push_back(entry);
  }
  return list;
}

// Removes the files and folders it names when it goes out of scope: the manifest, the scripts and Blender's log.
struct TemporaryFiles {
  std::vector<fs::path> paths;
  ~TemporaryFiles() {
    std::error_code ignored;
    for (const fs::path& p : paths) fs::remove_all(p, ignored);
  }
};

std::string tail(const fs::path& log, std::size_t chars) {
  std::ifstream in(log);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  return text.size() > chars ? "..." + text.substr(text.size() - chars) : text;
}

}  // namespace

BlendReport makeBlend(const BlendOptions& options) {
  const fs::path out = options.out;
  const RunRecord run = [&] {
    RunRecord r = readRunRecord(out, " (wobble run SCENE --pc2 --out " + out.string() + ")");
    if (options.scene) r.scene = *options.scene;
    return r;
  }();
  const SceneFile scene = loadScene(run.scene, run.overrides);
  const fs::path mesh = out / "mesh";

  // The inputs, checked before Blender starts: every body's base mesh and a point cache of the run's frames.
  std::vector<ObjVertexOrder> orders;
  std::vector<Pc2File> caches;
  json bodies = json::array();
  for (const BodySlot& slot : scene.system->bodies()) {
    const std::string& name = slot.body.name;
    const fs::path pc2 = Pc2Writer::path(mesh, name), obj = ObjSequenceWriter::basePath(mesh, name);
    for (const fs::path& p : {pc2, obj})
      if (!fs::is_regular_file(p))
        throw InputError(p.string() + ": not found: the run wrote no point cache for body '" + name +
                         "' (rerun with --pc2, or set pc2 = true in the scene's [output] table)");
    orders.emplace_back(slot.body.surface);
    try {
      caches.push_back(readPc2(pc2));
    } catch (const std::runtime_error& e) {
      throw InputError(e.what());
    }
    const Pc2Header& h = caches.back().header;
    if (std::size_t(h.points) != orders.back().size() || h.start_frame != float(run.first_frame) ||
        h.samples != run.last_frame - run.first_frame + 1)
      throw InputError(pc2.string() + ": " + std::to_string(h.points) + " points from frame " +
                       std::to_string(int(h.start_frame)) + ", " + std::to_string(h.samples) + " samples; the run (" +
                       (out / "run.json").string() + ") wrote frames " + std::to_string(run.first_frame) + ".." +
                       std::to_string(run.last_frame) + " of a body with " + std::to_string(orders.back().size()) +
                       " surface particles (has " + run.scene.string() + " changed since?)");
    const BodyLook& look = scene.render.bodies.at(name);
    const auto texture = scene.textures.find(name);
    bodies.push_back(
        {{"name", name},
         {"obj", fs::relative(obj, out).string()},
         {"pc2", fs::relative(pc2, out).string()},
         {"color", vec(look.color)},
         {"material", look.material},
         {"gelatine",
          {{"ior", look.gelatine.ior},
           {"roughness", look.gelatine.roughness},
           {"absorption_color", vec(look.gelatine.absorption_color)},
           {"absorption_depth", look.gelatine.absorption_depth},
           {"scatter", look.gelatine.scatter},
           {"scatter_albedo", vec(look.gelatine.scatter_albedo)},
           {"print", look.gelatine.print}}},
         {"texture",
          texture == scene.textures.end() ? "" : fs::relative(mesh / texture->second.filename(), out).string()}});
  }

  const auto blender = findProgram("blender");
  if (!blender)
    throw std::runtime_error("blender not found on PATH: cannot build " + (out / (scene.name + ".blend")).string() +
                             " (install Blender 3.4 or later, e.g. apt-get install blender; the point caches in " +
                             mesh.string() + " also load by hand: docs/blender.md)");

  const OutputFolder folder(out);  // not while a run writes there
  const json camera = {{"fov_deg", scene.render.camera.fov_deg},
                       {"shutter", scene.render.camera.shutter},
                       {"views", cameraViews(scene, run, caches, orders)}};
  const RenderOptionsConfig& o = scene.render.options;
  json manifest = {{"scene", scene.name},
                   {"out_dir", fs::absolute(out).lexically_normal().string()},
                   {"fps", scene.fps},
                   {"frame_start", run.first_frame},
                   {"frame_end", run.last_frame},
                   {"resolution", {scene.render.camera.resolution[0], scene.render.camera.resolution[1]}},
                   {"bodies", bodies},
                   {"colliders", colliders(scene, run)},
                   {"camera", camera},
                   {"sun", {{"direction", vec(o.sun_direction)}, {"angle_deg", 2 * o.sun_radius_deg}}}};
  if (o.environment.named())  // render/environment.h: replaces the sun and the sky
    manifest["environment"] = {{"file", fs::absolute(o.environment.file).lexically_normal().string()},
                               {"rotation_deg", o.environment.rotation_deg},
                               {"strength", o.environment.strength}};

  BlendReport report;
  report.blend = out / (scene.name + ".blend");
  TemporaryFiles temporary;
  const fs::path manifest_file = io::temporarySibling(report.blend, "tmp");
  // The script and the module it imports, in a folder of their own.
  const fs::path scripts = io::temporarySibling(out / "blender-scripts", "tmp");
  const fs::path script = scripts / "make_blend.py";
  const fs::path log = io::temporarySibling(out / "blender.log", "tmp");
  // Absolute: Blender's save operator refuses a relative file path (`wobble blend out/scene` from the project root).
  const fs::path partial = fs::absolute(io::temporarySibling(report.blend, "partial"));
  temporary.paths = {manifest_file, scripts, log, partial};
  io::writeTextFile(manifest_file, manifest.dump(1) + "\n");
  fs::create_directory(scripts);
  io::writeTextFile(script, kBlendScript);
  io::writeTextFile(scripts / "cycles_nodes.py", kCyclesNodes);
  const int status = runProgram({blender->string(), "-b", "--factory-startup", "--python-exit-code", "1", "--python",
                                 script.string(), "--", manifest_file.string(), partial.string()},
                                log);
  if (interrupted()) {
    report.interrupted = true;
    return report;
  }
  if (status != 0 || !fs::is_regular_file(partial))
    throw std::runtime_error("blender failed building " + report.blend.string() + " (exit status " +
                             std::to_string(status) + "):\n" + tail(log, 2000));
  fs::rename(partial, report.blend);
  report.first_frame = run.first_frame;
  report.last_frame = run.last_frame;
  report.bodies = int(bodies.size());
  report.colliders = int(scene.system->colliders().size());
  report.camera_keys = camera["views"].size() > 1 ? int(camera["views"].size()) : 0;
  return report;
}

}  // namespace wobble
