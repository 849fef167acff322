#include "app/pictures/render_scene.h"

#include <memory>
#include <stdexcept>
#include <type_traits>
#include <variant>

#include "app/scene/collider_kinds.h"
#include "app/scene/input_error.h"
#include "app/scene/material_kinds.h"
#include "render/image_texture.h"
#include "render/texture.h"

namespace wobble {
namespace {

image::Color toColor(const Vec3& c) { return c.cast<float>(); }

std::shared_ptr<const render::Texture> colliderTexture(const std::string& kind) {
  if (kind == "wood") return std::make_shared<render::WoodTexture>();
  // Two squares per tile, light and mid grey: enough contrast to read motion, not so much it flickers.
  if (kind == "checker")
    return std::make_shared<render::CheckerTexture>(image::Color(0.75f, 0.75f, 0.72f), image::Color(0.3f, 0.3f, 0.3f),
                                                    2.0f);
  return nullptr;
}

// The renderer's shapes, in float, for a collider's drawn shape (collider_kinds.h).
render::Quad toRender(const DrawnQuad& q) {
  return {q.center.cast<float>(), q.normal.cast<float>(), float(q.size), float(q.size / q.tile)};
}
render::Sphere toRender(const DrawnSphere& s) { return {s.center.cast<float>(), static_cast<float>(s.radius)}; }
render::Box toRender(const DrawnBox& b) { return {b.center.cast<float>(), b.size.cast<float>()}; }

// A mesh collider flat-shaded: each triangle its own three vertices and face normal (stairs keep sharp steps); UVs are
// the x-z position in metres, so a texture tiles across the floor plan.
render::TriangleMesh toRender(const DrawnMesh& m, const std::string& name) {
  render::TriangleMesh mesh;
  mesh.name = name;
  for (const auto& t : *m.triangles) {
    const Vec3 a = (*m.points)[t[0]] + m.center, b = (*m.points)[t[1]] + m.center, c = (*m.points)[t[2]] + m.center;
    const Vec3 n = (b - a).cross(c - a);
    const Eigen::Vector3f normal = (n.norm() > 0 ? Vec3(n.normalized()) : Vec3::UnitY()).cast<float>();
    const int base = static_cast<int>(mesh.positions.size());
    for (const Vec3& p : {a, b, c}) {
      mesh.positions.push_back(p.cast<float>());
      mesh.normals.push_back(normal);
      mesh.uv.emplace_back(float(p.x()), float(p.z()));
    }
    mesh.triangles.push_back({base, base + 1, base + 2});
  }
  return mesh;
}

// An environment map lights the scene alone: it replaces the sky, and the sun (an outdoor map holds its own).
render::Lights environmentLights(const EnvironmentConfig& env) {
  render::Lights lights;
  try {
    lights.environment = std::make_shared<const render::EnvironmentMap>(
        render::EnvironmentMap::load(env.file, float(env.rotation_deg), float(env.strength)));
  } catch (const std::exception& e) {  // unreadable pixels: the header was checked when the scene was read
    throw InputError(std::string(e.what()) + " (render.environment)");
  }
  return lights;
}

render::TriangleMesh bodyMesh(const Body& body) {
  const SurfaceFrame frame = evaluateSurface(body.surface, body.x, 0);
  render::TriangleMesh mesh;
  mesh.name = body.name;
  mesh.positions = frame.positions;
  mesh.normals = frame.normals;
  mesh.uv = body.surface.uv;
  mesh.triangles = body.surface.triangles;
  return mesh;
}

}  // namespace

RenderScene::RenderScene(const SceneFile& scene) {
  for (const BodySlot& slot : scene.system->bodies()) {
    const Body& body = slot.body;
    const BodyLook& look = scene.render.bodies.at(body.name);
    std::shared_ptr<const render::Texture> texture;
    if (const auto file = scene.textures.find(body.name); file != scene.textures.end())
      texture = std::make_shared<render::ImageTexture>(render::ImageTexture::load(file->second));
    const auto material = scene_.addMaterial(materialKind(look.material).make(body.name, look, texture));
    body_shapes_.push_back(scene_.addMesh(bodyMesh(body), material));
  }
  for (const auto& c : scene.system->colliders()) {
    const ColliderLook& look = scene.render.colliders.at(c->name());
    const ColliderKind& kind = colliderKind(look.type);
    const auto material =
        scene_.addMaterial(render::Material{c->name(), toColor(look.color), colliderTexture(look.texture)});
    const render::ShapeId shape = std::visit(
        [&](const auto& drawn) {
          using Drawn = std::decay_t<decltype(drawn)>;
          if constexpr (std::is_same_v<Drawn, DrawnQuad>) return scene_.addQuad(c->name(), toRender(drawn), material);
          if constexpr (std::is_same_v<Drawn, DrawnSphere>)
            return scene_.addSphere(c->name(), toRender(drawn), material);
          if constexpr (std::is_same_v<Drawn, DrawnBox>) return scene_.addBox(c->name(), toRender(drawn), material);
          if constexpr (std::is_same_v<Drawn, DrawnMesh>) return scene_.addMesh(toRender(drawn, c->name()), material);
        },
        kind.drawn(*c, look, 0));
    if (kind.moves) moving_.push_back({shape, c.get(), &kind, look});
  }
  const RenderOptionsConfig& o = scene.render.options;
  render::SunLight sun;
  sun.direction = o.sun_direction.cast<float>();
  sun.angular_radius_deg = static_cast<float>(o.sun_radius_deg);
  scene_.lights.suns = {sun};
  scene_.lights.sky = render::Sky{};
  if (o.environment.named()) scene_.lights = environmentLights(o.environment);
  scene_.commit();
}

void RenderScene::update(double t, std::span<const SurfaceFrame> surfaces) {
  const std::vector<SurfaceFrame> pose(surfaces.begin(), surfaces.end());
  update({&t, 1}, {&pose, 1});
}

void RenderScene::update(std::span<const double> times, std::span<const std::vector<SurfaceFrame>> poses) {
  if (times.empty() || poses.size() != times.size()) throw std::logic_error("RenderScene::update: a pose per time");
  for (const auto& surfaces : poses)
    if (surfaces.size() != body_shapes_.size()) throw std::logic_error("RenderScene::update: wrong body count");
  for (std::size_t b = 0; b < body_shapes_.size(); ++b) {
    std::vector<render::Scene::MeshPose> mesh_poses;
    for (const auto& surfaces : poses) mesh_poses.push_back({surfaces[b].positions, surfaces[b].normals});
    scene_.updateMeshMotion(body_shapes_[b], mesh_poses);
  }
  for (const MovingCollider& m : moving_) {
    std::vector<DrawnShape> drawn;
    for (const double t : times) drawn.push_back(m.kind->drawn(*m.collider, m.look, t));
    std::visit(
        [&](const auto& first) {
          using Drawn = std::decay_t<decltype(first)>;
          const auto all = [&](const auto& convert) {
            std::vector<std::decay_t<decltype(convert(first))>> out;
            for (const DrawnShape& d : drawn) out.push_back(convert(std::get<Drawn>(d)));
            return out;
          };
          if constexpr (std::is_same_v<Drawn, DrawnQuad>)
            scene_.updateQuadMotion(m.shape, all([](const DrawnQuad& q) { return toRender(q); }));
          if constexpr (std::is_same_v<Drawn, DrawnSphere>)
            scene_.updateSphereMotion(m.shape, all([](const DrawnSphere& q) { return toRender(q); }));
          if constexpr (std::is_same_v<Drawn, DrawnBox>)
            scene_.updateBoxMotion(m.shape, all([](const DrawnBox& q) { return toRender(q); }));
          if constexpr (std::is_same_v<Drawn, DrawnMesh>) {
            const auto meshes = all([&](const DrawnMesh& q) { return toRender(q, m.collider->name()); });
            std::vector<render::Scene::MeshPose> mesh_poses;
            for (const render::TriangleMesh& mesh : meshes) mesh_poses.push_back({mesh.positions, mesh.normals});
            scene_.updateMeshMotion(m.shape, mesh_poses);
          }
        },
        drawn.front());
  }
  scene_.commit();
}

}  // namespace wobble
