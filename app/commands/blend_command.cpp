#include "app/commands/blend_command.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <functional>
#include <map>
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
#include "app/pictures/render_scene.h"
#include "app/run/camera_rig.h"
#include "app/scene/collider_kinds.h"
#include "app/scene/input_error.h"
#include "app/scene/scene_file.h"
#include "image/png_io.h"
#include "io/atomic_file.h"
#include "io/text_file.h"
#include "render/image_texture.h"
#include "render/scene_export.h"

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

// The files written for the .blend (baked textures, the environment map's copy), in OUT/blender/; each written
// atomically, and the new ones removed again unless commit() is called (a failed Blender leaves none behind).
class BlendFiles {
 public:
  explicit BlendFiles(const fs::path& out) : out_(out), dir_(out / "blender") {}
  ~BlendFiles() {
    if (committed_) return;
    std::error_code ignored;
    for (const fs::path& p : written_) fs::remove(p, ignored);
    if (created_dir_) fs::remove(dir_, ignored);  // only if empty
  }
  // A file for `name`, through write(temporary path); returns its path relative to OUT. An I/O error names the file
  // and the reason (exit 1).
  std::string add(const std::string& name, const std::function<void(const fs::path&)>& write) {
    const fs::path target = dir_ / name;
    const bool existed = fs::exists(target);
    try {
      if (!fs::is_directory(dir_)) created_dir_ = fs::create_directories(dir_);
      io::writeAtomically(target, write);
    } catch (const std::exception& e) {
      throw std::runtime_error(target.string() + ": cannot write this file for the .blend: " + e.what());
    }
    if (!existed) written_.push_back(target);
    return fs::relative(target, out_).generic_string();
  }
  void commit() { committed_ = true; }

 private:
  fs::path out_, dir_;
  std::vector<fs::path> written_;
  bool created_dir_ = false, committed_ = false;
};

// wobble's render::Material as cycles_nodes.material reads it; texture: a path relative to OUT, or none.
json materialJson(const render::Material& m, const std::string& texture) {
  json j = {{"name", m.name}, {"color", vec(m.color)}, {"coat", m.coat}, {"ior", m.ior}, {"roughness", m.roughness}};
  j["texture"] = texture.empty() ? json(nullptr) : json(texture);
  if (m.dielectric)
    j.update({{"dielectric", true},
              {"absorption", vec(m.absorption)},
              {"scatter", m.scatter},
              {"scatter_albedo", vec(m.scatter_albedo)},
              {"print", m.print}});
  return j;
}

// The UV rectangle a collider's shape covers, over which its procedural texture is baked (wood is not periodic: each
// board its own tone and grain), at kTexelsPerTile texels per tile of UV, at most kMaxTexels a side.
struct UvRect {
  Eigen::Vector2f lo{0, 0}, hi{1, 1};
};
constexpr int kTexelsPerTile = 256, kMaxTexels = 4096;

// Each collider as wobble draws it (collider_kinds.h, app/pictures/render_scene.cpp): a sphere, or the renderer's own
// triangles with their UVs (a plane's square, a box, a mesh), placed relative to the drawn centre; the centre at
// every frame for a moving one, else once. rects: each collider material's UV rectangle.
json colliders(const SceneFile& scene, const RunRecord& run, const render::Scene& drawn, std::map<int, UvRect>& rects) {
  json list = json::array();
  std::size_t shape = scene.system->bodies().size();  // RenderScene adds the bodies first, then the colliders
  for (const auto& c : scene.system->colliders()) {
    const ColliderLook& look = scene.render.colliders.at(c->name());
    const ColliderKind& kind = colliderKind(look.type);
    const auto centerAt = [&](double t) {
      return std::visit([](const auto& d) { return d.center; }, kind.drawn(*c, look, t));
    };
    const Vec3 center = centerAt(0);
    const render::Scene::ShapeView view = drawn.shapeView(render::ShapeId(int(shape++)));
    json entry = {{"name", c->name()}, {"material", view.material}};
    UvRect rect;  // a sphere's UVs span [0, 1]^2 (render/scene.cpp)
    if (view.sphere) {
      entry.update({{"type", "sphere"}, {"radius", view.sphere->radius}});
    } else {
      json points = json::array(), uv = json::array();
      for (const auto& p : view.mesh->positions) points.push_back(vec(Vec3(p.cast<double>() - center)));
      if (!view.mesh->uv.empty()) {
        rect.lo = rect.hi = view.mesh->uv.front();
        for (const auto& t : view.mesh->uv) {
          rect.lo = rect.lo.cwiseMin(t);
          rect.hi = rect.hi.cwiseMax(t);
          uv.push_back({t.x(), t.y()});
        }
      }
      entry.update({{"type", "mesh"}, {"points", points}, {"uv", uv}, {"triangles", view.mesh->triangles}});
    }
    entry["uv_rect"] = {rect.lo.x(), rect.lo.y(), rect.hi.x(), rect.hi.y()};
    rects[view.material] = rect;
    json centers = json::array();
    if (kind.moves)
      for (int k = run.first_frame; k <= run.last_frame; ++k) centers.push_back(vec(centerAt(scene.frameTime(k))));
    if (centers.empty()) centers.push_back(vec(center));
    entry["centers"] = centers;
    list.push_back(entry);
  }
  return list;
}

// Every material of the scene wobble draws: a body's image texture is the run's copy in OUT/mesh; a procedural one
// (wood, checker) is baked into OUT/blender/<material>.png over its collider's UV rectangle.
json materials(const SceneFile& scene, const render::Scene& drawn, const std::map<int, UvRect>& rects,
               const fs::path& out, BlendFiles& files) {
  json list = json::array();
  for (int i = 0; i < int(drawn.materialCount()); ++i) {
    const render::Material& m = drawn.material(render::MaterialId(i));
    std::string texture;
    if (dynamic_cast<const render::ImageTexture*>(m.texture.get())) {
      texture = fs::relative(out / "mesh" / scene.textures.at(m.name).filename(), out).generic_string();
    } else if (m.texture) {
      const auto found = rects.find(i);
      const UvRect rect = found == rects.end() ? UvRect{} : found->second;
      const auto texels = [](float extent) {
        return std::clamp(int(std::ceil(double(extent) * kTexelsPerTile)), 16, kMaxTexels);
      };
      const image::Image8 baked = render::bakeTexture(*m.texture, rect.lo, rect.hi, texels(rect.hi.x() - rect.lo.x()),
                                                      texels(rect.hi.y() - rect.lo.y()));
      texture = files.add(m.name + ".png", [&](const fs::path& temp) { image::writePng(temp, baked); });
    }
    list.push_back(materialJson(m, texture));
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
    if (options.scene) {  // another scene file, with the run's overrides laid over it (not the carried scene)
      r.scene = *options.scene;
      r.carried.clear();
    }
    return r;
  }();
  const SceneFile scene = loadRecordedScene(out, run);
  const fs::path mesh = out / "mesh";
  // What wobble's renderer draws (app/pictures/render_scene.h): its materials, shapes, sun and sky, or environment map.
  const RenderScene drawn(scene);

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
    bodies.push_back({{"name", name},
                      {"obj", fs::relative(obj, out).generic_string()},
                      {"pc2", fs::relative(pc2, out).generic_string()},
                      {"material", drawn.scene().shapeView(render::ShapeId(int(bodies.size()))).material}});
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
  const render::Lights& lights = drawn.scene().lights;
  BlendFiles files(out);
  json suns = json::array();
  for (const render::SunLight& sun : lights.suns)
    suns.push_back({{"direction", vec(sun.direction.normalized())},
                    {"irradiance", vec(sun.irradiance)},
                    {"angular_radius_deg", sun.angular_radius_deg}});
  std::map<int, UvRect> rects;
  json manifest = {{"scene", scene.name},
                   {"out_dir", fs::absolute(out).lexically_normal().string()},
                   {"fps", scene.fps},
                   {"frame_start", run.first_frame},
                   {"frame_end", run.last_frame},
                   {"resolution", {scene.render.camera.resolution[0], scene.render.camera.resolution[1]}},
                   {"bodies", bodies},
                   {"colliders", colliders(scene, run, drawn.scene(), rects)},
                   {"camera", camera},
                   {"suns", suns},
                   {"sky",
                    {{"zenith", vec(lights.sky.zenith)},
                     {"horizon", vec(lights.sky.horizon)},
                     {"ground", vec(lights.sky.ground)},
                     {"up", vec(lights.sky.up)}}},
                   {"bounces", o.bounces},
                   {"clamp_indirect", o.clamp_indirect},
                   {"shadow_caustics", o.caustics == "photons"},
                   {"exposure", o.exposure},
                   {"pack", options.pack}};
  manifest["materials"] = materials(scene, drawn.scene(), rects, out, files);
  if (lights.environment) {  // render/environment.h: replaces the sun and the sky; a copy beside the .blend
    const fs::path& file = o.environment.file;
    manifest["environment"] = {{"file", "//" + files.add(file.filename().string(),
                                                         [&](const fs::path& temp) {
                                                           fs::copy_file(file, temp,
                                                                         fs::copy_options::overwrite_existing);
                                                         })},
                               {"rotation_deg", o.environment.rotation_deg},
                               {"strength", o.environment.strength}};
  }

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
  files.commit();
  report.first_frame = run.first_frame;
  report.last_frame = run.last_frame;
  report.bodies = int(bodies.size());
  report.colliders = int(scene.system->colliders().size());
  report.camera_keys = camera["views"].size() > 1 ? int(camera["views"].size()) : 0;
  return report;
}

}  // namespace wobble
