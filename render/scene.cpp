// Scene: shapes, materials and their Embree geometries; ray queries with interpolated hit data (see scene.h).
#include "render/scene.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include <Eigen/Geometry>

#include "render/embree/embree_device.h"
#include "render/embree/embree_mesh.h"
#include "render/embree/embree_scene.h"
#include "render/embree/embree_sphere.h"

namespace wobble::render {

using Eigen::Vector2f;
using Eigen::Vector3f;

struct Scene::Shape {
  enum class Kind { Mesh, Quad, Box, Sphere } kind;
  std::string name;
  MaterialId material;
  TriangleMesh mesh;  // CPU copy for interpolation (Mesh, Quad, Box)
  Quad quad;          // Quad
  Box box;            // Box
  Sphere sphere;      // Sphere
  Bounds bounds;      // set by commit()
  std::unique_ptr<EmbreeTriangleMesh> rtc_mesh;
  std::unique_ptr<EmbreeSphere> rtc_sphere;

  // A quad or a box is a triangle mesh made from its parameters, the same way when added and at every update.
  static constexpr Kind kindOf(const Quad&) { return Kind::Quad; }
  static constexpr Kind kindOf(const Box&) { return Kind::Box; }
  void set(const Quad& q) {
    mesh = quadMesh(name, q);
    quad = q;
  }
  void set(const Box& b) {
    mesh = boxMesh(name, b);
    box = b;
  }
};

namespace {

constexpr const char* kKindNames[] = {"mesh", "quad", "box", "sphere"};

}  // namespace

Scene::Scene() : device_(std::make_unique<EmbreeDevice>()), rtc_(std::make_unique<EmbreeScene>(device_->get())) {}
// Shapes (geometries) must go before the Embree scene, and the scene before the device.
Scene::~Scene() {
  shapes_.clear();
  rtc_.reset();
}
Scene::Scene(Scene&&) noexcept = default;
Scene& Scene::operator=(Scene&&) noexcept = default;

MaterialId Scene::addMaterial(Material material) {
  checkMaterial(material);
  materials_.push_back(std::move(material));
  return static_cast<MaterialId>(materials_.size() - 1);
}

const std::string& Scene::shapeName(ShapeId id) const { return shapes_.at(id)->name; }

Scene::ShapeView Scene::shapeView(ShapeId id) const {
  const Shape& s = *shapes_.at(id);
  const bool sphere = s.kind == Shape::Kind::Sphere;
  return {s.name, sphere ? nullptr : &s.mesh, sphere ? &s.sphere : nullptr, s.material};
}

RTCScene Scene::embreeScene() const { return rtc_->get(); }

Scene::Shape& Scene::shape(ShapeId id, const char* expected_kind) {
  if (id < 0 || std::size_t(id) >= shapes_.size())
    throw std::out_of_range("scene: no shape with id " + std::to_string(id));
  Shape& s = *shapes_[id];
  if (std::string(kKindNames[static_cast<int>(s.kind)]) != expected_kind)
    throw std::invalid_argument("scene: shape '" + s.name + "' is a " + kKindNames[static_cast<int>(s.kind)] +
                                ", not a " + expected_kind);
  return s;
}

ShapeId Scene::attach(std::unique_ptr<Shape> s) {
  if (s->material < 0 || std::size_t(s->material) >= materials_.size())
    throw std::invalid_argument("scene: shape '" + s->name + "' uses material " + std::to_string(s->material) +
                                ", but only " + std::to_string(materials_.size()) + " exist");
  const auto id = static_cast<ShapeId>(shapes_.size());
  if (s->kind == Shape::Kind::Sphere) {
    s->rtc_sphere = std::make_unique<EmbreeSphere>(device_->get());
    s->rtc_sphere->set(s->sphere.center, s->sphere.radius);
    rtc_->attach(s->rtc_sphere->get(), static_cast<unsigned>(id));
  } else {
    s->rtc_mesh = std::make_unique<EmbreeTriangleMesh>(device_->get(), s->mesh.triangles, s->mesh.positions.size(),
                                                       RTC_BUILD_QUALITY_MEDIUM);
    s->rtc_mesh->setVertices(s->mesh.positions);
    rtc_->attach(s->rtc_mesh->get(), static_cast<unsigned>(id));
  }
  device_->check("scene: adding shape '" + s->name + "'");
  shapes_.push_back(std::move(s));
  committed_ = false;
  return id;
}

ShapeId Scene::addMesh(TriangleMesh mesh, MaterialId material) {
  checkMesh(mesh);
  auto s = std::make_unique<Shape>();
  s->kind = Shape::Kind::Mesh;
  s->name = mesh.name;
  s->material = material;
  s->mesh = std::move(mesh);
  return attach(std::move(s));
}

void Scene::updateMesh(ShapeId id, std::span<const Vector3f> positions, std::span<const Vector3f> normals) {
  Shape& s = shape(id, "mesh");
  const std::size_t n = s.mesh.positions.size();
  if (positions.size() != n)
    throw std::invalid_argument("mesh '" + s.name + "': " + std::to_string(positions.size()) +
                                " positions, but the mesh has " + std::to_string(n) + " vertices");
  if (!normals.empty() && normals.size() != n)
    throw std::invalid_argument("mesh '" + s.name + "': " + std::to_string(normals.size()) +
                                " normals, but the mesh has " + std::to_string(n) + " vertices");
  checkFinite(s.name, "position", positions);
  checkFinite(s.name, "normal", normals);
  s.mesh.positions.assign(positions.begin(), positions.end());
  if (!normals.empty()) s.mesh.normals.assign(normals.begin(), normals.end());
  s.rtc_mesh->setVertices(s.mesh.positions);
  device_->check("mesh '" + s.name + "': updating vertices");
  committed_ = false;
}

template <typename Shaped>
ShapeId Scene::addShaped(const std::string& name, const Shaped& params, MaterialId material) {
  auto s = std::make_unique<Shape>();
  s->kind = Shape::kindOf(params);
  s->name = name;
  s->material = material;
  s->set(params);
  return attach(std::move(s));
}

template <typename Shaped>
void Scene::updateShaped(ShapeId id, const Shaped& params) {
  Shape& s = shape(id, kKindNames[static_cast<int>(Shape::kindOf(params))]);
  s.set(params);
  s.rtc_mesh->setVertices(s.mesh.positions);
  committed_ = false;
}

ShapeId Scene::addQuad(const std::string& name, const Quad& quad, MaterialId material) {
  return addShaped(name, quad, material);
}
void Scene::updateQuad(ShapeId id, const Quad& quad) { updateShaped(id, quad); }
ShapeId Scene::addBox(const std::string& name, const Box& box, MaterialId material) {
  return addShaped(name, box, material);
}
void Scene::updateBox(ShapeId id, const Box& box) { updateShaped(id, box); }

ShapeId Scene::addSphere(const std::string& name, const Sphere& sphere, MaterialId material) {
  checkSphere(name, sphere);
  auto s = std::make_unique<Shape>();
  s->kind = Shape::Kind::Sphere;
  s->name = name;
  s->material = material;
  s->sphere = sphere;
  return attach(std::move(s));
}

void Scene::updateSphere(ShapeId id, const Sphere& sphere) {
  Shape& s = shape(id, "sphere");
  checkSphere(s.name, sphere);
  s.sphere = sphere;
  s.rtc_sphere->set(sphere.center, sphere.radius);
  committed_ = false;
}

void Scene::commit() {
  checkLights(lights);
  rtc_->commit();
  device_->check("scene: commit");
  for (auto& s : shapes_) {
    Bounds box;
    if (s->kind == Shape::Kind::Sphere) {
      box.extend(s->sphere.center - Vector3f::Constant(s->sphere.radius));
      box.extend(s->sphere.center + Vector3f::Constant(s->sphere.radius));
    } else {
      for (const Vector3f& p : s->mesh.positions) box.extend(p);
    }
    s->bounds = padded(box, 1e-4f);
  }
  committed_ = true;
}

namespace {

// Whether a ray from `o` along `d` stays on its side of the plane n . x = n . c, never reaching it. The origins of
// leaving rays are offset from the surface by far more than this test's rounding (path_tracer.h).
bool awayFromPlane(const Vector3f& n, const Vector3f& c, const Vector3f& o, const Vector3f& d) {
  const float side = n.dot(o - c), heading = n.dot(d);
  return (side > 0 && heading >= 0) || (side < 0 && heading <= 0);
}

}  // namespace

bool Scene::provablyMisses(const Ray& ray, ShapeId leaving) const {
  if (leaving < 0 || std::size_t(leaving) >= shapes_.size()) return false;
  const Shape& s = *shapes_[leaving];
  const Vector3f &o = ray.origin, &d = ray.direction;
  bool away = false;
  switch (s.kind) {
    case Shape::Kind::Mesh:
      return false;
    case Shape::Kind::Quad:
      away = awayFromPlane(s.quad.normal, s.quad.center, o, d);
      break;
    case Shape::Kind::Box:  // a convex body: beyond one of its face planes and heading further out
      for (int a = 0; a < 3 && !away; ++a) {
        const float half = 0.5f * s.box.size[a];
        away = (o[a] > s.box.center[a] + half && d[a] >= 0) || (o[a] < s.box.center[a] - half && d[a] <= 0);
      }
      break;
    case Shape::Kind::Sphere:  // outside, and getting further from the centre
      away =
          (o - s.sphere.center).squaredNorm() > s.sphere.radius * s.sphere.radius && (o - s.sphere.center).dot(d) >= 0;
      break;
  }
  if (!away) return false;
  // Each other shape's own box, not one box around them all: a ray leaving the elevator upwards misses the floor's
  // flat box though the floor surrounds the elevator.
  for (const auto& other : shapes_)
    if (other.get() != &s && mayHit(other->bounds, ray)) return false;
  return true;
}

bool Scene::occluded(const Ray& ray, ShapeId leaving) const {
  return !provablyMisses(ray, leaving) && rtc_->occluded(ray);
}

std::optional<SurfaceHit> Scene::intersect(const Ray& ray, ShapeId leaving) const {
  if (provablyMisses(ray, leaving)) return std::nullopt;
  const RTCRayHit rh = rtc_->intersect(ray);
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return std::nullopt;
  const Shape& s = *shapes_[rh.hit.geomID];
  SurfaceHit h;
  h.t = rh.ray.tfar;
  h.shape = static_cast<int>(rh.hit.geomID);
  h.primitive = static_cast<int>(rh.hit.primID);
  h.material = s.material;
  if (s.kind == Shape::Kind::Sphere) {
    const Vector3f d = (ray.at(h.t) - s.sphere.center).normalized();
    h.p = s.sphere.center + s.sphere.radius * d;  // back onto the surface: less self-intersection
    h.ng = h.ns = d;
    const float pi = std::numbers::pi_v<float>;
    h.uv = Vector2f(0.5f + std::atan2(d.x(), d.z()) / (2 * pi), 0.5f + std::asin(std::clamp(d.y(), -1.0f, 1.0f)) / pi);
    return h;
  }
  const auto& tri = s.mesh.triangles[rh.hit.primID];
  const float b1 = rh.hit.u, b2 = rh.hit.v, b0 = 1.0f - b1 - b2;
  const Vector3f &p0 = s.mesh.positions[tri[0]], &p1 = s.mesh.positions[tri[1]], &p2 = s.mesh.positions[tri[2]];
  h.p = b0 * p0 + b1 * p1 + b2 * p2;
  const Vector3f n = (p1 - p0).cross(p2 - p0);
  h.ng = n.norm() > 0 ? n.normalized() : Vector3f(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z).normalized();
  h.ns = h.ng;
  if (!s.mesh.normals.empty()) {
    const Vector3f ns = b0 * s.mesh.normals[tri[0]] + b1 * s.mesh.normals[tri[1]] + b2 * s.mesh.normals[tri[2]];
    if (ns.norm() > 1e-12f) h.ns = ns.normalized();
  }
  h.uv = s.mesh.uv.empty() ? Vector2f::Zero()
                           : Vector2f(b0 * s.mesh.uv[tri[0]] + b1 * s.mesh.uv[tri[1]] + b2 * s.mesh.uv[tri[2]]);
  return h;
}

void Scene::uvDerivatives(SurfaceHit& h) const {
  h.dpdu = h.dpdv = Vector3f::Zero();
  const Shape& s = *shapes_.at(h.shape);
  if (s.kind == Shape::Kind::Sphere) {
    // u = 1/2 + longitude / 2 pi, v = 1/2 + latitude / pi (cos(latitude) = sqrt(x^2 + z^2)).
    const float pi = std::numbers::pi_v<float>, r = s.sphere.radius;
    const Vector3f d = (h.p - s.sphere.center) / r;
    const float cos_lat = std::sqrt(d.x() * d.x() + d.z() * d.z());
    h.dpdu = 2 * pi * r * Vector3f(d.z(), 0, -d.x());
    if (cos_lat > 1e-6f) h.dpdv = pi * r * Vector3f(-d.x() * d.y() / cos_lat, cos_lat, -d.z() * d.y() / cos_lat);
    return;
  }
  if (s.mesh.uv.empty()) return;
  const auto& tri = s.mesh.triangles[h.primitive];
  const Vector3f &p0 = s.mesh.positions[tri[0]], &p1 = s.mesh.positions[tri[1]], &p2 = s.mesh.positions[tri[2]];
  // Solve p1 - p0 = dpdu du1 + dpdv dv1, p2 - p0 = dpdu du2 + dpdv dv2 (pbrt's triangle derivatives).
  const Vector2f d1 = s.mesh.uv[tri[1]] - s.mesh.uv[tri[0]], d2 = s.mesh.uv[tri[2]] - s.mesh.uv[tri[0]];
  const float det = d1.x() * d2.y() - d1.y() * d2.x();
  if (std::abs(det) > 1e-12f) {
    const Vector3f e1 = p1 - p0, e2 = p2 - p0;
    h.dpdu = (d2.y() * e1 - d1.y() * e2) / det;
    h.dpdv = (d1.x() * e2 - d2.x() * e1) / det;
  }
}

}  // namespace wobble::render
