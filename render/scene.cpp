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
  TriangleMesh mesh;  // CPU copy for interpolation (Mesh, Quad, Box): the last pose
  Quad quad;          // Quad
  Box box;            // Box
  Sphere sphere;      // Sphere
  Bounds bounds;      // set by commit(): around every pose
  // Motion blur (more than one pose): each pose's positions and normals (normals empty: mesh.normals throughout), or
  // the sphere's poses. Empty for a still shape.
  std::vector<std::vector<Vector3f>> poses, pose_normals;
  std::vector<Sphere> sphere_poses;
  std::unique_ptr<EmbreeTriangleMesh> rtc_mesh;
  std::unique_ptr<EmbreeSphere> rtc_sphere;

  bool moving() const { return !poses.empty() || !sphere_poses.empty(); }
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

// Where a ray's time falls among `count` evenly spaced poses: between pose i and i + 1, at weight w of the way (as
// Embree interpolates).
struct PoseBlend {
  int i = 0;
  float w = 0;
};
PoseBlend poseBlend(std::size_t count, float time) {
  if (count < 2) return {};
  const float f = std::clamp(time, 0.0f, 1.0f) * float(count - 1);
  const int i = std::min(static_cast<int>(f), static_cast<int>(count) - 2);
  return {i, f - float(i)};
}

template <typename T>
T blend(const T& a, const T& b, float w) {
  return (1 - w) * a + w * b;
}

// The three corners (and shading normals) of triangle `primitive` at a ray's time.
struct TriangleAt {
  Vector3f p[3], n[3];
  bool normals = false;
};
template <typename ShapeT>
TriangleAt triangleAt(const ShapeT& s, int primitive, float time) {
  TriangleAt t;
  const auto& tri = s.mesh.triangles[primitive];
  const PoseBlend b = poseBlend(s.poses.size(), time);
  for (int k = 0; k < 3; ++k)
    t.p[k] = s.poses.empty() ? s.mesh.positions[tri[k]] : blend(s.poses[b.i][tri[k]], s.poses[b.i + 1][tri[k]], b.w);
  if (!s.pose_normals.empty()) {
    for (int k = 0; k < 3; ++k) t.n[k] = blend(s.pose_normals[b.i][tri[k]], s.pose_normals[b.i + 1][tri[k]], b.w);
    t.normals = true;
  } else if (!s.mesh.normals.empty()) {
    for (int k = 0; k < 3; ++k) t.n[k] = s.mesh.normals[tri[k]];
    t.normals = true;
  }
  return t;
}

template <typename ShapeT>
Sphere sphereAt(const ShapeT& s, float time) {
  if (s.sphere_poses.empty()) return s.sphere;
  const PoseBlend b = poseBlend(s.sphere_poses.size(), time);
  const Sphere &a = s.sphere_poses[b.i], &c = s.sphere_poses[b.i + 1];
  return {blend(a.center, c.center, b.w), blend(a.radius, c.radius, b.w)};
}

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

const Bounds& Scene::bounds(ShapeId id) const { return shapes_.at(id)->bounds; }

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
  const MeshPose pose{positions, normals};
  updateMeshMotion(id, {&pose, 1});
}

void Scene::updateMeshMotion(ShapeId id, std::span<const MeshPose> poses) {
  Shape& s = shape(id, "mesh");
  if (poses.empty()) throw std::invalid_argument("mesh '" + s.name + "': no pose");
  const std::size_t n = s.mesh.positions.size();
  const bool with_normals = !poses.front().normals.empty();
  for (const MeshPose& pose : poses) {
    if (pose.positions.size() != n)
      throw std::invalid_argument("mesh '" + s.name + "': " + std::to_string(pose.positions.size()) +
                                  " positions, but the mesh has " + std::to_string(n) + " vertices");
    if ((!pose.normals.empty() || with_normals) && pose.normals.size() != n)
      throw std::invalid_argument("mesh '" + s.name + "': " + std::to_string(pose.normals.size()) +
                                  " normals, but the mesh has " + std::to_string(n) + " vertices");
    checkFinite(s.name, "position", pose.positions);
    checkFinite(s.name, "normal", pose.normals);
  }
  const MeshPose& last = poses.back();
  s.mesh.positions.assign(last.positions.begin(), last.positions.end());
  if (with_normals) s.mesh.normals.assign(last.normals.begin(), last.normals.end());
  s.poses.clear();
  s.pose_normals.clear();
  if (poses.size() > 1)
    for (const MeshPose& pose : poses) {
      s.poses.emplace_back(pose.positions.begin(), pose.positions.end());
      if (with_normals) s.pose_normals.emplace_back(pose.normals.begin(), pose.normals.end());
    }
  std::vector<std::span<const Vector3f>> steps;
  for (const MeshPose& pose : poses) steps.push_back(pose.positions);
  s.rtc_mesh->setVertices(steps);
  device_->check("mesh '" + s.name + "': updating vertices");
  committed_ = false;
}

bool Scene::moving(ShapeId id) const { return shapes_.at(id)->moving(); }

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
void Scene::updateShaped(ShapeId id, std::span<const Shaped> poses) {
  Shape& s = shape(id, kKindNames[static_cast<int>(Shape::kindOf(poses.front()))]);
  s.poses.clear();
  std::vector<std::span<const Vector3f>> steps;
  if (poses.size() > 1) {
    for (const Shaped& pose : poses) {
      s.set(pose);
      s.poses.push_back(s.mesh.positions);
    }
    steps.assign(s.poses.begin(), s.poses.end());
  } else {
    s.set(poses.front());
    steps.push_back(s.mesh.positions);
  }
  s.rtc_mesh->setVertices(steps);
  committed_ = false;
}

ShapeId Scene::addQuad(const std::string& name, const Quad& quad, MaterialId material) {
  return addShaped(name, quad, material);
}
void Scene::updateQuad(ShapeId id, const Quad& quad) { updateShaped<Quad>(id, {&quad, 1}); }
void Scene::updateQuadMotion(ShapeId id, std::span<const Quad> poses) {
  if (poses.empty()) throw std::invalid_argument("scene: quad " + std::to_string(id) + ": no pose");
  updateShaped(id, poses);
}
ShapeId Scene::addBox(const std::string& name, const Box& box, MaterialId material) {
  return addShaped(name, box, material);
}
void Scene::updateBox(ShapeId id, const Box& box) { updateShaped<Box>(id, {&box, 1}); }
void Scene::updateBoxMotion(ShapeId id, std::span<const Box> poses) {
  if (poses.empty()) throw std::invalid_argument("scene: box " + std::to_string(id) + ": no pose");
  updateShaped(id, poses);
}

ShapeId Scene::addSphere(const std::string& name, const Sphere& sphere, MaterialId material) {
  checkSphere(name, sphere);
  auto s = std::make_unique<Shape>();
  s->kind = Shape::Kind::Sphere;
  s->name = name;
  s->material = material;
  s->sphere = sphere;
  return attach(std::move(s));
}

void Scene::updateSphere(ShapeId id, const Sphere& sphere) { updateSphereMotion(id, {&sphere, 1}); }

void Scene::updateSphereMotion(ShapeId id, std::span<const Sphere> poses) {
  Shape& s = shape(id, "sphere");
  if (poses.empty()) throw std::invalid_argument("sphere '" + s.name + "': no pose");
  std::vector<EmbreeSphere::Pose> steps;
  for (const Sphere& pose : poses) {
    checkSphere(s.name, pose);
    steps.push_back({pose.center, pose.radius});
  }
  s.sphere = poses.back();
  s.sphere_poses.clear();
  if (poses.size() > 1) s.sphere_poses.assign(poses.begin(), poses.end());
  s.rtc_sphere->set(steps);
  committed_ = false;
}

void Scene::commit() {
  checkLights(lights);
  rtc_->commit();
  device_->check("scene: commit");
  for (auto& s : shapes_) {
    Bounds box;
    if (s->kind == Shape::Kind::Sphere) {
      for (const Sphere& pose : s->sphere_poses.empty() ? std::span(&s->sphere, 1) : std::span(s->sphere_poses)) {
        box.extend(pose.center - Vector3f::Constant(pose.radius));
        box.extend(pose.center + Vector3f::Constant(pose.radius));
      }
    } else {
      for (const Vector3f& p : s->mesh.positions) box.extend(p);
      for (const auto& pose : s->poses)  // the poses between are their blends: inside too
        for (const Vector3f& p : pose) box.extend(p);
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
  if (s.moving()) return false;  // its planes move over the shutter
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
  h.time = ray.time;
  if (s.kind == Shape::Kind::Sphere) {
    const Sphere sphere = sphereAt(s, ray.time);
    if (!s.sphere_poses.empty()) {
      const PoseBlend b = poseBlend(s.sphere_poses.size(), ray.time);
      h.dpdt = float(s.sphere_poses.size() - 1) * (s.sphere_poses[b.i + 1].center - s.sphere_poses[b.i].center);
    }
    const Vector3f d = (ray.at(h.t) - sphere.center).normalized();
    h.p = sphere.center + sphere.radius * d;  // back onto the surface: less self-intersection
    h.ng = h.ns = d;
    const float pi = std::numbers::pi_v<float>;
    h.uv = Vector2f(0.5f + std::atan2(d.x(), d.z()) / (2 * pi), 0.5f + std::asin(std::clamp(d.y(), -1.0f, 1.0f)) / pi);
    return h;
  }
  const auto& tri = s.mesh.triangles[rh.hit.primID];
  const float b1 = rh.hit.u, b2 = rh.hit.v, b0 = 1.0f - b1 - b2;
  const TriangleAt at = triangleAt(s, h.primitive, ray.time);
  const Vector3f &p0 = at.p[0], &p1 = at.p[1], &p2 = at.p[2];
  h.p = b0 * p0 + b1 * p1 + b2 * p2;
  const Vector3f n = (p1 - p0).cross(p2 - p0);
  h.ng = n.norm() > 0 ? n.normalized() : Vector3f(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z).normalized();
  h.ns = h.ng;
  if (at.normals) {
    const Vector3f ns = b0 * at.n[0] + b1 * at.n[1] + b2 * at.n[2];
    if (ns.norm() > 1e-12f) h.ns = ns.normalized();
  }
  h.uv = s.mesh.uv.empty() ? Vector2f::Zero()
                           : Vector2f(b0 * s.mesh.uv[tri[0]] + b1 * s.mesh.uv[tri[1]] + b2 * s.mesh.uv[tri[2]]);
  if (!s.poses.empty()) {  // the velocity of the pose segment the ray's time is in
    const PoseBlend b = poseBlend(s.poses.size(), ray.time);
    const float bary[3] = {b0, b1, b2};
    for (int k = 0; k < 3; ++k) h.dpdt += bary[k] * (s.poses[b.i + 1][tri[k]] - s.poses[b.i][tri[k]]);
    h.dpdt *= float(s.poses.size() - 1);
  }
  return h;
}

void Scene::uvDerivatives(SurfaceHit& h) const {
  h.dpdu = h.dpdv = Vector3f::Zero();
  const Shape& s = *shapes_.at(h.shape);
  if (s.kind == Shape::Kind::Sphere) {
    // u = 1/2 + longitude / 2 pi, v = 1/2 + latitude / pi (cos(latitude) = sqrt(x^2 + z^2)).
    const Sphere sphere = sphereAt(s, h.time);
    const float pi = std::numbers::pi_v<float>, r = sphere.radius;
    const Vector3f d = (h.p - sphere.center) / r;
    const float cos_lat = std::sqrt(d.x() * d.x() + d.z() * d.z());
    h.dpdu = 2 * pi * r * Vector3f(d.z(), 0, -d.x());
    if (cos_lat > 1e-6f) h.dpdv = pi * r * Vector3f(-d.x() * d.y() / cos_lat, cos_lat, -d.z() * d.y() / cos_lat);
    return;
  }
  if (s.mesh.uv.empty()) return;
  const auto& tri = s.mesh.triangles[h.primitive];
  const TriangleAt at = triangleAt(s, h.primitive, h.time);
  const Vector3f &p0 = at.p[0], &p1 = at.p[1], &p2 = at.p[2];
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
