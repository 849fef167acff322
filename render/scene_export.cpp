// Scene + camera as OBJ, JSON and baked textures (see scene_export.h).
#include "render/scene_export.h"

#include <fstream>
#include <stdexcept>

#include <tbb/parallel_for.h>
#include <nlohmann/json.hpp>

#include "image/png_io.h"

namespace wobble::render {

namespace {

nlohmann::json vec(const Eigen::Vector3f& v) { return {v.x(), v.y(), v.z()}; }

}  // namespace

image::Image8 bakeTexture(const Texture& texture, int size) { return bakeTexture(texture, {0, 0}, {1, 1}, size, size); }

image::Image8 bakeTexture(const Texture& texture, const Eigen::Vector2f& lo, const Eigen::Vector2f& hi, int width,
                          int height) {
  image::Image8 baked(width, height, 3);
  const Eigen::Vector2f texel((hi.x() - lo.x()) / float(width), (hi.y() - lo.y()) / float(height));
  TextureFootprint footprint;  // each texel the texture's mean over it (texture.h: closed form, or a grid of lookups)
  footprint.duvdx = {texel.x(), 0};
  footprint.duvdy = {0, texel.y()};
  tbb::parallel_for(0, height, [&](int y) {
    for (int x = 0; x < width; ++x) {
      // Row 0 is the top of the image, v = hi (OBJ convention, as ImageTexture reads it).
      const Eigen::Vector2f uv(lo.x() + (float(x) + 0.5f) * texel.x(), hi.y() - (float(y) + 0.5f) * texel.y());
      const Color c = texture.evalFootprint(uv, footprint);
      for (int k = 0; k < 3; ++k) baked.at(x, y, k) = linearToSrgb8(c[k]);
    }
  });
  return baked;
}

void exportScene(const Scene& scene, const Camera& camera, const std::filesystem::path& dir) {
  std::filesystem::create_directories(dir);
  nlohmann::ordered_json j;
  const CameraParams& c = camera.params();
  j["camera"] = {{"position", vec(c.position)}, {"look_at", vec(c.look_at)}, {"up", vec(c.up)},
                 {"vfov_deg", c.vfov_deg},      {"width", c.width},          {"height", c.height}};
  j["suns"] = nlohmann::json::array();
  for (const SunLight& s : scene.lights.suns)
    j["suns"].push_back({{"direction", vec(s.direction.normalized())},
                         {"irradiance", vec(s.irradiance)},
                         {"angular_radius_deg", s.angular_radius_deg}});
  j["area_lights"] = nlohmann::json::array();
  for (const RectLight& r : scene.lights.rects)
    j["area_lights"].push_back({{"corner", vec(r.corner)},
                                {"edge_u", vec(r.edge_u)},
                                {"edge_v", vec(r.edge_v)},
                                {"radiance", vec(r.radiance)}});
  const Sky& sky = scene.lights.sky;
  j["sky"] = {{"zenith", vec(sky.zenith)},
              {"horizon", vec(sky.horizon)},
              {"ground", vec(sky.ground)},
              {"up", vec(sky.up.normalized())},
              {"model",
               "elevation e = d.up: horizon + sqrt(e) (zenith - horizon) for e >= 0, "
               "horizon + sqrt(min(1, -4 e)) (ground - horizon) below"}};
  if (const auto& env = scene.lights.environment; env && !env->file().empty())  // environment.h: replaces the sky
    j["environment"] = {{"file", std::filesystem::absolute(env->file()).lexically_normal().string()},
                        {"rotation_deg", env->rotationDeg()},
                        {"strength", env->strength()}};
  j["materials"] = nlohmann::json::array();
  for (std::size_t m = 0; m < scene.materialCount(); ++m) {
    const Material& mat = scene.material(MaterialId(m));
    nlohmann::ordered_json entry = {{"name", mat.name}, {"color", vec(mat.color)},    {"coat", mat.coat},
                                    {"ior", mat.ior},   {"roughness", mat.roughness}, {"texture", nullptr}};
    if (mat.dielectric)  // gelatine (dielectric.h): sigma_a and sigma_s per metre
      entry.update({{"dielectric", true},
                    {"absorption", vec(mat.absorption)},
                    {"scatter", mat.scatter},
                    {"scatter_albedo", vec(mat.scatter_albedo)},
                    {"print", mat.print}});
    if (mat.texture) {
      const std::string file = "texture_" + std::to_string(m) + ".png";
      image::writePng(dir / file, bakeTexture(*mat.texture));
      entry["texture"] = file;
    }
    j["materials"].push_back(entry);
  }

  std::ofstream obj(dir / "scene.obj");
  obj << "# wobble frame: every triangle mesh of the scene, world space, Y up (scene.json has the rest)\n";
  std::size_t base = 1;  // OBJ indices are 1-based and global
  j["shapes"] = nlohmann::json::array();
  for (std::size_t id = 0; id < scene.shapeCount(); ++id) {
    const Scene::ShapeView s = scene.shapeView(ShapeId(id));
    nlohmann::ordered_json shape = {{"name", s.name}, {"material", s.material}};
    if (s.sphere) {
      shape["sphere"] = {{"center", vec(s.sphere->center)}, {"radius", s.sphere->radius}};
      j["shapes"].push_back(shape);
      continue;
    }
    shape["obj_object"] = s.name;
    j["shapes"].push_back(shape);
    const TriangleMesh& m = *s.mesh;
    obj << "o " << s.name << "\n";
    for (const auto& p : m.positions) obj << "v " << p.x() << " " << p.y() << " " << p.z() << "\n";
    for (const auto& t : m.uv) obj << "vt " << t.x() << " " << t.y() << "\n";
    for (const auto& n : m.normals) obj << "vn " << n.x() << " " << n.y() << " " << n.z() << "\n";
    const bool uv = !m.uv.empty(), normals = !m.normals.empty();
    for (const auto& tri : m.triangles) {
      obj << "f";
      for (int k = 0; k < 3; ++k) {
        const std::size_t i = base + std::size_t(tri[k]);
        obj << " " << i;
        if (uv || normals) obj << "/" << (uv ? std::to_string(i) : "");
        if (normals) obj << "/" << i;
      }
      obj << "\n";
    }
    base += m.positions.size();
  }
  obj.close();
  if (!obj) throw std::runtime_error((dir / "scene.obj").string() + ": cannot write");
  std::ofstream out(dir / "scene.json");
  out << j.dump(2) << "\n";
  out.close();
  if (!out) throw std::runtime_error((dir / "scene.json").string() + ": cannot write");
}

}  // namespace wobble::render
