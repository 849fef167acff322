#include "render_scene.h"

#include <memory>
#include <stdexcept>

#include "render/image_texture.h"
#include "render/texture.h"
#include "sim/colliders/elevator.h"
#include "sim/colliders/plane.h"
#include "sim/colliders/sphere.h"

namespace wobble {
namespace {

render::Color toColor(const Vec3& c) { return c.cast<float>(); }

render::Material bodyMaterial(const std::string& name, const BodyLook& look,
                              std::shared_ptr<const render::Texture> texture) {
  if (look.material == "jelly") return render::Material::jelly(name, toColor(look.color), std::move(texture));
  return render::Material{name, toColor(look.color), std::move(texture)};
}

std::shared_ptr<const render::Texture> colliderTexture(const std::string& kind) {
  if (kind == "wood") return std::make_shared<render::WoodTexture>();
  // Two squares per tile, light and mid grey: enough contrast to read motion, not so much it flickers.
  if (kind == "checker")
    return std::make_shared<render::CheckerTexture>(render::Color(0.75f, 0.75f, 0.72f),
                                                    render::Color(0.3f, 0.3f, 0.3f), 2.0f);
  return nullptr;
}

// Drawn inset by the contact tolerance: a cloth resting on the sphere keeps its particles within epsilon of it, but
// its flat triangles cut the chords between them (sagitta s^2 / 8r, ~3.5 mm on the default cloth) and would let the
// exact sphere show through as specks.
render::Sphere sphereAt(const Sphere& s, double t) {
  return {s.center(t).cast<float>(), static_cast<float>(s.radius() - s.contact().epsilon)};
}

render::Box boxAt(const Elevator& e, double t) {
  // The slab: its top face is the platform top, `thickness` deep.
  const Vec3 center = e.topCenter(t) - Vec3(0, e.thickness() / 2, 0);
  return {center.cast<float>(), Vec3(e.size(), e.thickness(), e.size()).cast<float>()};
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

RenderScene::RenderScene(const Scene& scene) {
  for (const BodySlot& slot : scene.system->bodies()) {
    const Body& body = slot.body;
    std::shared_ptr<const render::Texture> texture;
    if (const auto file = scene.textures.find(body.name); file != scene.textures.end())
      texture = std::make_shared<render::ImageTexture>(render::ImageTexture::load(file->second));
    const auto material = scene_.addMaterial(bodyMaterial(body.name, scene.render.bodies.at(body.name), texture));
    body_shapes_.push_back(scene_.addMesh(bodyMesh(body), material));
  }
  for (const auto& c : scene.system->colliders()) {
    const ColliderLook& look = scene.render.colliders.at(c->name());
    const auto material = scene_.addMaterial(
        render::Material{c->name(), toColor(look.color), colliderTexture(look.texture)});
    if (const auto* plane = dynamic_cast<const Plane*>(c.get())) {
      const double size = look.plane_size;
      const render::Quad quad{plane->point().cast<float>(), plane->normal().cast<float>(), float(size),
                              float(size / look.texture_scale)};
      scene_.addQuad(c->name(), quad, material);
    } else if (const auto* sphere = dynamic_cast<const Sphere*>(c.get())) {
      moving_.push_back({scene_.addSphere(c->name(), sphereAt(*sphere, 0), material), c.get()});
    } else if (const auto* elevator = dynamic_cast<const Elevator*>(c.get())) {
      moving_.push_back({scene_.addBox(c->name(), boxAt(*elevator, 0), material), c.get()});
    } else {
      throw std::logic_error("RenderScene: no drawing for collider '" + c->name() + "'");
    }
  }
  const RenderOptionsConfig& o = scene.render.options;
  render::SunLight sun;
  sun.direction = o.sun_direction.cast<float>();
  sun.angular_radius_deg = static_cast<float>(o.sun_radius_deg);
  scene_.lights.suns = {sun};
  scene_.lights.sky = render::Sky{};
  scene_.commit();
}

void RenderScene::update(double t, std::span<const SurfaceFrame> surfaces) {
  if (surfaces.size() != body_shapes_.size()) throw std::logic_error("RenderScene::update: wrong body count");
  for (std::size_t b = 0; b < surfaces.size(); ++b)
    scene_.updateMesh(body_shapes_[b], surfaces[b].positions, surfaces[b].normals);
  for (const MovingCollider& m : moving_) {
    if (const auto* sphere = dynamic_cast<const Sphere*>(m.collider))
      scene_.updateSphere(m.shape, sphereAt(*sphere, t));
    else if (const auto* elevator = dynamic_cast<const Elevator*>(m.collider))
      scene_.updateBox(m.shape, boxAt(*elevator, t));
  }
  scene_.commit();
}

}  // namespace wobble
